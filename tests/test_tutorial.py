"""examples/tutorial.ipynb runs from top to bottom in a fresh kernel and shows what its
text promises: a run, its events, a sweep's table and figure, the model's predictions, the
rotor's growth rate from rest."""

from __future__ import annotations

import re
from pathlib import Path

import nbformat
from nbclient import NotebookClient

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"


def outputs(cell: nbformat.NotebookNode) -> tuple[str, set[str]]:
    """A code cell's printed text and the MIME types of its displayed data."""
    text = "".join(o.get("text", "") for o in cell.outputs if o.output_type == "stream")
    mimes = {m for o in cell.outputs for m in o.get("data", {})}
    return text, mimes


def test_the_tutorial_notebook_runs_and_shows_its_results() -> None:
    notebook = nbformat.read(EXAMPLES / "tutorial.ipynb", as_version=4)
    client = NotebookClient(
        notebook,
        timeout=300,
        kernel_name="python3",
        resources={"metadata": {"path": str(EXAMPLES)}},
    )
    client.execute()  # raises CellExecutionError, naming the cell, if one fails
    code = [cell for cell in notebook.cells if cell.cell_type == "code"]
    # nothing on stderr: tqdm's "IProgress not found" warned in every run without ipywidgets
    warned = [o.text for c in code for o in c.outputs if o.get("name") == "stderr"]
    assert warned == []
    run, _, omega, events, sweep, figure, prediction, stability, _ = code
    text, _ = outputs(run)
    assert "completed after" in text and "inversion probability: 1.0" in text
    assert "image/png" in outputs(omega)[1]
    assert events.outputs[0]["data"]["text/html"].count("<tr>") == 1 + 2  # header, 2 cycles
    text, _ = outputs(sweep)
    assert "3 runs computed" in text
    assert re.findall(r"^ +(0\.2|1|3) +[01]\.\d{3} ", text, re.MULTILINE) == ["0.2", "1", "3"]
    assert "image/png" in outputs(figure)[1]
    text, _ = outputs(prediction)
    assert len(re.findall(r"P = [01]\.\d{3}$", text, re.MULTILINE)) == 6
    text, _ = outputs(stability)
    assert re.match(r"lambda = \+1[45]\.\d{4} \+0\.0000i \(residual", text)  # grows, real
