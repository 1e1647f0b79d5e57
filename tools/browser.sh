#!/usr/bin/env bash
# The studio's browser tests: real Chromium (Debian's `chromium`, installed if
# missing) driven by playwright-core, against a real `geode serve` built here.
set -euo pipefail
cd "$(dirname "$0")/.."

if [ ! -x /usr/bin/chromium ]; then
  echo "installing chromium (Debian) for the browser tests" >&2
  if [ "$(id -u)" = 0 ]; then apt_get=apt-get; else apt_get="sudo apt-get"; fi
  DEBIAN_FRONTEND=noninteractive $apt_get install -y -q chromium >&2 \
    || { DEBIAN_FRONTEND=noninteractive $apt_get update -q >&2 && DEBIAN_FRONTEND=noninteractive $apt_get install -y -q chromium >&2; }
fi
[ -d studio/node_modules/playwright-core ] || (cd studio && npm ci --no-audit --no-fund --loglevel=error >&2)
cargo build -p geode-cli >&2
cd studio && GEODE_BIN="$PWD/../target/debug/geode" npm run --silent e2e
