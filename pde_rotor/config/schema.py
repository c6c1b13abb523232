"""The schema: :class:`RotorConfig`, one validated pydantic model of every parameter.

Its sections live in one module each (:mod:`.geometry`, :mod:`.surface` for camphor and
flow, :mod:`.rotor` for the rotor's dynamics and noise, :mod:`.protocol`, :mod:`.grid`,
:mod:`.numerics` for numerics and solver, :mod:`.output`, :mod:`.bodies`); this module
joins them and holds the checks across sections.

Every default is the value used in the paper's section "Numerical results"
(Koyano, Kitahata, Nakata & Gorecki, Chaos 2020). Scripts, tests and the CLI build
:class:`RotorConfig` objects; no other module repeats a parameter value.

Units are the paper's dimensionless units: length in units of the camphor
diffusion length sqrt(D/a), time in units of 1/a.
"""

from __future__ import annotations

import fractions
import hashlib
import json
import math
from typing import Any

import numpy as np
from pydantic import Field, model_validator

from .bodies import (
    BodyConfig,
    BodyLoads,
    FixedAxisMotion,
    FixedMotion,
    FreeMotion,
    PillConfig,
    PolygonPlate,
    StartConfig,
    TrackMotion,
)
from .contact import CONTACT_MODES, CONTACT_STEP, ContactConfig, dashpot_step, euler_damping
from .errors import FieldError
from .fields import X_SATURATION, _Section
from .geometry import GeometryConfig
from .grid import DISH_CENTRE, DISH_WALL, GridConfig
from .numerics import NumericsConfig, SolverConfig
from .output import OutputConfig
from .protocol import ProtocolConfig
from .rotor import CALIBRATED_SIGMA, PAPER_STEADY_OMEGA, NoiseConfig, RotorDynamicsConfig
from .surface import CamphorConfig, FlowConfig
from .vessel import check_vessel

TIME_KEYS = (
    "protocol.t_ini",
    "protocol.t_stop",
    "protocol.t_release",
    "output.timeseries_interval",
    "output.event_interval",
    "output.snapshot_interval",
    "output.movie_interval",
)
"""Times that must be integer multiples of grid.dt (the schedule counts whole steps)."""


SHORTHAND_KEYS = (
    "geometry.n_corners",
    "geometry.radius",
    "geometry.pill_radius",
    "geometry.pill_inset",
    "geometry.asymmetry",
    "rotor.phi0",
    "rotor.omega0",
)
"""Keys of the paper's single rotor (the ``geometry:`` shorthand) that a ``bodies:`` list
replaces: with bodies they must keep their defaults. geometry.smoothing stays global,
rotor.inertia, rotor.friction and noise.sigma are the bodies' defaults, rotor.torque the
torque convention of every body."""


class RotorConfig(_Section):
    """Complete description of one simulation (all sections have the paper's defaults).

    Without ``bodies`` the surface holds the paper's rotor described by ``geometry`` and
    ``rotor`` (the shorthand); with ``bodies`` it holds those objects
    (:mod:`pde_rotor.config.bodies`, :meth:`body_list`).
    """

    geometry: GeometryConfig = Field(default_factory=GeometryConfig)
    camphor: CamphorConfig = Field(default_factory=CamphorConfig)
    flow: FlowConfig = Field(default_factory=FlowConfig)
    rotor: RotorDynamicsConfig = Field(default_factory=RotorDynamicsConfig)
    noise: NoiseConfig = Field(default_factory=NoiseConfig)
    protocol: ProtocolConfig = Field(default_factory=ProtocolConfig)
    grid: GridConfig = Field(default_factory=GridConfig)
    numerics: NumericsConfig = Field(default_factory=NumericsConfig)
    solver: SolverConfig = Field(default_factory=SolverConfig)
    output: OutputConfig = Field(default_factory=OutputConfig)
    contact: ContactConfig = Field(default_factory=ContactConfig)
    bodies: list[BodyConfig] | None = Field(
        None,
        description=(
            "the camphor objects on the surface (null: the single rotor of geometry and "
            "rotor, the paper's)"
        ),
    )

    @model_validator(mode="before")
    @classmethod
    def _bodies_not_null(cls, data: Any) -> Any:
        """A ``bodies`` key without a list (a bare ``bodies:`` line, or ``--set
        bodies=null``) is refused as ``bodies: []`` is: the shorthand rotor is the config
        without the key, never one whose list was lost."""
        if isinstance(data, dict) and "bodies" in data and data["bodies"] is None:
            msg = (
                "a bodies key without entries (a bare `bodies:` line) (allowed: a list of at "
                "least one body, or no bodies key for the rotor of geometry:)"
            )
            raise FieldError("bodies", None, msg)
        return data

    @model_validator(mode="after")
    def _numerically_sound(self) -> RotorConfig:
        dx = self.grid.dx
        smoothing = self.geometry.smoothing
        if dx > 2 * smoothing:
            msg = (
                f"too coarse for geometry.smoothing = {smoothing:g} (allowed: dx <= 2 * "
                f"smoothing = {2 * smoothing:g}, to resolve the edges of F and G)"
            )
            raise FieldError("grid.dx", dx, msg)
        if self.bodies is None:
            self._rotor_in_dish()
            if self.grid.wall != DISH_WALL:
                msg = (
                    "implemented for runs with a bodies: list only (allowed: absorbing for the "
                    "single rotor of geometry:, or that rotor written as one fixed_axis body "
                    "under bodies:)"
                )
                raise FieldError("grid.wall", self.grid.wall, msg)
            widths = self.numerics.footprint_widths
            if widths != X_SATURATION:
                msg = (
                    f"cuts the footprints of a bodies: list only (allowed: the default "
                    f"{X_SATURATION:g} for the single rotor of geometry:, or that rotor "
                    f"written as one fixed_axis body under bodies:)"
                )
                raise FieldError("numerics.footprint_widths", widths, msg)
        else:
            self._bodies_in_dish()
        check_vessel(self.grid, self.bodies is not None, self.body_list(), self.geometry.smoothing)
        limit = self.dt_limit()
        if self.grid.dt > limit:
            msg = f"above the explicit stability limit (allowed: dt <= {limit:.4g} for this dx)"
            raise FieldError("grid.dt", self.grid.dt, msg)
        self._contact_sound()
        dt = self.grid.dt
        if self.bodies is None:
            kick = self.kick_scale()
            if kick >= PAPER_STEADY_OMEGA:
                limit = PAPER_STEADY_OMEGA * self.rotor.inertia / math.sqrt(2 * dt)
                msg = (
                    f"kicks omega by sqrt(2 dt) sigma / I = {kick:.3g} per step, more than the "
                    f"steady rotation omega = {PAPER_STEADY_OMEGA:g} at the paper's parameters: "
                    f"the rotor would not rotate (allowed: sigma < {limit:.3g} for dt = {dt:g}, "
                    f"I = {self.rotor.inertia:g}; calibrated: {CALIBRATED_SIGMA:g})"
                )
                raise FieldError("noise.sigma", self.noise.sigma, msg)
        else:
            self._bodies_noise()
        for key in self.time_keys():
            value = self.get(key)
            if value is None:
                continue
            steps = round(value / dt)
            if abs(steps * dt - value) > 1e-9 * max(1.0, value):
                below, above = math.floor(value / dt) * dt, math.ceil(value / dt) * dt
                fitting = self.fitting_dt()
                suggestion = (
                    f"grid.dt = {fitting:.6g}, which divides every time, or " if fitting else ""
                )
                msg = (
                    f"not an integer multiple of grid.dt = {dt:g} (allowed: {suggestion}"
                    f"k * dt, e.g. {below:.10g} or {above:.10g})"
                )
                raise FieldError(key, value, msg)
        return self

    def _rotor_in_dish(self) -> None:
        """The shorthand's rotor, at the origin, lies inside the dish with water around."""
        dx = self.grid.dx
        if self.geometry.radius + 2 * dx >= self.grid.domain_radius:
            msg = (
                f"leaves no water around the plate (allowed: domain_radius > "
                f"geometry.radius + 2 dx = {self.geometry.radius + 2 * dx:g})"
            )
            raise FieldError("grid.domain_radius", self.grid.domain_radius, msg)
        support = self.geometry.support_radius
        if support > self.grid.domain_radius:
            msg = (
                f"smaller than the reach of the smoothed plate indicator F, R + "
                f"{X_SATURATION:g} delta / cos(pi/N) = {support:.4g} (allowed: domain_radius "
                f">= {support:.4g}, or reduce geometry.smoothing)"
            )
            raise FieldError("grid.domain_radius", self.grid.domain_radius, msg)
        centre = self.grid.domain_centre
        off = math.hypot(*centre)
        room = self.grid.domain_radius - dx - support
        if centre != DISH_CENTRE and off >= room:
            msg = (
                f"puts the rotor's axis, the origin, {off:.4g} from the dish centre, where its "
                f"smoothed plate (reach {support:.4g}) meets the rim (allowed: |domain_centre| "
                f"< domain_radius - dx - {support:.4g} = {room:.4g})"
            )
            raise FieldError("grid.domain_centre", list(centre), msg)

    def _bodies_in_dish(self) -> None:
        """With bodies: no shorthand key is set, names are unique, every footprint lies
        inside the dish (one cell from its rim) and no two footprints meet."""
        paper = RotorConfig()
        for key in SHORTHAND_KEYS:
            value, default = self.get(key), paper.get(key)
            if value != default:
                msg = (
                    f"belongs to the single rotor of the geometry: shorthand, which a bodies: "
                    f"list replaces (allowed: the default {default:g}; each body has its own "
                    f"plate, pills and start, and only geometry.smoothing acts on all)"
                )
                raise FieldError(key, value, msg)
        if not self.bodies:
            msg = "no bodies (allowed: at least one body, or no bodies key for geometry's rotor)"
            raise FieldError("bodies", [], msg)
        bodies = self.body_list()
        smoothing = self.geometry.smoothing
        reach = [body.reach(smoothing) for body in bodies]
        names: dict[str, int] = {}
        for k, body in enumerate(bodies):
            overlap = body.pill_overlap()
            if overlap is not None:
                i, j, apart = overlap
                pills = body.pills
                radii = pills[i].radius + pills[j].radius
                msg = (
                    f"overlaps pills[{i}] of body {body.name!r}: their centres lie {apart:.4g} "
                    f"apart, less than the sum of their radii {radii:.4g}, where their sources "
                    "would add up (allowed: pills apart, or one pill with the supply of both)"
                )
                raise FieldError(f"bodies[{k}].pills[{j}]", [pills[j].x, pills[j].y], msg)
            if body.name in names:
                msg = f"the name of bodies[{names[body.name]}] too (allowed: a name of its own)"
                raise FieldError(f"bodies[{k}].name", body.name, msg)
            names[str(body.name)] = k
        cx, cy = self.grid.domain_centre
        rim = self.grid.domain_radius - self.grid.dx
        footprint = f"plate, pills and the smoothing's reach {X_SATURATION:g} delta"
        for k, body in enumerate(bodies):
            x, y = body.start.x, body.start.y
            off = math.hypot(x - cx, y - cy)
            if off + reach[k] >= rim and self.grid.vessel is None:  # a vessel: check_vessel
                allowed = (
                    f"|start - grid.domain_centre| < {rim - reach[k]:.4g}"
                    if rim > reach[k]
                    else f"grid.domain_radius > {reach[k] + self.grid.dx:.4g}"
                )
                msg = (
                    f"body {body.name!r} reaches {off + reach[k]:.4g} from the dish centre (its "
                    f"footprint of radius {reach[k]:.4g}: {footprint}), not inside "
                    f"grid.domain_radius - dx = {rim:.4g} (allowed: {allowed})"
                )
                if (cx, cy) != DISH_CENTRE and math.hypot(x, y) + reach[k] < rim:
                    # the body fits the dish about the origin: the moved centre is the cause
                    msg = f"moves the dish off body {body.name!r} at start [{x:g}, {y:g}]: " + msg
                    raise FieldError("grid.domain_centre", [cx, cy], msg)
                raise FieldError(f"bodies[{k}].start", [x, y], msg)
            for i in range(k):
                other = bodies[i]
                apart = math.hypot(x - other.start.x, y - other.start.y)
                if apart < reach[k] + reach[i]:
                    msg = (
                        f"body {body.name!r} overlaps body {other.name!r}: their footprints "
                        f"(radius {reach[k]:.4g} and {reach[i]:.4g}: {footprint}) meet at "
                        f"distance {apart:.4g} (allowed: distance >= {reach[k] + reach[i]:.4g})"
                    )
                    raise FieldError(f"bodies[{k}].start", [x, y], msg)

    def _contact_sound(self) -> None:
        """Contact needs bodies, and the step must resolve it for every body that moves:
        dt sqrt(kappa / m) <= CONTACT_STEP (a spring of period 2 pi sqrt(m / kappa) over
        at least 12 steps), the dashpot's lambda gamma dt / m <= 1 (:func:`dashpot_step`),
        and forward Euler only with gamma >= kappa dt - mu A / lambda for the least damped
        body (:func:`~pde_rotor.config.contact.euler_damping`)."""
        contact = self.contact
        if not contact.enabled:
            return
        if self.bodies is None:
            msg = "acts between the bodies of a bodies: list (allowed: false without one)"
            raise FieldError("contact.enabled", True, msg)
        moving = [
            body for body in self.body_list() if isinstance(body.motion, (FreeMotion, TrackMotion))
        ]
        if not moving:
            return
        dt = self.grid.dt
        mass = min(body.motion.mass for body in moving)
        limit = CONTACT_STEP**2 * mass / dt**2
        if contact.stiffness > limit:
            msg = (
                f"is too stiff for dt = {dt:g} and the lightest moving body's mass "
                f"{mass:g}: dt sqrt(kappa / m) > {CONTACT_STEP:g} (allowed: "
                f"stiffness <= {limit:.4g}, or a smaller grid.dt)"
            )
            raise FieldError("contact.stiffness", contact.stiffness, msg)
        if dashpot_step(contact.damping, dt, mass) > 1.0:
            msg = (
                f"is too strong for dt = {dt:g} and the lightest moving body's mass {mass:g}: "
                f"{CONTACT_MODES:g} gamma dt / m > 1 (allowed: damping <= "
                f"{mass / (CONTACT_MODES * dt):.4g}, or a smaller grid.dt)"
            )
            raise FieldError("contact.damping", contact.damping, msg)
        if self.numerics.integrator != "euler":
            return
        friction = min(body.motion.friction * body.area() for body in moving)
        least = euler_damping(contact.stiffness, dt, friction)
        if contact.damping < least:
            msg = (
                f"lets forward Euler ring the contact spring up (numerics.integrator = euler, "
                f"contact.stiffness = {contact.stiffness:g}, grid.dt = {dt:g}, least friction "
                f"mu A = {friction:.4g}: lambda (kappa dt - gamma) > mu A for lambda = "
                f"{CONTACT_MODES:g}) (allowed: contact.damping >= {least:.4g}, "
                f"numerics.integrator: heun, or grid.dt <= "
                f"{(contact.damping + friction / CONTACT_MODES) / contact.stiffness:.4g})"
            )
            raise FieldError("contact.damping", contact.damping, msg)

    def _bodies_noise(self) -> None:
        """No body's torque noise kicks its omega by more than the paper's steady rotation
        per step (the rule of noise.sigma, with each body's own sigma and I)."""
        dt = self.grid.dt
        for k, body in enumerate(self.body_list()):
            if isinstance(body.motion, FixedMotion) or not body.noise_sigma:
                continue
            inertia = body.motion.inertia
            kick = math.sqrt(2.0 * dt) * body.noise_sigma / inertia
            if kick >= PAPER_STEADY_OMEGA:
                own = self.bodies is not None and self.bodies[k].noise_sigma is not None
                key = f"bodies[{k}].noise_sigma" if own else "noise.sigma"
                limit = PAPER_STEADY_OMEGA * inertia / math.sqrt(2 * dt)
                msg = (
                    f"kicks the omega of body {body.name!r} by sqrt(2 dt) sigma / I = "
                    f"{kick:.3g} per step, more than the paper rotor's steady omega = "
                    f"{PAPER_STEADY_OMEGA:g} (allowed: sigma < {limit:.3g} for dt = {dt:g}, "
                    f"I = {inertia:g})"
                )
                raise FieldError(key, body.noise_sigma, msg)

    def body_list(self) -> list[BodyConfig]:
        """The bodies on the surface, every inherited key resolved (:mod:`.bodies`).

        Without ``bodies``: one body, the paper's rotor of the shorthand
        (:meth:`rotor_body`).
        """
        if self.bodies is not None:
            return [
                body.resolved(
                    k,
                    supply=self.camphor.supply,
                    inertia=self.rotor.inertia,
                    friction=self.rotor.friction,
                    sigma=self.noise.sigma,
                    centre=self.grid.domain_centre,
                )
                for k, body in enumerate(self.bodies)
            ]
        return [self.rotor_body()]

    def rotor_body(self) -> BodyConfig:
        """The paper's rotor of the shorthand (``geometry:``, ``rotor:``) as a body.

        Its plate is the polygon (geometry.n_corners, geometry.radius); its pills lie at
        R_c e(2 pi j / N + Delta), j = 1..N, computed with the expression of
        :func:`pde_rotor.model.geometry.pill_angles` and ``pill_centres`` (bit for bit
        their positions at phi = 0), with geometry.pill_radius and camphor.supply; it
        turns about the origin (fixed_axis with rotor.inertia, rotor.friction), starts
        at rotor.phi0, rotor.omega0, is stopped by the run's protocol, kicked by the
        run's noise.sigma and loaded by every key of :class:`BodyLoads` in ``rotor:``
        (rotor.external_torque). The one body of :meth:`body_list` without ``bodies``;
        with them, the run record's body fields (:mod:`pde_rotor.kernels.records`).
        """
        geo = self.geometry
        n = geo.n_corners
        angles = 0.0 + 2 * np.pi * np.arange(1, n + 1) / n + geo.asymmetry
        centres = geo.pill_distance * np.stack([np.cos(angles), np.sin(angles)], axis=1)
        pills = [
            PillConfig(x=float(px), y=float(py), radius=geo.pill_radius, supply=self.camphor.supply)
            for px, py in centres
        ]
        rotor = self.rotor
        return BodyConfig(
            name="body0",
            plate=PolygonPlate(n_corners=n, radius=geo.radius),
            pills=pills,
            motion=FixedAxisMotion(inertia=rotor.inertia, friction=rotor.friction),
            start=StartConfig(angle=rotor.phi0, omega=rotor.omega0),
            protocol=self.protocol,
            noise_sigma=self.noise.sigma,
            **{key: getattr(rotor, key) for key in BodyLoads.model_fields},
        )

    def time_keys(self) -> list[str]:
        """:data:`TIME_KEYS` and the times of every body's own protocol
        (``bodies[k].protocol.t_stop``): the times that must be whole steps."""
        keys = list(TIME_KEYS)
        for k, body in enumerate(self.bodies or []):
            if body.protocol is not None:
                keys += [
                    f"bodies[{k}].protocol.{name}" for name in ("t_ini", "t_stop", "t_release")
                ]
        return keys

    def fitting_dt(self) -> float | None:
        """A round time step <= grid.dt that divides every time of :meth:`time_keys`.

        The times are read as decimals (at most 6 digits after the point). The step is the
        largest of 1, 2, 2.5, 4 or 5 times a power of ten that divides them all, or else
        their greatest common divisor over a whole number; None below 1e-3 of grid.dt.
        """
        exact = [fractions.Fraction(t).limit_denominator(10**6) for t in self._times() if t]
        dt = fractions.Fraction(self.grid.dt)
        if not exact:
            return None
        top = math.floor(math.log10(self.grid.dt))
        for power in range(top, top - 4, -1):
            for mantissa in ("5", "4", "2.5", "2", "1"):
                step = fractions.Fraction(mantissa) * fractions.Fraction(10) ** power
                if step <= dt and all((t / step).denominator == 1 for t in exact):
                    return float(step)
        common = exact[0]
        for value in exact[1:]:  # gcd(a/b, c/d) = gcd(a d, c b) / (b d)
            numerator = math.gcd(
                common.numerator * value.denominator, value.numerator * common.denominator
            )
            common = fractions.Fraction(numerator, common.denominator * value.denominator)
        step = common / math.ceil(common / dt)
        return float(step) if step >= 1e-3 * dt else None

    def _times(self) -> list[float]:
        return [value for key in self.time_keys() if (value := self.get(key)) is not None]

    def get(self, key: str) -> Any:
        """Value at a dotted key path, e.g. ``config.get("protocol.t_stop")`` or
        ``config.get("bodies[1].start.x")``."""
        node: Any = self
        for part in key.split("."):
            name, _, index = part.partition("[")
            node = getattr(node, name)
            if index:
                node = node[int(index.rstrip("]"))]
        return node

    def far_from_paper(self, factor: float = 10.0) -> list[str]:
        """The model parameters more than `factor` away from the paper's values, furthest first.

        What a diverged run names as its likely cause (``camphor.supply = 500, 500 times
        the paper's 1``) beside the time step.
        """
        paper = type(self)()
        found: list[tuple[float, str]] = []
        for section in ("geometry", "camphor", "flow", "rotor"):
            ours, theirs = getattr(self, section), getattr(paper, section)
            for name in type(ours).model_fields:
                value, default = getattr(ours, name), getattr(theirs, name)
                numbers = (int, float)
                if isinstance(value, bool) or not isinstance(value, numbers) or not default:
                    continue
                ratio = abs(value / default) if value else math.inf
                spread = max(ratio, 1 / ratio) if ratio else math.inf
                if spread > factor:
                    found.append(
                        (
                            spread,
                            f"{section}.{name} = {value:g}, {value / default:.3g} times "
                            f"the paper's {default:g}",
                        )
                    )
        return [text for _, text in sorted(found, reverse=True)]

    def kick_scale(self, dt: float | None = None) -> float:
        """Euler-Maruyama factor of the torque noise, sqrt(2 dt) sigma / I (Eq. (noiseav)).

        omega gains this times one standard normal per step of length dt (default
        ``grid.dt``); 0 without noise.
        """
        step = self.grid.dt if dt is None else dt
        return math.sqrt(2.0 * step) * self.noise.sigma / self.rotor.inertia

    def dt_limit(self) -> float:
        """Largest stable explicit Euler step of the linear terms of Eqs. (eqc), (eqv), (eq_motion).

        For the 5-point Laplacian the forward Euler amplification factor of the stiffest
        mode is 1 - dt (8 D / dx^2 + a); stability needs it >= -1. The same holds for v
        with D_eta and eta + eta_b, and for each body's omega and velocity with its
        friction rates (:meth:`BodyConfig.friction_rates`): mu J / I, where J bounds
        int F r^2 dA by the circumscribed disk, pi R^4 / 2, and mu A / m. Advection adds the
        cell-Peclet condition dt <= 2 D / |v|^2, which depends on the flow reached; a run
        that violates it is caught by the solver's NaN/Inf check.
        """
        dx2 = self.grid.dx**2
        cam, flow = self.camphor, self.flow
        rates = [8 * cam.diffusion / dx2 + cam.evaporation]
        if flow.enabled:
            rates.append(8 * flow.viscosity / dx2 + flow.drag + flow.bulk_drag)
        for body in self.body_list():
            rates.extend(body.friction_rates())
        return 2.0 / max(rates)

    def physics(self) -> dict[str, Any]:
        """The config as a JSON mapping without what changes no result: the output section
        (what is recorded), the solver section (where it runs) and the numerics settings
        its scheme ignores (:meth:`NumericsConfig.acting`). Runs with equal mappings give
        the same result on every machine and backend (sweep run keys, stored gallery runs).
        """
        data = self.model_dump(mode="json", exclude={"output", "solver"})
        data["numerics"] = self.numerics.acting()
        return data

    def config_hash(self) -> str:
        """Short SHA-256 of the canonical JSON of the model, protocol, noise and grid.

        The ``solver`` and ``output`` sections are left out: runs that differ only in
        what they record (or where they ran) share the hash of their physics.
        """
        data = self.model_dump(mode="json", exclude={"solver", "output"})
        text = json.dumps(data, sort_keys=True, separators=(",", ":"))
        return hashlib.sha256(text.encode()).hexdigest()[:16]
