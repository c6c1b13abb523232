"""The layout the README and tests/README.md describe is the package's.

The README's layout table has a row per folder of the package naming each of its
modules (a top-level module in the first cell of a row), and the tests mirror the
package: ``pde_rotor/<folder>/<module>.py`` has ``tests/<folder>/test_<module>.py``, or
tests/README.md names the module, where it is tested and why it has no module of its own.
"""

from __future__ import annotations

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PACKAGE = ROOT / "pde_rotor"
MODULES = sorted(p for p in PACKAGE.rglob("*.py") if p.name != "__init__.py")


def table_rows(text: str, header: str) -> list[list[str]]:
    """The body rows of the first Markdown table whose header row starts with `header`."""
    lines = text.splitlines()
    start = next(i for i, line in enumerate(lines) if line.startswith(header))
    rows = []
    for line in lines[start + 2 :]:
        if not line.startswith("|"):
            break
        rows.append([cell.strip() for cell in line.strip().strip("|").split("|")])
    return rows


def layout_rows() -> dict[str, str]:
    """The README's layout table: first cell -> the row's text."""
    text = (ROOT / "README.md").read_text(encoding="utf-8").split("## Layout", 1)[1]
    return {row[0]: " | ".join(row) for row in table_rows(text, "| folder |")}


def mirror(module: Path) -> Path:
    """tests/<folder>/test_<module>.py of pde_rotor/<folder>/<module>.py."""
    relative = module.relative_to(PACKAGE)
    return ROOT / "tests" / relative.parent / f"test_{relative.name}"


def untested() -> dict[str, list[str]]:
    """tests/README.md's table of modules without a test module: path -> its cells."""
    text = (ROOT / "tests" / "README.md").read_text(encoding="utf-8")
    rows = table_rows(text, "| module |")
    return {row[0].strip("`"): row for row in rows}


def test_the_layout_table_names_every_module():
    rows = layout_rows()
    missing = []
    for module in MODULES:
        relative = module.relative_to(PACKAGE)
        if relative.parent == Path():
            named = any(
                f"`{module.name}`" in cell or f"`pde_rotor/{module.name}`" in cell for cell in rows
            )
        else:
            row = rows.get(f"`pde_rotor/{relative.parent.as_posix()}/`", "")
            named = re.search(rf"`{module.stem}`", row) is not None
        if not named:
            missing.append(str(relative))
    assert missing == []


def test_every_module_has_its_test_module_or_a_reason():
    """A module without tests/<folder>/test_<module>.py is in tests/README.md's table with
    where it is tested and why; a module listed there has no test module of its own
    (the entry would be stale) and exists."""
    listed = untested()
    silent = [
        str(m.relative_to(ROOT))
        for m in MODULES
        if not mirror(m).exists() and str(m.relative_to(ROOT)) not in listed
    ]
    assert silent == []
    for path, cells in listed.items():
        assert (ROOT / path).exists(), f"tests/README.md lists {path}, which does not exist"
        assert not mirror(ROOT / path).exists(), f"{path} has its test module now"
        assert len(cells) == 3 and all(cells), f"tests/README.md: {path} needs where and why"
