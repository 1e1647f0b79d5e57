#!/usr/bin/env bash
# Cooks every shipped example (frame 1, its output node) and prints its content hash:
# run before and after a refactor, and `diff` the two lists.
set -euo pipefail
cd "$(dirname "$0")/.."
geode="${GEODE:-target/release/geode}"
out="$(mktemp -d)"
trap 'rm -rf "$out"' EXIT
for ex in examples/*.json; do
    name="$(basename "$ex" .json)"
    if "$geode" cook "$ex" -o "$out/$name.bgeo" >/dev/null 2>"$out/$name.log"; then
        hash="$("$geode" info "$out/$name.bgeo" --json | sed -n 's/.*"content_hash": *"\([0-9a-f]*\)".*/\1/p')"
        echo "$name $hash"
    else
        echo "$name cook-failed: $(tail -1 "$out/$name.log")"
    fi
done
