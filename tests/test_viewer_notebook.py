"""notebooks/quickstart.ipynb runs top to bottom without blocking (its own asserts compare TF with FK)."""

from __future__ import annotations

from pathlib import Path

import nbformat
import pytest
from nbclient import NotebookClient

NOTEBOOK = Path(__file__).resolve().parents[1] / "notebooks" / "quickstart.ipynb"


@pytest.mark.timeout(300)
def test_quickstart_notebook_executes():
    nb = nbformat.read(NOTEBOOK, as_version=4)
    NotebookClient(
        nb, timeout=120, kernel_name="python3", resources={"metadata": {"path": str(NOTEBOOK.parent)}}
    ).execute()
    outputs = [o for cell in nb.cells if cell.cell_type == "code" for o in cell.get("outputs", [])]
    assert not [o for o in outputs if o.get("output_type") == "error"]
    text = "".join(o.get("text", "") for o in outputs if o.get("output_type") == "stream")
    assert "check ok: True" in text and "TF agrees with robot.frame_pose" in text
    iframes = [o for o in outputs if "text/html" in o.get("data", {}) and "iframe" in o["data"]["text/html"]]
    assert iframes and "http://127.0.0.1:" in iframes[0]["data"]["text/html"], "the viewer is not embedded"
