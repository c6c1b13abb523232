"""A fresh rigid-rotor ensemble runner for every estimator test (:mod:`.rigid`)."""

from __future__ import annotations

from collections import OrderedDict

import pytest

from pde_rotor.sweep.estimators import restart

from .rigid import RigidRotor


@pytest.fixture
def rigid(monkeypatch) -> RigidRotor:
    """A fresh rigid-rotor runner, with no steady state cached from another test."""
    monkeypatch.setattr(restart, "_WARM", OrderedDict())
    return RigidRotor()
