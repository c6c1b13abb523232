"""Run configuration: one validated schema holding every parameter of the model.

Every default is the value used in the paper's section "Numerical results"
(Koyano, Kitahata, Nakata & Gorecki, Chaos 2020). Scripts, tests and the CLI build
:class:`RotorConfig` objects; no other module repeats a parameter value.

Units are the paper's dimensionless units: length in units of the camphor
diffusion length sqrt(D/a), time in units of 1/a.

Configs are written as YAML (:func:`load_config`, :func:`dump_config`) and can be
changed from the command line with ``--set key.path=value`` (:func:`apply_overrides`).
Every invalid input raises :class:`ConfigError` whose message is one line that names
the key path and the allowed values (:func:`format_validation_error`), before anything
is compiled.
"""

from __future__ import annotations

import hashlib
import json
import math
import re
import types
from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import Annotated, Any, Literal, Union, get_args, get_origin

import yaml
from pydantic import BaseModel, BeforeValidator, ConfigDict, Field, ValidationError, model_validator
from pydantic.fields import FieldInfo


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


class FieldError(ValueError):
    """A cross-field check failed; carries the key path it is about.

    Attributes:
        path: dotted key path relative to the model that raised it (e.g. ``pill_radius``
            inside ``geometry``, or ``grid.dx`` at the top level).
        value: the offending value.
    """

    def __init__(self, path: str, value: Any, message: str):
        super().__init__(message)
        self.path = path
        self.value = value

    def __reduce__(self) -> tuple[type[FieldError], tuple[str, Any, str]]:
        """Pickle with all three arguments (a worker process sends its errors back)."""
        return type(self), (self.path, self.value, str(self))


class ConfigError(ValueError):
    """Invalid configuration input; ``str(err)`` is one readable line."""


class _Section(BaseModel):
    """Base of all config sections: unknown keys and silent coercions are errors."""

    model_config = ConfigDict(extra="forbid", strict=False, validate_assignment=True)


class GeometryConfig(_Section):
    """Rotor geometry: regular N-gon plate with N camphor pills (paper Fig. 1, Eqs. (rc), (rj))."""

    n_corners: Int = Field(6, ge=3, le=24, description="N: number of plate corners and pills")
    radius: PositiveFloat = Field(0.5, description="R: circumradius of the plate")
    pill_radius: PositiveFloat = Field(0.1, description="rho: radius of one camphor pill")
    pill_inset: NonNegativeFloat = Field(
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


CALIBRATED_SIGMA = 1.5e-7
"""Noise intensity calibrated at the paper's resolution (dx = delta = 0.025, dt = 1e-4)
on the default scheme (``consistent``): Dw = (sigma/I)^2 = 2.25e-4.

With it the Delta = 2e-5 plateau at t_stop = 3 is the paper's 0.2 (Fig. 7b):
configs/sweeps/science_calibration.yaml measured P = 0.197 [0.108, 0.332] here, from
100 stops per direction at each of seven intensities (data/science_calibration.nc);
fitted with the decision model, the crossing lies at sigma = 1.49e-7, 95 % range
1.36e-7 to 1.63e-7 (docs/statistics.md). The paper-resolution configs
(configs/paper_fig*.yaml, pde_rotor/bases/paper.yaml) carry this value;
tests/test_config.py keeps them equal.
"""

PAPER_SCHEME_SIGMA = 2.0e-8
"""The intensity once calibrated on the ``paper`` scheme, whose lattice torque alone
gives the Delta = 2e-5 plateau 0.18 (so it calibrates the grid more than the noise;
docs/statistics.md). The stored paper-scheme reports (data/calibration.nc,
predictions.nc, predictions_no_flow.nc) hold it; the gallery draws them at it."""


PAPER_STEADY_OMEGA = 176.06
"""Steady angular velocity of the noise-free rotor at the paper's parameters and grid
(docs/model.md: 176.0626; the paper: "~176"): the scale of the rotation against which
:class:`RotorConfig` judges the noise."""


class NoiseConfig(_Section):
    """Torque noise xi(t) of Eq. (eq_motion), <xi(t) xi(s)> = 2 sigma^2 delta(t-s), Eq. (noiseav).

    Integrated by Euler-Maruyama, so results do not depend on dt. The paper's
    sigma = 0.1 taken literally destroys the rotation (docs/model.md); the default is
    no noise, and :data:`CALIBRATED_SIGMA` is the intensity calibrated to the paper.
    """

    sigma: NonNegativeFloat = Field(0.0, description="sigma: torque noise intensity")
    seed: Int | None = Field(
        None, ge=0, description="seed of the numpy Generator (null: drawn and recorded per run)"
    )


class ProtocolConfig(_Section):
    """Stop-and-release operations (paper section "Model", last part)."""

    t_ini: NonNegativeFloat = Field(10.0, description="t_ini: free rotation before the first stop")
    t_stop: NonNegativeFloat = Field(0.5, description="t_stop: duration of one forced stop")
    t_release: PositiveFloat = Field(10.0, description="t_release: free rotation after a stop")
    cycles: Int = Field(100, ge=0, description="M: number of stop-and-release cycles")

    @property
    def period(self) -> float:
        """Cycle period T = t_stop + t_release."""
        return self.t_stop + self.t_release

    @property
    def t_end(self) -> float:
        """End of the protocol, t_ini + M T."""
        return self.t_ini + self.cycles * self.period

    @model_validator(mode="after")
    def _something_to_run(self) -> ProtocolConfig:
        if self.t_end <= 0:
            msg = "nothing to simulate: t_ini + cycles * (t_stop + t_release) = 0 (allowed: > 0)"
            raise FieldError("t_ini", self.t_ini, msg)
        return self


class GridConfig(_Section):
    """Cartesian grid covering the circular domain of radius L (Dirichlet c = v = 0 outside)."""

    domain_radius: PositiveFloat = Field(3.0, description="L: radius of the circular domain")
    dx: PositiveFloat = Field(0.025, description="grid spacing")
    dt: PositiveFloat = Field(1e-4, description="explicit Euler time step")


class NumericsConfig(_Section):
    """How F, G and the torque are discretised on the grid (docs/model.md, "Schemes")."""

    scheme: Literal["paper", "consistent"] = Field(
        "consistent",
        description=(
            "consistent: F and G through an isotropic prefilter and the torque in contour "
            "form, almost free of the grid's lattice torque; paper: point values of F and "
            "G and the area-form torque with central differences, as in the paper "
            "(docs/model.md, Schemes)"
        ),
    )
    integrator: Literal["euler", "heun"] = Field(
        "euler",
        description=(
            "euler: forward Euler, the paper's method (first order in dt); heun: Heun's "
            "second-order method at twice the cost per step (CPU backend only)"
        ),
    )
    plate_filter_kernel: Literal["gaussian", "sharpened"] = Field(
        "gaussian",
        description=(
            "consistent scheme: prefilter of the plate's F, the Gaussian N_eps (changes "
            "the model at order eps^2) or sharpened 2 N_eps - N_(sqrt2 eps) (zero second "
            "moment; docs/model.md, Schemes)"
        ),
    )
    plate_filter_width: float = Field(
        0.7,
        ge=0.25,
        le=2.0,
        description="consistent scheme: width eps of the plate's prefilter, in units of dx",
    )
    pill_filter_kernel: Literal["gaussian", "sharpened"] = Field(
        "sharpened",
        description=(
            "consistent scheme: prefilter of the pills' G (gaussian or sharpened, as "
            "plate_filter_kernel); the sharpened kernel keeps the pills' second moment, "
            "which the asymmetry torque feels (docs/model.md, Schemes)"
        ),
    )
    pill_filter_width: float = Field(
        0.95,
        ge=0.25,
        le=2.0,
        description="consistent scheme: width eps of the pills' prefilter, in units of dx",
    )
    table_refinement: Int = Field(
        8, ge=4, le=32, description="consistent scheme: nodes per dx of the plate's F table"
    )
    contour_nodes: Int = Field(
        32, ge=4, le=256, description="consistent scheme: Gauss-Legendre nodes per plate edge"
    )
    band_nodes: Int = Field(
        6,
        ge=1,
        le=24,
        description="consistent scheme: Gauss nodes across the smoothed plate edge",
    )

    def acting(self) -> dict[str, Any]:
        """The settings that change a result of this scheme (JSON values): every one for
        ``consistent``, only ``scheme`` and ``integrator`` for ``paper``, whose point
        values ignore the prefilter and contour settings."""
        data = self.model_dump(mode="json")
        if self.scheme == "paper":
            return {key: data[key] for key in ("scheme", "integrator")}
        return data


class SolverConfig(_Section):
    """Where the time steps run."""

    backend: Literal["cpu", "gpu", "auto"] = Field(
        "cpu",
        description=(
            "compute backend: cpu (fused numba kernel), gpu (needs the optional gpu extra "
            "and a GPU), auto (gpu when available, else cpu)"
        ),
    )


class OutputConfig(_Section):
    """What a run records (trackers of :mod:`pde_rotor.trackers`) and how often."""

    timeseries_interval: PositiveFloat = Field(
        0.01, description="time between rows of timeseries.nc (t, phi, omega, torque, ...)"
    )
    event_interval: PositiveFloat = Field(
        0.01, description="time between omega samples used to detect the commit after a release"
    )
    commit_fraction: Fraction = Field(
        0.5,
        description=(
            "a released rotor has committed to a direction once |omega| >= commit_fraction * "
            "|omega before the stop|"
        ),
    )
    snapshot_interval: PositiveFloat | None = Field(
        10.0, description="time between field snapshots in snapshots.h5 (null: none)"
    )
    movie: bool = Field(True, description="render movie.mp4 while the run goes")
    movie_interval: PositiveFloat = Field(0.05, description="simulated time between movie frames")
    movie_fps: Int = Field(20, ge=1, le=120, description="frames per second of movie.mp4")
    movie_dpi: Int = Field(100, ge=20, le=600, description="resolution of the movie frames")
    movie_view: PositiveFloat = Field(
        1.5, description="half width of the square shown in the movie (paper Fig. 3: 1.5)"
    )
    progress: bool = Field(True, description="show a progress bar (simulated time, ETA, omega)")
    checkpoint_seconds: PositiveFloat = Field(
        60.0, description="wall-clock seconds between rewrites of timeseries.nc during a run"
    )


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


class RotorConfig(_Section):
    """Complete description of one simulation (all sections have the paper's defaults)."""

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
        if self.geometry.radius + 2 * dx >= self.grid.domain_radius:
            msg = (
                f"leaves no water around the plate (allowed: domain_radius > "
                f"geometry.radius + 2 dx = {self.geometry.radius + 2 * dx:g})"
            )
            raise FieldError("grid.domain_radius", self.grid.domain_radius, msg)
        from .core import X_SATURATION

        n = self.geometry.n_corners
        support = self.geometry.radius + X_SATURATION * smoothing / math.cos(math.pi / n)
        if support > self.grid.domain_radius:
            msg = (
                f"smaller than the reach of the smoothed plate indicator F, R + "
                f"{X_SATURATION:g} delta / cos(pi/N) = {support:.4g} (allowed: domain_radius "
                f">= {support:.4g}, or reduce geometry.smoothing)"
            )
            raise FieldError("grid.domain_radius", self.grid.domain_radius, msg)
        limit = self.dt_limit()
        if self.grid.dt > limit:
            msg = f"above the explicit stability limit (allowed: dt <= {limit:.4g} for this dx)"
            raise FieldError("grid.dt", self.grid.dt, msg)
        dt = self.grid.dt
        kick = math.sqrt(2 * dt) * self.noise.sigma / self.rotor.inertia
        if kick >= PAPER_STEADY_OMEGA:
            limit = PAPER_STEADY_OMEGA * self.rotor.inertia / math.sqrt(2 * dt)
            msg = (
                f"kicks omega by sqrt(2 dt) sigma / I = {kick:.3g} per step, more than the "
                f"steady rotation omega = {PAPER_STEADY_OMEGA:g} at the paper's parameters: "
                f"the rotor would not rotate (allowed: sigma < {limit:.3g} for dt = {dt:g}, "
                f"I = {self.rotor.inertia:g}; calibrated: {CALIBRATED_SIGMA:g})"
            )
            raise FieldError("noise.sigma", self.noise.sigma, msg)
        for key in TIME_KEYS:
            value = self.get(key)
            if value is None:
                continue
            steps = round(value / dt)
            if abs(steps * dt - value) > 1e-9 * max(1.0, value):
                below, above = math.floor(value / dt) * dt, math.ceil(value / dt) * dt
                msg = (
                    f"not an integer multiple of grid.dt = {dt:g} (allowed: k * dt, "
                    f"e.g. {below:.10g} or {above:.10g})"
                )
                raise FieldError(key, value, msg)
        return self

    def get(self, key: str) -> Any:
        """Value at a dotted key path, e.g. ``config.get("protocol.t_stop")``."""
        node: Any = self
        for part in key.split("."):
            node = getattr(node, part)
        return node

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


# ---------------------------------------------------------------------------------------
# YAML in and out
# ---------------------------------------------------------------------------------------

PROVENANCE_KEY = "provenance"
"""Top-level key of a run's config.yaml holding versions and hash; ignored when loading."""


class _Loader(yaml.SafeLoader):
    """Safe YAML loader that reads 1e-4 as a float and refuses duplicate keys."""


_Loader.add_implicit_resolver(
    "tag:yaml.org,2002:float",
    re.compile(r"^[-+]?(?:[0-9][0-9_]*)(?:\.[0-9_]*)?[eE][-+]?[0-9]+$"),
    list("-+0123456789"),
)


def _construct_mapping(loader: _Loader, node: yaml.MappingNode, deep: bool = False) -> dict:
    loader.flatten_mapping(node)
    result: dict = {}
    for key_node, value_node in node.value:
        key = loader.construct_object(key_node, deep=deep)
        if key in result:
            mark = key_node.start_mark
            msg = f"line {mark.line + 1}: duplicate key {key!r}"
            raise ConfigError(msg)
        result[key] = loader.construct_object(value_node, deep=deep)
    return result


_Loader.add_constructor(yaml.resolver.BaseResolver.DEFAULT_MAPPING_TAG, _construct_mapping)


def parse_yaml(text: str, source: str = "<string>") -> Any:
    """Parse YAML text (floats like 1e-4 included); errors become one-line ConfigErrors."""
    try:
        return yaml.load(text, Loader=_Loader)
    except ConfigError as err:
        msg = f"{source}: {err}"
        raise ConfigError(msg) from None
    except yaml.YAMLError as err:
        mark = getattr(err, "problem_mark", None)
        where = f" at line {mark.line + 1}, column {mark.column + 1}" if mark else ""
        problem = getattr(err, "problem", None) or str(err).splitlines()[0]
        msg = f"{source}: invalid YAML{where}: {problem}"
        raise ConfigError(msg) from None


def read_config_data(path: str | Path) -> dict[str, Any]:
    """Read a YAML config file into a plain dict (provenance removed), without validating."""
    path = Path(path)
    if path.is_dir():
        path = path / "config.yaml"
    if not path.exists():
        msg = f"config file {str(path)!r} not found"
        raise ConfigError(msg)
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as err:
        msg = f"config file {str(path)!r} cannot be read: {err}"
        raise ConfigError(msg) from None
    data = parse_yaml(text, source=str(path))
    if data is None:
        msg = (
            f"{path}: the file is empty or holds only comments; a config names at least one "
            "section (e.g. protocol: {t_stop: 1.0}); write {} to run every default (the "
            "paper's grid and 100 stop-and-release cycles)"
        )
        raise ConfigError(msg)
    if not isinstance(data, dict):
        msg = (
            f"{path}: the top level must be a mapping of sections "
            f"({', '.join(RotorConfig.model_fields)}), got {type(data).__name__}"
        )
        raise ConfigError(msg)
    data.pop(PROVENANCE_KEY, None)
    return data


def load_config(path: str | Path, overrides: Iterable[str] = ()) -> RotorConfig:
    """Load and validate a YAML config file, then apply ``--set`` overrides.

    Args:
        path: YAML file (or a run directory holding config.yaml).
        overrides: strings ``key.path=value``; value is parsed as YAML.

    Raises:
        ConfigError: one line naming the file or key path and the allowed values.
    """
    data = read_config_data(path)
    if {"axes", "samples"} & set(data) and not set(RotorConfig.model_fields) & set(data):
        msg = (
            f"{path} is a sweep file (keys {', '.join(data)}), not a run config: "
            "`pde-rotor sweep FILE --dry-run` checks it"
        )
        raise ConfigError(msg)
    data = apply_overrides(data, overrides)
    return validate_config(data)


def validate_config(data: Mapping[str, Any]) -> RotorConfig:
    """Build a :class:`RotorConfig` from a nested mapping; errors become ConfigErrors."""
    try:
        return RotorConfig.model_validate(dict(data))
    except ValidationError as err:
        raise ConfigError(format_validation_error(err)) from None


_KEY_PATH = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*(\.[A-Za-z_][A-Za-z0-9_]*)*$")


def parse_override(text: str) -> tuple[list[str], Any]:
    """Split ``key.path=value`` into the key path and the YAML-parsed value."""
    key, sep, raw = text.partition("=")
    key = key.strip()
    if not sep or not _KEY_PATH.match(key):
        msg = (
            f"--set {text!r}: expected KEY.PATH=VALUE with a dotted key path, "
            "e.g. --set protocol.t_stop=1.5"
        )
        raise ConfigError(msg)
    if raw.strip() == "":
        msg = f"--set {text!r}: missing value after '=' for {key}"
        raise ConfigError(msg)
    value = parse_yaml(raw, source=f"--set {key}")
    return key.split("."), value


def set_key(data: dict[str, Any], key: str, value: Any) -> None:
    """Set the dotted key `key` (``protocol.t_stop``) of a nested mapping, creating sections.

    The one dotted-key setter of the package: overrides, sweep axes and the gallery use it.

    Raises:
        ConfigError: a part of the key path holds a value, not a section (one line).
    """
    path = key.split(".")
    node = data
    for depth, part in enumerate(path[:-1]):
        child = node.get(part)
        if child is None:
            child = node[part] = {}
        if not isinstance(child, dict):
            msg = f"{'.'.join(path[: depth + 1])} is a value, not a section"
            raise ConfigError(msg)
        node = child
    node[path[-1]] = value


def apply_overrides(data: Mapping[str, Any], overrides: Iterable[str]) -> dict[str, Any]:
    """Return a copy of `data` with every ``key.path=value`` override applied (in order).

    Unknown keys are left for the schema to reject, so overrides and files give the
    same error messages.
    """
    result = json.loads(json.dumps(data, default=str)) if data else {}
    for text in overrides:
        path, value = parse_override(text)
        try:
            set_key(result, ".".join(path), value)
        except ConfigError as err:
            raise ConfigError(f"--set {text!r}: {err}") from None
    return result


def dump_config(config: RotorConfig, provenance: Mapping[str, Any] | None = None) -> str:
    """The fully resolved config as YAML (every key), optionally with a provenance block.

    :func:`load_config` reads it back to an equal :class:`RotorConfig`.
    """
    data: dict[str, Any] = {}
    if provenance:
        data[PROVENANCE_KEY] = dict(provenance)
    data.update(config.model_dump(mode="json"))
    return yaml.safe_dump(data, sort_keys=False, default_flow_style=False)


# ---------------------------------------------------------------------------------------
# one-line error messages
# ---------------------------------------------------------------------------------------

_PROBLEMS = {
    "extra_forbidden": "unknown key",
    "float_parsing": "expected a number",
    "float_type": "expected a number",
    "int_parsing": "expected an integer",
    "int_type": "expected an integer",
    "int_from_float": "expected an integer, got a fraction",
    "bool_parsing": "expected true or false",
    "bool_type": "expected true or false",
    "finite_number": "must be finite",
    "literal_error": "not one of the allowed values",
    "model_type": "expected a section (a mapping of keys)",
    "model_attributes_type": "expected a section (a mapping of keys)",
    "dict_type": "expected a section (a mapping of keys)",
    "greater_than": "out of range",
    "greater_than_equal": "out of range",
    "less_than": "out of range",
    "less_than_equal": "out of range",
}


def _model_at(path: tuple[str, ...]) -> type[BaseModel] | None:
    """The section model that the key path leads into (None if it leaves the schema)."""
    model: type[BaseModel] = RotorConfig
    for part in path:
        field = model.model_fields.get(part)
        if field is None:
            return None
        ann = field.annotation
        if not (isinstance(ann, type) and issubclass(ann, BaseModel)):
            return None
        model = ann
    return model


def _unwrap(ann: Any) -> tuple[Any, list[Any], bool]:
    """Split an annotation into (base type, constraint metadata, whether None is allowed)."""
    optional = False
    if get_origin(ann) in (Union, types.UnionType):
        args = [arg for arg in get_args(ann) if arg is not type(None)]
        optional = len(args) < len(get_args(ann))
        ann = args[0]
    metadata: list[Any] = []
    if get_origin(ann) is Annotated:
        ann, *extras = get_args(ann)
        for extra in extras:
            metadata.extend(extra.metadata if isinstance(extra, FieldInfo) else [extra])
    return ann, metadata, optional


def allowed_values(path: tuple[str, ...]) -> str:
    """Describe the allowed values of the field at `path` (e.g. ``float > 0``)."""
    if not path:
        return "sections " + ", ".join(RotorConfig.model_fields)
    parent = _model_at(path[:-1])
    if parent is None or path[-1] not in parent.model_fields:
        return ""
    field = parent.model_fields[path[-1]]
    sub = _model_at(path)
    if sub is not None:
        return "a section with keys " + ", ".join(sub.model_fields)
    base, metadata, optional = _unwrap(field.annotation)
    metadata = [*field.metadata, *metadata]
    if get_origin(base) is Literal:
        kind = "one of " + ", ".join(str(arg) for arg in get_args(base))
    elif base is bool:
        kind = "true or false"
    elif base is int:
        kind = "integer"
    else:
        kind = "number"
    lower = upper = ""
    for meta in metadata:  # annotated_types.Gt(gt=...), Ge, Lt, Le
        if getattr(meta, "gt", None) is not None:
            lower = f"{meta.gt:g} <"
        elif getattr(meta, "ge", None) is not None:
            lower = f"{meta.ge:g} <="
        elif getattr(meta, "lt", None) is not None:
            upper = f"< {meta.lt:g}"
        elif getattr(meta, "le", None) is not None:
            upper = f"<= {meta.le:g}"
    if lower and not upper:
        value, sym = lower.split(" ")
        kind += f", {path[-1]} {sym.replace('<', '>')} {value}"
    elif lower or upper:
        kind += ", " + " ".join(part for part in (lower, path[-1], upper) if part)
    if optional:
        kind += " or null"
    return kind


def _show(value: Any) -> str:
    if isinstance(value, dict):
        return "{...}"
    text = repr(value) if isinstance(value, str) else json.dumps(value, default=str)
    return text if len(text) <= 40 else text[:37] + "..."


def _format_one(error: Mapping[str, Any]) -> str:
    loc = tuple(str(part) for part in error["loc"])
    kind = error["type"]
    ctx = error.get("ctx") or {}
    cause = ctx.get("error")
    if kind == "value_error" and isinstance(cause, FieldError):
        path = ".".join((*loc, cause.path))
        return f"{path} = {_show(cause.value)}: {cause}"
    path = ".".join(loc) if loc else "<top level>"
    if kind == "extra_forbidden":
        parent = _model_at(loc[:-1])
        keys = ", ".join(parent.model_fields) if parent else ""
        where = ".".join(loc[:-1]) or "top level"
        return f"{path}: unknown key (allowed keys in {where}: {keys})"
    value = error.get("input")
    if kind == "value_error":
        message = str(cause) if cause is not None else error["msg"]
    elif isinstance(value, float) and not math.isfinite(value):
        message = "must be a finite number"
    else:
        message = _PROBLEMS.get(kind, error["msg"].lower())
    allowed = allowed_values(loc)
    suffix = f" (allowed: {allowed})" if allowed else ""
    return f"{path} = {_show(value)}: {message}{suffix}"


def format_validation_error(err: ValidationError, limit: int = 3) -> str:
    """One line describing the first `limit` problems of a validation error."""
    errors = err.errors()
    parts = [_format_one(e) for e in errors[:limit]]
    more = len(errors) - limit
    if more > 0:
        parts.append(f"and {more} more")
    return "; ".join(parts)
