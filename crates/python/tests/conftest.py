"""Shared pieces of the Python package's tests: the repository's paths."""

import pathlib

import pytest

REPO = pathlib.Path(__file__).resolve().parents[3]


@pytest.fixture
def examples() -> pathlib.Path:
    return REPO / "examples"


def oracle(module: str):
    """Imports a reference tool's module. Missing, it fails the test, unless
    GEODE_SKIP_ORACLES=1 says to skip what needs one (the test then says
    `skipping:`), as geode's Rust oracle tests do."""
    import importlib
    import os

    try:
        return importlib.import_module(module)
    except ImportError as e:
        if os.environ.get("GEODE_SKIP_ORACLES") == "1":
            pytest.skip(f"skipping: {module} is not installed (GEODE_SKIP_ORACLES=1)")
        pytest.fail(f"the oracle {module} is not installed ({e}); tools/test.sh installs it, GEODE_SKIP_ORACLES=1 skips")
