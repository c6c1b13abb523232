"""Estimated wall time of a run or a sweep, from measured costs per step and per frame.

One step of the fused solver updates c and v on every cell inside the disk of radius L
(a cost per *interior* cell) and, while the plate turns, recomputes F and G and the
rotor integrals on the cells within reach of the plate (a cost per *support* cell, the
disk of radius :attr:`pde_rotor.model.geometry.RotorShape.support_radius`, which grows with the
edge width delta). ``benchmarks/bench_cost.py`` measures the constants below on one
thread, in CPU seconds (which the load of other work does not inflate):

* the interior cost is the Euler update's, 0.038 ms for the 45 244 interior cells of the
  paper's grid (dx = delta = 0.025);
* the support cost of each scheme is the rest of a turning plate's step per support cell,
  the mean over three grids (dx = delta = 0.025, 0.05 and 1/30: 5 834, 3 441 and 4 559
  support cells), which it gives to within 13 % (paper: 0.101, 0.061, 0.089 ms/step;
  consistent: 0.169, 0.105, 0.134).

A cost per cell alone would put the coarse grid at a quarter of the paper's; it costs
more than half, because the support shrinks less than the disk. A stopped plate keeps
its F and G, so on the support cells a stop step costs only the rotor integrals (the
torque of Eq. (torque) is still computed every step): a third constant per scheme, fitted
alike (paper: 0.062, 0.023, 0.041 ms/step; consistent: 0.090, 0.044, 0.066). Every figure
here is for one idle core of the project's machine (docs/results.md, 2026-11-26); the
sweep estimate adds the load it finds on the machine (:class:`SweepEstimate`) and the
threads of each run (:func:`thread_speedup`). Other machines differ by their speed.

A run with ``bodies:`` steps another kernel (:func:`bodies_step_seconds`): the field update
on every wet cell (with or without the flow, and a no-flux wall's cut cells), and per body
its box of (2 R / dx)^2 cells (R its footprint), where its plate terms enter the update,
its forces are integrated every step (unless it is fixed) and F and G are redrawn while it
moves (not while it is fixed or held); Heun's method does all of it twice and averages the
fields. ``benchmarks/calibrate_cost.py`` measures these steps (every config of
configs/bodies/ with Euler and Heun, runs of the crowd sweeps, single bodies in
dishes) and fits :data:`BODIES_STEP_COSTS` to them (docs/results.md, 2026-11-28).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

from ..config import RotorConfig
from ..model.setup import Setup
from ..solver.threads import other_load, usable_cores

if TYPE_CHECKING:
    from . import Run

SECONDS_PER_CELL_STEP = 8.4e-10
"""Wall time of one step per interior cell (field update of Eqs. (eqc), (eqv))."""
SECONDS_PER_SUPPORT_CELL_STEP: dict[str, float] = {"paper": 1.3e-8, "consistent": 2.45e-8}
"""Wall time of one step of a turning plate per support cell (F, G and the rotor
integrals), per ``numerics.scheme``: the consistent scheme's filtered F and G and contour
torque cost 1.7 times the paper scheme's step on the paper's grid."""
SECONDS_PER_STOPPED_SUPPORT_CELL_STEP: dict[str, float] = {"paper": 4.1e-9, "consistent": 9.6e-9}
"""Wall time of one step of a stopped plate per support cell (the rotor integrals only;
F and G keep the stop angle), per ``numerics.scheme``."""
SECONDS_PER_MOVIE_FRAME = 0.07
"""Wall time to render and encode one movie frame at ``output.movie_dpi = 100``
(configs/quickstart.yaml: 215 frames add 15 s)."""
SECONDS_PER_CALL = 1.5e-3
"""Set-up of one call of the CPU ensemble backend per member (a Simulation and its py-pde
stepper), besides :data:`SECONDS_PER_CALL_CELL` per interior cell: 2.0 ms on the coarse
grid, 3.4 ms on the paper's (``pde_rotor.backends.cpu.run_ensemble`` of one step). A
restart calls it at each commitment check."""
SECONDS_PER_CALL_CELL = 4.1e-8
"""The part of :data:`SECONDS_PER_CALL` that grows with the interior cells."""
CALLS_PER_RESTART = 2
"""Calls of a restart besides its commitment checks: the approach to the stop and the stop."""
START_SECONDS = 5.0
"""Wall time a sweep on a LocalCluster spends besides its runs: the cluster's and its
workers' start (imports, the compiled kernels read from numba's cache) and the report
(configs/sweeps/cost_check.yaml: 30 s for runs that took 25 s)."""
COMMIT_TIME = 0.8
"""Release time until a restart has committed to a direction: the mean ``t_commit`` of
the 6814 releases stored under data/sweeps/ is 0.82 (0.77 to 0.87 by sweep)."""
BODIES_STEP_COSTS: dict[str, float] = {
    "cell": 5.47e-10,
    "flow_cell": 1.65e-09,
    "no_flux_cell": 6.55e-10,
    "no_flux_flow_cell": 9.24e-10,
    "no_flux_box_cell": 5.47e-09,
    "paper_box_cell": 4.06e-09,
    "consistent_box_cell": 2.11e-08,
    "drawn_pill_cell": 5.16e-09,
    "heun_average_cell": 9.55e-10,
}
"""CPU seconds of one step of the bodies' kernel per unit of each term of
:func:`bodies_step_terms` (one thread on one core of the project's machine), fitted by
``benchmarks/calibrate_cost.py`` to measured steps of every config of configs/bodies/
with Euler and Heun, runs of the crowd sweeps (30 disks in the dish; 4, 6, 11 and 16
boats in the ring) and single bodies in dishes, on the idle machine after a body's
contour circles were taken in two passes and a strip's drawing was vectorised
(docs/results.md, 2026-11-29). Per wet cell: ``cell`` the
field update without flow, ``flow_cell`` what the flow adds, ``no_flux_cell`` what a
no-flux wall's cut-cell update adds, ``no_flux_flow_cell`` what the flow adds there
besides. Per cell of a body's box (2 R / dx)^2, R its footprint's reach:
``no_flux_box_cell`` its plate terms in the cut-cell update (every body, behind a no-flux
wall; in the open update they cost what a bare cell costs), ``<scheme>_box_cell`` its
force integrals (every body but a ``fixed`` one, held or not; with ``consistent`` also
its filtered F and the contour form; a body that spans its channel ``paper_box_cell`` on
either scheme, its integrals being the area form's over the wet cells: measured, its
consistent run costs what its paper run does, docs/results.md, 2026-11-29).
``drawn_pill_cell``: per cell of each pill's box (2 (rho + w delta) / dx)^2, w =
``numerics.footprint_widths``, its source term G (and F without a plate) redrawn while
the body moves (the plate's own F is within the fit's noise). ``heun_average_cell``:
Heun's average per wet cell and field (c, and v with the flow). A change of the bodies'
or the vessel's step calls for the script again; it prints these constants in this form."""
COLLECTIVE_SET_UP_SECONDS = 1.5
"""CPU time of a collective run besides its steps (its Simulation, the bodies' placement,
the recorded measures): the crowd dish's runs that ended at t = 1 took 1.0 to 2.3 s more
than their steps (benchmarks/crowd_cost.py, docs/results.md, 2026-11-28)."""
LONG_RUN_SECONDS = 600.0
"""Runs estimated to take longer than this announce their estimate before they start."""


def cell_counts(config: RotorConfig) -> tuple[int, int]:
    """(interior cells, support cells) of the config's grid: the areas of the dish (or of
    ``grid.vessel``, whose step walks only its wet cells) and of the support over dx^2."""
    dx2 = config.grid.dx**2
    support = Setup(config).shape.support_radius
    vessel = config.grid.vessel
    area = math.pi * config.grid.domain_radius**2 if vessel is None else vessel.area()
    return (
        round(area / dx2),
        round(math.pi * support**2 / dx2),
    )


def call_seconds(config: RotorConfig) -> float:
    """Estimated set-up of one call of the CPU ensemble backend for one member."""
    return SECONDS_PER_CALL + SECONDS_PER_CALL_CELL * cell_counts(config)[0]


def step_seconds(config: RotorConfig, stopped: bool = False) -> float:
    """Estimated wall time of one solver step on the config's grid, of a turning plate
    or (`stopped`) of a stopped one."""
    interior, support = cell_counts(config)
    table = SECONDS_PER_STOPPED_SUPPORT_CELL_STEP if stopped else SECONDS_PER_SUPPORT_CELL_STEP
    return interior * SECONDS_PER_CELL_STEP + support * table[config.numerics.scheme]


def moving_shares(config: RotorConfig) -> list[float]:
    """Each body's share of the run's steps in which it moves (and is redrawn): 0 for a
    ``fixed`` body, else 1 less the share of t_end its own stops hold it."""
    t_end = config.protocol.t_end
    shares = []
    for body in config.bodies or []:
        moving = 0.0 if body.motion.kind == "fixed" else 1.0
        if moving and body.protocol is not None and t_end > 0:
            held = body.protocol.cycles * body.protocol.t_stop
            moving = max(0.0, 1.0 - min(held, t_end) / t_end)
        shares.append(moving)
    return shares


def bodies_step_terms(
    config: RotorConfig, moving: Sequence[float] | None = None
) -> dict[str, float]:
    """What one step of a run with ``bodies:`` walks, by the key of
    :data:`BODIES_STEP_COSTS` that prices it: the wet cells (with the flow, behind a
    no-flux wall), each body's box of (2 R / dx)^2 cells (its plate terms behind a no-flux
    wall, its force integrals unless it is ``fixed``: the area form's for a body that
    spans its channel, whatever the scheme) and its pills' boxes (redrawn in the
    share `moving` of the steps, each body's, default :func:`moving_shares`). Heun's method
    (:func:`pde_rotor.kernels.bodies.advance_bodies`) draws, sums and updates the fields
    twice a step (at the state and at the prediction) and averages the fields once: twice
    every term, and ``heun_average_cell``.
    """
    interior = cell_counts(config)[0]
    flow = config.flow.enabled
    walled = no_flux_walls(config)
    delta, dx = config.geometry.smoothing, config.grid.dx
    widths = config.numerics.footprint_widths
    bodies = config.bodies or []
    shares = moving_shares(config) if moving is None else moving
    terms = dict.fromkeys(BODIES_STEP_COSTS, 0.0)
    terms["cell"] = interior
    terms["flow_cell"] = interior if flow else 0.0
    terms["no_flux_cell"] = interior if walled else 0.0
    terms["no_flux_flow_cell"] = interior if walled and flow else 0.0
    for body, share in zip(bodies, shares, strict=True):
        box = (2 * body.reach(delta, widths) / dx) ** 2
        terms["no_flux_box_cell"] += box if walled else 0.0
        if body.motion.kind != "fixed":
            scheme = "paper" if getattr(body.motion, "spans", False) else config.numerics.scheme
            terms[f"{scheme}_box_cell"] += box
            for pill in body.pills:
                pill_box = (2 * (pill.radius + widths * delta) / dx) ** 2
                terms["drawn_pill_cell"] += share * pill_box
    if config.numerics.integrator == "heun":
        terms = {key: 2.0 * value for key, value in terms.items()}
        terms["heun_average_cell"] = interior * (3 if flow else 1)
    return terms


def bodies_step_seconds(config: RotorConfig, moving: Sequence[float] | None = None) -> float:
    """Estimated CPU time of one step of a run with ``bodies:``, averaged over the run
    (:func:`bodies_step_terms` priced by :data:`BODIES_STEP_COSTS`): each body redrawn
    while it moves (a fixed body never, a body with stops not while held)."""
    terms = bodies_step_terms(config, moving)
    return sum(BODIES_STEP_COSTS[key] * count for key, count in terms.items())


def no_flux_walls(config: RotorConfig) -> bool:
    """Whether the config's dish or vessel has a no-flux wall (cut cells that cost every
    step): ``grid.wall``, or a wall of ``grid.vessel``."""
    vessel = config.grid.vessel
    walls = [config.grid.wall] + [
        getattr(vessel, name)
        for name in ("wall", "inner_wall", "outer_wall")
        if hasattr(vessel, name)
    ]
    return "no_flux" in walls


def protocol_seconds(config: RotorConfig) -> float:
    """Estimated wall time of the whole protocol (t_end), its M stops at the cost of a
    stopped plate (with ``bodies:``, :func:`bodies_step_seconds` every step)."""
    if config.bodies is not None:
        return steps(config.protocol.t_end, config) * bodies_step_seconds(config)
    n_stopped = config.protocol.cycles * steps(config.protocol.t_stop, config)
    n_moving = steps(config.protocol.t_end, config) - n_stopped
    return n_moving * step_seconds(config) + n_stopped * step_seconds(config, stopped=True)


def steps(duration: float, config: RotorConfig) -> int:
    """Number of steps of length grid.dt in `duration`."""
    return round(duration / config.grid.dt)


@dataclass(frozen=True)
class RunEstimate:
    """Estimated cost of one ``pde-rotor run``.

    Attributes:
        steps: solver steps to t_end.
        cells: interior cells of the grid.
        frames: movie frames rendered (0 without a movie).
        seconds: estimated wall time.
    """

    steps: int
    cells: int
    frames: int
    seconds: float

    @property
    def long(self) -> bool:
        """Whether the run is expected to take longer than :data:`LONG_RUN_SECONDS`."""
        return self.seconds > LONG_RUN_SECONDS

    def describe(self) -> str:
        """``about 5.1 h (10.6 M steps on 45 k cells, 21200 movie frames; an estimate)``."""
        movie = f", {self.frames} movie frames" if self.frames else ""
        return (
            f"about {format_duration(self.seconds)} ({format_count(self.steps)} steps on "
            f"{format_count(self.cells)} cells{movie}; an estimate from measured costs on one "
            "core)"
        )


def estimate_run(config: RotorConfig, movie: bool | None = None) -> RunEstimate:
    """Estimated cost of running `config` with its trackers.

    Args:
        config: the run configuration.
        movie: whether a movie is rendered (default: ``output.movie``).
    """
    n = steps(config.protocol.t_end, config)
    movie = config.output.movie if movie is None else movie
    frames = math.floor(config.protocol.t_end / config.output.movie_interval + 1e-9) + 1
    frames = frames if movie else 0
    seconds = protocol_seconds(config) + frames * SECONDS_PER_MOVIE_FRAME
    return RunEstimate(n, cell_counts(config)[0], frames, seconds)


THREAD_SERIAL_FRACTION = 0.1
"""Share of a step's one-thread time that more threads do not shorten (the parallel
regions' start and the serial sums), Amdahl's law: a step on T threads takes
s + (1 - s) / T of its one-thread time. Placeholder until bench_threads.py measures it."""


def thread_speedup(threads: int) -> float:
    """How many times faster one run steps on `threads` threads than on one (Amdahl's
    law with :data:`THREAD_SERIAL_FRACTION`), on otherwise idle cores."""
    return 1.0 / (THREAD_SERIAL_FRACTION + (1.0 - THREAD_SERIAL_FRACTION) / threads)


@dataclass(frozen=True)
class SweepEstimate:
    """Estimated cost of the runs of a sweep still to compute.

    Attributes:
        runs: runs to compute.
        core_seconds: their estimated compute time on one core, spin-ups included.
        workers: worker processes they are spread over (None: unknown, a scheduler's).
        load: the cores other work keeps busy when estimated
            (:func:`pde_rotor.solver.threads.other_load`).
        cores: the cores this process may use.
        threads: threads of each worker's runs (``pde-rotor sweep --threads``).
        restarts: whether the runs are restarts (whose release time is assumed); None
            where there are none to compute (no note).
    """

    runs: int
    core_seconds: float
    workers: int | None
    load: float = 0.0
    cores: int = 1
    threads: int = 1
    restarts: bool | None = True

    @property
    def busy_workers(self) -> int:
        """Workers that get runs (no more than there are runs)."""
        return min(self.workers or 1, self.runs or 1)

    @property
    def slowdown(self) -> float:
        """How much slower each worker runs on a machine busy with other work: the
        threads wanting a core (the other work's plus the workers') per core, at least 1."""
        if not self.workers:
            return 1.0
        return max(1.0, (self.load + self.busy_workers * self.threads) / self.cores)

    @property
    def wall_seconds(self) -> float:
        """Estimated wall time: the core-seconds spread over the workers, each run
        :func:`thread_speedup` faster on its threads, times :attr:`slowdown`, and the
        workers' start (:data:`START_SECONDS`)."""
        runs = self.core_seconds / (self.busy_workers * thread_speedup(self.threads))
        return runs * self.slowdown + (START_SECONDS if self.workers else 0.0)

    def describe(self) -> str:
        """``about 52 min of one core, 26 min on 2 workers (...)``."""
        text = f"about {format_duration(self.core_seconds)} of one core"
        if self.workers and self.runs:
            busy = (
                f" at the machine's present load of {self.load:.1f} on {self.cores} cores"
                if self.slowdown > 1
                else ""
            )
            each = f" of {self.threads} threads" if self.threads > 1 else ""
            workers = f"{self.workers} worker{'s' if self.workers != 1 else ''}"
            text += f", {format_duration(self.wall_seconds)} on {workers}{each}{busy}"
        assumed = {
            True: f"; restarts assumed to commit {COMMIT_TIME:g} time unit after their release",
            False: "; runs that end early cost less",
            None: "",
        }[self.restarts]
        return f"{text} (an estimate from measured costs per step{assumed})"


def estimate_sweep(runs: Sequence[Run], workers: int | None, threads: int = 1) -> SweepEstimate:
    """Estimated cost of computing `runs` of one sweep (no trackers, no movie).

    * protocol estimator: t_end of each run (:func:`protocol_seconds`); collective (a
      bodies run): likewise, every step at :func:`bodies_step_seconds`, and
      :data:`COLLECTIVE_SET_UP_SECONDS` a run;
    * restart: the stop (steps of a stopped plate) and a release of :data:`COMMIT_TIME`
      (at most the release cap) per run, with the set-up of its calls of the CPU backend
      (:func:`call_seconds`: the approach, the stop and a commitment check every
      ``check_interval``), plus the noise-free spin-up (``warmup``) that
      each worker computes once per spin-up state it meets (:func:`pde_rotor.sweep.warm_key`);
    * bank: as restart, with one stop per group of runs that share it.

    Args:
        runs: the runs to compute (:meth:`pde_rotor.sweep.Sweep.runs`, finished ones
            left out).
        workers: worker processes (None: unknown; spin-ups are counted once).
        threads: threads of each worker's runs.
    """
    from . import RestartEstimator, stop_group, warm_key

    points: dict[tuple[tuple[int, ...], int], tuple[RotorConfig, str | None, float, float]] = {}
    stops: set[str] = set()
    warm: dict[str, int] = {}
    total = 0.0
    for run in runs:
        # the runs of a point and direction differ only in their noise seed
        if (run.point, run.direction) not in points:
            config = RotorConfig.model_validate(run.config)
            if run.estimator["kind"] in ("protocol", "collective"):
                seconds = protocol_seconds(config)
                if run.estimator["kind"] == "collective":
                    seconds += COLLECTIVE_SET_UP_SECONDS
                points[run.point, run.direction] = (config, None, seconds, 0.0)
            else:
                estimator = RestartEstimator.model_validate({**run.estimator, "kind": "restart"})
                spin_up = warm_key(config, estimator, run.direction)
                cap = estimator.release_cap or config.protocol.t_release
                checks = math.ceil(min(cap, COMMIT_TIME) / estimator.check_interval - 1e-9)
                release = steps(min(cap, COMMIT_TIME), config) * step_seconds(config)
                release += (CALLS_PER_RESTART + checks) * call_seconds(config)
                stop = steps(config.protocol.t_stop, config) * step_seconds(config, stopped=True)
                points[run.point, run.direction] = (config, spin_up, release, stop)
        # per run: its release (restart, bank) or its whole protocol (protocol estimator)
        config, spin_up, per_run, stop = points[run.point, run.direction]
        total += per_run
        if spin_up is None:
            continue
        group = stop_group(run)
        if group not in stops:
            stops.add(group)
            total += stop
        warm[spin_up] = warm.get(spin_up, 0) + 1
        if warm[spin_up] <= (workers or 1):
            total += steps(run.estimator["warmup"], config) * step_seconds(config)
    restarts = any(run.estimator["kind"] in ("restart", "bank") for run in runs) if runs else None
    return SweepEstimate(len(runs), total, workers, other_load(), usable_cores(), threads, restarts)


def format_duration(seconds: float) -> str:
    """``40 s``, ``12 min``, ``5.1 h``, ``3.2 days``."""
    if seconds < 90:
        return f"{seconds:.0f} s"
    if seconds < 5400:
        return f"{seconds / 60:.0f} min"
    if seconds < 2 * 86400:
        return f"{seconds / 3600:.1f} h"
    return f"{seconds / 86400:.1f} days"


def format_count(n: float) -> str:
    """``950``, ``45 k``, ``10.6 M``, ``1.2 G``."""
    for size, suffix in ((1e9, " G"), (1e6, " M"), (1e3, " k")):
        if n >= size:
            value = n / size
            return f"{value:.{1 if value < 100 else 0}f}{suffix}".replace(".0 ", " ")
    return f"{n:.0f}"
