"""The documentation site (mkdocs.yml): the pages and the API reference built from the
docstrings, with warnings as errors, and the relative links of the pages."""

from __future__ import annotations

import importlib
import re
import subprocess
import sys
from pathlib import Path

import pytest
import yaml

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"
LINK = re.compile(r"\]\(([^)\s#]+)(?:#[^)]*)?\)")


def api_modules() -> list[str]:
    """The modules docs/api.md documents (its ``::: module`` lines)."""
    text = (DOCS / "api.md").read_text(encoding="utf-8")
    return re.findall(r"^::: ([\w.]+)$", text, re.MULTILINE)


@pytest.mark.docs
def test_the_site_builds_strictly_with_every_api_module(tmp_path) -> None:
    """`mkdocs build --strict`: a docstring griffe cannot parse as Google style (say, a
    parameter it does not find in the signature) or a link to a missing page fails the
    build; every module of docs/api.md is rendered."""
    site = tmp_path / "site"
    build = subprocess.run(
        [sys.executable, "-m", "mkdocs", "build", "--strict", "--site-dir", str(site)],
        cwd=ROOT,
        capture_output=True,
        text=True,
        timeout=300,
        check=False,
    )
    assert build.returncode == 0, build.stderr
    html = (site / "api" / "index.html").read_text(encoding="utf-8")
    modules = api_modules()
    assert {"pde_rotor.api", "pde_rotor.config", "pde_rotor.sweep.plot"} <= set(modules)
    for module in modules:
        assert f'id="{module}"' in html, module
    assert 'id="pde_rotor.sweep.plot.report_figure"' in html


def test_every_page_is_in_the_nav_and_every_api_module_imports() -> None:
    config = yaml.safe_load((ROOT / "mkdocs.yml").read_text(encoding="utf-8"))
    nav = {page for entry in config["nav"] for page in entry.values()}
    assert nav == {path.name for path in DOCS.glob("*.md")}
    for module in api_modules():
        importlib.import_module(module)


PAGES = [*sorted(DOCS.glob("*.md")), ROOT / "README.md"]


@pytest.mark.parametrize("page", PAGES, ids=[page.name for page in PAGES])
def test_relative_links_point_at_files(page: Path) -> None:
    """Links that leave docs/ (../gallery/README.md) are not checked by mkdocs: every
    relative link of a page must name a file or folder of the repository."""
    text = page.read_text(encoding="utf-8")
    targets = [t for t in LINK.findall(text) if not re.match(r"[a-z]+:", t)]
    missing = [t for t in targets if not (page.parent / t).exists()]
    assert missing == []
