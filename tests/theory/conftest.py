"""The camphor disk of the schema's defaults, shared by the theory tests."""

from __future__ import annotations

import pytest

from pde_rotor.config import RotorConfig
from pde_rotor.theory.disk import CamphorDisk


@pytest.fixture(scope="module")
def disk() -> CamphorDisk:
    return CamphorDisk.from_config(RotorConfig())
