"""The vessel that holds the water: ``grid.vessel``, an annular channel or a rectangular tank.

Left out, the vessel is the circular dish of radius ``grid.domain_radius`` with the wall
``grid.wall`` (the paper's absorbing dish by default), exactly as before the key existed.
Set, it is one of

* ``annulus``: the channel inner_radius < r < outer_radius about ``grid.domain_centre``
  (the ring channel of camphor boats), each wall ``absorbing`` (c = 0 beyond it) or
  ``no_flux`` (no camphor crosses it);
* ``rectangle``: the tank |x| < a, |y| < b about ``grid.domain_centre``, half widths
  [a, b], its wall ``absorbing`` or ``no_flux``.

The square grid covers the square |x|, |y| <= ``grid.domain_radius`` (and one ring of
cells more), which must hold the vessel (``extent``: R2, or max(a, b)). Vessels run with
a ``bodies:`` list (:mod:`pde_rotor.model.vessel` builds their cut cells).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import TYPE_CHECKING, Annotated, Literal, Protocol

from pydantic import Field, model_validator

from .errors import FieldError
from .fields import X_SATURATION, PositiveFloat, _Section

if TYPE_CHECKING:
    from .bodies import BodyConfig

WallKind = Literal["absorbing", "no_flux"]
"""absorbing: c = 0 on and beyond the wall (the paper's dish); no_flux: dc/dn = 0 there."""

CHANNEL_CELLS = 4
"""The narrowest channel or tank, in cells: the walls' cut cells stay apart."""


class AnnulusVessel(_Section):
    """The annular channel inner_radius < r < outer_radius."""

    shape: Literal["annulus"]
    inner_radius: PositiveFloat = Field(description="R1: radius of the inner wall")
    outer_radius: PositiveFloat = Field(description="R2: radius of the outer wall")
    inner_wall: WallKind = Field("no_flux", description="the inner wall for the camphor")
    outer_wall: WallKind = Field("no_flux", description="the outer wall for the camphor")

    @model_validator(mode="after")
    def _ordered(self) -> AnnulusVessel:
        if self.inner_radius >= self.outer_radius:
            msg = f"not below outer_radius = {self.outer_radius:g} (allowed: R1 < R2)"
            raise FieldError("inner_radius", self.inner_radius, msg)
        return self

    def extent(self) -> float:
        """Half the side of the smallest square about the centre that holds the vessel."""
        return self.outer_radius

    def width(self) -> float:
        """The channel's width R2 - R1."""
        return self.outer_radius - self.inner_radius

    def clearance(self, x: float, y: float) -> float:
        """Distance from (x, y) (about the centre) to the nearer wall, negative outside."""
        r = math.hypot(x, y)
        return min(self.outer_radius - r, r - self.inner_radius)

    def area(self) -> float:
        """pi (R2^2 - R1^2)."""
        return math.pi * (self.outer_radius**2 - self.inner_radius**2)


class RectangleVessel(_Section):
    """The rectangular tank |x| < a, |y| < b."""

    shape: Literal["rectangle"]
    half_widths: tuple[PositiveFloat, PositiveFloat] = Field(description="[a, b]: half widths")
    wall: WallKind = Field("no_flux", description="the tank's wall for the camphor")

    def extent(self) -> float:
        """Half the side of the smallest square about the centre that holds the vessel."""
        return max(self.half_widths)

    def width(self) -> float:
        """The tank's narrower width 2 min(a, b)."""
        return 2 * min(self.half_widths)

    def clearance(self, x: float, y: float) -> float:
        """Distance from (x, y) (about the centre) to the nearest wall, negative outside."""
        a, b = self.half_widths
        return min(a - abs(x), b - abs(y))

    def area(self) -> float:
        """4 a b."""
        return 4 * self.half_widths[0] * self.half_widths[1]


VesselShape = Annotated[AnnulusVessel | RectangleVessel, Field(discriminator="shape")]
"""``grid.vessel``: one of the vessels, told apart by its ``shape``."""


class _Grid(Protocol):
    """The keys of the grid section :func:`check_vessel` reads."""

    vessel: AnnulusVessel | RectangleVessel | None
    wall: str
    domain_radius: float
    domain_centre: tuple[float, float]
    dx: float


def check_vessel(
    grid: _Grid, has_bodies: bool, bodies: Sequence[BodyConfig], smoothing: float
) -> None:
    """A vessel runs with bodies, alone (no grid.wall beside it), inside the grid, wide
    enough for its walls' cut cells, with every body's footprint one cell inside it but
    for a body that spans its channel (:func:`check_spanning`).

    Args:
        grid: the grid section.
        has_bodies: whether the run has a bodies: list.
        bodies: the bodies, every key resolved.
        smoothing: geometry.smoothing (the footprints' reach).

    Raises:
        FieldError: naming the offending key.
    """
    vessel = grid.vessel
    if vessel is None:
        return
    if not has_bodies:
        msg = "implemented for runs with a bodies: list only (allowed: leave it out)"
        raise FieldError("grid.vessel", vessel.shape, msg)
    if grid.wall != "absorbing":
        msg = "belongs to the dish; a vessel names its own walls (allowed: leave it out)"
        raise FieldError("grid.wall", grid.wall, msg)
    if vessel.extent() > grid.domain_radius:
        msg = (
            f"too small for the {vessel.shape} (the grid covers |x|, |y| <= domain_radius; "
            f"allowed: domain_radius >= {vessel.extent():.6g})"
        )
        raise FieldError("grid.domain_radius", grid.domain_radius, msg)
    if vessel.width() < CHANNEL_CELLS * grid.dx:
        msg = (
            f"the {vessel.shape}, {vessel.width():.4g} wide, is narrower than {CHANNEL_CELLS} "
            f"cells (allowed: width >= {CHANNEL_CELLS * grid.dx:.4g}, or a smaller grid.dx)"
        )
        raise FieldError("grid.vessel", vessel.shape, msg)
    cx, cy = grid.domain_centre
    for k, body in enumerate(bodies):
        if getattr(body.motion, "spans", False):
            check_spanning(grid, k, body, smoothing)
            continue
        reach = body.reach(smoothing)
        room = vessel.clearance(body.start.x - cx, body.start.y - cy)
        if room < reach + grid.dx:
            msg = (
                f"body {body.name!r} lies {room:.4g} from the {vessel.shape}'s nearest wall, "
                f"within its footprint's radius {reach:.4g} plus one cell (allowed: a start "
                f"at least {reach + grid.dx:.4g} inside every wall)"
            )
            raise FieldError(f"bodies[{k}].start", [body.start.x, body.start.y], msg)


def check_spanning(grid: _Grid, k: int, body: BodyConfig, smoothing: float) -> None:
    """A body that spans its channel (``spans: true`` in its motion) runs in an annulus
    whose walls are both no-flux, on a track about the annulus' centre, its centre inside
    the channel, its footprint inside the grid and each pill's footprint one cell inside
    both walls, so that all its camphor is supplied on wet whole cells (its plate may
    cross the walls; docs/bodies.md, the spanning boat).

    Args:
        grid: the grid section (its vessel set).
        k: the body's index.
        body: the body, every key resolved (a track body).
        smoothing: geometry.smoothing (the footprints' reach).

    Raises:
        FieldError: naming the offending key.
    """
    vessel = grid.vessel
    key = f"bodies[{k}].motion.spans"
    if not isinstance(vessel, AnnulusVessel) or "absorbing" in (
        vessel.inner_wall,
        vessel.outer_wall,
    ):
        msg = (
            "a body spans the channel of an annulus whose walls are both no_flux, its plate "
            "crossing them (allowed: false, or grid.vessel an annulus with no_flux walls)"
        )
        raise FieldError(key, True, msg)
    cx, cy = grid.domain_centre
    motion = body.motion
    if motion.centre is not None and tuple(motion.centre) != (cx, cy):
        msg = (
            f"a spanning body's track is centred on the annulus' centre {[cx, cy]} (allowed: "
            "null, or that centre)"
        )
        raise FieldError(f"bodies[{k}].motion.centre", list(motion.centre), msg)
    x, y = body.start.x - cx, body.start.y - cy
    if vessel.clearance(x, y) <= 0:
        msg = f"outside the {vessel.shape} (allowed: a start between its walls)"
        raise FieldError(f"bodies[{k}].start", [body.start.x, body.start.y], msg)
    reach = body.reach(smoothing)
    if math.hypot(x, y) + reach > grid.domain_radius - grid.dx:
        msg = (
            f"the footprint of body {body.name!r}, of radius {reach:.4g}, reaches past the grid "
            f"(allowed: domain_radius >= {math.hypot(x, y) + reach + grid.dx:.4g})"
        )
        raise FieldError("grid.domain_radius", grid.domain_radius, msg)
    c, s = math.cos(body.start.angle), math.sin(body.start.angle)
    for j, pill in enumerate(body.pills):
        room = vessel.clearance(x + c * pill.x - s * pill.y, y + s * pill.x + c * pill.y)
        need = pill.radius + X_SATURATION * smoothing + grid.dx
        if room < need:
            msg = (
                f"a spanning body's pill lies {room:.4g} from the {vessel.shape}'s nearest "
                f"wall, within its radius plus {X_SATURATION:g} delta plus one cell (allowed: "
                f"at least {need:.4g} inside both walls, so that its camphor falls on wet cells)"
            )
            raise FieldError(f"bodies[{k}].pills[{j}]", [pill.x, pill.y], msg)
