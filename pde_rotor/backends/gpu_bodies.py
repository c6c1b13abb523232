"""K camphor bodies on the GPU: the host side of :mod:`pde_rotor.kernels.cuda_bodies`.

:class:`BodiesBatch` holds E members of the bodies' model (one ``bodies:`` config each,
sharing the grid, the numerics, the number of bodies and pills, and the scheme's
tables) in device memory, and advances them in one launch per call, block m advancing
member m, with forward Euler or Heun (``numerics.integrator``). Three users:

* :func:`gpu_bodies_stepper`: the stepper of one run (``pde-rotor run CONFIG --backend
  gpu`` with ``bodies:``), driven by py-pde's Controller between the trackers'
  interrupts exactly as the CPU's :class:`pde_rotor.solver.bodies.BodiesStepper`, whose
  noise stream (K standard normals per step, in step order) and early ends it shares;
* :func:`run_rotor_ensemble`: E rotors (no ``bodies:``), each as its ``fixed_axis`` body:
  how the GPU's rotor ensembles and single runs integrate with Heun
  (:func:`pde_rotor.backends.gpu.run_ensemble`; the rotor's own kernel,
  :mod:`pde_rotor.kernels.cuda`, has forward Euler only);
* :func:`run_bodies_ensemble`: E members (a sweep's points, seeds) to a common end
  time, every body's pose and forces recorded at a fixed interval
  (:class:`BodiesEnsembleResult`).
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from ..config import RotorConfig
from ..kernels.cuda_bodies import N_SUMS, bodies_kernel
from ..kernels.cuda_target import cuda, simulator_enabled
from ..kernels.records import make_body_records, make_body_tables, make_record
from ..kernels.wall import NO_WALL
from ..model.protocol import steps_of
from ..model.setup import Setup, as_setup
from ..model.surface import POSE_COLUMNS, BodiesState, SurfacePDE
from ..solver.bodies import raise_early_end
from .ensemble import RECORD_FIELDS, EnsemblePlan, EnsembleResult, EnsembleState

PHI, OMEGA, TORQUE, FRICTION, STOPPED = (
    POSE_COLUMNS.index(name) for name in ("phi", "omega", "torque", "friction", "stopped")
)
"""The pose's columns that hold the rotor's state (:class:`~pde_rotor.model.pde.RotorState`)."""

GPU_END = " on the gpu backend"
"""How an early end's message names this backend
(:func:`pde_rotor.solver.bodies.raise_early_end`)."""

SIMULATOR_THREADS = 2
"""Threads per block in numba's CUDA simulator (each a Python thread)."""

GPU_THREADS = 128
"""Threads per block on a GPU."""


def _same(arrays: Sequence[np.ndarray], first: Sequence[np.ndarray]) -> bool:
    return all(
        a.shape == b.shape and np.array_equal(a, b) for a, b in zip(arrays, first, strict=True)
    )


class BodiesBatch:
    """E members of the bodies' model in device memory (see the module docstring).

    Attributes:
        pdes: the members' models.
        dt: the common time step.
        heun: whether the members integrate with Heun's method.
        threads: threads per block.
    """

    def __init__(
        self, pdes: Sequence[SurfacePDE], dt: float, heun: bool, threads: int | None = None
    ):
        """
        Args:
            pdes: the members' models (common grid, numerics and bodies' layout).
            dt: time step.
            heun: Heun's method (else forward Euler).
            threads: threads per block (a power of two; default: 2 in the simulator, 128
                on a GPU).

        Raises:
            ValueError: members that cannot share one launch (one line, naming the member).
        """
        self.pdes = list(pdes)
        self.dt = dt
        self.heun = heun
        self.threads = threads or (SIMULATOR_THREADS if simulator_enabled() else GPU_THREADS)
        if self.threads & (self.threads - 1) or not 1 <= self.threads <= 1024:
            raise ValueError(f"threads per block = {self.threads}: a power of two in 1..1024")
        first = self.pdes[0]
        n = first.domain.coords.size
        self.n = n
        records, pills, params, tables, walls = [], [], [], None, None
        for m, pde in enumerate(self.pdes):
            if pde.domain.grid != first.domain.grid or pde.config.numerics != first.config.numerics:
                raise ValueError(f"member {m}: its grid or numerics differ from member 0's")
            setup = pde.setup.at(dt)
            rec, pill = make_body_records(setup)
            table = make_body_tables(pde.bodies, pde.body_scheme, rec, n)[:7]
            cells = pde.domain.cut_cells
            coefficient = dt * pde.config.camphor.diffusion / pde.domain.dx**2
            wall = NO_WALL if cells is None else cells.arrays(coefficient)
            if m == 0:
                tables, walls = table, wall
            elif rec.shape != records[0].shape or pill.shape != pills[0].shape:
                raise ValueError(
                    f"member {m}: its number of bodies or pills differs from member 0's"
                )
            elif not (_same(table, tables) and _same(wall, walls)):
                msg = (
                    f"member {m}: its bodies' scheme tables or dish wall differ from member "
                    "0's (members share the bodies' shapes, smoothing and camphor.diffusion)"
                )
                raise ValueError(msg)
            records.append(rec)
            pills.append(pill)
            params.append(make_record(setup)[0])
        e, k = len(self.pdes), len(records[0])
        corners = max(1, *(b.shape.n_corners for b in first.bodies))
        n_pills = max(1, len(pills[0]))
        nn = n * n
        contour = bool(params[0]["contour"])
        walled = walls[0].size > 0
        coords, lo, hi, _, _ = first.domain.arrays()
        self.centre = np.array(first.domain.centre)
        self.d_buf = cuda.to_device(np.zeros(3 * e * 3 * nn))
        self.d_state = (
            self.d_buf,
            cuda.to_device(np.zeros((e, nn))),
            cuda.to_device(np.zeros((e, nn))),
            cuda.to_device(np.full((e, nn), -1, dtype=np.int64)),
        )
        self.d_surface = (
            cuda.to_device(coords),
            cuda.to_device(np.stack([lo, hi]).astype(np.int64)),
        )
        self.d_pose = cuda.to_device(np.zeros((e, k, len(POSE_COLUMNS))))
        self.d_body = cuda.to_device(np.stack(records))
        self.d_arrays = (
            cuda.to_device(np.stack([p if len(p) else np.zeros((1, 7)) for p in pills])),
            self.d_pose,
            cuda.to_device(np.full((e, k, 3), np.nan)),
            cuda.to_device(np.zeros((e, k, 4), dtype=np.int64)),
        )
        self.d_scratch = (
            cuda.to_device(np.zeros((e, k, 2, corners))),
            cuda.to_device(np.zeros((e, 2, n_pills))),
            cuda.to_device(np.zeros((e, k, 2, 9))),
            cuda.to_device(np.zeros((e, k, 6))),
            cuda.to_device(np.zeros((e, 2 * nn if contour else 1))),
        )
        self.d_tables = tuple(cuda.to_device(np.ascontiguousarray(t)) for t in tables)
        self.d_walls = (
            tuple(cuda.to_device(a) for a in walls),
            cuda.to_device(np.zeros((e, nn if walled else 1))),
        )
        self.d_params = cuda.to_device(np.array(params))
        self.kicks = np.stack(records)["kick"]
        self.d_status = cuda.to_device(np.full((e, 4), -1, dtype=np.int64))
        self.parity = 0
        self.n_members, self.n_bodies = e, k

    def put(self, data: np.ndarray, poses: np.ndarray) -> None:
        """Load the members' fields (E, 3, n, n) and poses (E, K, 15) (dish coordinates)."""
        flat = np.ascontiguousarray(data, dtype=float).reshape(-1)
        size = flat.size
        self.d_buf[:size].copy_to_device(flat)
        self.d_buf[size : 2 * size].copy_to_device(flat)
        local = np.array(poses, dtype=float)
        local[..., 0] -= self.centre[0]
        local[..., 1] -= self.centre[1]
        self.d_pose.copy_to_device(local)
        self.parity = 0

    def get(self) -> tuple[np.ndarray, np.ndarray]:
        """The members' fields (E, 3, n, n) and poses (E, K, 15) (dish coordinates)."""
        size = self.n_members * 3 * self.n * self.n
        data = self.d_buf[self.parity * size : (self.parity + 1) * size].copy_to_host()
        poses = self.d_pose.copy_to_host()
        poses[..., 0] += self.centre[0]
        poses[..., 1] += self.centre[1]
        return data.reshape(self.n_members, 3, self.n, self.n), poses

    def normals(self, rngs: Sequence[np.random.Generator], n_steps: int) -> np.ndarray:
        """(E, n_steps K) standard normals: each noisy member's K per step from its own
        Generator, in step order (as :meth:`BodiesStepper.normals` draws them)."""
        xi = np.zeros((self.n_members, max(1, n_steps * self.n_bodies)))
        for m, rng in enumerate(rngs):
            if np.any(self.kicks[m]):
                xi[m, : n_steps * self.n_bodies] = rng.standard_normal(n_steps * self.n_bodies)
        return xi

    def advance(self, step0: int, n_steps: int, xi: np.ndarray) -> np.ndarray:
        """Advance every member by `n_steps` steps from global step `step0`.

        Returns:
            (E, 4) status: per member the global step at which its run ended (-1: none),
            the reason (``STATUS_*`` of :mod:`pde_rotor.kernels.bodies`), the body and
            the other body.
        """
        launch = bodies_kernel(self.threads)[
            self.n_members, self.threads, 0, N_SUMS * self.threads * 8
        ]
        steps = (np.int64(step0), np.int64(n_steps), np.int64(self.parity), np.int64(self.heun))
        launch(
            self.d_state,
            self.d_surface,
            self.d_body,
            self.d_arrays,
            self.d_scratch,
            self.d_tables,
            self.d_walls,
            self.d_params,
            (cuda.to_device(xi), self.d_status),
            steps,
        )
        self.parity = (self.parity + n_steps) % 2
        return self.d_status.copy_to_host()


@dataclass
class GpuBodiesStepper:
    """The GPU step of one run's bodies, the signature of the CPU's
    :class:`~pde_rotor.solver.bodies.BodiesStepper` (one member of a :class:`BodiesBatch`).

    Attributes:
        pde: the model.
        dt: time step.
        rng: Generator of the noise, K standard normals per step in step order.
    """

    pde: SurfacePDE
    dt: float
    rng: np.random.Generator

    def __post_init__(self) -> None:
        heun = self.pde.config.numerics.integrator == "heun"
        self.batch = BodiesBatch([self.pde], self.dt, heun)

    def __call__(self, data: np.ndarray, bodies: BodiesState, step0: int, n_steps: int) -> None:
        """Advance `data` and `bodies` together by `n_steps` steps from step `step0`.

        Raises:
            SimulationDivergedError: the state became NaN/Inf (time, body).
            BodyContactError: a body reached the dish's edge or another body.
        """
        batch = self.batch
        batch.put(data[None], bodies.poses[None])
        status = batch.advance(step0, n_steps, batch.normals([self.rng], n_steps))[0]
        fields, poses = batch.get()
        data[...] = fields[0]
        bodies.poses[...] = poses[0]
        if status[0] >= 0:
            raise_early_end(self.pde, status[0] * self.dt, status[1:], bodies, data, GPU_END)
        if not np.isfinite(data).all():
            raise_early_end(
                self.pde, (step0 + n_steps) * self.dt, status[1:], bodies, data, GPU_END
            )


def gpu_bodies_stepper(pde: SurfacePDE, dt: float, rng: np.random.Generator) -> GpuBodiesStepper:
    """The stepper factory of a bodies run on the GPU (:class:`GpuBodiesStepper`)."""
    return GpuBodiesStepper(pde=pde, dt=dt, rng=rng)


def run_rotor_ensemble(
    plan: EnsemblePlan,
    rngs: Sequence[np.random.Generator],
    initial: EnsembleState,
    progress: Callable[[int, int], None] | None = None,
    threads_per_block: int | None = None,
) -> EnsembleResult:
    """A rotor ensemble on the bodies' kernel, each member's rotor as its ``fixed_axis``
    body: how :func:`pde_rotor.backends.gpu.run_ensemble` integrates with Heun (the
    rotor's own kernel has forward Euler only). The records of the rotor's kernel: phi,
    omega, the torques and the stop flag after each record step, int c dA over the grid;
    the noise one standard normal per step, in step order, from each member's Generator.

    Args:
        plan: the members and their steps (:func:`pde_rotor.backends.ensemble.make_plan`).
        rngs: one Generator per member.
        initial: the members' state at the plan's first step.
        progress: ``progress(steps_done, steps_total)`` after every record.
        threads_per_block: see :class:`BodiesBatch`.
    """
    wall = time.perf_counter()
    heun = plan.configs[0].numerics.integrator == "heun"
    batch = BodiesBatch([SurfacePDE(s) for s in plan.setups], plan.dt, heun, threads_per_block)
    poses = np.zeros((plan.n_members, 1, len(POSE_COLUMNS)))
    poses[:, 0, PHI], poses[:, 0, OMEGA] = initial.rotor[:, 0], initial.rotor[:, 1]
    batch.put(initial.data, poses)
    records = np.full((plan.n_members, plan.record_steps.size, len(RECORD_FIELDS)), np.nan)
    records[:, 0, :5] = initial.rotor
    records[:, 0, 5] = initial.data[:, 0].sum(axis=(1, 2)) * plan.domain.cell_area
    rotor = initial.rotor.copy()
    ends = [int(s) for s in plan.record_steps[1:]]
    if plan.record_steps[-1] < plan.step_end:  # t_end between two records: advance to it
        ends.append(plan.step_end)
    step = plan.step_start
    status = np.full(plan.n_members, -1, dtype=np.int64)
    for row, end in enumerate(ends, start=1):
        n_steps = end - step
        status = batch.advance(step, n_steps, batch.normals(rngs, n_steps))[:, 0]
        step = end
        data, poses = batch.get()
        rotor = poses[:, 0, [PHI, OMEGA, TORQUE, FRICTION, STOPPED]]
        if row < plan.record_steps.size:
            records[:, row, :5] = rotor
            records[:, row, 5] = data[:, 0].sum(axis=(1, 2)) * plan.domain.cell_area
        if progress is not None:
            progress(step - plan.step_start, plan.n_steps)
    final = EnsembleState(data=batch.get()[0], rotor=rotor, step=plan.step_end)
    return EnsembleResult.from_records(
        plan, records, status, final, "gpu", time.perf_counter() - wall
    )


@dataclass(frozen=True)
class BodiesEnsembleResult:
    """Every body's pose and forces of E members at the record times.

    Attributes:
        configs: the members' configurations.
        t: record times (T,).
        poses: (E, T, K, 15): columns :data:`pde_rotor.model.surface.POSE_COLUMNS`; NaN
            after a member's run ended.
        ended_at: per member the time its run ended (NaN: it did not), `reason` why
            (``STATUS_*``, 0: it did not).
        data: (E, 3, n, n) the fields at the end.
        wall_seconds: wall-clock time of the run.
    """

    configs: tuple[RotorConfig, ...]
    t: np.ndarray
    poses: np.ndarray
    ended_at: np.ndarray
    reason: np.ndarray
    data: np.ndarray
    wall_seconds: float


def run_bodies_ensemble(
    configs: Sequence[Setup | RotorConfig],
    t_end: float | None = None,
    *,
    record_interval: float | None = None,
    rngs: Sequence[np.random.Generator] | None = None,
    threads_per_block: int | None = None,
) -> BodiesEnsembleResult:
    """Advance E members with ``bodies:`` on the GPU from their start poses (c = v = 0).

    Args:
        configs: one configuration or setup (:class:`~pde_rotor.model.setup.Setup`) per
            member (common grid, numerics, bodies' layout).
        t_end: end time (default: the latest ``protocol.t_end``).
        record_interval: time between records (default: ``output.timeseries_interval``
            of member 0); a multiple of dt.
        rngs: one Generator per member (default: ``default_rng(noise.seed)``).
        threads_per_block: see :class:`BodiesBatch`.

    Raises:
        ValueError: members that cannot share one launch, or bad times (one line).
    """
    wall = time.perf_counter()
    setups = tuple(as_setup(member) for member in configs)
    configs = tuple(setup.config for setup in setups)
    if not configs or any(c.bodies is None for c in configs):
        raise ValueError("run_bodies_ensemble needs configs with a bodies: list")
    dt = configs[0].grid.dt
    heun = configs[0].numerics.integrator == "heun"
    pdes = [SurfacePDE(s) for s in setups]
    batch = BodiesBatch(pdes, dt, heun, threads_per_block)
    t_end = max(c.protocol.t_end for c in configs) if t_end is None else t_end
    every = steps_of(record_interval or configs[0].output.timeseries_interval, dt)
    step_end = steps_of(t_end, dt)
    rngs = [np.random.default_rng(c.noise.seed) for c in configs] if rngs is None else list(rngs)
    states = [pde.initial_state() for pde in pdes]
    batch.put(np.stack([s.data for s in states]), np.stack([s.bodies.poses for s in states]))
    records = [batch.get()[1]]
    times = [0.0]
    step = 0
    status = np.full((len(configs), 4), -1, dtype=np.int64)
    while step < step_end:
        n_steps = min(every, step_end - step)
        status = batch.advance(step, n_steps, batch.normals(rngs, n_steps))
        step += n_steps
        poses = batch.get()[1]
        poses[status[:, 0] >= 0] = np.nan
        records.append(poses)
        times.append(step * dt)
    data, _ = batch.get()
    ended = np.where(status[:, 0] >= 0, status[:, 0] * dt, np.nan)
    return BodiesEnsembleResult(
        configs=configs,
        t=np.array(times),
        poses=np.stack(records, axis=1),
        ended_at=ended,
        reason=np.where(status[:, 0] >= 0, status[:, 1], 0),
        data=data,
        wall_seconds=time.perf_counter() - wall,
    )
