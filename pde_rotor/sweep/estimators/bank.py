"""What the bank estimator adds to restarts: one noise-free stop shared by every noise.

The noise acts only on the moving rotor, so the end-of-stop state depends on the stop
angle, the direction and the noise-free configuration alone. A bank run approaches its
stop and stops noise-free; the members of an ensemble whose configurations (noise
aside) and states are equal are computed once (:func:`run_distinct`), and each release
continues with its own noise, whose first draw acts at the end of the stop
(:class:`DelayedNoise`). :mod:`.releases` runs them as ensembles.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence

import numpy as np

from ...backends.base import EnsembleRunner
from ...backends.ensemble import EnsembleResult, EnsembleState
from ...config import RotorConfig
from ...model.setup import Setup, as_setup


class DelayedNoise:
    """Noise draws for a bank release that continues a stop: zeros for the `delay` steps
    still in the stop (where a kick has no effect), then the draws of `rng`, so that its
    first draw acts at the end of the stop."""

    def __init__(self, rng: np.random.Generator, delay: int) -> None:
        self.rng = rng
        self.delay = delay

    def standard_normal(self, n: int) -> np.ndarray:
        """The next `n` draws (what the backends ask a Generator for)."""
        head = min(n, self.delay)
        self.delay -= head
        return np.concatenate([np.zeros(head), self.rng.standard_normal(n - head)])


def noise_free(configs: Sequence[RotorConfig]) -> list[RotorConfig]:
    """Copies of `configs` without noise: the approach to a bank run's stop and the stop."""
    quiet = []
    for config in configs:
        q = config.model_copy(deep=True)
        q.noise.sigma = 0.0
        quiet.append(q)
    return quiet


def run_distinct(
    ensemble: EnsembleRunner,
    members: Sequence[Setup | RotorConfig],
    state: EnsembleState,
    t_end: float,
    record_interval: float,
) -> EnsembleResult:
    """A noise-free ensemble call that computes members with equal configurations (noise
    aside) and equal states once, returned as the result of every member.

    Args:
        ensemble: the backend's ``run_ensemble``.
        members: the members' noise-free configurations, or their setups.
        state: the members' state.
        t_end: the time to advance to.
        record_interval: the time between records.
    """
    setups = [as_setup(member) for member in members]
    firsts: dict[tuple[str, bytes, bytes], int] = {}
    inverse = []
    for m, setup in enumerate(setups):
        key = (
            setup.config.model_dump_json(exclude={"noise"}),
            state.data[m].tobytes(),
            state.rotor[m].tobytes(),
        )
        inverse.append(firsts.setdefault(key, len(firsts)))
    unique = [next(m for m, i in enumerate(inverse) if i == j) for j in range(len(firsts))]
    initial = EnsembleState(state.data[unique], state.rotor[unique], state.step)
    result = ensemble(
        [setups[m] for m in unique], t_end, record_interval=record_interval, initial=initial
    )
    return _expand(result, setups, np.array(inverse))


def _expand(result: EnsembleResult, setups: Sequence[Setup], inverse: np.ndarray) -> EnsembleResult:
    """`result` of the distinct members, as the result of every member (`inverse`:
    member -> distinct member)."""
    state = result.state
    return dataclasses.replace(
        result,
        setups=tuple(setups),
        phi=result.phi[inverse],
        omega=result.omega[inverse],
        torque=result.torque[inverse],
        friction=result.friction[inverse],
        stopped=result.stopped[inverse],
        camphor_total=result.camphor_total[inverse],
        diverged_at=result.diverged_at[inverse],
        state=EnsembleState(state.data[inverse], state.rotor[inverse], state.step),
    )
