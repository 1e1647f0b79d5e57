#!/usr/bin/env bash
# Runs every test: the studio front end's (tools/studio.sh), the workspace's
# with the external reference validators (Khronos glTF validator from npm,
# Pixar's usd-core, trimesh, manifold3d and scipy from PyPI, OpenSubdiv from Debian for
# tools/osd_ref, oneTBB from Debian for manifold: tools/debian.sh) installed first and a one-machine Slurm cluster (Debian's
# slurm-wlm and munge, tools/slurm.sh) running for the farm tests, then the
# Python package built by maturin and its pytest suite (tools/python.sh), then the
# studio in real Chromium (tools/browser.sh), so that nothing has to be
# installed or started by hand. The cluster is stopped on exit.
set -euo pipefail
cd "$(dirname "$0")/.."

if [ ! -d tools/node_modules/gltf-validator ]; then
  echo "installing gltf-validator (npm) into tools/node_modules" >&2
  npm install --prefix tools --no-audit --no-fund --loglevel=error >&2
fi
if [ ! -x tools/.venv/bin/python ] || ! tools/.venv/bin/python -c "import pxr, trimesh, rtree, manifold3d, scipy, pymeshlab, igl" 2>/dev/null; then
  echo "installing usd-core, trimesh, rtree, manifold3d, scipy, pymeshlab and libigl (PyPI) into tools/.venv" >&2
  python3 -m venv tools/.venv
  tools/.venv/bin/python -m pip install --quiet --disable-pip-version-check usd-core trimesh rtree manifold3d scipy pymeshlab libigl >&2
fi

# OpenSubdiv for the Catmull-Clark reference program and TBB for manifold's
# parallel booleans (Debian's libosd-dev and libtbb-dev).
bash tools/debian.sh
if [ ! -x tools/osd_ref/osd_ref ] || [ tools/osd_ref/osd_ref.cpp -nt tools/osd_ref/osd_ref ]; then
  echo "building tools/osd_ref against OpenSubdiv" >&2
  g++ -O2 -o tools/osd_ref/osd_ref tools/osd_ref/osd_ref.cpp -losdCPU >&2
fi

# Slurm's daemons for `geode farm --scheduler slurm` (root installs and
# starts them; elsewhere the Slurm tests are skipped, and say so).
if [ "$(id -u)" = 0 ]; then
  SLURM_CONF="$(bash tools/slurm.sh start)"
  export SLURM_CONF
  trap 'bash tools/slurm.sh stop' EXIT
else
  echo "not root: Slurm cannot be installed here; the farm's Slurm tests are skipped (GEODE_SKIP_SLURM=1)" >&2
  export GEODE_SKIP_SLURM=1
fi

export GEODE_OSD_REF="$PWD/tools/osd_ref/osd_ref"
export GEODE_PYTHON="$PWD/tools/.venv/bin/python"
bash tools/studio.sh
cargo test --workspace "$@"
bash tools/python.sh
bash tools/browser.sh
