"""The sweep file: its schema (:class:`SweepSpec`), shipped bases and ``--set`` overrides.

Every error is a :class:`SweepError` whose text is one line naming the key (and, for an
invalid point, the point), raised before anything runs.
"""

from __future__ import annotations

import copy
import math
import re
from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import Annotated, Any, Literal

import numpy as np
from pydantic import ConfigDict, Field, ValidationError, model_validator

from ..config import (
    ConfigError,
    RotorConfig,
    parse_override,
    read_config_data,
    set_key,
    validate_config,
)
from ..config.stable import StableModel
from .placement import CrowdSpec

BASES_DIR = Path(__file__).resolve().parent.parent / "bases"
"""Base configurations shipped with the package; a sweep file names them by stem."""
SWEEP_KEYS = "name, description, base, set.KEY, axes.KEY, estimator.KEY, crowd.KEY, samples, seed"
"""The keys ``pde-rotor sweep --set`` can change (KEY: a dotted config key)."""


class SweepError(ValueError):
    """Invalid sweep specification or sweep directory; ``str(err)`` is one line."""


class _Strict(StableModel):
    """Base of the sweep file's models: unknown keys are errors; an estimator key added at
    its default enters no run key (:mod:`pde_rotor.config.stable`)."""

    model_config = ConfigDict(extra="forbid")


class RangeSpec(_Strict):
    """Evenly spaced axis values from start to stop inclusive: give ``num`` or ``step``."""

    start: float
    stop: float
    num: int | None = Field(None, ge=1, description="number of values (numpy.linspace)")
    step: float | None = Field(None, gt=0, description="spacing; stop is included if reached")

    @model_validator(mode="after")
    def _one_of(self) -> RangeSpec:
        if (self.num is None) == (self.step is None):
            msg = "a range needs exactly one of num or step"
            raise ValueError(msg)
        if self.step is not None and self.stop < self.start:
            msg = "a range with step needs stop >= start"
            raise ValueError(msg)
        return self

    def values(self) -> list[float]:
        """The axis values, rounded to 12 significant digits (0.1 * 3 -> 0.3)."""
        if self.num is not None:
            raw = np.linspace(self.start, self.stop, self.num)
        else:
            assert self.step is not None
            count = math.floor((self.stop - self.start) / self.step + 1e-9) + 1
            raw = self.start + self.step * np.arange(count)
        return [_clean(float(v)) for v in raw]


def _clean(value: Any) -> Any:
    """Round floats to 12 significant digits so that values from ranges are canonical."""
    if isinstance(value, float) and math.isfinite(value):
        return float(f"{value:.12g}")
    return value


class RestartEstimator(_Strict):
    """Independent restarts from a stored steady rotating state (one stop each)."""

    kind: Literal["restart"] = "restart"
    warmup: float = Field(
        8.0, gt=0, description="noise-free spin-up time to the steady rotating state"
    )
    spinup_omega: float = Field(
        50.0, gt=0, description="|omega0| of the spin-up, signed by the direction wanted"
    )
    commit_fraction: float = Field(
        0.5, gt=0, lt=1, description="committed once |omega| >= this * |omega before the stop|"
    )
    check_interval: float = Field(0.05, gt=0, description="time between commitment checks")
    release_cap: float | None = Field(
        None, gt=0, description="longest release [default: protocol.t_release]"
    )


class BankEstimator(RestartEstimator):
    """Restarts whose stops are shared by every noise intensity (a stop bank).

    The noise acts only while the rotor moves (Eq. (eq_motion); during a stop phi and
    omega are frozen), so the state at the end of a stop depends only on the stop angle,
    the direction before the stop and the noise-free configuration. Runs that differ only
    in their ``noise`` section (a ``noise.sigma`` axis) share one stop, computed once,
    and each is released from it with its own noise. Each stop angle is drawn uniformly
    over one period 2 pi / N, independently for every sample, direction and point
    (seeded from the sweep seed). The values of a noise axis then form a paired design:
    the report compares them with McNemar's exact test.
    """

    kind: Literal["bank"] = "bank"  # type: ignore[assignment]


class ProtocolEstimator(_Strict):
    """The paper's protocol: one run of t_ini and M stop-and-release cycles per sample."""

    kind: Literal["protocol"] = "protocol"


class CollectiveEstimator(_Strict):
    """One run of a bodies config per sample, its collective measures recorded
    (:mod:`pde_rotor.sweep.estimators.collective`, docs/collective.md)."""

    kind: Literal["collective"] = "collective"
    measures: Literal["auto", "ring", "dish"] = Field(
        "auto", description="ring (an annular vessel's default) or dish (any other vessel)"
    )
    record_interval: float = Field(0.5, gt=0, description="time between records")
    settle: float = Field(
        0.0, ge=0, description="records before this time enter no time average (transient)"
    )
    bins: int = Field(24, ge=1, description="bins of g(r) over 0 < r < r_max")
    r_max: float | None = Field(
        None, gt=0, description="range of g(r) [default: the diameter of the centres' disk]"
    )

    def resolve(self, config: RotorConfig) -> Literal["ring", "dish"]:
        """The measures of `config`'s runs: ``measures``, or by the vessel where ``auto``
        (an annulus: ring; the dish: dish).

        Raises:
            ValueError: dish measures in a rectangular tank (g(r) is normalised for a
                disk), or ring measures outside an annulus or dish (one line).
        """
        shape = getattr(config.grid.vessel, "shape", "dish")
        measures = self.measures
        if measures == "auto":
            measures = "ring" if shape == "annulus" else "dish"
        if measures == "dish" and shape != "dish":
            msg = (
                f"estimator.measures = dish needs the circular dish (grid.vessel is a {shape}): "
                "g(r) is normalised for a disk"
            )
            raise ValueError(msg)
        if measures == "ring" and shape == "rectangle":
            msg = "estimator.measures = ring needs an annulus or the dish, not a rectangle"
            raise ValueError(msg)
        return measures


Estimator = Annotated[
    RestartEstimator | BankEstimator | ProtocolEstimator | CollectiveEstimator,
    Field(discriminator="kind"),
]


class SweepSpec(_Strict):
    """A sweep: base configuration, axes, estimator, samples per point and seed."""

    name: str = Field("sweep", description="name shown in the progress bar and the report")
    description: str = ""
    base: str | dict[str, Any] = Field(
        default_factory=dict,
        description="shipped base (coarse, paper), config file (relative to the sweep file) "
        "or mapping",
    )
    set: dict[str, Any] = Field(
        default_factory=dict, description="dotted-key overrides applied to the base"
    )
    axes: dict[str, list[Any] | RangeSpec] = Field(default_factory=dict)
    estimator: Estimator = Field(default_factory=RestartEstimator)
    crowd: CrowdSpec | None = Field(
        None, description="the bodies: N copies of one body, placed by a rule (sweep.placement)"
    )
    samples: int = Field(
        ge=1, description="restart: runs per direction; protocol, collective: runs"
    )
    seed: int = Field(ge=0, description="sweep seed (SeedSequence entropy)")

    @model_validator(mode="after")
    def _axes_ok(self) -> SweepSpec:
        for key, values in self.axes.items():
            if key.startswith("noise.seed"):
                msg = "noise.seed cannot be an axis: seeds are derived from the sweep seed"
                raise ValueError(msg)
            if isinstance(values, list) and not values:
                msg = f"axis {key} has no values"
                raise ValueError(msg)
            if key.startswith("crowd.") and self.crowd is None:
                msg = f"axis {key}: the sweep has no crowd section"
                raise ValueError(msg)
        if self.crowd is not None and self.estimator.kind != "collective":
            msg = "crowd: a crowd is measured by the collective estimator (estimator.kind)"
            raise ValueError(msg)
        return self

    def axis_values(self) -> dict[str, list[Any]]:
        """Every axis with its list of values (ranges expanded), in file order."""
        return {
            key: values.values() if isinstance(values, RangeSpec) else [_clean(v) for v in values]
            for key, values in self.axes.items()
        }


_TYPE_ERRORS = {"list_type", "dict_type", "model_type", "model_attributes_type", "float_type"}
_UNION_TAGS = {
    "list[any]",
    "RangeSpec",
    "restart",
    "bank",
    "protocol",
    "collective",
    "ring",
    "scatter",
    "CrowdSpec",
    "str",
    "dict[str,any]",
}


def spec_error(err: ValidationError) -> str:
    """One line for a sweep schema error; of a union's failures, the most specific one."""
    errors = err.errors()
    specific = [e for e in errors if e["type"] not in _TYPE_ERRORS] or errors
    first = specific[0]
    parts = [str(p) for p in first["loc"]]
    loc = ".".join(p for p in parts if p not in _UNION_TAGS and "[" not in p)
    message = first["msg"].removeprefix("Value error, ")
    if first["type"] == "missing":
        message = f"missing ({sweep_format()})"
    return f"{loc or 'top level'}: {message}"


def shipped_bases() -> list[str]:
    """Names of the base configurations shipped with the package."""
    return sorted(path.stem for path in BASES_DIR.glob("*.yaml"))


def sweep_format() -> str:
    """What a sweep file looks like, for error messages."""
    return (
        f"a sweep file has base (a shipped base: {', '.join(shipped_bases())}; a config file; "
        "or a mapping), axes ({config.key: [values]}), estimator, samples and seed, e.g. "
        "configs/sweeps/fig5_quick.yaml"
    )


def shipped_base(name: str) -> Path:
    """The file of the shipped base `name` (e.g. "paper").

    Raises:
        SweepError: no shipped base has that name.
    """
    path = BASES_DIR / f"{name}.yaml"
    if not path.is_file():
        msg = (
            f"base: {name!r} is not a shipped base (shipped: {', '.join(shipped_bases())}); "
            "a config file is named with its .yaml suffix"
        )
        raise SweepError(msg)
    return path


def read_base(base: str, root: Path | None) -> dict[str, Any]:
    """The config mapping a sweep's ``base`` string names: a shipped base by its name
    (``paper``), else a YAML file, relative to the sweep file's directory `root`."""
    if re.fullmatch(r"[A-Za-z0-9_-]+", base):
        path = shipped_base(base)
    else:
        path = Path(base)
        if not path.is_absolute() and root is not None:
            path = root / path
    try:
        return read_config_data(path)
    except ConfigError as err:
        msg = f"base: {err} (shipped bases are named without a path: {', '.join(shipped_bases())})"
        raise SweepError(msg) from None


def apply_sweep_overrides(data: Mapping[str, Any], overrides: Iterable[str]) -> dict[str, Any]:
    """A copy of the sweep file's mapping with ``--set KEY=VALUE`` overrides applied.

    KEY is one of :data:`SWEEP_KEYS`: a top-level key (``samples=10``, ``base=coarse``),
    ``estimator.KEY``, ``set.CONFIG.KEY`` (an override of the base config) or
    ``axes.CONFIG.KEY`` (the axis values; null removes the axis). VALUE is YAML.

    Raises:
        SweepError: one line naming the override and the keys allowed.
    """
    result = copy.deepcopy(dict(data))
    for text in overrides:
        try:
            path, value = parse_override(text)
        except ConfigError as err:
            raise SweepError(str(err)) from None
        head, rest = path[0], ".".join(path[1:])
        nested = head in ("set", "axes") or (head == "estimator" and len(path) == 2)
        if head == "crowd" and rest:
            crowd = copy.deepcopy(result.get("crowd") or {})
            try:
                set_key(crowd, rest, value)
            except ConfigError as err:
                raise SweepError(f"--set {text!r}: {err}") from None
            result["crowd"] = crowd
            continue
        if rest and nested:
            section = result.get(head) or {}
            if not isinstance(section, dict):
                msg = f"--set {text!r}: {head} of the sweep file is not a mapping"
                raise SweepError(msg)
            section = dict(section)
            if head == "axes" and value is None:
                section.pop(rest, None)
            else:
                section[rest] = value
            result[head] = section
        elif not rest and head in SweepSpec.model_fields and head not in ("set", "axes"):
            result[head] = value
        else:
            hint = f"; the base config's keys: set.{rest}=VALUE" if head == "base" else ""
            msg = f"--set {text!r}: not a key of the sweep file (allowed: {SWEEP_KEYS}){hint}"
            raise SweepError(msg)
    return result


def looks_like_run_config(data: Any) -> bool:
    """Whether `data` is a mapping of run-config sections and nothing a sweep file has."""
    return isinstance(data, dict) and bool(data) and set(data) <= set(RotorConfig.model_fields)


def validate_point(data: Mapping[str, Any], where: str) -> RotorConfig:
    """Validate the config of one point; `where` names the point in the one-line error.

    Raises:
        SweepError: ``sweep point WHERE: KEY = VALUE: problem``, the key said once where
            it is the point's own axis.
    """
    try:
        return validate_config(copy.deepcopy(dict(data)))
    except ConfigError as err:
        message = str(err)
        for coordinate in where.split(", "):  # the point's own key is the problem
            key = coordinate.split(" = ")[0]
            for prefix in (f"{coordinate}:", f"{key}:"):
                if message.startswith(prefix):
                    message = message[len(prefix) :].lstrip()
        raise SweepError(f"sweep point {where}: {message}") from None
