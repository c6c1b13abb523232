"""The ``geometry:`` section: the paper's rotor, a regular N-gon plate with N pills.

The shorthand for one body (:meth:`pde_rotor.config.RotorConfig.body_list`): its plate and
pills, Eqs. (rc), (rj) and paper Fig. 1.
"""

from __future__ import annotations

import math
from typing import Annotated

from pydantic import Field, model_validator

from .errors import FieldError
from .fields import (
    PAPER_N_CORNERS,
    PAPER_PILL_RADIUS,
    PAPER_PLATE_RADIUS,
    X_SATURATION,
    FiniteFloat,
    Int,
    NonNegativeFloat,
    PositiveFloat,
    _Section,
)
from .recorded import BuiltInto


class GeometryConfig(_Section):
    """Rotor geometry: regular N-gon plate with N camphor pills (paper Fig. 1, Eqs. (rc), (rj))."""

    n_corners: Int = Field(
        PAPER_N_CORNERS, ge=3, le=24, description="N: number of plate corners and pills"
    )
    radius: Annotated[PositiveFloat, BuiltInto("apothem")] = Field(
        PAPER_PLATE_RADIUS, description="R: circumradius of the plate"
    )
    pill_radius: PositiveFloat = Field(
        PAPER_PILL_RADIUS, description="rho: radius of one camphor pill"
    )
    pill_inset: Annotated[NonNegativeFloat, BuiltInto("pill_distance")] = Field(
        0.05, description="p: extra inward shift of the pills, Eq. (rc)"
    )
    asymmetry: FiniteFloat = Field(
        0.0,
        description=(
            "Delta: angular shift of every pill from its corner [rad], Eq. (rj); |Delta| < pi/N"
        ),
    )
    smoothing: PositiveFloat = Field(0.025, description="delta: width of the tanh edges of F and G")

    @property
    def pill_distance(self) -> float:
        """R_c = R - rho / cos(pi/N) - p, Eq. (rc)."""
        return self.radius - self.pill_radius / math.cos(math.pi / self.n_corners) - self.pill_inset

    @property
    def support_radius(self) -> float:
        """Radius outside which F = G = 0 to within 4.3e-18: R + X_SATURATION delta / cos(pi/N).

        The plate's F is 1/2 [1 + tanh((R cos(pi/N) - h) / delta)] with the gauge
        h >= |r| cos(pi/N), and the pills lie inside the plate.
        """
        return self.radius + X_SATURATION * self.smoothing / math.cos(math.pi / self.n_corners)

    def edge_clearance(self) -> float:
        """Distance from a pill centre to the nearer edge of its corner.

        The two edges of a corner have normals at angles pi/N -/+ Delta from the pill
        direction, so the clearance is R cos(pi/N) - R_c cos(pi/N - |Delta|).
        """
        half = math.pi / self.n_corners
        return self.radius * math.cos(half) - self.pill_distance * math.cos(
            half - abs(self.asymmetry)
        )

    def max_asymmetry(self) -> float:
        """Largest |Delta| for which the pills stay inside the plate (nan if none does)."""
        half = math.pi / self.n_corners
        ratio = (self.radius * math.cos(half) - self.pill_radius) / self.pill_distance
        if ratio < math.cos(half):
            return math.nan
        return half - math.acos(min(1.0, ratio))

    @model_validator(mode="after")
    def _pills_inside_plate(self) -> GeometryConfig:
        half = math.pi / self.n_corners
        if abs(self.asymmetry) >= half:
            msg = (
                f"a shift of pi/N or more moves each pill past the middle of its edge, nearer "
                f"the next corner (Delta and Delta - 2 pi/N are the same rotor); allowed: "
                f"|asymmetry| < pi/N = {half:.4g} rad for n_corners = {self.n_corners}"
            )
            raise FieldError("asymmetry", self.asymmetry, msg)
        r_c = self.pill_distance
        if r_c <= 0:
            rho_max = (self.radius - self.pill_inset) * math.cos(math.pi / self.n_corners)
            msg = (
                f"pill distance R_c = R - rho/cos(pi/N) - p = {r_c:.4g} must be > 0 "
                f"(allowed: pill_radius < {rho_max:.4g} for radius = {self.radius:g}, "
                f"pill_inset = {self.pill_inset:g}, n_corners = {self.n_corners})"
            )
            raise FieldError("pill_radius", self.pill_radius, msg)
        if self.edge_clearance() < self.pill_radius - 1e-12:
            limit = self.max_asymmetry()
            if math.isnan(limit) or abs(self.asymmetry) <= limit:
                msg = (
                    f"pills stick out of the plate even at asymmetry 0 (edge clearance "
                    f"{self.edge_clearance():.4g} < pill_radius); increase pill_inset or "
                    "reduce pill_radius"
                )
                raise FieldError("pill_radius", self.pill_radius, msg)
            msg = (
                f"pills stick out of the plate (edge clearance {self.edge_clearance():.4g} "
                f"< pill_radius {self.pill_radius:g}); allowed: |asymmetry| <= {limit:.4g} "
                f"rad for these radius, pill_radius, pill_inset"
            )
            raise FieldError("asymmetry", self.asymmetry, msg)
        apart = 2 * r_c * math.sin(half)
        if apart < 2 * self.pill_radius - 1e-12:
            # R_c sin(pi/N) >= rho with R_c = R - rho / cos(pi/N) - p
            rho_max = (self.radius - self.pill_inset) * math.sin(half) / (1 + math.tan(half))
            msg = (
                f"the pills of neighbouring corners overlap: their centres lie 2 R_c sin(pi/N) "
                f"= {apart:.4g} apart, less than 2 rho = {2 * self.pill_radius:g}, where their "
                f"sources would add up (allowed: pill_radius <= {rho_max:.4g} for these "
                f"n_corners, radius, pill_inset, or fewer corners)"
            )
            raise FieldError("pill_radius", self.pill_radius, msg)
        return self
