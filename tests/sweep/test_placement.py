"""The crowd section: placements on a ring and scattered in a disk, seeded per sample."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pde_rotor.sweep.placement import CrowdError, CrowdSpec, place

BODY = {
    "plate": {"shape": "none"},
    "pills": [{"radius": 0.1}],
    "motion": {"kind": "free", "mass": 1.0e-3, "inertia": 5.0e-6},
}


def crowd(**placement) -> CrowdSpec:
    return CrowdSpec(count=7, body=BODY, placement=placement, seed=4)


def centres(bodies: list[dict]) -> np.ndarray:
    return np.array([[b["start"]["x"], b["start"]["y"]] for b in bodies])


def test_ring_placement_is_even_and_heads_along_the_circle() -> None:
    bodies = place(crowd(kind="ring", radius=2.0, speed=0.5), (1.0, -1.0), sample=0)
    xy = centres(bodies) - [1.0, -1.0]
    np.testing.assert_allclose(np.hypot(*xy.T), 2.0)
    angles = np.arctan2(xy[:, 1], xy[:, 0])
    np.testing.assert_allclose(np.mod(np.diff(angles), 2 * math.pi), 2 * math.pi / 7)
    for body, (x, y) in zip(bodies, xy, strict=True):
        heading = body["start"]["angle"]
        assert math.cos(heading) * x + math.sin(heading) * y == pytest.approx(0, abs=1e-12)
        assert math.cos(heading) * -y + math.sin(heading) * x == pytest.approx(2.0)  # CCW
        np.testing.assert_allclose(
            body["start"]["velocity"], [0.5 * math.cos(heading), 0.5 * math.sin(heading)]
        )
    assert [b["name"] for b in bodies] == [f"body{k}" for k in range(7)]
    assert "start" not in BODY  # the template is not changed


def test_ring_jitter_moves_each_body_by_less_than_half_its_share() -> None:
    bodies = place(crowd(kind="ring", radius=1.0, jitter=0.5), (0.0, 0.0), sample=0)
    xy = centres(bodies)
    shift = np.arctan2(xy[:, 1], xy[:, 0]) - 2 * math.pi * np.arange(7) / 7
    shift = np.mod(shift + math.pi, 2 * math.pi) - math.pi
    assert np.abs(shift).max() <= 0.25 * 2 * math.pi / 7 and np.abs(shift).max() > 0


def test_scatter_is_seeded_by_sample_and_keeps_its_distance() -> None:
    spec = crowd(kind="scatter", radius=2.0, min_distance=0.9)
    first, again, other = (place(spec, (0.0, 0.0), s) for s in (0, 0, 1))
    assert first == again and first != other
    xy = centres(first)
    assert np.hypot(*xy.T).max() <= 2.0
    i, j = np.triu_indices(7, 1)
    assert np.hypot(*(xy[i] - xy[j]).T).min() >= 0.9


def test_a_crowded_scatter_is_refused_in_one_line() -> None:
    with pytest.raises(CrowdError, match="no room for body") as err:
        place(crowd(kind="scatter", radius=0.5, min_distance=1.0), (0.0, 0.0), 0)
    assert "\n" not in str(err.value)


TINY = {
    "grid": {"domain_radius": 2.0, "dx": 0.04, "dt": 2.0e-4, "wall": "no_flux"},
    "geometry": {"smoothing": 0.02},
    "numerics": {"scheme": "paper"},
    "protocol": {"t_ini": 0.02, "cycles": 0},
}


def spec(**changes) -> dict:
    return {
        "base": TINY,
        "crowd": {
            "count": 2,
            "body": BODY,
            "placement": {"kind": "scatter", "radius": 1.0, "min_distance": 1.05},
        },
        "axes": {"crowd.count": [1, 2, 3], "crowd.body.motion.friction": [0.2, 0.3]},
        "estimator": {"kind": "collective", "record_interval": 0.01},
        "samples": 2,
        "seed": 0,
    } | changes


def test_crowd_axes_set_the_bodies_of_each_run() -> None:
    from pde_rotor.sweep import Sweep, SweepSpec

    sweep = Sweep.from_spec(SweepSpec.model_validate(spec()))
    runs = sweep.runs()
    assert len(runs) == 3 * 2 * 2 and sweep.directions() == (0,)
    for run in runs:
        bodies = run.config["bodies"]
        assert len(bodies) == run.coords["crowd.count"]
        assert {b["motion"]["friction"] for b in bodies} == {
            run.coords["crowd.body.motion.friction"]
        }
    assert len({r.key for r in runs}) == len(runs)
    again = Sweep.from_spec(SweepSpec.model_validate(spec()))
    assert [r.key for r in again.runs()] == [r.key for r in runs]


@pytest.mark.parametrize(
    ("changes", "message"),
    [
        ({"crowd": None}, "axis crowd.count: the sweep has no crowd section"),
        ({"estimator": {"kind": "protocol"}}, "crowd: a crowd is measured by the collective"),
        (
            {"estimator": {"kind": "collective", "record_interval": 0.0101}},
            "record_interval = 0.0101 is not an integer multiple of grid.dt",
        ),
        (
            {"estimator": {"kind": "collective", "measures": "ring"}},
            None,
        ),
    ],
)
def test_bad_crowd_sweeps_are_refused_in_one_line(changes: dict, message: str | None) -> None:
    from pde_rotor.sweep import Sweep, SweepError, SweepSpec

    try:
        Sweep.from_spec(SweepSpec.model_validate(spec(**changes)))
    except (SweepError, ValueError) as err:
        assert message is not None and message in str(err)
        assert "\n" not in str(err).split("\n  ")[0]
    else:
        assert message is None  # ring measures of a dish: angles about its centre


def test_ring_measures_refuse_a_tank_and_dish_measures_an_annulus() -> None:
    from pde_rotor.sweep import Sweep, SweepError, SweepSpec

    grid = {k: v for k, v in TINY["grid"].items() if k != "wall"}
    annulus = TINY | {
        "grid": grid | {"vessel": {"shape": "annulus", "inner_radius": 0.2, "outer_radius": 2.0}}
    }
    data = spec(base=annulus, estimator={"kind": "collective", "measures": "dish"})
    data["crowd"]["placement"] = {"kind": "ring", "radius": 1.1}
    data["axes"] = {"crowd.count": [2]}
    with pytest.raises(SweepError, match="g\\(r\\) is normalised for a disk"):
        Sweep.from_spec(SweepSpec.model_validate(data))


def test_set_changes_a_crowd_key() -> None:
    from pde_rotor.sweep import apply_sweep_overrides

    changed = apply_sweep_overrides(spec(), ["crowd.placement.radius=0.8", "crowd.count=5"])
    assert changed["crowd"]["placement"]["radius"] == 0.8 and changed["crowd"]["count"] == 5
    assert spec()["crowd"]["placement"]["radius"] == 1.0
