"""Track bodies in the linear analysis: boats on a circle in a no-flux annulus.

The Jacobian against the reference's own step of a track boat; the symmetric boat's
pitchfork against kicked runs of the reference; two boats' spectrum split into the modes
that move them together (m = 0) and against each other (m = 1).
"""

from __future__ import annotations

import math
from types import ModuleType
from typing import Any

import numpy as np
import pytest

from pde_rotor.config import ConfigError, RotorConfig
from pde_rotor.stability import DiscreteModel, follow, leading_modes, linearise
from pde_rotor.stability.continuation import config_at, expand_key
from pde_rotor.sweep.placement import CrowdSpec, place

KEY = "bodies[*].motion.friction"
AMP = 1e-5
"""The kick's speed: the slow pair is the lattice's spring, whose force is linear in the
boat's move only over a small part of a cell (at 1e-4 its frequency is off by 5 %)."""


def ring_data(
    count: int = 1, friction: float = 0.2, fine: bool = False, speed: float = 0.0
) -> dict[str, Any]:
    """`count` symmetric boats (strip 0.3 x 0.15, pill at the centre) evenly spaced on a
    track about the centre of a no-flux annulus. fine: dx = 0.05, delta = 0.025, 0.55 < r <
    2.45, track radius 1.5; else dx = 0.1, delta = 0.05, 1 < r < 4.4, radius 2.7."""
    dx, radius, inner, outer = (0.05, 1.5, 0.55, 2.45) if fine else (0.1, 2.7, 1.0, 4.4)
    boat = {
        "name": "boat",
        "plate": {"shape": "strip", "length": 0.3, "width": 0.15},
        "pills": [{"x": 0.0, "y": 0.0, "radius": 0.05}],
        "motion": {"kind": "track", "mass": 1e-3, "friction": friction, "speed": speed},
    }
    crowd = {"count": count, "body": boat, "placement": {"kind": "ring", "radius": radius}}
    bodies = place(CrowdSpec.model_validate(crowd), (0.0, 0.0), 0)
    vessel = {"shape": "annulus", "inner_radius": inner, "outer_radius": outer}
    return {
        "grid": {
            "domain_radius": outer,
            "dx": dx,
            "dt": 4e-4 if fine else 2e-3,
            "vessel": {**vessel, "inner_wall": "no_flux", "outer_wall": "no_flux"},
        },
        "geometry": {"smoothing": dx / 2},
        "numerics": {"scheme": "consistent", "integrator": "euler"},
        "flow": {"enabled": False},
        "bodies": bodies,
    }


def reference_steps(model: DiscreteModel, x: np.ndarray, lin, dt: float, k: int) -> np.ndarray:
    """`k` forward Euler steps of the reference (SurfacePDE.reference_step) from the rest
    state + x (all coordinates), read back as unknowns: the boats' arc positions and
    speeds from their poses."""
    n, a = lin.n_fields, lin.active
    c, v = lin.layout.unpack(x[:n])
    q = model.q0.copy()
    q[a] += x[n : n + a.size]
    state = model.state(lin.rest.c + c, v, q, x[n + a.size :])
    for _ in range(k):
        state = model.pde.reference_step(state, dt)
    s, w = model.arc_coordinates(state.bodies.poses)
    fields = lin.layout.pack(state.fields[0].data - lin.rest.c, state.fields[1].data)
    return np.concatenate([fields, s[a], w])


@pytest.mark.parametrize(
    ("scheme", "flow"),
    [("paper", False), ("paper", True), ("consistent", True)],
    ids=["paper", "paper-flow", "consistent-flow"],
)
def test_steps_of_a_track_boat_follow_the_jacobian(scheme: str, flow: bool) -> None:
    data = ring_data(friction=0.1, fine=True)
    data["flow"]["enabled"] = flow
    data["numerics"]["scheme"] = scheme
    config = RotorConfig.model_validate(data)
    model = DiscreteModel(config)
    lin = linearise(model, positions=True)
    assert lin.labels == ["boat0.s", "boat0.w"]
    assert np.abs(lin.rest_acceleration).max() < 1e-9  # the symmetric boat rests
    dt = config.grid.dt
    direction = np.random.default_rng(4).standard_normal(lin.size)
    direction /= np.abs(direction).max()
    base = reference_steps(model, np.zeros(lin.size), lin, dt, 3)
    assert np.abs(base).max() < 1e-12  # the rest state is the step's fixed point
    errors = []
    for eps in (1e-3, 1e-4):
        linear = eps * direction
        for _ in range(3):
            linear = linear + dt * lin.matvec(linear)
        moved = reference_steps(model, eps * direction, lin, dt, 3)
        error = np.abs(moved - base - linear) / eps
        errors.append((error[: lin.n_fields].max(), error[lin.n_fields :].max()))
    # the error of the linear prediction is of the order of the perturbation: it falls
    # tenfold with it, but for the consistent scheme's fields, whose tables are linear
    # interpolants in the plate's pose (a floor of ~1e-4 of the boat's move)
    assert max(errors[0]) < 1e-2
    assert errors[1][1] < errors[0][1] / 8
    if scheme == "paper":
        assert errors[1][0] < errors[0][0] / 8


def kicked_rate(mu: float, span: tuple[float, float], kicks: ModuleType) -> tuple[complex, complex]:
    """The leading eigenvalue with the boat's coordinate at friction `mu`, and e^{lambda t}
    fitted to the boat's (s, w) in a reference run (the implicit cut-cell step for c, as
    the compiled loop takes it) from the rest state kicked along the real part of that
    mode (|w| = AMP: the field's faster modes hardly excited), over the times `span`."""
    config = RotorConfig.model_validate(ring_data(friction=mu))
    model = DiscreteModel(config)
    lin = linearise(model, positions=True)
    spectrum = leading_modes(lin, k=4)
    mode = lin.split(spectrum.vectors[:, 0], spectrum.leading)
    size = AMP / abs(mode["dp"][0])
    state = model.state(
        lin.rest.c + size * mode["dc"].real,
        np.zeros((2, *model.shape)),
        size * mode["dq"].real,
        size * mode["dp"].real,
    )
    dt = config.grid.dt
    every = round(0.05 / dt)
    times, series = [], []
    for i in range(round(span[1] / dt) + 1):
        if i % every == 0:
            s, w = model.arc_coordinates(state.bodies.poses)
            times.append(i * dt)
            series.append([s[0], w[0]])
        c = model.pde.camphor_step(state, dt)
        state = model.pde.reference_step(state, dt)
        state.fields[0].data[...] = c
    times, series = np.array(times), np.array(series)
    keep = times >= span[0]
    fit = kicks.oscillation_fit(times[keep], series[keep])
    assert fit.residual < 0.05
    return spectrum.leading, complex(fit.rate)


def test_symmetric_boat_onset_against_kicked_runs(kicks: ModuleType) -> None:
    """Alone in the annulus the boat's rest state is symmetric under moving it along its
    track: its onset is a pitchfork in the frame that turns with it. The lattice makes
    that move a weak spring (K), which the kicked runs feel: with the coordinate the onset
    is a slow Hopf pair near the same friction, and runs of the reference kicked along that
    pair's mode grow below it and decay above it at its rate and frequency."""
    data = ring_data()
    comoving = follow(data, KEY, [0.1, 0.4], k=4)
    assert len(comoving.crossings) == 1
    onset = comoving.crossings[0]
    assert onset.kind == "pitchfork"
    assert onset.direction == "stabilising"
    full = follow(data, KEY, [0.1, 0.4], k=4, positions=True)
    assert len(full.crossings) == 1
    mu_c = full.crossings[0].value
    assert mu_c == pytest.approx(onset.value, rel=0.05)  # the lattice's spring only
    for factor, sign in ((0.8, 1.0), (1.2, -1.0)):
        lam, fitted = kicked_rate(factor * mu_c, (0.25, 2.0), kicks)
        assert sign * fitted.real > 0 and sign * lam.real > 0
        assert fitted.real == pytest.approx(lam.real, rel=0.05)
        assert abs(fitted.imag) == pytest.approx(abs(lam.imag), rel=0.02)


def test_one_boat_alone_keeps_no_coordinate_by_default() -> None:
    """The default frame turns with the boat: no neutral eigenvalue; with its coordinate
    the turn's eigenvalue is there, near 0 (the lattice's spring only)."""
    lin = linearise(DiscreteModel(RotorConfig.model_validate(ring_data(friction=0.6))))
    assert lin.positions and lin.kept.shape == (1, 0) and lin.labels == ["boat0.w"]
    assert leading_modes(lin, k=2).leading.real < -0.5
    full = leading_modes(lin.with_positions(True), k=3)
    assert abs(full.leading) < 0.2


def test_two_boats_split_into_the_modes_that_move_them_together_and_apart() -> None:
    """Two boats opposite each other, a symmetry of the grid too (the half turn): every
    mode moves them with equal speeds, together (m = 0: the common turn) or against each
    other (m = 1: their spacing, the one relative coordinate, which only these move)."""
    data = ring_data(count=2, friction=0.3)
    lin = linearise(DiscreteModel(RotorConfig.model_validate(data)))
    assert lin.labels == ["relative0", "boat0.w", "boat1.w"]
    relative = lin.kept[:, 0]
    assert relative == pytest.approx(np.array([1, -1]) / math.sqrt(2)) or relative == (
        pytest.approx(np.array([-1, 1]) / math.sqrt(2))
    )
    spectrum = leading_modes(lin, k=6)
    kinds = []
    for j, lam in enumerate(spectrum.eigenvalues):
        parts = lin.split(spectrum.vectors[:, j], lam)
        w = parts["dp"]
        if np.abs(w).max() < 1e-6 * np.abs(spectrum.vectors[:, j]).max():
            continue  # a field mode that moves no boat
        together = abs(w[0] - w[1]) < 1e-6 * np.abs(w).max()
        apart = abs(w[0] + w[1]) < 1e-6 * np.abs(w).max()
        assert together != apart
        # the spacing moves with the boats' speeds against each other only
        spacing = abs(spectrum.vectors[lin.n_fields, j])
        assert (spacing < 1e-6 * np.abs(w).max()) == together
        kinds.append(together)
    assert any(kinds) and not all(kinds)


def test_a_key_of_every_body_at_once() -> None:
    data = ring_data(count=3)
    assert expand_key(data, KEY) == [f"bodies[{k}].motion.friction" for k in range(3)]
    config = config_at(data, KEY, 0.37)
    assert [b.motion.friction for b in config.bodies] == [0.37] * 3
    with pytest.raises(ConfigError, match=r"^--param bodies\[\*\]\.motion\.frction = 0\.1: "):
        config_at(data, "bodies[*].motion.frction", 0.1)
    with pytest.raises(ConfigError, match=r"^--param crowd\[\*\]\.x = 0\.1: crowd is not a list"):
        config_at(data, "crowd[*].x", 0.1)
    with pytest.raises(ConfigError, match=r"^--param bodies\[\*\]\.motion\.frction"):
        follow(data, "bodies[*].motion.frction", [0.1, 0.2])
