"""The ``contact:`` section: the short-range repulsion between bodies and from the walls.

The model has no contact: footprints (plate, pills and the smoothing's reach 20 delta,
:meth:`pde_rotor.config.BodyConfig.reach`) that meet, or a footprint that reaches a wall,
end the run. With ``contact.enabled`` a soft linear spring acts on the gap between
footprints instead: for bodies i, j with centres d apart and footprint radii rho_i, rho_j,
the gap g = d - rho_i - rho_j, and for g < ell (``range``)

    f_i = kappa (ell - g) (X_i - X_j) / d,   f_j = -f_i,

kappa the ``stiffness``; from a wall, g is the footprint's clearance from it and the force
kappa (ell - g) points into the vessel along the wall's normal. The force is largest,
kappa ell, where the footprints touch; it acts on free bodies (added to Eq. (eq_motion)'s
force) and on track bodies (projected on the tangent, so along the track). Footprints, not
plates, are kept apart because each cell of the grid has one owner (docs/bodies.md).
"""

from __future__ import annotations

from pydantic import Field

from .fields import PositiveFloat, _Section

CONTACT_STIFFNESS = 100.0
"""Default kappa: at touch kappa ell = 10, some 300 times the camphor force on a boat of
length 0.3 at its steady speed (mu A V = 0.03 for mu = 1, A = 0.03, V = 0.9)."""

CONTACT_RANGE = 0.1
"""Default ell: two cells of the coarse grid (dx = 0.05)."""

CONTACT_STEP = 0.5
"""Largest dt sqrt(kappa / m): the spring's period 2 pi sqrt(m / kappa) spans at least
12 steps (checked by :class:`pde_rotor.config.RotorConfig`)."""


class ContactConfig(_Section):
    """Soft repulsion between footprints and from the vessel's walls (module docstring)."""

    enabled: bool = Field(
        False, description="whether bodies repel (false: footprints that meet end the run)"
    )
    stiffness: PositiveFloat = Field(
        CONTACT_STIFFNESS, description="kappa: force per unit overlap of the contact range"
    )
    range: PositiveFloat = Field(
        CONTACT_RANGE, description="ell: the gap between footprints below which they repel"
    )
