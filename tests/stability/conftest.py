"""Coarse configs of the stability tests: the paper's rotor and three bodies layouts."""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path
from types import ModuleType
from typing import Any

import pytest

from pde_rotor.config import RotorConfig

COARSE_GRID = {"dx": 0.05, "dt": 4e-4}
ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="session")
def kicks() -> ModuleType:
    """benchmarks/stability_kicks.py as a module (benchmarks/ is not a package): its kicked
    runs and oscillation fit."""
    name = "stability_kicks"
    if name not in sys.modules:
        spec = importlib.util.spec_from_file_location(name, ROOT / "benchmarks" / f"{name}.py")
        assert spec is not None and spec.loader is not None
        module = importlib.util.module_from_spec(spec)
        sys.modules[name] = module
        spec.loader.exec_module(module)
    return sys.modules[name]


def rotor_data(scheme: str = "consistent", flow: bool = True) -> dict[str, Any]:
    """The paper's rotor on the coarse grid (the schema's defaults otherwise)."""
    return {"grid": dict(COARSE_GRID), "numerics": {"scheme": scheme}, "flow": {"enabled": flow}}


def disk_data(wall: str = "absorbing", radius: float = 3.0, mass: float = 2e-3) -> dict[str, Any]:
    """A free camphor disk (radius 0.1) at the centre of a dish, no flow, paper scheme."""
    return {
        "grid": {**COARSE_GRID, "domain_radius": radius, "wall": wall},
        "numerics": {"scheme": "paper"},
        "geometry": {"smoothing": 0.025},
        "flow": {"enabled": False},
        "bodies": [
            {
                "name": "disk",
                "plate": {"shape": "none"},
                "pills": [{"x": 0.0, "y": 0.0, "radius": 0.1}],
                "motion": {"kind": "free", "mass": mass, "inertia": 1e-5, "friction": 0.17},
            }
        ],
    }


@pytest.fixture
def rotor_config() -> RotorConfig:
    """The paper's rotor, default scheme, with flow, coarse grid."""
    return RotorConfig.model_validate(rotor_data())
