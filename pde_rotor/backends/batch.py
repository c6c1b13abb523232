"""Batches of independent member runs for sweeps: configs in, inversion results out.

:func:`run_batch` takes any list of member configurations (e.g. the points and
samples of a sweep), groups the members that can share one ensemble (same ``grid`` and
``numerics`` sections, same starting step), runs each group through
:func:`pde_rotor.backends.run_ensemble` in chunks of at most ``max_members`` and
returns one :class:`MemberRun` per config, in the order given. Each member's stops are
classified by the one inversion rule (:mod:`pde_rotor.statistics.inversion`) with its own
``output.event_interval`` and ``output.commit_fraction``, exactly as the
:class:`~pde_rotor.trackers.InversionTracker` of a single run does.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from ..config import RotorConfig
from ..model.protocol import steps_of
from ..model.setup import Setup, as_setup
from ..statistics.inversion import ReleaseEvent
from .ensemble import EnsembleResult, EnsembleState


@dataclass(frozen=True)
class MemberRun:
    """What a sweep needs of one member run.

    Attributes:
        config: the member's configuration.
        backend: the backend that ran it, "cpu" or "gpu".
        events: one classified release per stop reached (:mod:`pde_rotor.statistics.inversion`).
        protocol_omegas: omega just before each stop reached, then at the member's
            ``protocol.t_end`` (if reached): the input of
            :func:`pde_rotor.statistics.proportions.protocol_counts`, the paper's estimator.
        diverged_at: time at which the state stopped being finite (NaN: never).
        rotor: final [phi, omega, torque, friction, stopped] at the batch's end time.
    """

    config: RotorConfig
    backend: str
    events: list[ReleaseEvent]
    protocol_omegas: list[float]
    diverged_at: float
    rotor: np.ndarray


def _record_steps(setups: Sequence[Setup], step0: int) -> int:
    """Steps between records: the gcd of every step a member's classification reads."""
    steps = [step0]
    for setup in setups:
        cfg = setup.config
        dt = cfg.grid.dt
        schedule = setup.at(dt).schedule
        steps += [
            steps_of(cfg.output.event_interval, dt),
            schedule.n_ini,
            schedule.n_stop,
            schedule.n_period,
            steps_of(cfg.protocol.t_end, dt),
        ]
    return max(1, int(np.gcd.reduce(np.array(steps, dtype=np.int64))))


def _member(result: EnsembleResult, m: int, step_end: int) -> MemberRun:
    """Member m of `result`: its events, the paper estimator's omegas, its end state."""
    setup = result.setups[m]
    cfg = setup.config
    dt = cfg.grid.dt
    events = result.release_events(m, cfg.output.commit_fraction, cfg.output.event_interval)
    schedule = setup.at(dt).schedule
    ends = np.append(schedule.stop_steps(), steps_of(cfg.protocol.t_end, dt))
    steps = np.round(result.t / dt).astype(np.int64)
    omegas = [float(result.omega[m, steps == s][0]) for s in ends if s in steps and s <= step_end]
    return MemberRun(
        config=cfg,
        backend=result.backend,
        events=events,
        protocol_omegas=[w for w in omegas if math.isfinite(w)],
        diverged_at=float(result.diverged_at[m]),
        rotor=result.state.rotor[m].copy(),
    )


def run_batch(
    configs: Sequence[Setup | RotorConfig],
    *,
    backend: str = "auto",
    max_members: int | None = None,
    initial: EnsembleState | None = None,
) -> list[MemberRun]:
    """Run independent members in batches and classify their stops.

    Every member runs to the latest ``protocol.t_end`` of its group (a member whose own
    protocol ends earlier goes on rotating freely; its results only use its protocol).

    Args:
        configs: one validated configuration per member, or its setup
            (:class:`~pde_rotor.model.setup.Setup`, made here once if not); noise seeds
            as each wants.
        backend: ``cpu``, ``gpu`` or ``auto`` (:func:`pde_rotor.backends.resolve_backend`).
        max_members: most members per ensemble call (None: a whole group at once).
        initial: states to start from, one member per config, all at ``initial.step``
            (e.g. a sweep's warm states); None: the paper's initial condition.

    Returns:
        One :class:`MemberRun` per config, in the order of `configs`.

    Raises:
        ValueError: no configs, max_members < 1, or `initial` of the wrong length.
        pde_rotor.backends.BackendError: "gpu" requested without a usable GPU.
    """
    from . import run_ensemble

    setups = [as_setup(member) for member in configs]
    configs = [setup.config for setup in setups]
    if not configs:
        msg = "run_batch needs at least one member config"
        raise ValueError(msg)
    if max_members is not None and max_members < 1:
        msg = f"max_members = {max_members} must be at least 1"
        raise ValueError(msg)
    if initial is not None and len(initial.data) != len(configs):
        msg = f"initial holds {len(initial.data)} members for {len(configs)} configs"
        raise ValueError(msg)
    groups: dict[str, list[int]] = {}
    for m, cfg in enumerate(configs):
        key = cfg.model_dump_json(include={"grid", "numerics"})
        groups.setdefault(key, []).append(m)
    out: list[MemberRun | None] = [None] * len(configs)
    size = max_members or len(configs)
    for members in groups.values():
        for first in range(0, len(members), size):
            chunk = members[first : first + size]
            part = [setups[m] for m in chunk]
            start = None
            if initial is not None:
                start = EnsembleState(initial.data[chunk], initial.rotor[chunk], initial.step)
            step0 = 0 if start is None else start.step
            dt = part[0].config.grid.dt
            result = run_ensemble(
                part,
                backend=backend,
                record_interval=_record_steps(part, step0) * dt,
                initial=start,
            )
            step_end = round(result.t[-1] / dt)
            for k, m in enumerate(chunk):
                out[m] = _member(result, k, step_end)
    return [run for run in out if run is not None]
