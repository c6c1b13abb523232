"""Bodies in numpy: each body's plate indicator F_k, pill indicator G_k and plate velocity.

The numpy reference of the camphor objects of a ``bodies:`` config
(:mod:`pde_rotor.config.bodies`); the paper's rotor is the one body of the ``geometry:``
shorthand (:meth:`pde_rotor.config.RotorConfig.body_list`), for which F_k and G_k are
:func:`pde_rotor.model.geometry.plate_indicator` and ``pill_indicator`` bit for bit at
phi = 0 (F at every angle).

Every indicator is 1/2 (1 + tanh(x / delta)) of a signed distance x (scheme ``paper``,
point values; the equations after Eq. (rj)), evaluated in the body frame: a point r is
measured from the body's position X first, r - X, so that a body moved by whole cells
gives the same values moved by whole cells. Per plate shape:

* polygon: x = R cos(pi/N) - max_j (r - X) . e_j with the edge normals
  e_j = e(phi + 2 pi (j - 1/2) / N), as the paper's plate;
* disk: x = R - |r - X|;
* strip: x = -max(|x'| - L/2, |y'| - W/2) with (x', y') = R(-phi) (r - X): the gauge's
  level sets are rectangles, and F is the minimum of the two slabs' profiles (as the
  polygon's is the minimum over its edges);
* none: F_k is the pills' own indicator G_k.

Each pill adds 1/2 (1 + tanh((rho_j - |r - X - R(phi) p_j|) / delta)) to G_k and
s_j / (pi rho_j^2) times that to the source of Eq. (eqc). The plate moves with
u_k = U_k + omega_k z x (r - X_k), which Eq. (eqv) relaxes v towards under F_k.

The footprint of a body (:attr:`BodyShape.reach`) is the radius about X beyond which
F_k and G_k are set to 0: w delta beyond plate and pills, w = ``numerics.footprint_widths``
(default X_SATURATION = 20, where the tanh tail is 4.3e-18; at w every dropped term is below
e^(-2 w)). It is the support of the compiled loops (:func:`body_support`) and the disk on
which the numpy reference keeps F_k and G_k (:func:`footprint_mask`). The contact radius
(:attr:`BodyShape.contact`) is the footprint at X_SATURATION whatever w: the disk the config
keeps inside the dish and apart from the other bodies', where contact springs act and
where a body leaves a vessel, so that the footprint's precision moves no contact.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from ..config import (
    X_SATURATION,
    BodyConfig,
    FreeMotion,
    PolygonPlate,
    ProtocolConfig,
    TrackMotion,
)
from .domain import Domain
from .geometry import edge_normal_angles, support_rows


class Pose(NamedTuple):
    """A body's pose: its position X = (x, y) (the axis it turns about) and angle phi."""

    x: float
    y: float
    phi: float


@dataclass(frozen=True, eq=False)
class BodyShape:
    """What a body's indicators need, derived once from its config.

    Attributes:
        plate: the plate's shape, one of ``polygon``, ``disk``, ``strip``, ``none``.
        n_corners: N of a polygon (0 otherwise).
        radius: R, circumradius of a polygon or radius of a disk (0 otherwise).
        apothem: R cos(pi/N) of a polygon (0 otherwise).
        length: L of a strip (0 otherwise).
        width: W of a strip (0 otherwise).
        pills: (P, 4) read-only array, one row (x, y, rho, s0) per pill, x and y in the
            body frame.
        smoothing: delta, the width of every tanh edge (geometry.smoothing).
        extent: radius about X of the smallest disk holding plate and pills.
        reach: the footprint, radius about X beyond which F_k = G_k = 0: the extent plus
            w delta (``numerics.footprint_widths``; every dropped term below e^(-2 w)).
        contact: the contact radius, the footprint at w = X_SATURATION (4.3e-18) whatever
            the footprint's w: contact springs, a vessel's walls and the config's checks
            of starts read it.
        widths: w, the footprint's margin beyond plate and pills in units of delta.
    """

    plate: str
    n_corners: int
    radius: float
    apothem: float
    length: float
    width: float
    pills: np.ndarray
    smoothing: float
    extent: float
    reach: float
    contact: float
    widths: float

    @classmethod
    def from_config(
        cls, body: BodyConfig, smoothing: float, widths: float = X_SATURATION
    ) -> BodyShape:
        """The shape of a resolved body (:meth:`RotorConfig.body_list`), its footprint
        `widths` smoothing widths beyond plate and pills (``numerics.footprint_widths``)."""
        plate = body.plate
        pills = np.array([[p.x, p.y, p.radius, p.supply] for p in body.pills], dtype=float).reshape(
            -1, 4
        )
        if np.isnan(pills).any():
            msg = "the body is not resolved: a pill's supply is null (use RotorConfig.body_list)"
            raise ValueError(msg)
        pills.setflags(write=False)
        return cls(
            plate=plate.shape,
            n_corners=getattr(plate, "n_corners", 0),
            radius=getattr(plate, "radius", 0.0),
            apothem=plate.apothem if isinstance(plate, PolygonPlate) else 0.0,
            length=getattr(plate, "length", 0.0),
            width=getattr(plate, "width", 0.0),
            pills=pills,
            smoothing=smoothing,
            extent=body.extent(),
            reach=body.reach(smoothing, widths),
            contact=body.reach(smoothing),
            widths=widths,
        )


MOTIONLESS = math.inf
"""The mass of a body that does not translate and the inertia of one that does not turn:
force / m and torque / I vanish."""


class Track(NamedTuple):
    """The circle a ``track`` body is kept on (:mod:`pde_rotor.physics.motion`).

    Attributes:
        centre: C, (x, y) of the track's centre.
        radius: R.
        direction: d = +1 (counterclockwise) or -1, the direction of travel.
        force: f_t, the external force along the direction of travel.
        spans: whether the body spans the channel (its plate crosses the vessel's no-flux
            walls; its integrals are taken over the wet cells only).
    """

    centre: tuple[float, float]
    radius: float
    direction: float
    force: float
    spans: bool = False


@dataclass(frozen=True, eq=False)
class Body:
    """One camphor object: its shape, motion, start and protocol.

    Attributes:
        name: the body's label (``body{k}`` by default).
        shape: the plate and pills (:class:`BodyShape`).
        motion: ``fixed``, ``fixed_axis``, ``free`` or ``track``.
        mass: m of a free or track body; :data:`MOTIONLESS` otherwise.
        inertia: I of a turning body; :data:`MOTIONLESS` for a fixed or track one (a
            track body's heading is the track's).
        friction: mu of the coupling -mu int F_k (u_k - v) dA; 0 for a fixed body.
        noise_sigma: sigma of the torque noise on its rotation, Eq. (noiseav).
        start: the pose at t = 0.
        omega0: the angular velocity at t = 0.
        velocity0: the velocity U at t = 0.
        protocol: its stop-and-release schedule (None: never stopped).
        config: the resolved config it was built from, whose own numeric keys (the
            external loads, a new term's constants) the records and the numpy reference
            read as they are (:mod:`pde_rotor.config.recorded`).
        track: the circle of a ``track`` body (None for the others).
    """

    name: str
    shape: BodyShape
    motion: str
    mass: float
    inertia: float
    friction: float
    noise_sigma: float
    start: Pose
    omega0: float
    velocity0: tuple[float, float]
    protocol: ProtocolConfig | None
    config: BodyConfig
    track: Track | None = None

    @property
    def spans(self) -> bool:
        """Whether the body spans its channel (:attr:`Track.spans`)."""
        return self.track is not None and self.track.spans

    @classmethod
    def from_config(cls, body: BodyConfig, shape: BodyShape) -> Body:
        """The body of a resolved body config (:meth:`RotorConfig.body_list`) whose plate
        and pills are `shape` (:meth:`BodyShape.from_config` of the same config; both
        made by :attr:`pde_rotor.model.setup.Setup.bodies`)."""
        motion = body.motion
        if isinstance(motion, TrackMotion):
            return cls._on_track(body, motion, shape)
        turns = motion.kind != "fixed"
        if turns and (motion.inertia is None or motion.friction is None):
            msg = "the body is not resolved: inertia or friction is null (use body_list)"
            raise ValueError(msg)
        start = body.start
        return cls(
            name=str(body.name),
            shape=shape,
            motion=motion.kind,
            mass=motion.mass if isinstance(motion, FreeMotion) else MOTIONLESS,
            inertia=float(motion.inertia) if turns else MOTIONLESS,
            friction=float(motion.friction) if turns else 0.0,
            noise_sigma=float(body.noise_sigma or 0.0),
            start=Pose(start.x, start.y, start.angle),
            omega0=start.omega,
            velocity0=start.velocity,
            protocol=body.protocol,
            config=body,
        )

    @classmethod
    def _on_track(cls, body: BodyConfig, motion: TrackMotion, shape: BodyShape) -> Body:
        """The body of a resolved track body config: its start velocity w(0) e_theta and
        omega(0) = w(0) / R from the signed speed w(0) = d ``speed``."""
        if motion.radius is None or motion.centre is None:
            msg = "the body is not resolved: the track's radius or centre is null (use body_list)"
            raise ValueError(msg)
        start = body.start
        cx, cy = motion.centre
        theta = math.atan2(start.y - cy, start.x - cx)
        speed = motion.sign * motion.speed
        return cls(
            name=str(body.name),
            shape=shape,
            motion=motion.kind,
            mass=motion.mass,
            inertia=MOTIONLESS,
            friction=float(motion.friction),
            noise_sigma=0.0,
            start=Pose(start.x, start.y, start.angle),
            omega0=speed / motion.radius,
            velocity0=(-speed * math.sin(theta), speed * math.cos(theta)),
            protocol=body.protocol,
            config=body,
            track=Track((cx, cy), motion.radius, motion.sign, motion.force, motion.spans),
        )


def pill_offsets(shape: BodyShape, phi: float) -> np.ndarray:
    """R(phi) p_j: the pill centres relative to the body's position, (P, 2)."""
    c, s = math.cos(phi), math.sin(phi)
    px, py = shape.pills[:, 0], shape.pills[:, 1]
    return np.stack([c * px - s * py, s * px + c * py], axis=1)


def pill_centres(shape: BodyShape, pose: Pose) -> np.ndarray:
    """X + R(phi) p_j: the pill centres on the surface, (P, 2)."""
    return np.array([pose.x, pose.y]) + pill_offsets(shape, pose.phi)


def _pill_terms(x: np.ndarray, y: np.ndarray, shape: BodyShape, pose: Pose) -> list[np.ndarray]:
    """Each pill's 1/2 [1 + tanh((rho_j - |r - X - R(phi) p_j|) / delta)]."""
    rx, ry = x - pose.x, y - pose.y
    terms = []
    for (qx, qy), rho in zip(pill_offsets(shape, pose.phi), shape.pills[:, 2], strict=True):
        dist = np.hypot(rx - qx, ry - qy)
        terms.append(0.5 * (1.0 + np.tanh((rho - dist) / shape.smoothing)))
    return terms


def pill_indicator(x: np.ndarray, y: np.ndarray, shape: BodyShape, pose: Pose) -> np.ndarray:
    """G_k = sum_j 1/2 [1 + tanh((rho_j - |r - X - R(phi) p_j|) / delta)] (numpy reference)."""
    out = np.zeros(np.broadcast(x, y).shape)
    for term in _pill_terms(x, y, shape, pose):
        out += term
    return out


def pill_source(x: np.ndarray, y: np.ndarray, shape: BodyShape, pose: Pose) -> np.ndarray:
    """The body's camphor source of Eq. (eqc): sum_j s_j / (pi rho_j^2) times pill j's term."""
    out = np.zeros(np.broadcast(x, y).shape)
    terms = _pill_terms(x, y, shape, pose)
    for term, (_, _, rho, supply) in zip(terms, shape.pills, strict=True):
        out += supply / (math.pi * rho**2) * term
    return out


def plate_indicator(x: np.ndarray, y: np.ndarray, shape: BodyShape, pose: Pose) -> np.ndarray:
    """F_k at the points (x, y) for the body at `pose` (numpy reference, scheme ``paper``).

    See the module docstring for each shape's signed distance; a body without a plate
    gives its pills' indicator.
    """
    if shape.plate == "none":
        return pill_indicator(x, y, shape, pose)
    rx, ry = x - pose.x, y - pose.y
    if shape.plate == "polygon":
        ang = edge_normal_angles(shape.n_corners, pose.phi)
        proj = np.max([rx * math.cos(a) + ry * math.sin(a) for a in ang], axis=0)
        return 0.5 * (1.0 + np.tanh((shape.apothem - proj) / shape.smoothing))
    if shape.plate == "disk":
        return 0.5 * (1.0 + np.tanh((shape.radius - np.hypot(rx, ry)) / shape.smoothing))
    c, s = math.cos(pose.phi), math.sin(pose.phi)
    along, across = c * rx + s * ry, -s * rx + c * ry
    gauge = np.maximum(np.abs(along) - shape.length / 2, np.abs(across) - shape.width / 2)
    return 0.5 * (1.0 + np.tanh(-gauge / shape.smoothing))


def plate_velocity(
    x: np.ndarray,
    y: np.ndarray,
    shape: BodyShape,
    pose: Pose,
    velocity: tuple[float, float],
    omega: float,
) -> np.ndarray:
    """F_k u_k, the plate velocity u_k = U + omega z x (r - X) weighted by F_k, (2, ...).

    The term Eq. (eqv) relaxes v towards, eta F_k (u_k - v), and the friction of
    Eq. (eq_motion) integrates.
    """
    f = plate_indicator(x, y, shape, pose)
    ux, uy = velocity
    return np.stack([f * (ux - omega * (y - pose.y)), f * (uy + omega * (x - pose.x))])


def body_support(domain: Domain, shape: BodyShape, pose: Pose) -> tuple[np.ndarray, np.ndarray]:
    """Column range [lo, hi) per row of the domain's cells within the body's footprint.

    The only cells where F_k or G_k are not 0; the body's pose is on the surface, the
    domain's coordinates are measured from the dish centre.
    """
    return support_rows(domain.coords, shape.reach, centre=domain.dish_frame(pose.x, pose.y))


def footprint_mask(domain: Domain, shape: BodyShape, pose: Pose) -> np.ndarray:
    """(n, n): whether each cell's centre lies in the body's footprint,
    |r - X|^2 < reach^2, where F_k and G_k are kept (numpy reference of the compiled
    ``footprint_chord``, in the same frame, :meth:`Domain.dish_frame`)."""
    x_k, y_k = domain.dish_frame(pose.x, pose.y)
    rx = domain.coords[:, None] - x_k
    ry = domain.coords[None, :] - y_k
    return rx * rx + ry * ry < shape.reach * shape.reach
