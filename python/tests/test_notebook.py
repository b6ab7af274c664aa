"""The example notebook runs headless from top to bottom (its cells assert what they show)."""

import pathlib

import nbclient
import nbformat

ROOT = pathlib.Path(__file__).resolve().parents[2]


def test_the_case_study_notebook_runs(monkeypatch):
    monkeypatch.setenv("TELESCOPIC_ROOT", str(ROOT))
    path = ROOT / "examples" / "notebooks" / "case-study.ipynb"
    notebook = nbformat.read(path, as_version=4)
    assert all(c.get("outputs", []) == [] for c in notebook.cells), "committed without outputs"
    client = nbclient.NotebookClient(
        notebook, timeout=600, kernel_name="python3", resources={"metadata": {"path": str(ROOT)}}
    )
    client.execute()
    printed = "".join(
        o.get("text", "") for c in notebook.cells if c.cell_type == "code" for o in c.outputs
    )
    assert "0.4983" in printed and "with the controller" in printed
