"""The interface every ensemble backend implements.

An ensemble backend advances E members that share one grid from an
:class:`~pde_rotor.backends.ensemble.EnsembleState` (or the paper's initial condition)
to `t_end`, records the rotor at a fixed interval, draws each member's noise from its
own Generator and reports per member the time at which its state stopped being
finite. :mod:`pde_rotor.backends.cpu` and :mod:`pde_rotor.backends.gpu` are such backends
(the modules themselves satisfy :class:`EnsembleBackend`), and the sweep estimators
(:mod:`pde_rotor.sweep.estimators`) are written against :class:`EnsembleRunner` only, so
the same estimator code runs on either.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Protocol, runtime_checkable

import numpy as np

from ..config import RotorConfig
from ..model.setup import Setup
from .ensemble import EnsembleResult, EnsembleState


@runtime_checkable
class EnsembleRunner(Protocol):
    """A backend's ``run_ensemble``: advance the members and return their records."""

    def __call__(
        self,
        configs: Sequence[Setup | RotorConfig],
        t_end: float | None = None,
        *,
        record_interval: float | None = None,
        initial: EnsembleState | None = None,
        rngs: Sequence[np.random.Generator] | None = None,
        progress: Callable[[int, int], None] | None = None,
    ) -> EnsembleResult:
        """Advance every member to `t_end`.

        Args:
            configs: one configuration per member, or its setup
                (:class:`~pde_rotor.model.setup.Setup`), all with the same ``grid`` and
                ``numerics`` sections.
            t_end: final time (default: the latest ``protocol.t_end``), a multiple of dt.
            record_interval: time between records, a multiple of dt.
            initial: the state to continue from (default: c = v = 0, phi0, omega0 at 0).
            rngs: one Generator per member for its noise, drawn in step order (default:
                ``default_rng(noise.seed)``); a Generator passed to consecutive calls
                continues its stream.
            progress: called as ``progress(steps_done, steps_total)``.

        Returns:
            The records, the divergence time of each member (NaN: none) and the final
            state.
        """
        ...


@runtime_checkable
class EnsembleBackend(Protocol):
    """An ensemble backend: a module (or object) with a ``run_ensemble`` runner."""

    def run_ensemble(
        self,
        configs: Sequence[Setup | RotorConfig],
        t_end: float | None = None,
        *,
        record_interval: float | None = None,
        initial: EnsembleState | None = None,
        rngs: Sequence[np.random.Generator] | None = None,
        progress: Callable[[int, int], None] | None = None,
    ) -> EnsembleResult:
        """Advance every member to `t_end` (the arguments of :class:`EnsembleRunner`)."""
        ...
