#!/usr/bin/env bash
# Installs the Debian packages geode's build and tests use when they are
# missing: libosd-dev (OpenSubdiv, for the Catmull-Clark reference program
# tools/osd_ref) and libtbb-dev (oneTBB: manifold's parallel backend, which
# crates/manifold/build.rs picks up when it is there), python3-openvdb
# (pyopenvdb: the reference reader and writer of the VDB tests, run by the
# system python3) and blender (3.4: the VDB tests import geode's files as
# volumes). Needs root or sudo.
set -euo pipefail

missing=()
[ -f /usr/include/opensubdiv/far/topologyRefiner.h ] || missing+=(libosd-dev)
[ -f /usr/include/tbb/task_arena.h ] || missing+=(libtbb-dev)
/usr/bin/python3 -c 'import pyopenvdb' 2>/dev/null || missing+=(python3-openvdb)
command -v blender >/dev/null || missing+=(blender)
[ ${#missing[@]} -eq 0 ] && exit 0

echo "installing ${missing[*]} (Debian)" >&2
if [ "$(id -u)" = 0 ]; then apt_get=apt-get; else apt_get="sudo apt-get"; fi
export DEBIAN_FRONTEND=noninteractive
$apt_get install -y -q --no-install-recommends "${missing[@]}" >&2 \
  || { $apt_get update -q >&2 && $apt_get install -y -q --no-install-recommends "${missing[@]}" >&2; }
# A build made before TBB was there is serial: build manifold again.
if [[ " ${missing[*]} " == *" libtbb-dev "* ]]; then
  cargo clean -q -p geode-manifold 2>/dev/null || true
fi
