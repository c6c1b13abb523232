"""The ``grid:`` section: the Cartesian grid, the time step and the circular dish."""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import Field

from .fields import (
    FiniteFloat,
    PositiveFloat,
    _Section,
)
from .recorded import BuiltInto
from .vessel import VesselShape

DISH_CENTRE = (0.0, 0.0)
"""Default centre of the dish: the origin, the paper rotor's axis."""
DISH_WALL = "absorbing"
"""Default wall of the dish: c = 0 on and outside the circle, the paper's."""


class GridConfig(_Section):
    """Cartesian grid covering the circular domain of radius L (v = 0 outside; c = 0 outside
    with the absorbing wall, dc/dr = 0 at L with the no-flux wall)."""

    domain_radius: Annotated[PositiveFloat, BuiltInto("vessel_b")] = Field(
        3.0, le=100.0, description="L: radius of the circular domain"
    )
    dx: PositiveFloat = Field(0.025, description="grid spacing")
    dt: Annotated[PositiveFloat, BuiltInto("dt")] = Field(
        1e-4, description="explicit Euler time step"
    )
    domain_centre: Annotated[tuple[FiniteFloat, FiniteFloat], BuiltInto("vessel_x")] = Field(
        DISH_CENTRE,
        description="[x, y]: centre of the circular domain (the dish) that holds the bodies",
    )
    wall: Literal["absorbing", "no_flux"] = Field(
        DISH_WALL,
        description=(
            "the dish wall for the camphor: absorbing (c = 0 on and outside the circle, the "
            "paper's) or no_flux (dc/dr = 0 at r = L on cut cells of the circle, the wall of "
            "Koyano, Suematsu & Kitahata 2019; bodies only); v = 0 at the wall either way"
        ),
    )
    vessel: VesselShape | None = Field(
        None, description="annulus or rectangle (config/vessel.py); null: the dish above"
    )
