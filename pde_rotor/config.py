"""Run configuration: one validated schema holding every parameter of the model.

Every default is the value used in the paper's section "Numerical results"
(Koyano, Kitahata, Nakata & Gorecki, Chaos 2020). Scripts, tests and the CLI build
:class:`RotorConfig` objects; no other module repeats a parameter value.

Units are the paper's dimensionless units: length in units of the camphor
diffusion length sqrt(D/a), time in units of 1/a.
"""

from __future__ import annotations

import math
from typing import Annotated, Literal

from pydantic import BaseModel, ConfigDict, Field, model_validator

PositiveFloat = Annotated[float, Field(gt=0, allow_inf_nan=False)]
NonNegativeFloat = Annotated[float, Field(ge=0, allow_inf_nan=False)]
FiniteFloat = Annotated[float, Field(allow_inf_nan=False)]


class _Section(BaseModel):
    """Base of all config sections: unknown keys and silent coercions are errors."""

    model_config = ConfigDict(extra="forbid", strict=False, validate_assignment=True)


class GeometryConfig(_Section):
    """Rotor geometry: regular N-gon plate with N camphor pills (paper Fig. 1, Eqs. (rc), (rj))."""

    n_corners: int = Field(6, ge=3, le=24, description="N: number of plate corners and pills")
    radius: PositiveFloat = Field(0.5, description="R: circumradius of the plate")
    pill_radius: PositiveFloat = Field(0.1, description="rho: radius of one camphor pill")
    pill_inset: NonNegativeFloat = Field(
        0.05, description="p: extra inward shift of the pills, Eq. (rc)"
    )
    asymmetry: FiniteFloat = Field(
        0.0, description="Delta: angular shift of every pill from its corner [rad], Eq. (rj)"
    )
    smoothing: PositiveFloat = Field(0.025, description="delta: width of the tanh edges of F and G")

    @property
    def pill_distance(self) -> float:
        """R_c = R - rho / cos(pi/N) - p, Eq. (rc)."""
        return self.radius - self.pill_radius / math.cos(math.pi / self.n_corners) - self.pill_inset

    @model_validator(mode="after")
    def _pills_inside_plate(self) -> GeometryConfig:
        r_c = self.pill_distance
        if r_c <= 0:
            msg = (
                f"geometry: pill distance R_c = R - rho/cos(pi/N) - p = {r_c:.4g} must be > 0 "
                "(reduce pill_radius or pill_inset)"
            )
            raise ValueError(msg)
        # clearance between a pill centre and the nearer of its corner's two edges, whose
        # normals make the angle pi/N -/+ Delta with the pill direction
        half = math.pi / self.n_corners
        edge_distance = self.radius * math.cos(half) - r_c * math.cos(half - abs(self.asymmetry))
        if edge_distance < self.pill_radius - 1e-12:
            msg = (
                f"geometry: pills stick out of the plate (edge clearance {edge_distance:.4g} < "
                f"pill_radius {self.pill_radius:.4g}); increase pill_inset or reduce |asymmetry|"
            )
            raise ValueError(msg)
        return self


class CamphorConfig(_Section):
    """Camphor surface concentration c, Eq. (eqc), and surface tension, Eq. (surfacetension)."""

    diffusion: PositiveFloat = Field(1.0, description="D: camphor diffusion coefficient")
    evaporation: NonNegativeFloat = Field(1.0, description="a: evaporation rate outside the plate")
    supply: NonNegativeFloat = Field(1.0, description="s0: camphor supply rate of one pill")
    tension_slope: NonNegativeFloat = Field(
        1.0, description="k: surface tension gamma = gamma0 - k c, Eq. (surfacetension)"
    )


class FlowConfig(_Section):
    """Surface flow v, Eq. (eqv)."""

    enabled: bool = Field(
        True, description="false: v = 0 in Eqs. (eqc) and (eq_motion), the paper's Fig. 8"
    )
    drag: NonNegativeFloat = Field(1.0, description="eta: relaxation of v to the plate velocity")
    bulk_drag: NonNegativeFloat = Field(1.0, description="eta_b: vertical viscous damping of v")
    viscosity: PositiveFloat = Field(1.0, description="D_eta: horizontal viscous diffusion of v")


class RotorDynamicsConfig(_Section):
    """Rotor dynamics, Eq. (eq_motion), and its initial condition."""

    inertia: PositiveFloat = Field(1e-5, description="I: moment of inertia")
    friction: NonNegativeFloat = Field(1e-4, description="mu: friction constant")
    phi0: FiniteFloat = Field(1.0, description="phi(0): initial angle [rad]")
    omega0: FiniteFloat = Field(0.1, description="dphi/dt(0): initial angular velocity")
    torque: Literal["physical", "printed"] = Field(
        "physical",
        description=(
            "physical: T = -k int F r x grad c dA (contour integral of gamma n); "
            "printed: T = int_Omega r x (-grad gamma) dA as printed in Eq. (torque)"
        ),
    )


class NoiseConfig(_Section):
    """Torque noise xi(t) of Eq. (eq_motion), <xi(t) xi(s)> = 2 sigma^2 delta(t-s), Eq. (noiseav).

    Integrated by Euler-Maruyama, so results do not depend on dt. The paper's
    sigma = 0.1 taken literally destroys the rotation (docs/model.md); the default is
    therefore no noise.
    """

    sigma: NonNegativeFloat = Field(0.0, description="sigma: torque noise intensity")
    seed: int | None = Field(None, ge=0, description="seed of the numpy Generator (None: random)")


class ProtocolConfig(_Section):
    """Stop-and-release operations (paper section "Model", last part)."""

    t_ini: NonNegativeFloat = Field(10.0, description="t_ini: free rotation before the first stop")
    t_stop: NonNegativeFloat = Field(0.5, description="t_stop: duration of one forced stop")
    t_release: PositiveFloat = Field(10.0, description="t_release: free rotation after a stop")
    cycles: int = Field(100, ge=0, description="M: number of stop-and-release cycles")

    @property
    def period(self) -> float:
        """Cycle period T = t_stop + t_release."""
        return self.t_stop + self.t_release

    @property
    def t_end(self) -> float:
        """End of the protocol, t_ini + M T."""
        return self.t_ini + self.cycles * self.period


class GridConfig(_Section):
    """Cartesian grid covering the circular domain of radius L (Dirichlet c = v = 0 outside)."""

    domain_radius: PositiveFloat = Field(3.0, description="L: radius of the circular domain")
    dx: PositiveFloat = Field(0.025, description="grid spacing")
    dt: PositiveFloat = Field(1e-4, description="explicit Euler time step")


class RotorConfig(_Section):
    """Complete description of one simulation (all sections have the paper's defaults)."""

    geometry: GeometryConfig = Field(default_factory=GeometryConfig)
    camphor: CamphorConfig = Field(default_factory=CamphorConfig)
    flow: FlowConfig = Field(default_factory=FlowConfig)
    rotor: RotorDynamicsConfig = Field(default_factory=RotorDynamicsConfig)
    noise: NoiseConfig = Field(default_factory=NoiseConfig)
    protocol: ProtocolConfig = Field(default_factory=ProtocolConfig)
    grid: GridConfig = Field(default_factory=GridConfig)

    @model_validator(mode="after")
    def _numerically_sound(self) -> RotorConfig:
        dx = self.grid.dx
        if dx > 2 * self.geometry.smoothing:
            msg = (
                f"grid.dx = {dx:g} is too coarse for geometry.smoothing = "
                f"{self.geometry.smoothing:g}: need dx <= 2 * smoothing to resolve F and G"
            )
            raise ValueError(msg)
        if self.geometry.radius + 2 * dx >= self.grid.domain_radius:
            msg = (
                f"grid.domain_radius = {self.grid.domain_radius:g} must exceed "
                f"geometry.radius + 2 dx = {self.geometry.radius + 2 * dx:g}"
            )
            raise ValueError(msg)
        limit = self.dt_limit()
        if self.grid.dt > limit:
            msg = f"grid.dt = {self.grid.dt:g} exceeds the explicit stability limit {limit:.4g}"
            raise ValueError(msg)
        return self

    def dt_limit(self) -> float:
        """Largest stable explicit Euler step of the linear terms of Eqs. (eqc), (eqv), (eq_motion).

        For the 5-point Laplacian the forward Euler amplification factor of the stiffest
        mode is 1 - dt (8 D / dx^2 + a); stability needs it >= -1. The same holds for v
        with D_eta and eta + eta_b, and for omega with the friction rate mu J / I, where J
        bounds int F r^2 dA by the circumscribed disk, pi R^4 / 2. Advection adds the
        cell-Peclet condition dt <= 2 D / |v|^2, which depends on the flow reached; a run
        that violates it is caught by the solver's NaN/Inf check.
        """
        dx2 = self.grid.dx**2
        cam, flow = self.camphor, self.flow
        rates = [8 * cam.diffusion / dx2 + cam.evaporation]
        if flow.enabled:
            rates.append(8 * flow.viscosity / dx2 + flow.drag + flow.bulk_drag)
        polar_moment = math.pi * self.geometry.radius**4 / 2
        rates.append(self.rotor.friction * polar_moment / self.rotor.inertia)
        return 2.0 / max(rates)
