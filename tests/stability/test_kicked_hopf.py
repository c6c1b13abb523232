"""A kicked disk in a no-flux dish oscillates at the frequency of the leading complex pair.

The disk of ``gallery/bodies_dish.py`` on the coarse grid in a small no-flux dish, below
its Hopf onset: held, moved off the centre, released; the oscillation fitted to its
position and velocity once the next eigenvalue's mode has fallen behind
(``benchmarks/stability_kicks.py``, the dish case) grows at Re lambda and turns at
Im lambda of the linearisation with the disk's position. Both are of the same discrete
model; what separates them is Euler's factor ln(1 + dt lambda)/dt - lambda (1e-4 of
lambda here), the implicit cut-cell step behind the wall and what is left of the faster
modes in the window.
"""

from __future__ import annotations

from types import ModuleType

import numpy as np
import pytest


def test_oscillation_fit_recovers_a_known_pair_beside_a_slow_term(kicks: ModuleType) -> None:
    times = np.arange(0.0, 6.0, 0.05)
    lam = complex(-0.14, 0.22)
    z = 1e-4 * np.exp(0.3j + lam * times)
    x, u = z.real + 2e-6, (lam * z).real
    fit = kicks.oscillation_fit(times, np.stack([x, u], axis=1))
    assert fit.rate == pytest.approx(lam, rel=1e-6)
    assert fit.offset == pytest.approx(2e-6 / np.abs(z.real).max(), rel=1e-6)
    assert fit.residual < 1e-8


def test_kicked_disk_in_a_dish_turns_at_the_hopf_pair(kicks: ModuleType) -> None:
    run = kicks.dish_kick(0.05, 4e-4, 1.75, 0.16, relax=2.0, decay=1e2, periods=0.5)
    lam, fit = run.pair, run.fit.rate
    assert lam.imag > 0.5 and lam.real > 0.1, "a growing oscillatory pair at this friction"
    assert fit.imag == pytest.approx(lam.imag, rel=5e-3)
    assert fit.real == pytest.approx(lam.real, rel=2e-2)
    assert run.fit.residual < 1e-3
    assert run.fit.offset < 1e-2
