"""The one version of the package (read by pyproject.toml, the CLI and the run records)."""

from __future__ import annotations

import platform
from importlib.metadata import PackageNotFoundError, version

__version__ = "0.1.0"

RECORDED = ("py-pde", "numba", "numpy", "xarray")
"""The packages that determine a run's results (distribution names)."""


def versions() -> dict[str, str]:
    """Versions of pde_rotor and of the packages that determine its results.

    Read from the installed distributions' metadata, without importing them (``pde-rotor
    info`` stays fast).
    """
    found = {"pde_rotor": __version__}
    for name in RECORDED:
        try:
            found[name] = version(name)
        except PackageNotFoundError:
            found[name] = "not installed"
    found["python"] = platform.python_version()
    return found
