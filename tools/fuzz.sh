#!/usr/bin/env bash
# Fuzzes geode's parsers and readers without cargo-fuzz: builds fuzz/ with
# libFuzzer and sanitizer coverage the way `cargo fuzz build` does (stable
# toolchain), runs each target for GEODE_FUZZ_SECONDS (default 60) over a
# scratch corpus seeded from fuzz/seeds/<target> (and the examples or test
# files the repository holds for it), and fails naming any
# crashing input, which it first copies into the regression folder that the
# test suite replays.
#
#   bash tools/fuzz.sh                    # the default targets, 60 s each
#   GEODE_FUZZ_SECONDS=10 bash tools/fuzz.sh hyperfun vm
#   GEODE_FUZZ_TARGETS=all bash tools/fuzz.sh
#
# The build goes to $CARGO_TARGET_DIR if set, else fuzz/target.
set -euo pipefail
cd "$(dirname "$0")/.."
root="$PWD"

seconds="${GEODE_FUZZ_SECONDS:-60}"
# The parsers issue 33 asked to be fuzzed in CI and the wrangle compiler
# (issue 34; seeds: the real snippets, `tools/vex_mutate.py --write-seeds`),
# the VDB reader (issue 37; seeds: OpenVDB's files and geode's);
# `all` adds the other readers. Every target is built whichever run.
default_targets="hyperfun vm field_codec expr network read_bgeo read_vdb vex_text"
all_targets="hyperfun vm field_codec expr network read_bgeo read_vdb read_obj read_ply read_stl read_gltf read_hs vex_text"
if [ "$#" -gt 0 ]; then
    targets="$*"
elif [ "${GEODE_FUZZ_TARGETS:-}" = all ]; then
    targets="$all_targets"
else
    targets="${GEODE_FUZZ_TARGETS:-$default_targets}"
fi

# Where a target's crash inputs are kept as regressions, replayed by `cargo test`.
regressions() {
    case "$1" in
        hyperfun | vm | field_codec) echo crates/frep/tests/fuzz_regressions/$1 ;;
        expr) echo crates/nodes/tests/fuzz_regressions/expr ;;
        network) echo crates/nodes/tests/fuzz_regressions/network ;;
        read_hs) echo crates/spline/tests/fuzz_regressions ;;
        vex_text) echo crates/vex/tests/fuzz_regressions ;;
        read_vdb) echo crates/io/tests/fuzz_regressions/vdb ;;
        *) echo crates/io/tests/fuzz_regressions ;;
    esac
}

# Seeds the repository already holds elsewhere, added to fuzz/seeds/<target>.
more_seeds() {
    case "$1" in
        hyperfun) ls examples/assets/*.hf ;;
        network) ls examples/*.json ;;
        read_bgeo) ls crates/io/tests/houdini/*.geo crates/io/tests/houdini/*.bgeo ;;
    esac
}

# The extension the io replay test reads a crash's format from.
extension() {
    case "$1" in
        read_bgeo) echo .bgeo ;;
        read_obj) echo .obj ;;
        read_ply) echo .ply ;;
        read_stl) echo .stl ;;
        read_gltf) echo .glb ;;
        read_vdb) echo .vdb ;;
        vm) echo .vm ;;
        hyperfun) echo .hf ;;
        field_codec) echo .bin ;;
        read_hs) echo .hs ;;
        *) echo .txt ;;
    esac
}

echo "== fuzz: building fuzz/ with libFuzzer and sanitizer coverage"
build_start=$(date +%s)
# cargo-fuzz's flags (`cargo fuzz build -O` with debug assertions and
# overflow checks on, so arithmetic that a file can overflow fails here).
export RUSTFLAGS="-Cpasses=sancov-module -Cllvm-args=-sanitizer-coverage-level=4 \
-Cllvm-args=-sanitizer-coverage-inline-8bit-counters -Cllvm-args=-sanitizer-coverage-pc-table \
-Cllvm-args=-sanitizer-coverage-trace-compares --cfg fuzzing -Cdebug-assertions -Coverflow-checks"
target_dir="${CARGO_TARGET_DIR:-$root/fuzz/target}"
# The instrumented build needs a host target triple so build scripts and
# proc macros are built without the sanitizer passes.
host="$(rustc -vV | sed -n 's/^host: //p')"
build() { (cd fuzz && cargo build --release --bins --target "$host" --target-dir "$target_dir" "$@"); }
# Offline first: CI and the sandbox may have no network, and the registry
# cache usually holds libfuzzer-sys already.
build --offline || build
echo "== fuzz: build took $(($(date +%s) - build_start)) s"

scratch="$(mktemp -d)"
trap 'rm -rf "$scratch"' EXIT
failed=""
for t in $targets; do
    bin="$target_dir/$host/release/$t"
    [ -x "$bin" ] || { echo "no fuzz target $t (fuzz/Cargo.toml lists them)"; exit 2; }
    corpus="$scratch/corpus/$t"
    artifacts="$scratch/artifacts/$t"
    mkdir -p "$corpus" "$artifacts"
    if [ -d "fuzz/seeds/$t" ]; then cp -r "fuzz/seeds/$t/." "$corpus/"; fi
    for f in $(more_seeds "$t"); do cp "$f" "$corpus/"; done
    echo "== fuzz: $t for $seconds s"
    # -rss_limit_mb: a reader must not need more than this on any input.
    # Exit status is not trusted alone: crashes are the files libFuzzer writes.
    "$bin" "$corpus" -max_total_time="$seconds" -artifact_prefix="$artifacts/" \
        -rss_limit_mb=2048 -timeout=60 -print_final_stats=1 >"$scratch/$t.log" 2>&1 || true
    grep -E '^(INFO: seed corpus|stat::number_of_executed_units)' "$scratch/$t.log" || true
    shopt -s nullglob
    # crash-, leak-, timeout- and oom- files fail the run; slow-unit- files
    # (an input over 10 s, under the 60 s timeout) are reported only.
    crashes=("$artifacts"/crash-* "$artifacts"/leak-* "$artifacts"/timeout-* "$artifacts"/oom-*)
    slow=("$artifacts"/slow-unit-*)
    shopt -u nullglob
    if [ "${#slow[@]}" -gt 0 ]; then
        echo "fuzz: $t: ${#slow[@]} input(s) took over 10 s (not a failure):"
        for u in "${slow[@]}"; do head -c 300 "$u" | tr -c '[:print:]\n' . ; echo; done
    fi
    if [ "${#crashes[@]}" -gt 0 ]; then
        dest="$(regressions "$t")"
        mkdir -p "$dest"
        for c in "${crashes[@]}"; do
            name="fuzz_${t}_$(basename "$c" | tr -c 'A-Za-z0-9_\n-' _)$(extension "$t")"
            cp "$c" "$dest/$name"
            echo "fuzz: $t crashed on $dest/$name (kept as a regression)"
            failed="$failed $dest/$name"
        done
        tail -n 40 "$scratch/$t.log"
    fi
done

if [ -n "$failed" ]; then
    echo "fuzz: crashes found:$failed"
    exit 1
fi
echo "== fuzz: no crashes ($targets)"
