"""Collective measures of N bodies moving round a ring (boats in an annular channel).

Each body k is reduced to the angle theta_k(t) of its centre about the vessel's centre
(:func:`ring_angles`); its arc position is r_k theta_k. From the angles at the record times:

* each body's angular velocity d theta_k / dt about the centre and its arc speed
  r_k d theta_k / dt, from its velocity (:func:`angular_velocity`);
* the gaps: body k's angular distance to the next body counter-clockwise, which sum to
  2 pi (:func:`gaps`); the spacing spread std(gaps) / mean(gaps) (:func:`spacing_spread`),
  0 for evenly spaced bodies;
* the lattice order |<exp(i N theta_k)>| (1 for evenly spaced bodies) and the cluster order
  max over 1 <= m <= N/2 of |<exp(i m theta_k)>| with its m (:func:`cluster_order`): 1 for
  m equal tight clusters evenly placed, of order 1/sqrt(N) for evenly spaced bodies
  (exactly 0 without noise);
* the mean signed arc speed against the mean |arc speed|: bodies that move but go nowhere
  on average oscillate about fixed places;
* the gap mobility mean_k std_t(gap_k) / mean gap (:func:`gap_mobility`): how much each
  body's own gap changes in time. A static pattern of clusters keeps every gap
  (mobility 0 at any spread); a density wave travels through the bodies, so each body's
  gap swings as much as the gaps differ among bodies (gaps g (1 + A cos(2 pi m k / N -
  Omega t)): spread and mobility both A / sqrt(2)).

:func:`ring_mode` names the state from the time averages by the thresholds
:data:`STOP_SPEED`, :data:`NET_SPEED`, :data:`UNIFORM_SPREAD` and :data:`WAVE_MOBILITY`
(docs/collective.md).
The reduced theory of the same system is :mod:`pde_rotor.theory.ring`.
"""

from __future__ import annotations

import math

import numpy as np

STOP_SPEED = 1e-2
"""Mean |arc speed| (length / time) below which the bodies are said to stop."""
UNIFORM_SPREAD = 0.2
"""Time-averaged spacing spread below which moving bodies are evenly spaced (uniform)."""
WAVE_MOBILITY = 0.5
"""Gap mobility over spacing spread above which an uneven spacing is a density wave (it
travels through the bodies) rather than clusters (each body keeps its gap)."""
NET_SPEED = 0.5
"""Fraction of the mean |arc speed| that the mean signed arc speed must reach for bodies
to be moving round the ring; below it they oscillate about fixed places."""
MODES = ("uniform", "clusters", "density wave", "stop", "oscillation")
"""The modes :func:`ring_mode` names, in the order of their codes 0..4 (oscillation, the
last, came after the first stores: the codes of the others are theirs)."""


def ring_angles(x: np.ndarray, y: np.ndarray, centre: tuple[float, float]) -> np.ndarray:
    """Angle of each centre (x, y) about `centre`, in [0, 2 pi); arrays of any shape."""
    return np.mod(np.arctan2(y - centre[1], x - centre[0]), 2 * math.pi)


def angular_velocity(
    dx: np.ndarray, dy: np.ndarray, u: np.ndarray, v: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Angular velocity about the centre and arc speed of bodies at (dx, dy) from the
    centre moving with velocity (u, v): (dx v - dy u) / r^2 and (dx v - dy u) / r."""
    moment = dx * v - dy * u
    r = np.hypot(dx, dy)
    return moment / r**2, moment / r


def gaps(theta: np.ndarray) -> np.ndarray:
    """(..., K) angular gap of each body to the next body counter-clockwise; each row sums
    to 2 pi (one body: its gap is the whole ring).

    Args:
        theta: (..., K) angles of the bodies (any branch).
    """
    theta = np.mod(theta, 2 * math.pi)
    order = np.argsort(theta, axis=-1)
    ordered = np.take_along_axis(theta, order, axis=-1)
    ahead = np.roll(ordered, -1, axis=-1)
    gap_sorted = np.mod(ahead - ordered, 2 * math.pi)
    if theta.shape[-1] == 1:
        gap_sorted = np.full_like(gap_sorted, 2 * math.pi)
    result = np.empty_like(gap_sorted)
    np.put_along_axis(result, order, gap_sorted, axis=-1)
    return result


def spacing_spread(theta: np.ndarray) -> np.ndarray:
    """std(gaps) / mean(gaps) at each record (mean gap 2 pi / N): 0 when evenly spaced.

    Args:
        theta: (..., K) angles.
    """
    g = gaps(theta)
    return g.std(axis=-1) / (2 * math.pi / g.shape[-1])


def lattice_order(theta: np.ndarray) -> np.ndarray:
    """|<exp(i N theta_k)>| over the K = N bodies: 1 when they are evenly spaced."""
    n = theta.shape[-1]
    return np.abs(np.exp(1j * n * theta).mean(axis=-1))


def cluster_order(theta: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Cluster order max_m |<exp(i m theta_k)>| over 1 <= m <= N/2, and that m.

    Both NaN for one body (no cluster can form). m tight clusters of equal size evenly
    spaced give 1 at that m; one tight cluster gives 1 at m = 1.

    Args:
        theta: (..., K) angles.

    Returns:
        (order, m) of the shape of theta without its last axis.
    """
    n = theta.shape[-1]
    if n < 2:
        nan = np.full(theta.shape[:-1], np.nan)
        return nan, nan.copy()
    ms = np.arange(1, n // 2 + 1)
    r = np.abs(np.exp(1j * ms[:, None] * theta[..., None, :]).mean(axis=-1))
    best = r.argmax(axis=-1)
    return np.take_along_axis(r, best[..., None], axis=-1)[..., 0], (ms[best]).astype(float)


def gap_mobility(theta: np.ndarray) -> float:
    """mean_k std_t(gap_k) / mean gap over the records (the bodies keep their order).

    Args:
        theta: (T, K) angles at the records.
    """
    g = gaps(theta)
    return float(g.std(axis=0).mean() / (2 * math.pi / g.shape[-1]))


def ring_mode(abs_speed: float, net_speed: float, spread: float, mobility: float) -> str:
    """The collective mode from time averages: one of :data:`MODES`.

    Bodies whose mean |arc speed| is below :data:`STOP_SPEED` stop; bodies that move but
    go nowhere on average (mean signed arc speed below :data:`NET_SPEED` of the mean |arc
    speed|: symmetric boats rocking against each other about their rest places, the Hopf
    state of docs/ring.md) oscillate; moving bodies are uniform, clusters or a density
    wave by their spacing spread and gap mobility.

    Args:
        abs_speed: mean |arc speed| of the bodies.
        net_speed: mean signed arc speed of the bodies (either direction round the ring).
        spread: time-averaged spacing spread.
        mobility: gap mobility (:func:`gap_mobility`).
    """
    if not abs(abs_speed) >= STOP_SPEED:
        return "stop"
    if abs(net_speed) < NET_SPEED * abs(abs_speed):
        return "oscillation"
    if spread < UNIFORM_SPREAD:
        return "uniform"
    return "density wave" if mobility >= WAVE_MOBILITY * spread else "clusters"
