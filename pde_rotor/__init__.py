"""pde_rotor: camphor-driven rotor under stop-and-release operations.

Implements the model of Koyano, Kitahata, Nakata & Gorecki, "On a simple model that
explains inversion of a self-propelled rotor under periodic stop-and-release
operations", Chaos 30, 2020, on py-pde.

``import pde_rotor`` is light: the solver, numba, py-pde and xarray are imported when
:func:`run`, :class:`RunResult`, :class:`RotorConfig` or :class:`Simulation` is first
used (PEP 562, :mod:`pde_rotor._lazy`).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from ._lazy import lazy_exports
from ._version import __version__

if TYPE_CHECKING:
    from .api import RunResult, run
    from .config import RotorConfig
    from .solver.simulation import Simulation

__all__ = ["RotorConfig", "RunResult", "Simulation", "__version__", "run"]

__getattr__, __dir__ = lazy_exports(__name__)
