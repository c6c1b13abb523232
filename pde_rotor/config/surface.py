"""The fields on the surface: the ``camphor:`` section, Eqs. (eqc) and (surfacetension),
and the ``flow:`` section, Eq. (eqv)."""

from __future__ import annotations

from typing import Annotated

from pydantic import Field

from .fields import (
    SCALE_BOUND,
    NonNegativeFloat,
    PositiveFloat,
    _Section,
)
from .recorded import BuiltInto, RecordAs


def _inverse_or_zero(saturation: float | None) -> float:
    """1 / c_sat of the saturating law, 0 for the linear one (null), so that the
    compiled Pi(c) / k = c / (1 + c / c_sat) is c bit for bit at 0."""
    return 0.0 if saturation is None else 1.0 / saturation


class CamphorConfig(_Section):
    """Camphor surface concentration c, Eq. (eqc), and surface tension, Eq. (surfacetension)."""

    diffusion: PositiveFloat = Field(
        1.0, le=SCALE_BOUND, description="D: camphor diffusion coefficient"
    )
    evaporation: NonNegativeFloat = Field(
        1.0, le=SCALE_BOUND, description="a: evaporation rate outside the plate"
    )
    supply: Annotated[NonNegativeFloat, BuiltInto("source")] = Field(
        1.0, le=SCALE_BOUND, description="s0: camphor supply rate of one pill"
    )
    tension_slope: NonNegativeFloat = Field(
        1.0,
        le=SCALE_BOUND,
        description="k: surface tension gamma = gamma0 - k c, Eq. (surfacetension)",
    )
    saturation: Annotated[PositiveFloat | None, RecordAs("inv_saturation", _inverse_or_zero)] = (
        Field(
            None,
            le=SCALE_BOUND,
            description=(
                "c_sat: saturating surface tension gamma = gamma0 - k c / (1 + c / c_sat) "
                "(null: the paper's linear law)"
            ),
        )
    )


class FlowConfig(_Section):
    """Surface flow v, Eq. (eqv)."""

    enabled: Annotated[bool, RecordAs("flow")] = Field(
        True, description="false: v = 0 in Eqs. (eqc) and (eq_motion), the paper's Fig. 8"
    )
    drag: NonNegativeFloat = Field(
        1.0, le=SCALE_BOUND, description="eta: relaxation of v to the plate velocity"
    )
    bulk_drag: NonNegativeFloat = Field(
        1.0, le=SCALE_BOUND, description="eta_b: vertical viscous damping of v"
    )
    viscosity: PositiveFloat = Field(
        1.0, le=SCALE_BOUND, description="D_eta: horizontal viscous diffusion of v"
    )
