"""The ``contact:`` section: the short-range repulsion between bodies and from the walls.

The model has no contact: footprints (plate, pills and the smoothing's reach 20 delta,
:meth:`pde_rotor.config.BodyConfig.reach`) that meet, or a footprint that reaches a wall,
end the run. With ``contact.enabled`` a spring and a dashpot act on the gap between
footprints instead: for bodies i, j with centres d apart and footprint radii rho_i, rho_j,
the gap g = d - rho_i - rho_j, and for g < ell (``range``)

    f_i = [kappa (ell - g) - gamma dg/dt] (X_i - X_j) / d,   f_j = -f_i,

kappa the ``stiffness``, gamma the ``damping`` and dg/dt = (X_i - X_j) . (U_i - U_j) / d
the gap's rate of change; from a wall, g is the footprint's clearance from it, dg/dt its
rate, and the force kappa (ell - g) - gamma dg/dt points into the vessel along the wall's
normal. The spring is largest, kappa ell, where the footprints touch; the dashpot damps
the gap's oscillation and, while the gap opens inside the range, may pull (it never holds
bodies at rest, where only the spring acts). The force acts on free bodies (added to Eq.
(eq_motion)'s force) and on track bodies (projected on the tangent, so along the track).
Footprints, not plates, are kept apart because each cell of the grid has one owner
(docs/bodies.md).

Forward Euler rings the spring up unless it is damped enough (:func:`euler_damping`).
"""

from __future__ import annotations

from pydantic import Field

from .fields import NonNegativeFloat, PositiveFloat, _Section

CONTACT_STIFFNESS = 100.0
"""Default kappa: at touch kappa ell = 10, some 300 times the camphor force on a boat of
length 0.3 at its steady speed (mu A V = 0.03 for mu = 1, A = 0.03, V = 0.9)."""

CONTACT_RANGE = 0.1
"""Default ell: two cells of the coarse grid (dx = 0.05)."""

CONTACT_STEP = 0.5
"""Largest dt sqrt(kappa / m): the spring's period 2 pi sqrt(m / kappa) spans at least
12 steps (checked by :class:`pde_rotor.config.RotorConfig`)."""

CONTACT_MODES = 4.0
"""lambda: the largest eigenvalue of the contact network's Laplacian that the checks of
:func:`euler_damping` and :func:`dashpot_step` allow for. A body against a wall has 1, a
pair 2, a train of bodies pressed together along a track (each between two neighbours,
the ring channel's clusters) less than 4, its shortest mode the neighbours moving
against each other."""


def euler_damping(stiffness: float, dt: float, friction_area: float) -> float:
    """The least ``contact.damping`` gamma at which forward Euler does not ring the spring up.

    A mode of the contact network with Laplacian eigenvalue lambda, in which each gap
    changes by x, obeys m x'' = -mu A x' - lambda (kappa x + gamma x') (bodies of mass m
    and friction mu A = mu int F dA, Eq. (eq_motion); no flow), i.e. x'' + beta x' +
    omega^2 x = 0 with beta = (mu A + lambda gamma) / m, omega^2 = lambda kappa / m. An
    Euler step multiplies an underdamped mode's squared amplitude by exactly
    |1 + s dt|^2 = 1 - beta dt + (omega dt)^2 (s = -beta / 2 +- i sqrt(omega^2 -
    beta^2 / 4)): the spring's growth (omega dt)^2 / 2 per step beats the damping
    beta dt / 2 per step where omega^2 dt > beta, i.e. lambda (kappa dt - gamma) > mu A.
    With lambda = :data:`CONTACT_MODES` the mode is damped for

        gamma >= kappa dt - mu A / lambda.

    Args:
        stiffness: kappa.
        dt: the time step.
        friction_area: mu A of the least damped moving body.

    Returns:
        The bound (negative where the friction alone damps the spring).
    """
    return stiffness * dt - friction_area / CONTACT_MODES


def dashpot_step(damping: float, dt: float, mass: float) -> float:
    """lambda gamma dt / m: the dashpot's relaxation of the fastest mode per step, lambda =
    :data:`CONTACT_MODES` (an explicit step of a decay rate r is monotone for r dt <= 1)."""
    return CONTACT_MODES * damping * dt / mass


class ContactConfig(_Section):
    """Repulsion between footprints and from the vessel's walls (module docstring)."""

    enabled: bool = Field(
        False, description="whether bodies repel (false: footprints that meet end the run)"
    )
    stiffness: PositiveFloat = Field(
        CONTACT_STIFFNESS, description="kappa: force per unit overlap of the contact range"
    )
    range: PositiveFloat = Field(
        CONTACT_RANGE, description="ell: the gap between footprints below which they repel"
    )
    damping: NonNegativeFloat = Field(
        0.0,
        description="gamma: force per unit rate of change of the gap, while within range",
    )
