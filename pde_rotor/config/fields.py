"""What every config section builds on: the number types, the section base, the bounds.

:mod:`.schema` (the run's sections), :mod:`.protocol` (the stop-and-release section) and
:mod:`.bodies` (the camphor objects on the surface) share them, so that a bound or a
default of the paper holds in one place.
"""

from __future__ import annotations

from typing import Annotated, Any

from pydantic import BeforeValidator, ConfigDict, Field

from .stable import StableModel

X_SATURATION = 20.0
"""|x| beyond which float64 1/2 (1 + tanh(x)) is exactly 1 (1 - tanh(20) = 8.5e-18 < 2^-54)
and below 4.3e-18: the smoothed indicators F and G (the equations after Eq. (rj)) are 0
or 1 beyond X_SATURATION delta of their edges, and the kernels evaluate them only within."""


def _reject_bool(value: Any) -> Any:
    """YAML ``true`` is not a number: refuse the silent coercion bool -> 1."""
    if isinstance(value, bool):
        msg = "expected a number, got a boolean"
        raise ValueError(msg)
    return value


_NoBool = BeforeValidator(_reject_bool)
PositiveFloat = Annotated[float, _NoBool, Field(gt=0, allow_inf_nan=False)]
NonNegativeFloat = Annotated[float, _NoBool, Field(ge=0, allow_inf_nan=False)]
FiniteFloat = Annotated[float, _NoBool, Field(allow_inf_nan=False)]
Fraction = Annotated[float, _NoBool, Field(gt=0, le=1, allow_inf_nan=False)]
Int = Annotated[int, _NoBool]


SCALE_BOUND = 1e3
"""Physical bounds: every rate and coefficient of the model lies within a factor 1e3 of
the paper's value (the paper's Table of parameters, all of order 1 in its dimensionless
units, except I and mu). Far beyond that the model leaves the regime the paper scaled it
for and the explicit step overflows float64 (``camphor.supply: 1e308``), so such a value
is refused in one line at ``check`` instead of starting a run that cannot work."""
OMEGA_BOUND = 1e4
"""Largest |omega0|: about 50 times the rotor's own steady angular velocity (176)."""
ANGLE_BOUND = 1e4
"""Largest |angle| of a start (rotor.phi0, a body's start.angle), in rad: about 1600
turns. An angle counts modulo 2 pi; far beyond this bound float64 loses its fraction of a
turn (at 1e16 rad nothing of it is left), so a larger one is a typo."""
VELOCITY_BOUND = 1e3
"""Largest |u_x|, |u_y| of a body's start velocity: ten times the rim speed of the paper's
rotor (176 x 0.5 = 88) and 500 times a free camphor disk's steady speed (about 2)."""
TIME_BOUND = 1e5
"""Longest t_ini, t_stop or t_release: 1e4 times the paper's 10."""
CYCLES_BOUND = 100_000
"""Most stop-and-release cycles in one run: 1000 times the paper's M = 100."""

PAPER_N_CORNERS = 6
"""N: corners of the paper's plate (Fig. 1), the default of a polygon plate."""
PAPER_PLATE_RADIUS = 0.5
"""R: circumradius of the paper's plate, the default radius of a polygon or disk plate."""
PAPER_PILL_RADIUS = 0.1
"""rho: radius of the paper's camphor pills, the default radius of every pill."""
PAPER_INERTIA = 1e-5
"""I: the paper's moment of inertia of the rotor."""
PAPER_FRICTION = 1e-4
"""mu: the paper's friction constant of the rotor."""


class _Section(StableModel):
    """Base of all config sections: unknown keys and silent coercions are errors; a key
    added to the schema at its default is left out of every dump (:mod:`.stable`)."""

    model_config = ConfigDict(extra="forbid", strict=False, validate_assignment=True)
