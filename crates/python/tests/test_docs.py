"""docs/python.md's examples run as written: the pipeline (a wedge over frames in a thread pool written to USD) and the first network."""

import os
import re

from conftest import REPO, oracle


def blocks() -> list[str]:
    text = (REPO / "docs" / "python.md").read_text()
    return re.findall(r"```python\n(.*?)```", text, re.S)


def test_the_guides_pipeline_writes_a_usd_wedge(tmp_path, monkeypatch):
    oracle("pxr")
    from pxr import Usd, UsdGeom

    pipeline = next(b for b in blocks() if "ThreadPoolExecutor" in b)
    (tmp_path / "examples").symlink_to(REPO / "examples")
    monkeypatch.chdir(tmp_path)
    scope: dict = {}
    exec(compile(pipeline, "docs/python.md", "exec"), scope)
    stage = Usd.Stage.Open(str(tmp_path / "out" / "wedge.usda"))
    meshes = {p.GetName(): UsdGeom.Mesh(p) for p in stage.Traverse() if p.IsA(UsdGeom.Mesh)}
    assert sorted(meshes) == ["amp_20", "amp_5"]
    assert len(meshes["amp_20"].GetPointsAttr().GetTimeSamples()) == 24
    # Each point moves along its normal by amp * sin(...): against the
    # undisplaced grid (amp 0), the 2.0 wedge moved every point 4 times as
    # far as the 0.5 wedge, at every frame.
    import numpy as np

    for frame in (1, 12, 24):
        still = scope["base"].cook(frame=frame).points["P"]
        low = np.array(meshes["amp_5"].GetPointsAttr().Get(frame)) - still
        high = np.array(meshes["amp_20"].GetPointsAttr().Get(frame)) - still
        assert np.abs(high).max() > 0.1
        np.testing.assert_allclose(high, 4 * low, atol=2e-4)


def test_the_guides_first_network_cooks_and_saves(tmp_path, monkeypatch):
    first = next(b for b in blocks() if "spin.json" in b)
    monkeypatch.chdir(tmp_path)
    scope: dict = {}
    exec(compile(first, "docs/python.md", "exec"), scope)
    assert scope["P"].shape == (8, 3)
    assert (tmp_path / "spin.json").exists()
    assert os.path.getsize(tmp_path / "spin.json") > 0
