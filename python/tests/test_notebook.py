"""The notebook a new user runs first (python/examples/first_steps.ipynb), executed headless:
any cell error fails. It reads ../shared/data beside the repository."""

import os
import pathlib

import nbclient
import nbformat

ROOT = pathlib.Path(__file__).resolve().parents[2]
NOTEBOOK = ROOT / "python" / "examples" / "first_steps.ipynb"


def test_the_first_steps_notebook_runs(monkeypatch):
    monkeypatch.setenv("MPLBACKEND", "Agg")
    monkeypatch.setenv("THEORY_SEARCH_DATA", str(ROOT / ".." / "shared" / "data"))
    nb = nbformat.read(NOTEBOOK, as_version=4)
    client = nbclient.NotebookClient(
        nb, timeout=600, kernel_name="python3", resources={"metadata": {"path": str(NOTEBOOK.parent)}}
    )
    client.execute()
    outputs = [o for c in nb.cells if c.cell_type == "code" for o in c.get("outputs", [])]
    assert not [o for o in outputs if o.get("output_type") == "error"]
    # The fit's result renders as HTML, Table 1 as a DataFrame.
    html = [o["data"]["text/html"] for o in outputs if "text/html" in o.get("data", {})]
    assert any("FitResult" in h for h in html) and any("<table" in h for h in html)
