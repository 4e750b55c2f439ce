"""notebooks/kinematics.ipynb runs top to bottom (its own asserts check the Jacobian and batched FK)."""

from __future__ import annotations

from pathlib import Path

import nbformat
from nbclient import NotebookClient

NOTEBOOK = Path(__file__).resolve().parents[1] / "notebooks" / "kinematics.ipynb"


def test_kinematics_notebook_executes():
    nb = nbformat.read(NOTEBOOK, as_version=4)
    NotebookClient(
        nb, timeout=300, kernel_name="python3", resources={"metadata": {"path": str(NOTEBOOK.parent)}}
    ).execute()
    outputs = [o for cell in nb.cells if cell.cell_type == "code" for o in cell.get("outputs", [])]
    assert not [o for o in outputs if o.get("output_type") == "error"]
    text = "".join(o.get("text", "") for o in outputs if o.get("output_type") == "stream")
    assert "max |J - J_fd|" in text and "100000 configurations" in text
    assert any("image/png" in o.get("data", {}) for o in outputs if o.get("output_type") == "display_data")
