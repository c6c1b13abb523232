"""pde_rotor: camphor-driven rotor under stop-and-release operations.

Implements the model of Koyano, Kitahata, Nakata & Gorecki, "On a simple model that
explains inversion of a self-propelled rotor under periodic stop-and-release
operations", Chaos 30, 2020, on py-pde.
"""

from __future__ import annotations

from ._version import __version__
from .api import RunResult, run
from .config import RotorConfig
from .solver.simulation import Simulation

__all__ = ["RotorConfig", "RunResult", "Simulation", "__version__", "run"]
