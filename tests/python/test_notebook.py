# The example notebook, docs/python.ipynb, run as a script: its code cells
# in order, in one namespace, at the small sizes WAVEPATH_NOTEBOOK_QUICK
# asks for (Debian's nbconvert and ipykernel are not installed; see
# docs/python.md).
import json
import os

from conftest import ROOT


def test_the_example_notebook_runs(tmp_path, monkeypatch):
    monkeypatch.setenv("WAVEPATH_NOTEBOOK_QUICK", "1")
    monkeypatch.setenv("WAVEPATH_ROOT", str(ROOT))
    monkeypatch.setenv("MPLBACKEND", "Agg")
    monkeypatch.chdir(tmp_path)
    notebook = json.loads((ROOT / "docs" / "python.ipynb").read_text())
    cells = [c for c in notebook["cells"] if c["cell_type"] == "code"]
    assert cells
    namespace = {"__name__": "__main__"}
    for i, cell in enumerate(cells):
        exec(compile("".join(cell["source"]), f"python.ipynb, code cell {i + 1}", "exec"), namespace)
    # What its cells leave behind: the convergence, the comparison, the sweep.
    assert namespace["rmse"][-1] < namespace["rmse"][0]
    assert namespace["verdict"].passed
    assert len(namespace["sweep"]) >= 3
