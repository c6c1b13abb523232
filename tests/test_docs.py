"""The numbers the docs share with the code and the stored data agree.

Each test reads a marked table or a marked sentence of a doc page and the value it states
from the code (the schema's defaults, ``pde_rotor.config``'s intensities, ``pde_rotor.paper``)
or from a stored file (``data/fig9.nc``, the decision tables and sweep reports in ``data/``),
and fails naming the doc and the value that disagree.
"""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from pde_rotor import config as config_module
from pde_rotor import paper
from pde_rotor.config import RotorConfig, load_config
from pde_rotor.decision.check import compare
from pde_rotor.decision.table import load_table
from pde_rotor.sweep.stored import load_report

ROOT = Path(__file__).resolve().parent.parent
DOCS = ROOT / "docs"
DATA = ROOT / "data"
PAGES = [*sorted(DOCS.glob("*.md")), ROOT / "README.md", ROOT / "gallery" / "README.md"]


def marked_table(page: Path, marker: str) -> list[list[str]]:
    """The body rows of the Markdown table after ``<!-- docs-test: marker -->`` in `page`."""
    text = page.read_text()
    tag = f"<!-- docs-test: {marker} -->"
    assert tag in text, f"{page.name}: no table marked {tag}"
    rows = []
    for line in text.split(tag, 1)[1].lstrip("\n").splitlines():
        if not line.startswith("|"):
            break
        rows.append([cell.strip() for cell in line.strip().strip("|").split("|")])
    assert len(rows) > 2, f"{page.name}: the table marked {marker} is empty"
    return rows[2:]  # header and separator


def number(text: str) -> float:
    """A number as the docs write it: 1.5e-7, 1e-4, 0.025, with a Unicode minus allowed."""
    return float(text.replace("\u2212", "-").strip("*` "))


def schema_default(key: str):
    """The schema's default of a dotted config key, e.g. ``grid.dx``."""
    section, field = key.split(".")
    return getattr(getattr(RotorConfig(), section), field)


def test_parameter_table_is_the_schemas_defaults():
    """docs/model.md's parameter table: each paper value is the schema's default."""
    rows = marked_table(DOCS / "model.md", "parameters")
    assert len(rows) >= 20
    for symbol, _meaning, value, key in rows:
        key = key.strip("`")
        default = schema_default(key)
        assert number(value) == pytest.approx(default, rel=1e-12), (
            f"docs/model.md: {symbol} = {value}, but {key} defaults to {default}"
        )


def _doc_default(cell: str):
    cell = cell.strip("`")
    if cell in ("true", "false"):
        return cell == "true"
    if cell == "null":
        return None
    if cell.startswith("["):
        return tuple(float(value) for value in cell.strip("[]").split(","))
    try:
        return float(cell)
    except ValueError:
        return cell


def test_usage_config_reference_defaults_are_the_schemas():
    """docs/usage.md's config reference: every default column entry is the schema's default."""
    text = (DOCS / "usage.md").read_text().split("## Config reference", 1)[1]
    rows = [line for line in text.splitlines() if line.startswith("| `")]
    assert len(rows) > 40
    for line in rows:
        key, default = (cell.strip() for cell in line.strip("|").split("|")[:2])
        key = key.strip("`")
        expected = schema_default(key)
        stated = _doc_default(default)
        if isinstance(expected, bool) or expected is None or isinstance(expected, str):
            assert stated == expected, f"docs/usage.md: {key} default {default}, schema {expected}"
        else:
            assert stated == pytest.approx(expected, rel=1e-12), (
                f"docs/usage.md: {key} default {default}, schema {expected}"
            )


RICHER_THAN_THE_ERROR = {
    "bodies[k].name",
    "bodies[k].plate.shape",
    "bodies[k].motion.kind",
    "bodies[k].start.velocity",
    "bodies[k].protocol",
    "grid.vessel",
}
"""Keys whose docs row says more than the one-line error can (rules across keys)."""


def test_usage_config_reference_ranges_are_the_errors():
    """The allowed column of every key states the range its one-line error states (the
    bodies' friction read 0.1 where the tool allows 1000)."""
    from pde_rotor.config.messages import allowed_values

    rows = [line for line in (DOCS / "usage.md").read_text().splitlines() if line.startswith("| `")]
    checked = 0
    for line in rows:
        cells = [cell.strip() for cell in line.strip().strip("|").split(" | ")]
        key = cells[0].strip("`")
        if len(cells) != 4 or "." not in key or "/" in key or key in RICHER_THAN_THE_ERROR:
            continue
        path: list[str | int] = []
        for part in key.split("."):
            name, _, index = part.partition("[")
            path += [name, 0] if index else [name]
        tool = allowed_values(tuple(path)).removesuffix(" or null")
        assert tool in cells[2], f"docs/usage.md: {key} allows {cells[2]!r}, the error {tool!r}"
        checked += 1
    assert checked > 50


def test_usage_states_what_a_smoothed_pill_supplies():
    """`camphor.supply` is s0, but a pill smoothed over delta supplies more: the row says
    how much, and its numbers are the integral of the code's own pill indicator."""
    import math
    import re

    import numpy as np

    from pde_rotor.config import RotorConfig
    from pde_rotor.model.geometry import RotorShape, pill_indicator

    (row,) = [
        line
        for line in (DOCS / "usage.md").read_text().splitlines()
        if line.startswith("| `camphor.supply`")
    ]
    assert "s0 (1 + pi^2 delta^2 / (12 rho^2))" in row
    stated = re.findall(r"([0-9.]+) s0 at delta = ([0-9.]+)", row)
    assert len(stated) == 2
    h = 0.002
    x = np.arange(-1.0, 1.0 + h / 2, h)
    X, Y = np.meshgrid(x, x, indexing="ij")
    for factor, delta in stated:
        geometry = RotorConfig.model_validate({"geometry": {"smoothing": float(delta)}}).geometry
        shape = RotorShape.from_config(geometry)
        supplied = pill_indicator(X, Y, shape, 0.0).sum() * h * h / shape.n_corners
        assert supplied / (math.pi * shape.pill_radius**2) == pytest.approx(
            float(factor), abs=6e-4
        ), (factor, delta)


def test_the_readme_names_the_quick_subset_and_it_exists():
    """README's everyday command selects the ``quick`` marker, and every path that marks
    tests quick (tests/conftest.py) is there."""
    from tests.conftest import QUICK

    readme = (DOCS.parent / "README.md").read_text()
    assert "python -m pytest -m quick -n 0" in readme
    assert all((DOCS.parent / path).exists() for path in QUICK)


def test_usage_shipped_configs_table_is_the_configs():
    """docs/usage.md's table of shipped configs: Delta, t_stop, cycles, grid
    and sigma of each file."""
    text = (DOCS / "usage.md").read_text().split("## Shipped configs", 1)[1].split("##", 1)[0]
    rows = [line for line in text.splitlines() if line.startswith("| `configs/")]
    assert {r.split("`")[1] for r in rows} == {
        f"configs/{p.name}" for p in (ROOT / "configs").glob("*.yaml")
    }
    for line in rows:
        cells = [c.strip() for c in line.strip("|").split("|")]
        path, _what, delta, t_stop, cycles, grid, sigma = cells[:7]
        cfg = load_config(ROOT / path.strip("`"))
        dx, dt, smoothing = (number(v) for v in grid.split(","))
        stated = {
            "geometry.asymmetry": number(delta),
            "protocol.t_stop": number(t_stop),
            "protocol.cycles": number(cycles.split()[0]),
            "grid.dx": dx,
            "grid.dt": dt,
            "geometry.smoothing": smoothing,
            "noise.sigma": number(sigma),
        }
        for key, value in stated.items():
            section, field = key.split(".")
            actual = getattr(getattr(cfg, section), field)
            assert value == pytest.approx(actual, rel=1e-12), f"docs/usage.md: {path} {key}"


@pytest.mark.parametrize(
    ("constant", "symbol"),
    [
        ("CALIBRATED_SIGMA", "\u03c3"),
        ("PAPER_SCHEME_SIGMA", "\u03c3"),
        ("PAPER_STEADY_OMEGA", "\u03c9"),
    ],
)
def test_sentences_that_name_a_constant_state_its_value(constant, symbol):
    """Every "sigma = X (`pde_rotor.config.NAME`)" in the docs (sigma or omega written as
    Greek letters) states NAME's value; there is one at least."""
    pattern = re.compile(rf"{symbol} = ([0-9.e+\u2212-]+)\**\s+\(`pde_rotor\.config\.{constant}`")
    found = [(page, m.group(1)) for page in PAGES for m in pattern.finditer(page.read_text())]
    assert found, f"no doc states {constant} as '{symbol} = X (`pde_rotor.config.{constant}`'"
    value = getattr(config_module, constant)
    for page, stated in found:
        assert number(stated) == pytest.approx(value, rel=1e-12), (
            f"{page.relative_to(ROOT)}: {symbol} = {stated}, but {constant} = {value}"
        )


def test_paper_configs_carry_the_calibrated_sigma():
    """The docs call the paper configs' sigma the calibrated one: it is, in every paper config."""
    for path in sorted((ROOT / "configs").glob("paper_fig*.yaml")):
        assert load_config(path).noise.sigma == config_module.CALIBRATED_SIGMA, path.name


def test_paper_values_table_is_pde_rotor_paper():
    """docs/statistics.md's table of the paper's stated values is pde_rotor.paper."""
    rows = marked_table(DOCS / "statistics.md", "paper-values")
    names = [row[0].strip("`") for row in rows]
    public = {n for n in vars(paper) if n.isupper()}
    assert set(names) == public, f"docs/statistics.md names {names}, pde_rotor.paper {public}"
    for name, value, _quote in rows:
        name = name.strip("`")
        assert number(value) == pytest.approx(getattr(paper, name), rel=1e-12), (
            f"docs/statistics.md: {name} = {value}, pde_rotor.paper.{name} = {getattr(paper, name)}"
        )


FIG9_SENTENCE = re.compile(r"fig9 sweep has measured (\d+) of its (\d+) cells")


def test_fig9_cell_count_is_the_stored_reports():
    """ "The fig9 sweep has measured N of its M cells": N and M as data/fig9.nc holds them."""
    with xr.open_dataset(DATA / "fig9.nc") as ds:
        measured = int((ds["runs_done"] > 0).sum())
        cells = int(ds["runs_done"].size)
    pages = [ROOT / "gallery" / "README.md", DOCS / "results.md"]
    for page in pages:
        found = FIG9_SENTENCE.findall(page.read_text())
        assert found, f"{page.relative_to(ROOT)}: no sentence '{FIG9_SENTENCE.pattern}'"
        for stated_measured, stated_cells in found:
            assert (int(stated_measured), int(stated_cells)) == (measured, cells), (
                f"{page.relative_to(ROOT)}: {stated_measured} of {stated_cells} cells, "
                f"data/fig9.nc: {measured} of {cells}"
            )


def test_decision_check_counts_are_the_stored_data():
    """docs/results.md's summary table: coverage counts and largest deviations of
    `pde-rotor predict check` recomputed from data/decision/ and data/*.nc."""

    rows = marked_table(DOCS / "results.md", "decision-check")
    assert len(rows) >= 5
    for table, reports, hold, of, deviation in rows:
        model = load_table(DATA / "decision" / table)
        comparison = compare(model, [load_report(DATA / r) for r in reports.split()])
        inside = sum(bool(row["inside"]) for row in comparison.rows)
        largest = comparison.largest_deviation()
        measured = largest["predicted"] - largest["measured"]
        where = f"docs/results.md: {table} against {reports}"
        assert (inside, len(comparison.rows)) == (int(hold), int(of)), (
            f"{where}: {hold} of {of} stated, {inside} of {len(comparison.rows)} computed"
        )
        assert math.isclose(round(measured, 3), number(deviation), abs_tol=1e-9), (
            f"{where}: largest deviation {deviation} stated, {measured:+.3f} computed"
        )


def test_no_issue_references_in_docs_or_code():
    """Docs, docstrings, comments and configs point at pages and commands, not at a
    tracker the reader cannot see."""
    section_escape = re.escape("\\" + "u00a7")  # a § written as an escape in code
    pattern = re.compile(rf"issue ?#?[0-9]+|§ ?[0-9]|{section_escape}", re.IGNORECASE)
    sources = [
        path
        for folder in ("pde_rotor", "tests", "gallery", "benchmarks", "configs", "examples")
        for suffix in ("*.py", "*.yaml", "*.ipynb", "*.md")
        for path in (ROOT / folder).rglob(suffix)
    ]
    for page in [*PAGES, *sources]:
        hits = pattern.findall(page.read_text(encoding="utf-8"))
        assert not hits, f"{page.relative_to(ROOT)}: {hits}"


def test_number_parses_the_docs_forms():
    assert number("\u22127.2e-7") == -7.2e-7
    assert number("**1.5e-7**") == 1.5e-7
    assert np.isclose(number("0.025"), 0.025)
