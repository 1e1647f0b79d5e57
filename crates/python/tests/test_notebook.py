"""The example notebook (examples/python_pipeline.ipynb) runs top to bottom in a real Jupyter kernel, and shows what it claims."""

import pytest

from conftest import REPO, oracle


def test_the_example_notebook_runs_and_shows_its_pictures_and_usd():
    nbformat = oracle("nbformat")
    nbclient = oracle("nbclient")
    oracle("pxr")
    path = REPO / "examples" / "python_pipeline.ipynb"
    nb = nbformat.read(path, as_version=4)
    client = nbclient.NotebookClient(nb, timeout=300, kernel_name="python3", resources={"metadata": {"path": str(path.parent)}})
    client.execute()
    outputs = [o for cell in nb.cells if cell.cell_type == "code" for o in cell.outputs]
    assert not [o for o in outputs if o.output_type == "error"]
    pictures = [o.get("data", {}) for o in outputs]
    assert sum("image/svg+xml" in d for d in pictures) == 2, "the networks did not draw themselves"
    assert sum("image/png" in d for d in pictures) == 2, "the geometries did not draw themselves"
    text = "".join(o.get("text", "") for o in outputs if o.output_type == "stream")
    assert "wrote 3 meshes with 8 frames each" in text
    # Each wedge's highest point at frame 8, as the wrangle's formula gives it
    # on the notebook's 32 x 32 grid: height * amp * (1 + 0.25 sin(6x + 8)).
    import ast

    import numpy as np

    line = next(l for l in text.splitlines() if l.startswith("{0.5:"))
    peaks = ast.literal_eval(line)
    u, v = np.meshgrid(np.linspace(-1, 1, 32), np.linspace(-1, 1, 32))
    shape = np.exp(-4 * (u**2 + v**2)) * (1 + 0.25 * np.sin(u * 6 + 8))
    for scale, peak in peaks.items():
        assert peak == pytest.approx(scale * shape.max(), abs=1e-3)
