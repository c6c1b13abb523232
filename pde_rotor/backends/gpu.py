"""GPU ensemble backend: E members of the rotor model in one batched CUDA computation.

The host side: whether a GPU (or numba's CUDA simulator) is there, the members'
parameters packed for the kernel, the noise drawn on the host, and the launches in
chunks of steps with the records copied back. The kernel and what it computes per
step are in :mod:`pde_rotor.kernels.cuda`: the same physics as the CPU solver
(:mod:`pde_rotor.kernels.cpu`) from the same source, the physics core
(:mod:`pde_rotor.physics`).

The noise: one standard normal per step per member, drawn on the host from a numpy
Generator seeded like the CPU solver's (``default_rng(noise.seed)``) in step order, so
both backends use the identical noise sequence.

The module imports numba-cuda at import time but compiles nothing until the first run;
:func:`unavailable_reason` says whether a GPU is present. With
``NUMBA_ENABLE_CUDASIM=1`` the kernels run in numba's CUDA simulator on the CPU
(slowly: for tests on tiny grids).
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING

import numpy as np

from ..kernels.cuda import MAX_CORNERS, advance_kernel
from ..kernels.cuda_target import cuda, simulator_enabled

if TYPE_CHECKING:  # imported by the functions that use them: `pde-rotor info` asks quickly
    from ..config import RotorConfig
    from ..model.pde import RotorPDE
    from ..model.setup import Setup
    from .ensemble import EnsemblePlan, EnsembleResult, EnsembleState

SIMULATOR_THREADS = 2
"""Default threads per block in numba's CUDA simulator (one Python thread each): the
simulator's cost grows with its threads (50 steps of the test grid of tests/backends/test_gpu.py:
7 s with 2 threads, 26 s with 8), and the reductions already take two threads."""


def unavailable_reason(allow_simulator: bool = False) -> str | None:
    """Why no kernel can run here (None: a GPU, or the simulator if allowed, is present)."""
    if simulator_enabled():
        return None if allow_simulator else "only numba's CUDA simulator is enabled"
    try:
        if not cuda.is_available():
            return "no CUDA GPU or driver found"
    except Exception as err:  # driver errors surface as various exception types
        return f"the CUDA driver failed ({type(err).__name__}: {err})"
    return None


def device_name() -> str:
    """The GPU the kernels run on, or numba's CUDA simulator."""
    if simulator_enabled():
        return "numba CUDA simulator (NUMBA_ENABLE_CUDASIM=1)"
    name = cuda.get_current_device().name
    return name.decode() if isinstance(name, bytes) else str(name)


def is_available(allow_simulator: bool = False) -> bool:
    """Whether a CUDA GPU (or, if allowed, the simulator) can run the kernels."""
    return unavailable_reason(allow_simulator=allow_simulator) is None


def _member_arrays(
    plan: EnsemblePlan,
) -> tuple[np.ndarray, np.ndarray, tuple[np.ndarray, ...]]:
    """(params, support, tables): the members' parameter records (E,) and supports of F
    and G (E, 2, n), and the tables all members share (:meth:`Scheme.kernel_tables`)."""
    from ..kernels.records import PARAMS, make_record
    from ..model.pde import RotorPDE

    n = plan.domain.coords.size
    n_members = plan.n_members
    params = np.empty(n_members, dtype=PARAMS)
    support = np.empty((n_members, 2, n), dtype=np.int64)
    models: dict[str, RotorPDE] = {}  # members often share all but seed and protocol
    for m, setup in enumerate(plan.setups):
        cfg = setup.config
        key = cfg.model_dump_json(include={"geometry", "camphor", "flow", "rotor", "grid"})
        pde = models.get(key)
        if pde is None:
            pde = models[key] = RotorPDE(setup)
        params[m] = make_record(setup.at(plan.dt))[0]
        tables = setup.scheme.kernel_tables()
        if m == 0:
            first_tables = tables
        elif not all(np.array_equal(a, b) for a, b in zip(tables, first_tables, strict=True)):
            msg = (
                f"member {m}: its F and G filter tables differ from member 0's; the "
                "consistent scheme on the GPU needs one geometry (radius, n_corners, "
                "pill_radius, smoothing) for all members (only asymmetry may differ)"
            )
            raise ValueError(msg)
        support[m, 0] = pde.domain.support_lo
        support[m, 1] = pde.domain.support_hi
        if pde.shape.n_corners > MAX_CORNERS:
            msg = f"member {m}: n_corners = {pde.shape.n_corners} > {MAX_CORNERS}"
            raise ValueError(msg)
    return params, support, first_tables


def _interior_rows(plan: EnsemblePlan, support: np.ndarray) -> np.ndarray:
    """[i0, i1): the rows with interior cells; checks that every support lies inside them.

    :func:`pde_rotor.model.domain.make_domain` guarantees that the support of F and G (radius
    R + 20 delta / cos(pi/N)) lies inside the interior; the kernel relies on it.

    Raises:
        ValueError: if a support cell is not an interior cell.
    """
    dom = plan.domain
    used = np.nonzero(dom.interior_hi > dom.interior_lo)[0]
    has_support = support[:, 1] > support[:, 0]
    outside = (support[:, 0] < dom.interior_lo) | (support[:, 1] > dom.interior_hi)
    if np.any(has_support & outside):
        msg = (
            "the support of F and G (radius R + 20 delta / cos(pi/N)) leaves the interior "
            f"cells; increase grid.domain_radius above {dom.radius:g}"
        )
        raise ValueError(msg)
    return np.array([used[0], used[-1] + 1], dtype=np.int64)


def _draw_normals(
    rngs: Sequence[np.random.Generator], noisy: np.ndarray, n_steps: int
) -> np.ndarray:
    """(E, n_steps) standard normals of the noise, each noisy member's in step order from
    its own Generator (the kernel scales them to the kicks of Eq. (noiseav))."""
    normals = np.zeros((noisy.size, max(n_steps, 1)))
    for m in np.flatnonzero(noisy):
        normals[m, :n_steps] = rngs[m].standard_normal(n_steps)
    return normals


def run_ensemble(
    configs: Sequence[Setup | RotorConfig],
    t_end: float | None = None,
    *,
    record_interval: float | None = None,
    initial: EnsembleState | None = None,
    rngs: Sequence[np.random.Generator] | None = None,
    progress: Callable[[int, int], None] | None = None,
    threads_per_block: int | None = None,
    min_blocks_per_sm: int | None = None,
    chunk_steps: int = 20_000,
    allow_simulator: bool = True,
) -> EnsembleResult:
    """Advance every member on the GPU (arguments: :func:`pde_rotor.backends.run_ensemble`).

    The kernel below integrates with forward Euler; with ``numerics.integrator: heun``
    the members run as their ``fixed_axis`` bodies on the bodies' kernel
    (:func:`pde_rotor.backends.gpu_bodies.run_rotor_ensemble`; `min_blocks_per_sm` and
    `chunk_steps` do not apply, a launch per record interval; `threads_per_block`
    defaults to that kernel's).

    Args:
        configs: one configuration or setup per member (common ``grid`` section).
        t_end: final time (default: latest protocol end).
        record_interval: time between records (default: ``output.timeseries_interval``).
        initial: state to continue from.
        rngs: one Generator per member (default: ``default_rng(noise.seed)``).
        progress: ``progress(steps_done, steps_total)`` after every launch.
        threads_per_block: threads advancing one member (a power of two <= 1024;
            a multiple of 32 on a GPU); default 256, and 8 in the simulator, which runs
            every thread as a Python thread.
        min_blocks_per_sm: launch bound passed to the compiler (see
            :func:`advance_kernel`); 0: none; default: 512 // threads_per_block (at
            least 1), which caps the kernel at 128 registers per thread (ptxas, sm_90:
            165 registers unbounded, 128 with 52 bytes of spills at (256, 2)).
        chunk_steps: steps per kernel launch; the host draws the next chunk's noise
            while the GPU runs the current one.
        allow_simulator: accept numba's CUDA simulator (``NUMBA_ENABLE_CUDASIM=1``).

    Raises:
        RuntimeError: no GPU (and no simulator if allowed).
        ValueError: invalid request (see :func:`~pde_rotor.backends.ensemble.make_plan`).
    """
    from .ensemble import RECORD_FIELDS, EnsembleResult, EnsembleState, default_rngs, make_plan

    wall = time.perf_counter()
    reason = unavailable_reason(allow_simulator=allow_simulator)
    if reason is not None:
        raise RuntimeError(f"GPU backend unavailable: {reason}")
    asked_threads = threads_per_block
    if threads_per_block is None:
        threads_per_block = SIMULATOR_THREADS if simulator_enabled() else 256
    if not 1 <= threads_per_block <= 1024 or threads_per_block & (threads_per_block - 1):
        msg = f"threads_per_block = {threads_per_block}: must be a power of two in 1..1024"
        raise ValueError(msg)
    if chunk_steps < 1:
        raise ValueError(f"chunk_steps = {chunk_steps} must be >= 1")
    plan = make_plan(configs, t_end, record_interval, initial)
    rngs = default_rngs(plan.configs) if rngs is None else list(rngs)
    if len(rngs) != plan.n_members:
        raise ValueError(f"{len(rngs)} generators for {plan.n_members} members")
    state = initial if initial is not None else EnsembleState.initial(plan.configs, plan.domain)
    if plan.configs[0].numerics.integrator == "heun":  # the rotor's kernel: Euler only
        from .gpu_bodies import run_rotor_ensemble

        return run_rotor_ensemble(plan, rngs, state, progress, asked_threads)
    params, support, tables = _member_arrays(plan)
    rows = _interior_rows(plan, support)
    noisy = params["kick"] != 0.0
    dom = plan.domain
    n_members = plan.n_members

    start = np.array(state.data, dtype=np.float64)  # a copy, C-contiguous
    for m, cfg in enumerate(plan.configs):
        if not cfg.flow.enabled:  # as stepping.advance: v = 0 without flow
            start[m, 1:] = 0.0
    size = start.size
    d_buf = cuda.device_array(2 * size)  # both buffers start as the initial state
    d_buf[:size].copy_to_device(start.reshape(-1))
    d_buf[size:].copy_to_device(start.reshape(-1))
    d_coords = cuda.to_device(dom.coords)
    d_interior = cuda.to_device(np.stack([dom.interior_lo, dom.interior_hi]).astype(np.int64))
    d_rows = cuda.to_device(rows)
    d_params = cuda.to_device(params)
    d_support = cuda.to_device(support)
    d_tables = tuple(cuda.to_device(table) for table in tables)
    d_rotor = cuda.to_device(state.rotor.copy())
    d_status = cuda.to_device(np.full(n_members, -1, dtype=np.int64))
    contour = params["contour"]
    d_coef = cuda.device_array(2 * n_members * dom.coords.size**2 if contour.any() else 1)
    records = np.full((n_members, plan.record_steps.size, len(RECORD_FIELDS)), np.nan)
    records[:, 0, :5] = state.rotor
    records[:, 0, 5] = state.data[:, 0].sum(axis=(1, 2)) * dom.cell_area
    if min_blocks_per_sm is None:
        min_blocks_per_sm = max(1, 512 // threads_per_block)
    kernel = advance_kernel(threads_per_block, min_blocks_per_sm)[
        n_members, threads_per_block, 0, 4 * threads_per_block * 8
    ]

    step, parity = plan.step_start, 0
    normals = _draw_normals(rngs, noisy, min(chunk_steps, plan.step_end - step))
    while step < plan.step_end:
        n_steps = min(chunk_steps, plan.step_end - step)
        first = step // plan.record_every + 1
        last = (step + n_steps) // plan.record_every
        shape = (n_members, max(last - first + 1, 1), len(RECORD_FIELDS))
        d_records = cuda.to_device(np.full(shape, np.nan))
        kernel(
            d_buf,
            (d_coords, d_interior, d_rows, d_support),
            d_params,
            d_tables,
            (d_rotor, cuda.to_device(normals), d_records, d_status, d_coef),
            (step, n_steps, parity, plan.record_every, first),
        )
        upcoming = min(chunk_steps, plan.step_end - step - n_steps)
        if upcoming > 0:  # drawn on the host while the GPU works
            normals = _draw_normals(rngs, noisy, upcoming)
        if last >= first:
            r0 = plan.record_index(first * plan.record_every)
            records[:, r0 : r0 + last - first + 1] = d_records.copy_to_host()[:, : last - first + 1]
        step += n_steps
        parity = (parity + n_steps) % 2
        if progress is not None:
            progress(step - plan.step_start, plan.n_steps)

    status = d_status.copy_to_host()
    final = EnsembleState(
        data=d_buf[parity * size : (parity + 1) * size].copy_to_host().reshape(start.shape),
        rotor=d_rotor.copy_to_host(),
        step=plan.step_end,
    )
    return EnsembleResult.from_records(
        plan, records, status, final, "gpu", time.perf_counter() - wall
    )


__all__ = [
    "device_name",
    "is_available",
    "run_ensemble",
    "simulator_enabled",
    "unavailable_reason",
]
