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

* :mod:`.schema`: the pydantic schema :class:`RotorConfig`, which joins the sections and
  checks across them;
* the sections, one module each with its bounds and the constants the paper and the
  calibration fix: :mod:`.geometry` (the paper's rotor), :mod:`.surface` (camphor and
  flow), :mod:`.rotor` (the rotor's dynamics and noise), :mod:`.grid` (grid and dish),
  :mod:`.numerics` (the scheme and the solver), :mod:`.output` (what a run records);
* :mod:`.bodies`: the ``bodies:`` list, the camphor objects on the surface (plates,
  pills, motions), of which the ``geometry:`` rotor is the shorthand for one;
* :mod:`.protocol`: the stop-and-release section, the run's and each body's;
* :mod:`.vessel`: ``grid.vessel``, the annular channel or rectangular tank that replaces
  the dish;
* :mod:`.contact`: ``contact:``, the soft repulsion between bodies and from the walls;
* :mod:`.fields`: the number types, the section base and the bounds they all share;
* :mod:`.stable`: the dumps, hashes and run keys that a key added at its default leaves
  unchanged;
* :mod:`.yaml_io`: YAML in and out, ``--set`` overrides, the dotted-key setter;
* :mod:`.messages`: one-line messages naming the key path and the allowed values;
* :mod:`.errors`: the two errors of configuration input;
* :mod:`.compare`: which physics settings two configs differ in;
* :mod:`.recorded`: how each key reaches the compiled records, declared next to the key.
"""

from __future__ import annotations

from .bodies import (
    FREE_FRICTION,
    BodyConfig,
    BodyLoads,
    DiskPlate,
    FixedAxisMotion,
    FixedMotion,
    FreeMotion,
    NoPlate,
    PillConfig,
    PolygonPlate,
    StartConfig,
    StripPlate,
    TrackMotion,
)
from .compare import physics_differences
from .contact import ContactConfig
from .errors import ConfigError, FieldError
from .fields import X_SATURATION
from .geometry import GeometryConfig
from .grid import DISH_CENTRE, GridConfig
from .messages import allowed_values, format_validation_error, key_text
from .numerics import NumericsConfig, SolverConfig
from .output import OutputConfig
from .protocol import ProtocolConfig
from .rotor import (
    CALIBRATED_SIGMA,
    PAPER_SCHEME_SIGMA,
    PAPER_STEADY_OMEGA,
    NoiseConfig,
    RotorDynamicsConfig,
)
from .schema import SHORTHAND_KEYS, TIME_KEYS, RotorConfig
from .surface import CamphorConfig, FlowConfig
from .yaml_io import (
    PROVENANCE_KEY,
    apply_overrides,
    dump_config,
    load_config,
    parse_override,
    parse_yaml,
    read_config_data,
    set_key,
    validate_config,
)

__all__ = [
    "CALIBRATED_SIGMA",
    "DISH_CENTRE",
    "FREE_FRICTION",
    "PAPER_SCHEME_SIGMA",
    "PAPER_STEADY_OMEGA",
    "PROVENANCE_KEY",
    "SHORTHAND_KEYS",
    "TIME_KEYS",
    "X_SATURATION",
    "BodyConfig",
    "BodyLoads",
    "CamphorConfig",
    "ConfigError",
    "ContactConfig",
    "DiskPlate",
    "FieldError",
    "FixedAxisMotion",
    "FixedMotion",
    "FlowConfig",
    "FreeMotion",
    "GeometryConfig",
    "GridConfig",
    "NoPlate",
    "NoiseConfig",
    "NumericsConfig",
    "OutputConfig",
    "PillConfig",
    "PolygonPlate",
    "ProtocolConfig",
    "RotorConfig",
    "RotorDynamicsConfig",
    "SolverConfig",
    "StartConfig",
    "StripPlate",
    "TrackMotion",
    "allowed_values",
    "apply_overrides",
    "dump_config",
    "format_validation_error",
    "key_text",
    "load_config",
    "parse_override",
    "parse_yaml",
    "physics_differences",
    "read_config_data",
    "set_key",
    "validate_config",
]
