"""The package's types hold: mypy --strict passes over it, and stubtest finds the native module's stubs true to the module."""

import subprocess
import sys

from conftest import REPO, oracle


def run(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", *args], capture_output=True, text=True, cwd=REPO)


def test_the_package_type_checks_strictly():
    oracle("mypy")
    r = run("mypy", "--strict", "--ignore-missing-imports", "crates/python/python/geode")
    assert r.returncode == 0, r.stdout + r.stderr


def test_the_native_stubs_match_the_native_module():
    oracle("mypy")
    r = run("mypy.stubtest", "geode._geode")
    assert r.returncode == 0, r.stdout + r.stderr
