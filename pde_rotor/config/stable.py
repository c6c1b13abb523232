"""Stable dumps: a key added to the schema at its default changes no dump, hash or run key.

A config's hash (:meth:`pde_rotor.config.RotorConfig.config_hash`) and a sweep's run keys
(:func:`pde_rotor.sweep.plan.run_key`) are SHA-256 digests of the config's JSON dump. Were
every key dumped, each new key would change every hash, and the committed sweep stores
(``data/sweeps/``) would no longer resume. Every config section (and every sweep
estimator) is therefore a :class:`StableModel`, whose one serializer leaves out of every
dump (JSON or Python, YAML files, hashes, run keys) each key that

* is not one of :data:`DUMPED_KEYS`, the keys every dump has carried since the first
  stores were committed (frozen: a new key is never added to it),
* has a default (a required key is always dumped),
* is not a variant's tag (a ``Literal`` of one value, such as a plate's ``shape``: the
  dump must say which variant it holds), and
* holds its default.

A key added later therefore needs nothing but its schema field: at its default it is
absent from every dump, and the dump, hash and run keys of every config that leaves it
there are those of before. A config that sets it differs in the dump, as its physics
does. Loading a dump restores the left-out keys at their defaults, so a dump still loads
to an equal config. tests/config/test_stable.py adds a key to the schema and recomputes
the committed hashes and run keys.
"""

from __future__ import annotations

from typing import Any, Literal, get_args, get_origin

from pydantic import BaseModel, SerializerFunctionWrapHandler, model_serializer

DUMPED_KEYS: dict[str, frozenset[str]] = {
    "RotorConfig": frozenset(
        (
            "geometry",
            "camphor",
            "flow",
            "rotor",
            "noise",
            "protocol",
            "grid",
            "numerics",
            "solver",
            "output",
        )
    ),
    "GeometryConfig": frozenset(
        ("n_corners", "radius", "pill_radius", "pill_inset", "asymmetry", "smoothing")
    ),
    "CamphorConfig": frozenset(("diffusion", "evaporation", "supply", "tension_slope")),
    "FlowConfig": frozenset(("enabled", "drag", "bulk_drag", "viscosity")),
    "RotorDynamicsConfig": frozenset(("inertia", "friction", "phi0", "omega0", "torque")),
    "NoiseConfig": frozenset(("sigma", "seed")),
    "ProtocolConfig": frozenset(("t_ini", "t_stop", "t_release", "cycles")),
    "GridConfig": frozenset(("domain_radius", "dx", "dt")),
    "NumericsConfig": frozenset(
        (
            "scheme",
            "integrator",
            "plate_filter_kernel",
            "plate_filter_width",
            "pill_filter_kernel",
            "pill_filter_width",
            "table_refinement",
            "contour_nodes",
            "band_nodes",
        )
    ),
    "SolverConfig": frozenset(("backend", "threads")),
    "OutputConfig": frozenset(
        (
            "timeseries_interval",
            "event_interval",
            "commit_fraction",
            "snapshot_interval",
            "movie",
            "movie_interval",
            "movie_fps",
            "movie_dpi",
            "movie_view",
            "progress",
            "checkpoint_seconds",
        )
    ),
    "BodyConfig": frozenset(
        ("name", "plate", "pills", "motion", "start", "protocol", "noise_sigma")
    ),
    "PolygonPlate": frozenset(("shape", "n_corners", "radius")),
    "DiskPlate": frozenset(("shape", "radius")),
    "StripPlate": frozenset(("shape", "length", "width")),
    "NoPlate": frozenset(("shape",)),
    "PillConfig": frozenset(("x", "y", "radius", "supply")),
    "FixedMotion": frozenset(("kind",)),
    "FixedAxisMotion": frozenset(("kind", "inertia", "friction")),
    "FreeMotion": frozenset(("kind", "mass", "inertia", "friction")),
    "StartConfig": frozenset(("x", "y", "angle", "omega", "velocity")),
    "RangeSpec": frozenset(("start", "stop", "num", "step")),
    "RestartEstimator": frozenset(
        ("kind", "warmup", "spinup_omega", "commit_fraction", "check_interval", "release_cap")
    ),
    "BankEstimator": frozenset(
        ("kind", "warmup", "spinup_omega", "commit_fraction", "check_interval", "release_cap")
    ),
    "ProtocolEstimator": frozenset(("kind",)),
    "SweepSpec": frozenset(
        ("name", "description", "base", "set", "axes", "estimator", "samples", "seed")
    ),
}
"""Keys dumped at any value, by model class: the schema of the first committed stores
(``grid.domain_centre``, ``grid.wall`` and ``bodies`` came later). Frozen: their hashes
and run keys are the stored ones."""


def _is_tag(annotation: Any) -> bool:
    """A ``Literal`` of one value: the tag naming a variant of a union."""
    return get_origin(annotation) is Literal and len(get_args(annotation)) == 1


_LEAVABLE: dict[type, tuple[tuple[str, Any], ...]] = {}
"""(name, default) of the keys a model class leaves out at their defaults, by class."""


def leavable_keys(cls: type[BaseModel]) -> tuple[tuple[str, Any], ...]:
    """(name, default) of the keys of `cls` that its dumps leave out at their defaults:
    those that have a default, are no tag and are not in :data:`DUMPED_KEYS` under the
    name of `cls` or of a class it derives from."""
    found = _LEAVABLE.get(cls)
    if found is None:
        frozen = frozenset().union(*(DUMPED_KEYS.get(k.__name__, ()) for k in cls.__mro__))
        found = tuple(
            (name, field.get_default(call_default_factory=True))
            for name, field in cls.model_fields.items()
            if name not in frozen and not field.is_required() and not _is_tag(field.annotation)
        )
        _LEAVABLE[cls] = found
    return found


class StableModel(BaseModel):
    """A model whose dumps leave out the keys added since :data:`DUMPED_KEYS` while they
    hold their defaults (the module docstring)."""

    @model_serializer(mode="wrap")
    def _stable_dump(self, handler: SerializerFunctionWrapHandler) -> dict[str, Any]:
        """The dump of every key, less the new keys at their defaults."""
        data = handler(self)
        for name, default in leavable_keys(type(self)):
            if name in data and getattr(self, name) == default:
                del data[name]
        return data
