"""Data shared by the ensemble backends: the batch's state, its plan and its result.

An ensemble is a list of :class:`~pde_rotor.config.RotorConfig`, one per member, that
share the ``grid`` and ``numerics`` sections; :func:`make_plan` makes each member's
setup (:class:`~pde_rotor.model.setup.Setup`) once, or takes the setups it is given,
and the backends and the result read the members' objects from them. Both backends
(:mod:`.cpu`, :mod:`.gpu`) take the same arguments, build the same :class:`EnsemblePlan`
and return the same :class:`EnsembleResult`, so a sweep can switch backends without
other changes.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import xarray as xr

from ..config import RotorConfig
from ..model.domain import Domain, make_domain
from ..model.protocol import steps_of
from ..model.setup import Setup, as_setup
from ..statistics.inversion import ReleaseEvent, release_events

ROTOR_FIELDS = ("phi", "omega", "torque", "friction", "stopped")
"""Columns of the rotor arrays (the order of :meth:`RotorState.as_array`)."""

RECORD_FIELDS = (*ROTOR_FIELDS, "camphor_total")
"""Columns of the records a backend takes: the rotor, then the total camphor int c dA."""


@dataclass
class EnsembleState:
    """Fields and rotor states of all members at one time.

    Attributes:
        data: (E, 3, n, n) = per member (c, v_x, v_y), the layout of ``state.data``.
        rotor: (E, 5) = per member [phi, omega, torque, friction, stopped].
        step: global step index reached (t = step dt), the same for all members.
    """

    data: np.ndarray
    rotor: np.ndarray
    step: int

    @classmethod
    def initial(cls, configs: Sequence[RotorConfig], domain: Domain) -> EnsembleState:
        """The paper's initial condition: c = v = 0, phi(0) and omega(0) from each config."""
        n = domain.coords.size
        rotor = np.zeros((len(configs), len(ROTOR_FIELDS)))
        for m, cfg in enumerate(configs):
            rotor[m, :2] = cfg.rotor.phi0, cfg.rotor.omega0
        return cls(data=np.zeros((len(configs), 3, n, n)), rotor=rotor, step=0)


@dataclass(frozen=True)
class EnsemblePlan:
    """What a call of ``run_ensemble`` will do, checked before any step.

    Attributes:
        setups: one setup per member (its configuration and objects).
        domain: the common grid and loop ranges.
        dt: common time step.
        step_start, step_end: global step range [step_start, step_end).
        record_every: steps between records.
        record_steps: global steps at which the rotor is recorded: step_start, then every
            multiple of record_every up to step_end.
    """

    setups: tuple[Setup, ...]
    domain: Domain
    dt: float
    step_start: int
    step_end: int
    record_every: int
    record_steps: np.ndarray

    @property
    def configs(self) -> tuple[RotorConfig, ...]:
        """The members' configurations."""
        return tuple(setup.config for setup in self.setups)

    @property
    def n_members(self) -> int:
        """E, the number of members."""
        return len(self.setups)

    @property
    def n_steps(self) -> int:
        """Number of steps to advance."""
        return self.step_end - self.step_start

    def record_index(self, step: int) -> int:
        """Index in :attr:`record_steps` of the record taken after global step `step`."""
        return int(np.searchsorted(self.record_steps, step))


def make_plan(
    members: Sequence[Setup | RotorConfig],
    t_end: float | None,
    record_interval: float | None,
    initial: EnsembleState | None,
) -> EnsemblePlan:
    """Check an ensemble request, make each member's setup once (a setup given is kept,
    :func:`~pde_rotor.model.setup.as_setup`) and turn times into step counts.

    Raises:
        ValueError: no members, members on different grids, t_end or record_interval
            not a multiple of dt, t_end before the initial state, or an initial state
            of the wrong shape.
    """
    setups = tuple(as_setup(member) for member in members)
    configs = tuple(setup.config for setup in setups)
    if not configs:
        msg = "an ensemble needs at least one member config"
        raise ValueError(msg)
    grid = configs[0].grid
    for m, cfg in enumerate(configs):
        if cfg.grid != grid:
            msg = (
                f"member {m} has grid {cfg.grid.model_dump()} but member 0 has "
                f"{grid.model_dump()}: all members of an ensemble share the grid section"
            )
            raise ValueError(msg)
        if cfg.numerics != configs[0].numerics:
            msg = (
                f"member {m} has numerics {cfg.numerics.model_dump()} but member 0 has "
                f"{configs[0].numerics.model_dump()}: all members share the numerics section"
            )
            raise ValueError(msg)
    dt = grid.dt
    domain = make_domain(grid, setups[0].shape)
    if t_end is None:
        t_end = max(cfg.protocol.t_end for cfg in configs)
    step_end = steps_of(t_end, dt)
    if record_interval is None:
        record_interval = configs[0].output.timeseries_interval
    record_every = steps_of(record_interval, dt)
    if record_every < 1:
        msg = f"record_interval = {record_interval:g} must be at least dt = {dt:g}"
        raise ValueError(msg)
    step_start = 0 if initial is None else int(initial.step)
    if initial is not None:
        n = domain.coords.size
        expected = {"data": (len(configs), 3, n, n), "rotor": (len(configs), len(ROTOR_FIELDS))}
        for name, shape in expected.items():
            got = getattr(initial, name).shape
            if got != shape:
                msg = f"initial.{name} has shape {got}, expected {shape}"
                raise ValueError(msg)
    if step_end < step_start:
        msg = f"t_end = {t_end:g} lies before the initial state's t = {step_start * dt:g}"
        raise ValueError(msg)
    first = (step_start // record_every + 1) * record_every
    records = np.concatenate(
        [[step_start], np.arange(first, step_end + 1, record_every, dtype=np.int64)]
    ).astype(np.int64)
    return EnsemblePlan(
        setups=setups,
        domain=domain,
        dt=dt,
        step_start=step_start,
        step_end=step_end,
        record_every=record_every,
        record_steps=records,
    )


def default_rngs(configs: Sequence[RotorConfig]) -> list[np.random.Generator]:
    """One Generator per member seeded like the CPU solver: ``default_rng(noise.seed)``."""
    return [np.random.default_rng(cfg.noise.seed) for cfg in configs]


@dataclass
class EnsembleResult:
    """Rotor time series of every member of an ensemble.

    Attributes:
        setups: the members' setups (their configurations and objects).
        t: record times, shape (T,).
        phi, omega: rotor angle and angular velocity after each record step, (E, T).
        torque, friction: surface-tension torque T, Eq. (torque), and friction torque
            of Eq. (eq_motion) of the last step before each record, (E, T).
        stopped: whether that step was in a stop phase, (E, T) bool.
        camphor_total: total camphor int c dA over the domain at each record, (E, T).
        diverged_at: per member the time of the step at which the state stopped being
            finite (NaN: never); records after it are NaN.
        state: fields and rotor states at the end.
        backend: "cpu" or "gpu".
        wall_seconds: wall-clock time of the run (compilation included).
    """

    setups: tuple[Setup, ...]
    t: np.ndarray
    phi: np.ndarray
    omega: np.ndarray
    torque: np.ndarray
    friction: np.ndarray
    stopped: np.ndarray
    camphor_total: np.ndarray
    diverged_at: np.ndarray
    state: EnsembleState
    backend: str
    wall_seconds: float

    @classmethod
    def from_records(
        cls,
        plan: EnsemblePlan,
        records: np.ndarray,
        diverged_step: np.ndarray,
        state: EnsembleState,
        backend: str,
        wall_seconds: float,
    ) -> EnsembleResult:
        """Build the result from the (E, T, 6) record array and the failing steps (-1: none)."""
        records = records.copy()
        diverged_at = np.full(plan.n_members, np.nan)
        for m, step in enumerate(diverged_step):
            if step >= 0:
                diverged_at[m] = step * plan.dt
                records[m, plan.record_steps > step] = np.nan
        return cls(
            setups=plan.setups,
            t=plan.record_steps * plan.dt,
            phi=records[..., 0],
            omega=records[..., 1],
            torque=records[..., 2],
            friction=records[..., 3],
            stopped=records[..., 4] == 1.0,
            camphor_total=records[..., 5],
            diverged_at=diverged_at,
            state=state,
            backend=backend,
            wall_seconds=wall_seconds,
        )

    @property
    def configs(self) -> tuple[RotorConfig, ...]:
        """The members' configurations."""
        return tuple(setup.config for setup in self.setups)

    @property
    def n_members(self) -> int:
        """E, the number of members."""
        return len(self.setups)

    def release_events(
        self, member: int, commit_fraction: float, check_interval: float | None = None
    ) -> list[ReleaseEvent]:
        """Inversion events of one member, classified by :mod:`pde_rotor.statistics.inversion`.

        Each stop's omega_before is the record at its start; the release is checked at
        every record from the release to the next stop (or the last record), or, with
        `check_interval`, at the records on its multiples and at the stop ends, the
        samples of :class:`pde_rotor.trackers.InversionTracker` with
        ``output.event_interval = check_interval``.

        Args:
            member: member index.
            commit_fraction: commitment threshold relative to |omega_before|, in [0, 1].
            check_interval: time between checks (a multiple of the record interval).

        Raises:
            ValueError: a stop start or end within the records was not recorded, or
                check_interval is not a multiple of the record interval.
        """
        setup = self.setups[member]
        dt = setup.config.grid.dt
        schedule = setup.at(dt).schedule
        steps = np.round(self.t / dt).astype(np.int64)
        starts = schedule.stop_steps()
        needed = np.concatenate([starts, starts + schedule.n_stop])
        keep = np.ones(steps.size, dtype=bool)
        if check_interval is not None:
            needed = schedule.sample_steps(steps_of(check_interval, dt), int(steps[-1]))
            keep = np.isin(steps, needed)
        inside = (needed >= steps[0]) & (needed <= steps[-1])
        missing = needed[inside & ~np.isin(needed, steps)]
        if missing.size:
            msg = (
                f"member {member}: no record at t = {missing[0] * dt:g}; the record "
                "interval must divide protocol.t_ini, t_stop, t_release and the check interval"
            )
            raise ValueError(msg)
        return release_events(
            steps[keep],
            self.omega[member, keep],
            starts,
            schedule.n_stop,
            dt,
            commit_fraction,
        )

    def to_dataset(self) -> xr.Dataset:
        """The time series as an xarray Dataset with dimensions (member, time)."""
        dims = ("member", "time")
        data = {
            "phi": (dims, self.phi, {"long_name": "rotor angle phi", "units": "rad"}),
            "omega": (dims, self.omega, {"long_name": "angular velocity dphi/dt"}),
            "torque": (dims, self.torque, {"long_name": "surface tension torque, Eq. (torque)"}),
            "friction": (dims, self.friction, {"long_name": "friction torque, Eq. (eq_motion)"}),
            "stopped": (dims, self.stopped, {"long_name": "step in a stop phase"}),
            "camphor_total": (dims, self.camphor_total, {"long_name": "total camphor int c dA"}),
            "diverged_at": ("member", self.diverged_at, {"long_name": "time of divergence"}),
            "asymmetry": ("member", [c.geometry.asymmetry for c in self.configs]),
            "t_stop": ("member", [c.protocol.t_stop for c in self.configs]),
            "sigma": ("member", [c.noise.sigma for c in self.configs]),
            "config_hash": ("member", [c.config_hash() for c in self.configs]),
        }
        return xr.Dataset(
            data,
            coords={"time": self.t, "member": np.arange(self.n_members)},
            attrs={"backend": self.backend, "wall_seconds": self.wall_seconds},
        )
