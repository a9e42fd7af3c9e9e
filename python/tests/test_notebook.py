"""docs/notebooks/rate-state-vs-amontons.ipynb runs from top to bottom on
the code as it is (so it cannot rot), its run files in a temporary
directory; the stored copy is the executed one (it renders on the host)."""

from __future__ import annotations

import os

import nbformat
from nbclient import NotebookClient

from conftest import ROOT

NOTEBOOK = ROOT / "docs" / "notebooks" / "rate-state-vs-amontons.ipynb"


def test_the_notebook_runs(tmp_path, monkeypatch):
    stored = nbformat.read(NOTEBOOK, as_version=4)
    nbformat.validate(stored)
    assert all(c.get("outputs") for c in stored.cells if c.cell_type == "code"), \
        "the stored notebook is the executed one"
    monkeypatch.setenv("FLOE_NOTEBOOK_OUT", str(tmp_path))
    nb = nbformat.read(NOTEBOOK, as_version=4)
    NotebookClient(nb, timeout=900, kernel_name="python3",
                   resources={"metadata": {"path": str(NOTEBOOK.parent)}}).execute()
    streams = "".join(o.get("text", "") for c in nb.cells for o in c.get("outputs", []))
    assert "steady shear stress, rate-and-state over Amontons" in streams
    for seed in (1, 2, 3):
        assert (tmp_path / f"seed{seed}" / "report.md").exists()
    assert (tmp_path / "stiff_seed1" / "rate-state.h5").exists()
    assert os.environ["FLOE_NOTEBOOK_OUT"] == str(tmp_path)
