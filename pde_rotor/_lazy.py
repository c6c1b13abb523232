"""Package attributes imported on first use (PEP 562), so that the CLI starts fast.

A package's ``__init__`` names what it hands on as ``from .module import name`` lines under
``if TYPE_CHECKING:``: type checkers, the API docs and the layer test read them as
imports, and :func:`lazy_exports` reads them to import each module when one of its names
is first used. ``pde-rotor --version`` then imports neither the solver nor numba, py-pde,
xarray or dask.
"""

from __future__ import annotations

import ast
import importlib
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any


def exported_names(init_file: str | Path) -> dict[str, str]:
    """Each name the ``if TYPE_CHECKING:`` imports of `init_file` bring in, with its module.

    Returns:
        ``{name: relative module}``, e.g. ``{"check_budget": ".budget"}``.
    """
    tree = ast.parse(Path(init_file).read_text(encoding="utf-8"))
    where: dict[str, str] = {}
    for node in tree.body:
        if not (isinstance(node, ast.If) and ast.unparse(node.test) == "TYPE_CHECKING"):
            continue
        for statement in node.body:
            if isinstance(statement, ast.ImportFrom):
                module = "." * statement.level + (statement.module or "")
                for alias in statement.names:
                    where[alias.asname or alias.name] = module
    return where


def lazy_exports(package: str) -> tuple[Callable[[str], Any], Callable[[], list[str]]]:
    """The module ``__getattr__`` and ``__dir__`` of `package` (call it in its ``__init__``).

    Example:
        >>> __getattr__, __dir__ = lazy_exports(__name__)  # doctest: +SKIP
    """
    module = sys.modules[package]
    assert module.__file__ is not None
    where = exported_names(module.__file__)

    def __getattr__(name: str) -> Any:  # noqa: N807
        if name not in where:
            msg = f"module {package!r} has no attribute {name!r}"
            raise AttributeError(msg)
        value = getattr(importlib.import_module(where[name], package), name)
        setattr(module, name, value)
        return value

    def __dir__() -> list[str]:  # noqa: N807
        return sorted(set(vars(module)) | set(where))

    return __getattr__, __dir__
