"""The cost estimate: cell counts of the real grid, the measured reference steps, movie frames."""

from __future__ import annotations

import math
import time

import pytest

from pde_rotor.config import validate_config
from pde_rotor.model.domain import make_domain
from pde_rotor.model.geometry import RotorShape
from pde_rotor.solver.simulation import Simulation
from pde_rotor.sweep import Sweep, SweepSpec
from pde_rotor.sweep.cost import (
    BODIES_STEP_COSTS,
    CALLS_PER_RESTART,
    COMMIT_TIME,
    LONG_RUN_SECONDS,
    SECONDS_PER_CELL_STEP,
    bodies_step_seconds,
    call_seconds,
    cell_counts,
    estimate_run,
    estimate_sweep,
    format_count,
    format_duration,
    no_flux_walls,
    protocol_seconds,
    step_seconds,
)

PAPER = {"numerics": {"scheme": "paper"}}
COARSE = {
    "grid": {"dx": 0.05, "dt": 4e-4},
    "geometry": {"smoothing": 0.05},
    "numerics": {"scheme": "paper"},
}
FINE_GRID = {"dx": 0.025, "dt": 1e-4}
"""Half the coarse dx at the same delta."""


@pytest.mark.parametrize("data", [PAPER, COARSE, {**COARSE, "grid": {"dx": 0.04, "dt": 2e-4}}])
def test_cell_counts_are_those_of_the_solver_grid(data):
    """The disk areas over dx^2 count the cells the kernel updates, within 0.5 %."""
    config = validate_config(data)
    domain = make_domain(config.grid, RotorShape.from_config(config.geometry))
    interior, support = cell_counts(config)
    assert interior == pytest.approx(domain.interior_mask.sum(), rel=5e-3)
    assert support == pytest.approx(domain.support_mask.sum(), rel=5e-3)


@pytest.mark.parametrize(
    "vessel",
    [
        {"shape": "annulus", "inner_radius": 0.5, "outer_radius": 3.0},
        {"shape": "rectangle", "half_widths": [3.0, 1.5]},
    ],
)
def test_cell_counts_of_a_vessel_are_its_wet_cells(vessel):
    """In a vessel the interior cells are those its step walks: its area over dx^2 (the
    sum of the volume fractions), the cells it wets within 5 % (its cut cells count
    whole)."""
    start = {"x": 1.75} if vessel["shape"] == "annulus" else {}
    config = validate_config(
        {
            **COARSE,
            "grid": {**COARSE["grid"], "vessel": vessel},
            "bodies": [{"pills": [{}], "start": start}],
        }
    )
    domain = make_domain(config.grid, RotorShape.from_config(config.geometry))
    interior, _ = cell_counts(config)
    assert interior == pytest.approx(domain.cut_cells.volume.sum(), rel=5e-3)
    assert interior == pytest.approx(domain.cut_cells.mask.sum(), rel=5e-2)


def test_step_cost_scales_with_the_cells_of_each_kind():
    """Halving dx at fixed delta puts four times the cells of both kinds on the grid
    and costs four times as much per step; a larger domain adds interior cells only, a
    wider edge (delta) support cells only, and each costs more, turning or stopped."""
    coarse, fine = validate_config(COARSE), validate_config({**COARSE, "grid": FINE_GRID})
    assert cell_counts(fine)[0] == pytest.approx(4 * cell_counts(coarse)[0], rel=1e-3)
    assert cell_counts(fine)[1] == pytest.approx(4 * cell_counts(coarse)[1], rel=1e-3)
    for stopped in (False, True):
        ratio = step_seconds(fine, stopped) / step_seconds(coarse, stopped)
        assert ratio == pytest.approx(4, rel=1e-3)
    wider = validate_config({**COARSE, "grid": {**COARSE["grid"], "domain_radius": 4.0}})
    assert cell_counts(wider)[1] == cell_counts(coarse)[1]
    assert cell_counts(wider)[0] > cell_counts(coarse)[0]
    softer = validate_config({**COARSE, "geometry": {"smoothing": 0.07}})
    assert cell_counts(softer)[0] == cell_counts(coarse)[0]
    assert cell_counts(softer)[1] > cell_counts(coarse)[1]
    for bigger in (wider, softer, fine):
        for stopped in (False, True):
            assert step_seconds(bigger, stopped) > step_seconds(coarse, stopped)
    consistent = validate_config({**COARSE, "numerics": {"scheme": "consistent"}})
    assert step_seconds(consistent) > step_seconds(coarse)


def test_run_cost_scales_with_its_steps():
    """Twice the steps (half dt, or twice the time) cost twice as much; each added
    cycle adds the same cost."""
    protocol = {"t_ini": 1.0, "t_stop": 0.4, "t_release": 0.8}

    def seconds(cycles: int = 2, dt: float = 4e-4, t_ini: float = 1.0) -> float:
        grid = {**COARSE["grid"], "dt": dt}
        data = {**COARSE, "grid": grid, "protocol": {**protocol, "t_ini": t_ini, "cycles": cycles}}
        return estimate_run(validate_config(data), movie=False).seconds

    assert seconds(dt=2e-4) == pytest.approx(2 * seconds(), rel=1e-9)
    assert seconds(cycles=4, t_ini=2.0) == pytest.approx(2 * seconds(), rel=1e-9)
    added = [seconds(m + 1) - seconds(m) for m in range(4)]
    assert added == pytest.approx([added[0]] * 4, rel=1e-9)
    assert added[0] > 0


def test_estimate_of_a_tiny_run_is_within_a_factor_of_ten_of_its_cpu_time():
    """A real run of 2500 steps on the small domain, timed in CPU seconds of this
    process (load from other processes does not count), after a first run that compiles
    the kernel: the estimate is right to a factor of 10 (machines differ in speed; a
    wrong unit or a cost per cell off by an order of magnitude is not)."""
    data = {
        **COARSE,
        "grid": {**COARSE["grid"], "domain_radius": 1.75},
        "numerics": {"scheme": "consistent"},
        "protocol": {"t_ini": 0.4, "t_stop": 0.2, "t_release": 0.4, "cycles": 1},
    }
    config = validate_config(data)
    Simulation(config).run(0.01)
    simulation = Simulation(config)
    start = time.process_time()
    simulation.run()
    measured = time.process_time() - start
    estimate = estimate_run(config, movie=False)
    assert estimate.steps == 2500
    assert estimate.seconds / 10 < measured < 10 * estimate.seconds


def test_run_estimate_counts_steps_and_movie_frames():
    config = validate_config({**COARSE, "protocol": {"t_ini": 1.0, "cycles": 0}})
    with_movie = estimate_run(config)
    assert with_movie.steps == 2500
    assert with_movie.frames == round(1.0 / config.output.movie_interval) + 1
    without = estimate_run(config, movie=False)
    assert without.frames == 0
    assert without.seconds == pytest.approx(2500 * step_seconds(config))
    assert with_movie.seconds > without.seconds
    assert not with_movie.long


def test_the_paper_defaults_are_a_long_run():
    estimate = estimate_run(validate_config({}))
    assert estimate.steps == 10_600_000
    assert estimate.seconds > LONG_RUN_SECONDS and estimate.long
    text = estimate.describe()
    assert text.startswith("about ") and "10.6 M steps" in text and "estimate" in text


def test_durations_and_counts_read_naturally():
    assert [format_duration(s) for s in (40, 720, 18_000, 400_000)] == [
        "40 s",
        "12 min",
        "5.0 h",
        "4.6 days",
    ]
    assert [format_count(n) for n in (950, 45_239, 10_600_000, 1_000_000)] == [
        "950",
        "45.2 k",
        "10.6 M",
        "1 M",
    ]


def sweep_of(estimator: dict, axes: dict, samples: int = 3) -> Sweep:
    base = {**COARSE, "protocol": {"t_ini": 2.0, "t_stop": 0.4, "t_release": 2.0, "cycles": 4}}
    spec = {"base": base, "axes": axes, "estimator": estimator, "samples": samples, "seed": 1}
    return Sweep.from_spec(SweepSpec.model_validate(spec))


@pytest.mark.parametrize("workers", [1, 2])
def test_restart_sweep_costs_stops_releases_and_one_spin_up_per_worker(workers):
    """3 samples per direction at 2 points: 12 stops (at the cost of a stopped plate) and
    releases of COMMIT_TIME; every worker spins up each point's rotor in both directions
    once."""
    sweep = sweep_of({"kind": "restart", "warmup": 2.0}, {"protocol.t_stop": [0.4, 0.8]})
    config = validate_config(sweep.base)
    per_step, dt = step_seconds(config), config.grid.dt
    stopped = step_seconds(config, stopped=True)
    turning = 12 * round(COMMIT_TIME / dt) + 2 * 2 * workers * round(2.0 / dt)
    expected = turning * per_step + 6 * (round(0.4 / dt) + round(0.8 / dt)) * stopped
    checks = round(COMMIT_TIME / 0.05)  # check_interval
    expected += 12 * (CALLS_PER_RESTART + checks) * call_seconds(config)
    estimate = estimate_sweep(sweep.runs(), workers)
    assert estimate.core_seconds == pytest.approx(expected)
    assert estimate.runs == 12
    assert f"on {workers} worker{'s' if workers > 1 else ''}" in estimate.describe()


def test_bank_sweep_shares_the_stop_across_the_noise_axis():
    bank = sweep_of({"kind": "bank", "warmup": 2.0}, {"noise.sigma": [0.0, 1e-6, 1e-5]}, 2)
    restart = sweep_of({"kind": "restart", "warmup": 2.0}, {"noise.sigma": [0.0, 1e-6, 1e-5]}, 2)
    config = validate_config(bank.base)
    stops_saved = (12 - 4) * round(0.4 / config.grid.dt) * step_seconds(config, stopped=True)
    difference = (
        estimate_sweep(restart.runs(), 1).core_seconds - estimate_sweep(bank.runs(), 1).core_seconds
    )
    assert difference == pytest.approx(stops_saved)


def test_protocol_sweep_costs_whole_protocol_runs():
    sweep = sweep_of({"kind": "protocol"}, {}, samples=5)
    config = validate_config(sweep.base)
    expected = 5 * protocol_seconds(config)
    assert estimate_sweep(sweep.runs(), None).core_seconds == pytest.approx(expected)


@pytest.mark.parametrize("scheme", ["paper", "consistent"])
def test_stops_cost_the_steps_of_a_stopped_plate(scheme):
    """A stopped plate keeps F and G, so its step costs less than a turning one but more
    than the field update alone (the torque is computed every step); a protocol's M
    stops are counted at that cost, its free rotation at the turning one."""
    config = validate_config(
        {
            "numerics": {"scheme": scheme},
            "protocol": {"t_ini": 1.0, "t_stop": 0.5, "t_release": 1.5, "cycles": 3},
        }
    )
    interior, _ = cell_counts(config)
    stopped, turning = step_seconds(config, stopped=True), step_seconds(config)
    assert interior * SECONDS_PER_CELL_STEP < stopped < turning
    dt = config.grid.dt
    expected = round(5.5 / dt) * turning + 3 * round(0.5 / dt) * stopped
    assert protocol_seconds(config) == pytest.approx(expected)
    assert estimate_run(config, movie=False).seconds == pytest.approx(expected)


def test_a_sweep_estimate_counts_the_load_already_on_the_machine():
    """Workers on a machine already busy share its cores: on 2 cores with a load of 2,
    two workers each run at half speed, and the estimate says so."""
    from pde_rotor.sweep.cost import SweepEstimate

    idle = SweepEstimate(runs=100, core_seconds=3600.0, workers=2, load=0.0, cores=2)
    busy = SweepEstimate(runs=100, core_seconds=3600.0, workers=2, load=2.0, cores=2)
    assert idle.slowdown == 1.0 and busy.slowdown == 2.0
    assert "30 min on 2 workers (" in idle.describe()
    assert "60 min on 2 workers at the machine's present load of 2.0 on 2 cores" in (
        busy.describe()
    )
    assert SweepEstimate(runs=100, core_seconds=3600.0, workers=None, load=5.0).slowdown == 1.0


def test_a_sweep_estimate_counts_the_threads_of_each_worker():
    """One worker of two threads on two idle cores: each run steps thread_speedup(2)
    faster; with a load of 1 already there, three threads share the two cores."""
    from pde_rotor.sweep.cost import START_SECONDS, SweepEstimate, thread_speedup

    assert thread_speedup(1) == 1.0 and 1.0 < thread_speedup(2) < 2.0
    idle = SweepEstimate(runs=10, core_seconds=3600.0, workers=1, cores=2, threads=2)
    busy = SweepEstimate(runs=10, core_seconds=3600.0, workers=1, load=1.0, cores=2, threads=2)
    assert idle.wall_seconds == pytest.approx(3600.0 / thread_speedup(2) + START_SECONDS)
    assert busy.slowdown == 1.5
    assert "on 1 worker of 2 threads (" in idle.describe()


@pytest.mark.parametrize(
    ("inner", "outer", "charged"),
    [("no_flux", "absorbing", True), ("absorbing", "absorbing", False)],
)
def test_a_vessel_with_a_no_flux_wall_pays_for_its_cut_cells(inner, outer, charged) -> None:
    """An annulus with a no-flux wall costs what the no-flux dish's cut cells cost per
    interior cell (with the flow's part there), and per cell of a body's box its plate
    terms in that update; with absorbing walls only it does not."""

    def config(inner_wall: str, outer_wall: str):
        vessel = {"shape": "annulus", "inner_radius": 1.0, "outer_radius": 2.5}
        return validate_config(
            {
                "grid": {
                    "domain_radius": 2.5,
                    "dx": 0.05,
                    "dt": 4e-4,
                    "vessel": vessel | {"inner_wall": inner_wall, "outer_wall": outer_wall},
                },
                "geometry": {"smoothing": 0.025},
                "bodies": [
                    {"pills": [{"radius": 0.1}], "motion": {"kind": "fixed"}, "start": {"x": 1.75}}
                ],
            }
        )

    with_walls, without = config(inner, outer), config("absorbing", "absorbing")
    assert no_flux_walls(with_walls) is charged
    walled = (
        (BODIES_STEP_COSTS["no_flux_cell"] + BODIES_STEP_COSTS["no_flux_flow_cell"])
        * cell_counts(with_walls)[0]  # the flow is on
        + BODIES_STEP_COSTS["no_flux_box_cell"] * (2 * 0.6 / 0.05) ** 2  # the pill's box
    )
    extra = walled if charged else 0.0
    assert bodies_step_seconds(with_walls) == pytest.approx(bodies_step_seconds(without) + extra)


def test_the_estimate_notes_what_it_assumes_of_the_runs_it_counts() -> None:
    from pde_rotor.sweep.cost import SweepEstimate

    restarts = SweepEstimate(runs=4, core_seconds=60.0, workers=1, cores=2).describe()
    bodies = SweepEstimate(runs=4, core_seconds=60.0, workers=1, cores=2, restarts=False)
    done = SweepEstimate(runs=0, core_seconds=0.0, workers=1, cores=2, restarts=None)
    assert f"restarts assumed to commit {COMMIT_TIME:g}" in restarts
    assert bodies.describe().endswith("measured costs per step; runs that end early cost less)")
    assert done.describe().endswith("(an estimate from measured costs per step)")
    assert estimate_sweep([], 1).restarts is None


def test_a_heun_step_of_bodies_is_two_euler_steps_and_an_average() -> None:
    """Heun evaluates every phase of the bodies' step twice (the state and the prediction)
    and averages the fields once: c on the wet cells, and v with the flow."""
    data = {"bodies": [{"pills": [{"radius": 0.1}], "start": {"x": 1.0}}]}
    for flow, fields in ((True, 3), (False, 1)):
        euler = validate_config(data | {"flow": {"enabled": flow}})
        heun = validate_config(
            data | {"flow": {"enabled": flow}, "numerics": {"integrator": "heun"}}
        )
        average = BODIES_STEP_COSTS["heun_average_cell"] * fields * cell_counts(heun)[0]
        assert bodies_step_seconds(heun) == pytest.approx(
            2.0 * bodies_step_seconds(euler) + average
        )


def test_a_body_costs_its_integrals_unless_fixed_and_its_pills_redraw_while_it_moves() -> None:
    """On the open dish a fixed body costs nothing beyond the wet cells (its plate terms
    are a bare cell's price); a free one its integrals over its box, and its pills'
    redraw in the share of the run it moves (none while held)."""
    strip = {"shape": "strip", "length": 0.4, "width": 0.2}
    body = {"plate": strip, "pills": [{"radius": 0.1}], "start": {"x": 1.0}}
    fixed = validate_config(PAPER | {"bodies": [body | {"motion": {"kind": "fixed"}}]})
    free = validate_config(
        PAPER | {"bodies": [body | {"motion": {"kind": "free", "mass": 1e-4, "friction": 0.2}}]}
    )
    dx, grow = fixed.grid.dx, 20 * fixed.geometry.smoothing
    box = (2 * math.hypot(0.2 + grow, 0.1 + grow) / dx) ** 2  # the strip's corner's reach
    pill_box = (2 * (0.1 + grow) / dx) ** 2
    assert bodies_step_seconds(fixed) == pytest.approx(
        cell_counts(fixed)[0] * (BODIES_STEP_COSTS["cell"] + BODIES_STEP_COSTS["flow_cell"])
    )
    sums = BODIES_STEP_COSTS["paper_box_cell"] * box
    drawn = BODIES_STEP_COSTS["drawn_pill_cell"] * pill_box
    assert bodies_step_seconds(free) == pytest.approx(bodies_step_seconds(fixed) + sums + drawn)
    held = bodies_step_seconds(free, moving=[0.0])
    assert held == pytest.approx(bodies_step_seconds(fixed) + sums)


def test_a_spanning_boat_costs_the_area_form_on_either_scheme() -> None:
    """A boat that spans its channel takes its integrals in the area form over the wet
    cells on both schemes (no contour form): its box is priced as ``paper_box_cell``
    on ``consistent`` too, where another track boat's is ``consistent_box_cell``."""
    ring = {"shape": "annulus", "inner_radius": 2.375, "outer_radius": 3.625}
    grid = {"domain_radius": 4.95, "dx": 0.05, "dt": 4e-4, "vessel": ring}
    boat = {
        "plate": {"shape": "strip", "length": 0.3, "width": 2.45},
        "pills": [{"x": -0.1, "radius": 0.05}],
        "motion": {"kind": "track", "mass": 1e-3, "friction": 0.3, "spans": True},
        "start": {"x": 3.0},
    }
    base = {"grid": grid, "geometry": {"smoothing": 0.025}, "bodies": [boat]}
    seconds = {
        scheme: bodies_step_seconds(validate_config(base | {"numerics": {"scheme": scheme}}))
        for scheme in ("paper", "consistent")
    }
    assert seconds["consistent"] == pytest.approx(seconds["paper"])
    narrow = {**boat, "plate": {"shape": "strip", "length": 0.3, "width": 0.2}}
    narrow["motion"] = {"kind": "track", "mass": 1e-3, "friction": 0.3}
    wide = {**grid, "vessel": {**ring, "inner_radius": 1.5, "outer_radius": 4.5}}
    plain = {
        scheme: bodies_step_seconds(
            validate_config(
                base | {"grid": wide, "bodies": [narrow], "numerics": {"scheme": scheme}}
            )
        )
        for scheme in ("paper", "consistent")
    }
    assert plain["consistent"] > plain["paper"]


def test_a_cut_footprint_costs_its_smaller_box() -> None:
    """With ``numerics.footprint_widths`` = w a free body's box and its pills' boxes grow
    by w delta, not 20 delta: the estimate prices the cells the drawing walks."""
    strip = {"shape": "strip", "length": 0.4, "width": 0.2}
    body = {"plate": strip, "pills": [{"radius": 0.1}], "start": {"x": 1.0}}
    body |= {"motion": {"kind": "free", "mass": 1e-4, "friction": 0.2}}
    paper = PAPER | {"bodies": [body]}
    free = validate_config(paper)
    cut = validate_config(
        paper | {"numerics": {**paper.get("numerics", {}), "footprint_widths": 8}}
    )
    dx, delta = free.grid.dx, free.geometry.smoothing
    boxes = {}
    for w in (20, 8):
        grow = w * delta
        box = (2 * math.hypot(0.2 + grow, 0.1 + grow) / dx) ** 2
        pill_box = (2 * (0.1 + grow) / dx) ** 2
        boxes[w] = BODIES_STEP_COSTS["paper_box_cell"] * box
        boxes[w] += BODIES_STEP_COSTS["drawn_pill_cell"] * pill_box
    assert bodies_step_seconds(free) - bodies_step_seconds(cut) == pytest.approx(
        boxes[20] - boxes[8]
    )


def test_a_collective_run_costs_its_steps_and_its_set_up() -> None:
    """A crowd sweep's run: every step at the bodies' step estimate, and its set-up."""
    from pathlib import Path

    from pde_rotor.sweep.cost import COLLECTIVE_SET_UP_SECONDS

    sweep_file = Path(__file__).resolve().parents[2] / "configs" / "sweeps" / "crowd_dish.yaml"
    run = Sweep.load(sweep_file).runs()[0]
    config = validate_config(run.config)
    assert estimate_sweep([run], None).core_seconds == pytest.approx(
        protocol_seconds(config) + COLLECTIVE_SET_UP_SECONDS
    )
