"""Bodies: the camphor objects on the surface, each with its plate, pills and motion.

A config's optional ``bodies:`` list generalises the paper's single rotor (the
``geometry:`` shorthand, :meth:`pde_rotor.config.RotorConfig.body_list`) to several
objects on one surface. Body k has

* a plate, whose smoothed indicator F_k enters Eqs. (eqc) and (eqv) as the paper's F
  does: a regular polygon (``n_corners``, circumradius ``radius``; the paper's plate),
  a disk (``radius``), a strip (a ``length`` x ``width`` rectangle centred on the body's
  origin, its long axis along the body's x axis), or ``none``: then the floating pills
  are the object and F_k is their own indicator;
* pills at positions of the body frame, each with its radius rho and supply s0 (the
  source s0 / (pi rho^2) inside it, Eq. (eqc));
* a pose (position X_k, angle phi_k) and a motion: ``fixed`` (never moves: a source or
  an obstacle), ``fixed_axis`` (turns about X_k with inertia I and friction mu,
  Eq. (eq_motion); the paper's rotor is this at the origin), ``free`` (translates
  with mass m and turns with inertia I; friction is the paper's coupling
  -mu int F_k (u_k - v) dA with the plate velocity u_k = U_k + omega_k z x (r - X_k))
  or ``track`` (a boat in a ring channel: kept on a circle about the vessel's centre,
  heading along it, one degree of freedom, the forces projected on the tangent;
  its external force ``external_force`` is projected too);
* optionally its own stop-and-release protocol and torque noise, and an external load
  (a constant force ``external_force`` on a free body and torque ``external_torque``
  about X_k, added to the right-hand sides of Eq. (eq_motion)).

Inheritance: a key left null takes the run's value when the bodies are resolved
(:meth:`BodyConfig.resolved`): a pill's ``supply`` the run's ``camphor.supply``; a
motion's ``inertia`` the run's ``rotor.inertia``; a ``fixed_axis`` motion's ``friction``
the run's ``rotor.friction`` (a free body's defaults to a camphor disk's own,
:data:`FREE_FRICTION`, not to the paper rotor's 1e-4, 1764 times below a disk's onset);
``noise_sigma`` the run's ``noise.sigma`` for a ``fixed_axis`` body and 0 otherwise;
``name`` is ``body{k}``. The positions and footprints here are what the config's checks
need (bodies inside the dish and apart, pills inside their plate); the numpy indicators
are in :mod:`pde_rotor.model.bodies`.
"""

from __future__ import annotations

import math
from typing import Annotated, Literal

from pydantic import Field, model_validator

from .errors import FieldError
from .fields import (
    ANGLE_BOUND,
    OMEGA_BOUND,
    PAPER_FRICTION,
    PAPER_INERTIA,
    PAPER_N_CORNERS,
    PAPER_PILL_RADIUS,
    PAPER_PLATE_RADIUS,
    SCALE_BOUND,
    VELOCITY_BOUND,
    X_SATURATION,
    FiniteFloat,
    Int,
    NonNegativeFloat,
    PositiveFloat,
    _Section,
)
from .protocol import ProtocolConfig
from .recorded import BuiltInto

INSIDE_TOLERANCE = 1e-12
"""A pill may touch its plate's edge to within this (the paper's pills touch both edges
of their corner at pill_inset = 0)."""


class PolygonPlate(_Section):
    """Regular N-gon plate, a corner on the body's x axis (the paper's plate, Fig. 1)."""

    shape: Literal["polygon"] = Field("polygon", description="a regular polygon")
    n_corners: Int = Field(PAPER_N_CORNERS, ge=3, le=24, description="N: number of corners")
    radius: PositiveFloat = Field(PAPER_PLATE_RADIUS, description="R: circumradius")

    @property
    def apothem(self) -> float:
        """R cos(pi/N): distance of the edges from the body's origin."""
        return self.radius * math.cos(math.pi / self.n_corners)

    def extent(self) -> float:
        """Radius of the smallest disk about the body's origin holding the plate: R."""
        return self.radius

    def area(self) -> float:
        """The plate's area, (N / 2) R^2 sin(2 pi / N)."""
        return self.n_corners / 2 * self.radius**2 * math.sin(2 * math.pi / self.n_corners)

    def reach(self, smoothing: float, widths: float = X_SATURATION) -> float:
        """Radius beyond which F < e^(-2 w), w = `widths` (4.3e-18 at the default
        X_SATURATION): R + w delta / cos(pi/N).

        F is 1/2 [1 + tanh((R cos(pi/N) - h) / delta)] with the gauge h >= |r| cos(pi/N);
        at the default the same expression as
        :attr:`pde_rotor.config.GeometryConfig.support_radius`.
        """
        return self.radius + widths * smoothing / math.cos(math.pi / self.n_corners)

    def margin(self, x: float, y: float) -> float:
        """Distance from (x, y) inside the plate to its nearest edge (negative outside)."""
        n = self.n_corners
        return self.apothem - max(
            x * math.cos(2 * math.pi * (j - 0.5) / n) + y * math.sin(2 * math.pi * (j - 0.5) / n)
            for j in range(1, n + 1)
        )


class DiskPlate(_Section):
    """Disk plate about the body's origin."""

    shape: Literal["disk"] = Field("disk", description="a disk")
    radius: PositiveFloat = Field(PAPER_PLATE_RADIUS, description="R: radius")

    def extent(self) -> float:
        """Radius of the smallest disk about the body's origin holding the plate: R."""
        return self.radius

    def area(self) -> float:
        """The plate's area, pi R^2."""
        return math.pi * self.radius**2

    def reach(self, smoothing: float, widths: float = X_SATURATION) -> float:
        """Radius beyond which F < e^(-2 w), w = `widths` (4.3e-18 at the default
        X_SATURATION): R + w delta."""
        return self.radius + widths * smoothing

    def margin(self, x: float, y: float) -> float:
        """Distance from (x, y) inside the plate to its edge (negative outside)."""
        return self.radius - math.hypot(x, y)


class StripPlate(_Section):
    """Rectangular strip centred on the body's origin, its long axis along the body's x."""

    shape: Literal["strip"] = Field("strip", description="a rectangle")
    length: PositiveFloat = Field(description="L: side along the body's x axis")
    width: PositiveFloat = Field(description="W: side along the body's y axis")

    def extent(self) -> float:
        """Radius of the smallest disk about the body's origin holding the plate."""
        return math.hypot(self.length / 2, self.width / 2)

    def area(self) -> float:
        """The plate's area, L W."""
        return self.length * self.width

    def reach(self, smoothing: float, widths: float = X_SATURATION) -> float:
        """Radius beyond which F < e^(-2 w), w = `widths` (4.3e-18 at the default
        X_SATURATION): the corner of the rectangle grown by w delta (F is a function of
        the gauge max(|x'| - L/2, |y'| - W/2))."""
        grow = widths * smoothing
        return math.hypot(self.length / 2 + grow, self.width / 2 + grow)

    def margin(self, x: float, y: float) -> float:
        """Distance from (x, y) inside the plate to its nearest edge (negative outside)."""
        return min(self.length / 2 - abs(x), self.width / 2 - abs(y))


class NoPlate(_Section):
    """No plate: the pills float by themselves and are the object (F_k = their indicator)."""

    shape: Literal["none"] = Field("none", description="no plate")

    def extent(self) -> float:
        """No plate: 0 (the pills give the body's extent)."""
        return 0.0

    def area(self) -> float:
        """No plate: 0 (the pills give the body's area)."""
        return 0.0

    def reach(self, smoothing: float, widths: float = X_SATURATION) -> float:
        """No plate: 0 (the pills give the body's reach)."""
        return 0.0


PlateConfig = Annotated[
    PolygonPlate | DiskPlate | StripPlate | NoPlate, Field(discriminator="shape")
]
"""The plate of a body, by its ``shape``; each shape allows only its own keys."""


class PillConfig(_Section):
    """One camphor pill, a disk of radius rho in the body frame with the source s0/(pi rho^2)."""

    x: FiniteFloat = Field(0.0, description="x of the centre in the body frame")
    y: FiniteFloat = Field(0.0, description="y of the centre in the body frame")
    radius: PositiveFloat = Field(PAPER_PILL_RADIUS, description="rho: radius of the pill")
    supply: NonNegativeFloat | None = Field(
        None,
        le=SCALE_BOUND,
        description="s0: supply rate of the pill (null: the run's camphor.supply)",
    )

    @property
    def distance(self) -> float:
        """|p|: distance of the centre from the body's origin."""
        return math.hypot(self.x, self.y)

    def reach(self, smoothing: float, widths: float = X_SATURATION) -> float:
        """Radius about the body's origin beyond which the pill's G < e^(-2 w),
        w = `widths` (4.3e-18 at the default X_SATURATION): |p| + rho + w delta."""
        return self.distance + self.radius + widths * smoothing


_Inertia = Annotated[
    PositiveFloat, Field(ge=PAPER_INERTIA / SCALE_BOUND, le=PAPER_INERTIA * SCALE_BOUND)
]
"""A body's I: within SCALE_BOUND of the paper's, as rotor.inertia."""
BODY_FRICTION_BOUND = 10 * SCALE_BOUND**2 * PAPER_FRICTION
"""Largest mu of a body, 1e7 times the paper rotor's (1e-4): a free camphor disk of the
paper's pills starts to move only below mu_c = 0.18 (docs/bodies.md), so its onset lies
far above the rotor's bound of SCALE_BOUND times the paper's value."""

_Friction = Annotated[NonNegativeFloat, Field(le=BODY_FRICTION_BOUND)]
"""A body's mu: at most :data:`BODY_FRICTION_BOUND`."""

FREE_FRICTION = 0.15
"""Default mu of a free body: a camphor disk's own friction, not the paper rotor's.

A free disk of the paper's pill (rho = 0.1, the paper's camphor) rests for mu above its
onset mu_c = K(0) / (pi rho^2) = 0.17635 and self-propels below it (a supercritical
pitchfork, docs/bodies.md); 0.15 = 0.85 mu_c sets it off at the steady speed U* = 1.97,
0.008 cells per step on the paper's grid (tests/config/test_bodies.py). The rotor's
mu = 1e-4 lies 1764 times below mu_c: a free body given it runs away into the rim.
Larger disks have a lower onset (0.127 at rho = 0.2, 0.100 at 0.3) and rest at 0.15; they
state their friction."""


class FixedMotion(_Section):
    """A body that never moves: a stationary camphor source or an obstacle (u_k = 0)."""

    kind: Literal["fixed"] = Field("fixed", description="never moves")


class FixedAxisMotion(_Section):
    """Rotation about the body's position X_k, Eq. (eq_motion) (the paper's rotor)."""

    kind: Literal["fixed_axis"] = Field("fixed_axis", description="turns about its position")
    inertia: _Inertia | None = Field(
        None, description="I: moment of inertia (null: the run's rotor.inertia)"
    )
    friction: _Friction | None = Field(
        None, description="mu: friction constant (null: the run's rotor.friction)"
    )


class FreeMotion(_Section):
    """Translation and rotation: m dU/dt = force, I domega/dt = torque about X_k."""

    kind: Literal["free"] = Field("free", description="translates and turns")
    mass: PositiveFloat = Field(description="m: mass (required)")
    inertia: _Inertia | None = Field(
        None, description="I: moment of inertia about X_k (null: the run's rotor.inertia)"
    )
    friction: _Friction = Field(
        FREE_FRICTION,
        description=(
            "mu: friction constant (default 0.15, 0.85 times the onset of a free camphor disk "
            "of the paper's pill, which then self-propels at a steady speed; docs/bodies.md)"
        ),
    )


TRACK_TOLERANCE = 1e-9
"""A track body's start may lie off its track's circle, and its start angle off the
tangent, by this (relative to the radius; absolute in radians)."""


class TrackMotion(_Section):
    """On a circular track about the vessel's centre, heading along it (a boat in a ring
    channel): m dw/dt = (f + f_fr + f_ext) . e_theta + d f_t for the arc speed w
    (:mod:`pde_rotor.physics.motion`)."""

    kind: Literal["track"] = Field("track", description="moves along a circle, heading tangent")
    mass: PositiveFloat = Field(description="m: mass (required)")
    friction: _Friction = Field(
        FREE_FRICTION, description="mu: friction constant (default that of a free body, 0.15)"
    )
    radius: PositiveFloat | None = Field(
        None,
        description="R: the track's radius (null: the start's distance from the centre)",
    )
    centre: tuple[FiniteFloat, FiniteFloat] | None = Field(
        None, description="C: the track's centre (null: grid.domain_centre, the vessel's)"
    )
    direction: Literal["counterclockwise", "clockwise"] = Field(
        "counterclockwise",
        description="d: the direction of travel, which the body's x axis (its front) faces",
    )
    speed: FiniteFloat = Field(
        0.0,
        ge=-VELOCITY_BOUND,
        le=VELOCITY_BOUND,
        description="w(0): the start speed along the direction of travel",
    )
    force: FiniteFloat = Field(
        0.0, description="f_t: a constant external force along the direction of travel"
    )
    spans: bool = Field(
        False,
        description=(
            "true: the body spans the channel, its plate crossing the vessel's no-flux walls "
            "(its integrals over the wet cells only; docs/bodies.md, the spanning boat)"
        ),
    )

    @property
    def sign(self) -> float:
        """d = +1 counterclockwise, -1 clockwise."""
        return 1.0 if self.direction == "counterclockwise" else -1.0

    def heading(self, x: float, y: float) -> float:
        """The body's angle at (x, y): the tangent theta + d pi / 2 (a resolved track)."""
        cx, cy = self.centre or (0.0, 0.0)
        return math.atan2(y - cy, x - cx) + self.sign * math.pi / 2


MotionConfig = Annotated[
    FixedMotion | FixedAxisMotion | FreeMotion | TrackMotion, Field(discriminator="kind")
]
"""How a body moves, by its ``kind``; each kind allows only its own keys."""


_Speed = Annotated[FiniteFloat, Field(ge=-VELOCITY_BOUND, le=VELOCITY_BOUND)]
"""A component of a body's start velocity: at most :data:`VELOCITY_BOUND` in size."""


class StartConfig(_Section):
    """The body's pose and velocities at t = 0."""

    x: FiniteFloat = Field(0.0, description="X: x of the body's origin (its axis)")
    y: FiniteFloat = Field(0.0, description="Y: y of the body's origin (its axis)")
    angle: FiniteFloat = Field(
        0.0, ge=-ANGLE_BOUND, le=ANGLE_BOUND, description="phi(0): angle of the body frame [rad]"
    )
    omega: FiniteFloat = Field(
        0.0, ge=-OMEGA_BOUND, le=OMEGA_BOUND, description="dphi/dt(0): angular velocity"
    )
    velocity: tuple[_Speed, _Speed] = Field(
        (0.0, 0.0), description="U(0) = [u_x, u_y]: velocity of a free body"
    )


class BodyLoads(_Section):
    """The constant external loads of Eq. (eq_motion) that every turning body takes, the
    shorthand's rotor included (its ``rotor:`` section derives from this class, and
    :meth:`pde_rotor.config.RotorConfig.rotor_body` hands each key to the rotor's body):
    a load added here reaches every body and the rotor alike."""

    external_torque: FiniteFloat = Field(
        0.0, description="a constant external torque about the body's origin, Eq. (eq_motion)"
    )


class BodyKeys(_Section):
    """A body's keys besides :class:`BodyLoads`: plate, pills, motion, start, protocol,
    noise, external force (a base of :class:`BodyConfig`, so that its keys come first)."""

    name: str | None = Field(
        None,
        pattern=r"^[A-Za-z0-9_-]+$",
        description="label of the body in records (null: body{k}, k its index)",
    )
    plate: PlateConfig = Field(default_factory=NoPlate, description="the plate (shape: ...)")
    pills: list[PillConfig] = Field(
        default_factory=list, description="camphor pills [{x, y, radius, supply}, ...]"
    )
    motion: MotionConfig = Field(
        default_factory=FixedAxisMotion, description="how the body moves (kind: ...)"
    )
    start: StartConfig = Field(default_factory=StartConfig, description="pose at t = 0")
    protocol: ProtocolConfig | None = Field(
        None, description="the body's own stops (null: never stopped)"
    )
    noise_sigma: Annotated[NonNegativeFloat | None, BuiltInto("kick")] = Field(
        None,
        description=(
            "sigma of the torque noise on the body's rotation, Eq. (noiseav) (null: the "
            "run's noise.sigma for a fixed_axis body, 0 otherwise)"
        ),
    )
    external_force: tuple[FiniteFloat, FiniteFloat] = Field(
        (0.0, 0.0),
        description="[f_x, f_y]: a constant external force on a free body, Eq. (eq_motion)",
    )


class BodyConfig(BodyLoads, BodyKeys):
    """One camphor object on the surface: plate, pills, motion, start, protocol, noise and
    its external loads (:class:`BodyKeys`, then :class:`BodyLoads`)."""

    def extent(self) -> float:
        """Radius of the smallest disk about the body's origin holding plate and pills."""
        return max([self.plate.extent(), *(pill.distance + pill.radius for pill in self.pills)])

    def area(self) -> float:
        """A = int F_k dA of the sharp body: the plate's area, which holds the pills; without
        a plate the pills' (disjoint) disks, sum pi rho^2."""
        if isinstance(self.plate, NoPlate):
            return sum(math.pi * pill.radius**2 for pill in self.pills)
        return self.plate.area()

    def reach(self, smoothing: float, widths: float = X_SATURATION) -> float:
        """Footprint: radius about the body's origin beyond which F_k and G_k are below
        e^(-2 w) (4.3e-18 at the default w = X_SATURATION), the plate's and pills' extent
        plus w delta (``numerics.footprint_widths``). At the default it is also the
        body's contact radius (:attr:`pde_rotor.model.bodies.BodyShape.contact`)."""
        return max(
            [self.plate.reach(smoothing, widths), *(p.reach(smoothing, widths) for p in self.pills)]
        )

    def pill_overlap(self) -> tuple[int, int, float] | None:
        """(i, j, distance) of the first pills i < j whose disks overlap (their sources
        would add up there, Eq. (eqc)), or None; pills may touch."""
        for j, pill in enumerate(self.pills):
            for i in range(j):
                other = self.pills[i]
                apart = math.hypot(pill.x - other.x, pill.y - other.y)
                if apart < pill.radius + other.radius - INSIDE_TOLERANCE:
                    return i, j, apart
        return None

    def friction_rates(self) -> list[float]:
        """Upper bounds of the body's friction relaxation rates (a resolved body).

        Turning: mu J / I with J bounded by the circumscribed disk's pi e^4 / 2 (e the
        :meth:`extent`); translating (free): mu A / m with A <= pi e^2. A fixed body has
        none. They bound the explicit step (:meth:`RotorConfig.dt_limit`).
        """
        motion = self.motion
        if isinstance(motion, FixedMotion):
            return []
        extent = self.extent()
        if isinstance(motion, TrackMotion):
            return [motion.friction * math.pi * extent**2 / motion.mass]
        rates = [motion.friction * (math.pi * extent**4 / 2) / motion.inertia]
        if isinstance(motion, FreeMotion):
            rates.append(motion.friction * math.pi * extent**2 / motion.mass)
        return rates

    @model_validator(mode="after")
    def _consistent(self) -> BodyConfig:
        if isinstance(self.plate, NoPlate) and not self.pills:
            msg = (
                "a body without a plate is its pills, and it has none (allowed: at least "
                "one pill, or a plate: {shape: polygon|disk|strip, ...})"
            )
            raise FieldError("pills", [], msg)
        if not isinstance(self.plate, NoPlate):
            for j, pill in enumerate(self.pills):
                if self.plate.margin(pill.x, pill.y) < pill.radius - INSIDE_TOLERANCE:
                    msg = (
                        f"the pill of radius {pill.radius:g} sticks out of the "
                        f"{self.plate.shape} plate (edge clearance "
                        f"{self.plate.margin(pill.x, pill.y):.4g} < radius; allowed: pills "
                        "inside their plate)"
                    )
                    raise FieldError(f"pills[{j}]", [pill.x, pill.y], msg)
        start, kind = self.start, self.motion.kind
        for key, value in (
            ("start.velocity", start.velocity),
            ("external_force", self.external_force),
        ):
            if kind not in ("free", "track") and value != (0.0, 0.0):
                msg = f"a {kind} body does not translate (allowed: [0, 0], or motion kind free)"
                raise FieldError(key, list(value), msg)
        if kind == "track":
            track_keys = (
                ("start.velocity", start.velocity != (0.0, 0.0), list(start.velocity),
                 "its speed is motion.speed"),
                ("start.omega", start.omega != 0, start.omega, "it turns with its place"),
                ("external_torque", self.external_torque != 0, self.external_torque,
                 "its heading is the track's"),
                ("noise_sigma", bool(self.noise_sigma), self.noise_sigma,
                 "its heading is the track's"),
            )  # fmt: skip
            for key, bad, value, why in track_keys:
                if bad:
                    msg = f"a track body does not take it: {why} (allowed: 0)"
                    raise FieldError(key, value, msg)
        if kind == "fixed":
            if start.omega != 0:
                msg = "a fixed body does not turn (allowed: 0, or motion kind fixed_axis)"
                raise FieldError("start.omega", start.omega, msg)
            if self.protocol is not None:
                msg = "a fixed body never moves, so it is never stopped (allowed: null)"
                raise FieldError("protocol", self.protocol.model_dump(), msg)
            if self.noise_sigma:
                msg = "a fixed body does not turn, so no torque noise acts (allowed: 0 or null)"
                raise FieldError("noise_sigma", self.noise_sigma, msg)
            if self.external_torque:
                msg = "a fixed body does not turn (allowed: 0, or motion kind fixed_axis)"
                raise FieldError("external_torque", self.external_torque, msg)
        return self

    def resolved(
        self,
        index: int,
        supply: float,
        inertia: float,
        friction: float,
        sigma: float,
        centre: tuple[float, float] = (0.0, 0.0),
    ) -> BodyConfig:
        """This body with every null key given the run's value (see the module docstring).

        Args:
            index: k, the body's index in ``bodies`` (its default name body{k}).
            supply: the run's camphor.supply.
            inertia: the run's rotor.inertia.
            friction: the run's rotor.friction (the default of a fixed_axis body).
            sigma: the run's noise.sigma (the default of a fixed_axis body).
            centre: the vessel's centre, grid.domain_centre (a track's default centre).

        Raises:
            FieldError: a track body whose start lies off its track or whose start angle
                is neither 0 nor the track's tangent.
        """
        data = self.model_dump()
        data["name"] = self.name if self.name is not None else f"body{index}"
        for pill in data["pills"]:
            if pill["supply"] is None:
                pill["supply"] = supply
        motion = data["motion"]
        if motion["kind"] == "track":
            _resolve_track(motion, data["start"], centre, f"bodies[{index}]")
        elif motion["kind"] != "fixed":
            for key, value in (("inertia", inertia), ("friction", friction)):
                if motion[key] is None:
                    motion[key] = value
        if data["noise_sigma"] is None:
            data["noise_sigma"] = sigma if motion["kind"] == "fixed_axis" else 0.0
        return type(self).model_validate(data)


def _resolve_track(motion: dict, start: dict, centre: tuple[float, float], key: str) -> None:
    """Give a track motion's null centre and radius their values (the vessel's centre,
    the start's distance from it) and set the start angle to the tangent, in place
    (`key`: the body's key in the config, bodies[k]).

    Raises:
        FieldError: the start off the circle, or a start angle neither 0 nor tangent.
    """
    if motion.get("centre") is None:
        motion["centre"] = tuple(centre)
    cx, cy = motion["centre"]
    x, y = start["x"], start["y"]
    off = math.hypot(x - cx, y - cy)
    if off == 0.0:
        msg = f"the start lies on the track's centre [{cx:g}, {cy:g}] (allowed: away from it)"
        raise FieldError(f"{key}.start", [x, y], msg)
    if motion.get("radius") is None:
        motion["radius"] = off
    radius = motion["radius"]
    if abs(off - radius) > TRACK_TOLERANCE * radius:
        msg = (
            f"lies {off:.6g} from the track's centre [{cx:g}, {cy:g}], off its circle of "
            f"motion.radius = {radius:g} (allowed: a start on the circle, or radius null)"
        )
        raise FieldError(f"{key}.start", [x, y], msg)
    direction = motion.get("direction", "counterclockwise")
    sign = 1.0 if direction == "counterclockwise" else -1.0
    heading = math.atan2(y - cy, x - cx) + sign * math.pi / 2
    angle = start["angle"]
    gap = math.remainder(angle - heading, 2 * math.pi)
    if angle != 0.0 and abs(gap) > TRACK_TOLERANCE:
        msg = (
            f"is not the track's tangent {heading:.6g} for the direction "
            f"{direction} (allowed: 0, which sets it, or the tangent)"
        )
        raise FieldError(f"{key}.start.angle", angle, msg)
    start["angle"] = heading
