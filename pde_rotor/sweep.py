"""Parameter sweeps of inversion statistics on dask.distributed: resumable, reproducible.

A sweep is a YAML file (:class:`SweepSpec`)::

    name: fig5_quick
    base: coarse                    # a shipped base (coarse, paper), a config file
                                    # (relative to this file) or an inline mapping
    set: {noise.sigma: 2.0e-6}      # optional dotted-key overrides of the base
    axes:                           # any dotted config key: a list or a range
      protocol.t_stop: {start: 0.5, stop: 3.0, step: 0.5}
      geometry.asymmetry: [0.0, 2.0e-5, 1.0e-4]
    estimator: {kind: restart}      # or {kind: bank}, or {kind: protocol} (M cycles per run)
    samples: 40                     # restart: stops per direction; protocol: runs per point
    seed: 20200501

Every combination of axis values is a *point*; every point has ``samples`` *runs* (the
restart estimator: ``samples`` runs from CCW and ``samples`` from CW rotation). A run is
fully described by its resolved configuration, whose ``noise.seed`` is derived with
numpy's SeedSequence from (sweep seed, the point's coordinate values, sample index,
direction): results depend neither on the scheduling order nor on the number of workers.
Each finished run is written to ``SWEEP_DIR/runs/<hash>.json``, named by a hash of its
resolved configuration and estimator settings, atomically (temporary file +
:func:`os.replace`); rerunning a sweep skips runs whose file exists, so a sweep killed at
any moment loses only the runs in flight. :func:`report` gathers the files into an
xarray Dataset (coordinates = axes; P with its 95 % interval, counts, mean |omega|),
written as NetCDF.

Estimators (see :mod:`pde_rotor.stats` and docs/statistics.md):

* ``protocol``: the paper's stop-and-release protocol, t_ini then M = protocol.cycles
  cycles in one run; the direction is the sign of omega just before each stop and at
  the end; P = inversions / M.
* ``restart``: independent single stops. Each worker process spins the rotor up once per
  (point configuration without protocol and noise, direction), noise-free from
  omega0 = +/- spinup_omega for ``warmup`` time units, and keeps that steady rotating
  state in memory. A sample branches from it, runs a random number of steps so that the
  stop angle is uniform over one period 2 pi / N of the hexagon (pi/3), stops for
  protocol.t_stop and is released until it has committed to a direction:
  |omega| >= commit_fraction |omega before the stop|, checked every check_interval, or
  at most release_cap (default protocol.t_release). P(inv | CCW) and P(inv | CW) are
  combined with the stationary weights of the two-state chain.
* ``bank``: restarts whose stop is shared by every noise intensity. The noise acts only
  on the moving rotor, so the end-of-stop state depends on the stop angle, the
  direction and the noise-free configuration alone; runs that differ only in their
  ``noise`` section (a ``noise.sigma`` axis) form one group (:func:`stop_group`),
  submitted as one task: the stop is computed once, noise-free, at the stop angle
  :func:`bank_offset` of the sample (a golden-ratio sequence, evenly covering the
  period), and each run is released from it with its own noise. Same statistics as
  ``restart``; with k noise intensities it costs one stop and k releases per sample
  instead of k stops and k releases.
"""

from __future__ import annotations

import copy
import hashlib
import itertools
import json
import math
import os
import re
import signal
import tempfile
import threading
import time
from collections import OrderedDict
from collections.abc import Iterable, Iterator, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Annotated, Any, Literal

import numpy as np
import xarray as xr
import yaml
from pydantic import BaseModel, ConfigDict, Field, ValidationError, model_validator

from .config import (
    ConfigError,
    RotorConfig,
    parse_override,
    parse_yaml,
    read_config_data,
    validate_config,
)
from .simulation import Simulation
from .stats import (
    CCW,
    CONFIDENCE,
    CW,
    DirectionCounts,
    Proportion,
    protocol_counts,
    restart_counts,
    two_state_chain,
)

RUNS_DIR = "runs"
"""Sub-directory of a sweep directory holding one JSON file per finished run."""
SPEC_FILE = "sweep.yaml"
"""Copy of the sweep specification (base inlined) kept in the sweep directory."""
REPORT_FILE = "report.nc"
"""NetCDF file written by :func:`report`."""
SCHEMA_VERSION = 1
"""Version of the run-file layout; part of every run hash."""
BASES_DIR = Path(__file__).resolve().parent / "bases"
"""Base configurations shipped with the package; a sweep file names them by stem."""
SWEEP_KEYS = "name, description, base, set.KEY, axes.KEY, estimator.KEY, samples, seed"
"""The keys ``pde-rotor sweep --set`` can change (KEY: a dotted config key)."""


class SweepError(ValueError):
    """Invalid sweep specification or sweep directory; ``str(err)`` is one line."""


# ---------------------------------------------------------------------------------------
# schema
# ---------------------------------------------------------------------------------------


class _Strict(BaseModel):
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
    and each is released from it with its own noise. The stop angle of sample i is the
    golden-ratio sequence frac(1/2 + i (sqrt(5) - 1) / 2) of one period 2 pi / N, so
    every prefix of samples covers the period evenly.
    """

    kind: Literal["bank"] = "bank"  # type: ignore[assignment]


class ProtocolEstimator(_Strict):
    """The paper's protocol: one run of t_ini and M stop-and-release cycles per sample."""

    kind: Literal["protocol"] = "protocol"


Estimator = Annotated[
    RestartEstimator | BankEstimator | ProtocolEstimator, Field(discriminator="kind")
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
    samples: int = Field(ge=1, description="restart: runs per direction; protocol: runs")
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
        return self

    def axis_values(self) -> dict[str, list[Any]]:
        """Every axis with its list of values (ranges expanded), in file order."""
        return {
            key: values.values() if isinstance(values, RangeSpec) else [_clean(v) for v in values]
            for key, values in self.axes.items()
        }


_TYPE_ERRORS = {"list_type", "dict_type", "model_type", "model_attributes_type", "float_type"}
_UNION_TAGS = {"list[any]", "RangeSpec", "restart", "bank", "protocol", "str", "dict[str,any]"}


def _spec_error(err: ValidationError) -> str:
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


def _read_base(base: str, root: Path | None) -> dict[str, Any]:
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


def _looks_like_run_config(data: Any) -> bool:
    """Whether `data` is a mapping of run-config sections and nothing a sweep file has."""
    return isinstance(data, dict) and bool(data) and set(data) <= set(RotorConfig.model_fields)


def _set_key(data: dict[str, Any], key: str, value: Any) -> None:
    """Set a dotted key in a nested dict, creating sections as needed."""
    parts = key.split(".")
    node = data
    for part in parts[:-1]:
        child = node.setdefault(part, {})
        if not isinstance(child, dict):
            msg = f"{key}: {part} is a value, not a section"
            raise SweepError(msg)
        node = child
    node[parts[-1]] = value


def _validate(data: Mapping[str, Any], where: str) -> RotorConfig:
    try:
        return validate_config(copy.deepcopy(dict(data)))
    except ConfigError as err:
        raise SweepError(f"{where}: {err}") from None


@dataclass(frozen=True)
class Run:
    """One run of a sweep (picklable, sent to a worker).

    Attributes:
        point: index of the point along each axis.
        coords: the point's axis values by dotted key.
        sample: sample index at the point.
        direction: +1 (CCW) or -1 (CW) for restarts, 0 for protocol runs.
        config: resolved configuration (JSON mapping, noise.seed set).
        estimator: estimator settings (JSON mapping).
        key: hash of config, estimator, direction and sample; the run file's name.
    """

    point: tuple[int, ...]
    coords: dict[str, Any]
    sample: int
    direction: int
    config: dict[str, Any]
    estimator: dict[str, Any]
    key: str


@dataclass
class Sweep:
    """A validated sweep: the specification, the base config and the plan of runs.

    Attributes:
        spec: the specification with ``base`` inlined as a mapping.
        base: the base configuration mapping (``set`` applied).
        axes: axis values by dotted key.
    """

    spec: SweepSpec
    base: dict[str, Any]
    axes: dict[str, list[Any]]
    _runs: list[Run] | None = field(default=None, repr=False)

    @classmethod
    def from_spec(cls, spec: SweepSpec, root: Path | None = None) -> Sweep:
        """Resolve the base (file or mapping), apply ``set`` and validate every point.

        Raises:
            SweepError: one line naming the problem (unknown key, invalid value, file).
        """
        if isinstance(spec.base, str):
            base = _read_base(spec.base, root)
        else:
            base = copy.deepcopy(spec.base)
        for key, value in spec.set.items():
            _set_key(base, key, value)
        _validate(base, "base")
        inlined = spec.model_copy(update={"base": base, "set": {}})
        sweep = cls(spec=inlined, base=base, axes=spec.axis_values())
        sweep.runs()  # validates every point
        return sweep

    @classmethod
    def load(cls, path: str | Path, overrides: Iterable[str] = ()) -> Sweep:
        """Read and validate a sweep YAML file (a sweep directory: its sweep.yaml).

        Args:
            path: the sweep file or directory.
            overrides: ``KEY=VALUE`` changes of the file's keys
                (:func:`apply_sweep_overrides`).
        """
        path = Path(path)
        if path.is_dir():
            path = path / SPEC_FILE
        try:
            data = parse_yaml(path.read_text(encoding="utf-8"), source=str(path))
        except OSError as err:
            msg = f"sweep file {str(path)!r} cannot be read: {err}"
            raise SweepError(msg) from None
        except ConfigError as err:
            raise SweepError(str(err)) from None
        if _looks_like_run_config(data):
            msg = (
                f"{path} is a run config (sections {', '.join(data)}), not a sweep file: "
                f"{sweep_format()}; `pde-rotor run` runs a config"
            )
            raise SweepError(msg)
        if not isinstance(data, dict):
            msg = f"{path}: expected a sweep file, got {type(data).__name__}: {sweep_format()}"
            raise SweepError(msg)
        data = apply_sweep_overrides(data, overrides)
        try:
            spec = SweepSpec.model_validate(data)
        except ValidationError as err:
            raise SweepError(f"{path}: {_spec_error(err)}") from None
        return cls.from_spec(spec, root=path.parent)

    @property
    def shape(self) -> tuple[int, ...]:
        """Number of values along each axis."""
        return tuple(len(v) for v in self.axes.values())

    def points(self) -> Iterator[tuple[tuple[int, ...], dict[str, Any]]]:
        """(index tuple, coordinates) of every point, in C order of the axes."""
        keys = list(self.axes)
        ranges = [range(n) for n in self.shape]
        for index in itertools.product(*ranges):
            yield index, {k: self.axes[k][i] for k, i in zip(keys, index, strict=True)}

    def directions(self) -> tuple[int, ...]:
        """Directions sampled per point: (CCW, CW) for restarts, (0,) for protocol runs."""
        return (0,) if self.spec.estimator.kind == "protocol" else (CCW, CW)

    def runs(self) -> list[Run]:
        """Every run of the sweep (validated, seeds derived, hashes computed)."""
        if self._runs is not None:
            return self._runs
        estimator = self.spec.estimator.model_dump(mode="json")
        runs: list[Run] = []
        for index, coords in self.points():
            data = copy.deepcopy(self.base)
            for key, value in coords.items():
                _set_key(data, key, value)
            where = ", ".join(f"{k} = {v}" for k, v in coords.items()) or "base"
            config = _validate(data, where)
            if self.spec.estimator.kind != "protocol":
                _check_restart(config, self.spec.estimator, where)
            for direction in self.directions():
                for sample in range(self.spec.samples):
                    seed = run_seed(self.spec.seed, coords, sample, direction)
                    resolved = config.model_copy(deep=True)
                    resolved.noise.seed = seed
                    cfg = _physics(resolved)
                    key = run_key(cfg, estimator, direction, sample)
                    runs.append(Run(index, coords, sample, direction, cfg, estimator, key))
        self._runs = runs
        return runs


def _physics(config: RotorConfig) -> dict[str, Any]:
    """The config as a JSON mapping without the output section (which changes no result)."""
    data = config.model_dump(mode="json")
    data.pop("output", None)
    return data


def _check_restart(config: RotorConfig, estimator: RestartEstimator, where: str) -> None:
    dt = config.grid.dt
    for name, value in (
        ("estimator.warmup", estimator.warmup),
        ("estimator.check_interval", estimator.check_interval),
        ("estimator.release_cap", estimator.release_cap),
    ):
        if value is not None and abs(round(value / dt) * dt - value) > 1e-9 * max(1.0, value):
            msg = f"{where}: {name} = {value:g} is not an integer multiple of grid.dt = {dt:g}"
            raise SweepError(msg)


def run_seed(sweep_seed: int, coords: Mapping[str, Any], sample: int, direction: int) -> int:
    """Noise seed of one run: SeedSequence(sweep seed, coordinates, sample, direction).

    The coordinates enter through the SHA-256 of their canonical JSON (keys sorted), so
    the seed of a run depends only on its own axis values, not on the order or number of
    other points; adding values to an axis leaves the seeds of existing points unchanged.
    """
    text = json.dumps(dict(coords), sort_keys=True, separators=(",", ":"), default=str)
    digest = hashlib.sha256(text.encode()).digest()
    words = np.frombuffer(digest, dtype=np.uint32).tolist()
    seq = np.random.SeedSequence([sweep_seed, *words, sample, direction + 1])
    return int(seq.generate_state(1, np.uint64)[0] >> np.uint64(1))


def run_key(
    config: Mapping[str, Any], estimator: Mapping[str, Any], direction: int, sample: int
) -> str:
    """Hash naming a run's file: SHA-256 of its resolved config and estimator settings."""
    payload = {
        "schema": SCHEMA_VERSION,
        "config": config,
        "estimator": estimator,
        "direction": direction,
        "sample": sample,
    }
    text = json.dumps(payload, sort_keys=True, separators=(",", ":"))
    return hashlib.sha256(text.encode()).hexdigest()[:24]


# ---------------------------------------------------------------------------------------
# one run (executed on a worker)
# ---------------------------------------------------------------------------------------

_WARM: OrderedDict[str, Simulation] = OrderedDict()
"""Steady rotating states of this process, by hash of the spin-up configuration."""
_WARM_MAX = 8


def _spin_up(
    config: RotorConfig, estimator: RestartEstimator, direction: int
) -> tuple[str, dict[str, Any]]:
    """The spin-up configuration of `config` in `direction` and its hash (the cache key)."""
    data = config.model_dump(mode="json")
    data["protocol"].update(t_ini=estimator.warmup, cycles=0)
    data["noise"].update(sigma=0.0, seed=0)
    data["rotor"]["omega0"] = direction * estimator.spinup_omega
    data.pop("output", None)
    return hashlib.sha256(json.dumps(data, sort_keys=True).encode()).hexdigest(), data


def warm_key(config: RotorConfig, estimator: RestartEstimator, direction: int) -> str:
    """Runs with equal keys share the spin-up of :func:`warm_state` (in one process)."""
    return _spin_up(config, estimator, direction)[0]


def warm_state(config: RotorConfig, estimator: RestartEstimator, direction: int) -> Simulation:
    """The steady rotating state for `config` and `direction`, computed once per process.

    The spin-up is noise-free and starts from omega0 = direction * spinup_omega, so the
    state is the same in every process whatever ran there before.

    Raises:
        RuntimeError: the rotor does not rotate in the requested direction after warmup.
    """
    key, data = _spin_up(config, estimator, direction)
    if key in _WARM:
        _WARM.move_to_end(key)
        return _WARM[key]
    sim = Simulation(RotorConfig.model_validate(data))
    sim.run(estimator.warmup)
    if np.sign(sim.rotor.omega) != direction:
        msg = (
            f"spin-up from omega0 = {direction * estimator.spinup_omega:g} ended with omega = "
            f"{sim.rotor.omega:.4g} at t = {sim.t:g}, not in the requested direction; "
            "raise estimator.spinup_omega"
        )
        raise RuntimeError(msg)
    _WARM[key] = sim
    while len(_WARM) > _WARM_MAX:
        _WARM.popitem(last=False)
    return sim


def _warm_group(run: Run) -> str:
    """Runs with equal value share the spin-up state (all but protocol and noise agree)."""
    data = {k: v for k, v in run.config.items() if k not in ("protocol", "noise")}
    return json.dumps([data, run.direction], sort_keys=True)


def _steps(duration: float, dt: float) -> int:
    return round(duration / dt)


GOLDEN = (math.sqrt(5.0) - 1.0) / 2.0
"""Increment of the stop-angle sequence of the bank estimator (in periods)."""


def bank_offset(sample: int, n_period: int) -> int:
    """Extra steps before the stop of bank sample `sample`: its stop angle, in steps.

    frac(1/2 + sample * GOLDEN) of the period (n_period steps): the first n samples
    leave no gap wider than about 2.6 / n of the period (three-gap theorem).
    """
    return int(((0.5 + sample * GOLDEN) % 1.0) * n_period)


@dataclass(frozen=True)
class _Timing:
    """Step counts of one restart: steps before the stop, stop, release cap, check."""

    n0: int
    n_stop: int
    n_cap: int
    n_check: int

    @classmethod
    def of(cls, config: RotorConfig, estimator: RestartEstimator, n0: int) -> _Timing:
        dt = config.grid.dt
        cap = estimator.release_cap
        cap = cap if cap is not None else config.protocol.t_release
        return cls(
            n0,
            _steps(config.protocol.t_stop, dt),
            _steps(cap, dt),
            max(1, _steps(estimator.check_interval, dt)),
        )

    def protocol(self, config: RotorConfig) -> RotorConfig:
        """`config` with the one-stop protocol of this restart."""
        dt = config.grid.dt
        data = config.model_dump(mode="json")
        data["protocol"].update(
            t_ini=self.n0 * dt, t_stop=self.n_stop * dt, t_release=self.n_cap * dt, cycles=1
        )
        return RotorConfig.model_validate(data)


def _period_steps(config: RotorConfig, warm: Simulation) -> int:
    """Steps per period 2 pi / N of the stop angle at the warm state's angular velocity."""
    period = 2 * math.pi / config.geometry.n_corners
    return max(1, round(period / (abs(warm.rotor.omega) * config.grid.dt)))


def _release(
    sim: Simulation, timing: _Timing, estimator: RestartEstimator, omega_before: float
) -> dict:
    """Release `sim` (at the end of its stop) until its direction is committed."""
    dt = sim.config.grid.dt
    threshold = estimator.commit_fraction * abs(omega_before)
    n = 0
    committed = False
    while n < timing.n_cap:
        n = min(n + timing.n_check, timing.n_cap)
        sim.run((timing.n0 + timing.n_stop + n) * dt)
        if abs(sim.rotor.omega) >= threshold:
            committed = True
            break
    before = int(np.sign(omega_before))
    after = int(np.sign(sim.rotor.omega)) if committed else 0
    return {
        "direction_before": before,
        "direction_after": after,
        "inverted": bool(after == -before),
        "committed": committed,
        "omega_before": float(omega_before),
        "omega_end": float(sim.rotor.omega),
        "t_commit": float(n * dt) if committed else math.nan,
    }


def run_restart(config: RotorConfig, estimator: RestartEstimator, direction: int) -> dict:
    """One independent stop from the steady state rotating in `direction`.

    The Generator seeded with ``config.noise.seed`` first draws the number of extra
    steps before the stop (uniform over one period 2 pi / N of the stop angle), then
    drives the noise of the branch.

    Returns:
        direction_before/after (+1, -1; after 0 if not committed), inverted, committed,
        omega_before (omega just before the stop), phi_stop (stop angle modulo 2 pi / N),
        extra_steps, t_commit (release time until commitment).
    """
    warm = warm_state(config, estimator, direction)
    dt = config.grid.dt
    rng = np.random.default_rng(config.noise.seed)
    extra = int(rng.integers(0, _period_steps(config, warm)))
    timing = _Timing.of(config, estimator, _steps(warm.t, dt) + extra)
    sim = warm.branch(timing.protocol(config), rng=rng)
    sim.run(timing.n0 * dt)
    omega_before, phi_stop = sim.rotor.omega, sim.rotor.phi
    sim.run((timing.n0 + timing.n_stop) * dt)
    result = _release(sim, timing, estimator, omega_before)
    period = 2 * math.pi / config.geometry.n_corners
    return {**result, "phi_stop": float(phi_stop % period), "extra_steps": extra}


def run_bank(
    configs: Sequence[RotorConfig], estimator: BankEstimator, direction: int, sample: int
) -> list[dict]:
    """One stop shared by `configs` (equal but for ``noise``), released once per config.

    The stop angle is sample's point of the golden-ratio sequence over one period
    2 pi / N; the steps before and during the stop are noise-free (during the stop the
    noise has no effect, Eq. (eq_motion)). Each release branches from the end-of-stop
    state with its config's noise, seeded from its ``noise.seed``.

    Returns:
        One result per config, as :func:`run_restart`, with ``torque_end``: the torque on
        the stopped plate at the end of the stop.
    """
    base = configs[0]
    warm = warm_state(base, estimator, direction)
    dt = base.grid.dt
    extra = bank_offset(sample, _period_steps(base, warm))
    timing = _Timing.of(base, estimator, _steps(warm.t, dt) + extra)
    quiet = timing.protocol(base)
    quiet.noise.sigma = 0.0
    stop = warm.branch(quiet)
    stop.run(timing.n0 * dt)
    omega_before, phi_stop = stop.rotor.omega, stop.rotor.phi
    stop.run((timing.n0 + timing.n_stop) * dt)
    torque_end = float(stop.rotor.torque)
    period = 2 * math.pi / base.geometry.n_corners
    results = []
    for config in configs:
        sim = stop.branch(timing.protocol(config))
        result = _release(sim, timing, estimator, omega_before)
        results.append(
            {
                **result,
                "phi_stop": float(phi_stop % period),
                "extra_steps": extra,
                "torque_end": torque_end,
            }
        )
    return results


def run_protocol(config: RotorConfig) -> dict:
    """One run of the paper's protocol; omega just before each stop and at the end.

    Returns:
        omegas (M + 1 values), and the inversion counts of :func:`protocol_counts`.
    """
    sim = Simulation(config)
    dt = config.grid.dt
    p = config.protocol
    n_ini, n_period = _steps(p.t_ini, dt), _steps(p.t_stop + p.t_release, dt)
    omegas = []
    for m in range(p.cycles + 1):
        sim.run((n_ini + m * n_period) * dt)
        omegas.append(float(sim.rotor.omega))
    counts = protocol_counts(omegas)
    return {
        "omegas": omegas,
        "inversions_ccw": counts.ccw.k,
        "n_ccw": counts.ccw.n,
        "inversions_cw": counts.cw.k,
        "n_cw": counts.cw.n,
    }


def _content(run: Run, result: dict, wall_time: float) -> dict[str, Any]:
    return {
        "key": run.key,
        "schema": SCHEMA_VERSION,
        "coords": run.coords,
        "sample": run.sample,
        "direction": run.direction,
        "estimator": run.estimator,
        "config": run.config,
        "result": result,
        "wall_time": wall_time,
    }


def execute(run: Run) -> dict[str, Any]:
    """Run one sweep run and return its file content (config, settings, result, timing)."""
    return execute_group([run])[0]


def execute_group(runs: Sequence[Run]) -> list[dict[str, Any]]:
    """Run a group of runs (one stop shared for the bank estimator); their file contents.

    The wall time of a bank group is split evenly among its runs.
    """
    start = time.perf_counter()
    kind = runs[0].estimator["kind"]
    configs = [RotorConfig.model_validate(run.config) for run in runs]
    if kind == "bank":
        estimator = BankEstimator.model_validate(runs[0].estimator)
        results = run_bank(configs, estimator, runs[0].direction, runs[0].sample)
    elif kind == "restart":
        estimator = RestartEstimator.model_validate(runs[0].estimator)
        pairs = zip(configs, runs, strict=True)
        results = [run_restart(c, estimator, r.direction) for c, r in pairs]
    else:
        results = [run_protocol(c) for c in configs]
    share = (time.perf_counter() - start) / len(runs)
    return [_content(run, result, share) for run, result in zip(runs, results, strict=True)]


def stop_group(run: Run) -> str:
    """Runs with equal value share one stop under the bank estimator (each run its own
    group under the other estimators)."""
    if run.estimator["kind"] != "bank":
        return run.key
    data = {k: v for k, v in run.config.items() if k != "noise"}
    return json.dumps([data, run.direction, run.sample], sort_keys=True)


# ---------------------------------------------------------------------------------------
# the store of finished runs
# ---------------------------------------------------------------------------------------


def _read_umask() -> int:
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


_UMASK = _read_umask()
"""The process umask, read once at import (reading it means setting it)."""


def _publish(tmp: str | Path, path: str | Path) -> None:
    """Give the finished temporary file the usual permissions and rename it atomically.

    (mkstemp creates files readable by their owner only.)
    """
    os.chmod(tmp, 0o666 & ~_UMASK)
    os.replace(tmp, path)


def write_json_atomic(path: Path, content: Mapping[str, Any]) -> None:
    """Write JSON to `path` via a temporary file in the same directory and os.replace."""
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".part")
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as handle:
            json.dump(content, handle, indent=1, allow_nan=True)
            handle.flush()
            os.fsync(handle.fileno())
        _publish(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


def run_path(sweep_dir: Path, key: str) -> Path:
    """File of the run with hash `key`."""
    return Path(sweep_dir) / RUNS_DIR / f"{key}.json"


def load_run(path: Path) -> dict[str, Any] | None:
    """Content of a run file, or None if it is missing or unreadable."""
    try:
        return json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return None


def finished(sweep_dir: Path, runs: Sequence[Run]) -> set[str]:
    """Keys of the runs whose result file exists (and is complete JSON with that key)."""
    done = set()
    for run in runs:
        content = load_run(run_path(sweep_dir, run.key))
        if content is not None and content.get("key") == run.key:
            done.add(run.key)
    return done


# ---------------------------------------------------------------------------------------
# execution on dask.distributed
# ---------------------------------------------------------------------------------------


@dataclass
class SweepOutcome:
    """What :func:`run_sweep` did.

    Attributes:
        total: runs of the sweep.
        skipped: runs already finished before this call.
        computed: runs computed by this call.
        failed: (run key, error message) of runs that raised.
        sweep_dir: where results are.
    """

    total: int
    skipped: int
    computed: int
    failed: list[tuple[str, str]]
    sweep_dir: Path


def usable_cores() -> int:
    """CPU cores this process may run on (all cores where affinity is unknown)."""
    affinity = getattr(os, "sched_getaffinity", None)
    return len(affinity(0)) if affinity is not None else os.cpu_count() or 1


def _start_client(scheduler: str | None, workers: int | None) -> tuple[Any, Any]:
    """A dask Client on the given scheduler, or on a new LocalCluster of processes."""
    from distributed import Client, LocalCluster

    if scheduler:
        return Client(scheduler), None
    n = workers or usable_cores()
    # Ctrl-C in a terminal signals the whole process group. The worker processes inherit
    # an ignored SIGINT (an ignored signal stays ignored across exec, and Python then
    # installs no KeyboardInterrupt handler), so only this process handles it: it closes
    # the cluster, which ends the workers quietly instead of with a traceback each.
    ignore = threading.current_thread() is threading.main_thread()
    previous = signal.signal(signal.SIGINT, signal.SIG_IGN) if ignore else None
    try:
        cluster = LocalCluster(
            n_workers=n,
            threads_per_worker=1,
            processes=True,
            dashboard_address=":0",  # any free port: several sweeps may run side by side
            silence_logs=40,
        )
    finally:
        if ignore:
            signal.signal(signal.SIGINT, previous if previous is not None else signal.SIG_DFL)
    return Client(cluster), cluster


def prepare(sweep: Sweep, sweep_dir: str | Path) -> Path:
    """Create the sweep directory and write the specification (base inlined) into it.

    Raises:
        SweepError: the directory holds a sweep with other base, estimator or seed (the
            runs would not be those of this sweep).
    """
    sweep_dir = Path(sweep_dir)
    (sweep_dir / RUNS_DIR).mkdir(parents=True, exist_ok=True)
    text = yaml.safe_dump(sweep.spec.model_dump(mode="json"), sort_keys=False)
    spec_path = sweep_dir / SPEC_FILE
    fd, tmp = tempfile.mkstemp(dir=sweep_dir, prefix=".sweep.", suffix=".part")
    with os.fdopen(fd, "w", encoding="utf-8") as handle:
        handle.write(text)
    _publish(tmp, spec_path)
    return sweep_dir


def run_sweep(
    sweep: Sweep | str | Path,
    sweep_dir: str | Path,
    *,
    scheduler: str | None = None,
    workers: int | None = None,
    progress: bool = True,
) -> SweepOutcome:
    """Run every unfinished run of a sweep on dask.distributed and store its result.

    Args:
        sweep: a :class:`Sweep` or the path of a sweep YAML file.
        sweep_dir: directory of the results (created; reused to resume).
        scheduler: address of a running dask scheduler (e.g. of a dask-jobqueue
            SLURMCluster); None starts a LocalCluster of worker processes.
        workers: number of LocalCluster workers (default: the usable CPU cores).
        progress: show a tqdm bar counting finished runs.

    Returns:
        Counts of skipped, computed and failed runs. Runs that raised are not stored
        and are retried by the next call.
    """
    if not isinstance(sweep, Sweep):
        sweep = Sweep.load(sweep)
    sweep_dir = prepare(sweep, sweep_dir)
    runs = sweep.runs()
    done = finished(sweep_dir, runs)
    todo = [run for run in runs if run.key not in done]
    # submit the runs of one spin-up state together, so that workers reuse warm states
    todo.sort(key=lambda r: (_warm_group(r), r.point, r.sample))
    groups: dict[str, list[Run]] = {}
    for run in todo:
        groups.setdefault(stop_group(run), []).append(run)
    failed: list[tuple[str, str]] = []
    computed = 0
    if todo:
        from distributed import as_completed
        from tqdm.auto import tqdm

        client, cluster = _start_client(scheduler, workers)
        bar = tqdm(
            total=len(runs),
            initial=len(done),
            unit="run",
            desc=sweep.spec.name,
            disable=not progress,
            dynamic_ncols=True,
        )
        try:
            futures = [
                client.submit(execute_group, group, key=f"runs-{group[0].key}")
                for group in groups.values()
            ]
            by_key = {f.key: g for f, g in zip(futures, groups.values(), strict=True)}
            for future in as_completed(futures):
                group = by_key[future.key]
                try:
                    contents = future.result()
                except Exception as err:
                    failed.extend((run.key, f"{type(err).__name__}: {err}") for run in group)
                    bar.set_postfix(failed=len(failed))
                    continue
                finally:
                    future.release()
                for run, content in zip(group, contents, strict=True):
                    write_json_atomic(run_path(sweep_dir, run.key), content)
                computed += len(group)
                bar.update(len(group))
        finally:
            bar.close()
            client.close()
            if cluster is not None:
                cluster.close()
    return SweepOutcome(len(runs), len(done), computed, failed, sweep_dir)


# ---------------------------------------------------------------------------------------
# report
# ---------------------------------------------------------------------------------------


def _dim_names(keys: Sequence[str]) -> dict[str, str]:
    """Short dimension names: the last part of each dotted key unless two collide."""
    last = [k.rsplit(".", 1)[-1] for k in keys]
    return {
        k: (s if last.count(s) == 1 else k.replace(".", "_"))
        for k, s in zip(keys, last, strict=True)
    }


P_ESTIMATORS: dict[str, str] = {
    "protocol": "inversions / M of the paper's protocol runs, all their stops pooled",
    "restart": (
        "two-state chain 2 a b / (a + b) of a = P_ccw, b = P_cw: the long-run fraction of "
        "inversions in M stops in a row (the paper's P), not the pooled inversions / stops"
    ),
}
"""What P is for each estimator (the bank estimator's P is the restart one's)."""

_VARIABLES: dict[str, tuple[str, str]] = {
    "P": ("inversion probability", "1"),  # + P_ESTIMATORS[estimator] in gather()
    "P_low": ("lower bound of the 95 % interval of P", "1"),
    "P_high": ("upper bound of the 95 % interval of P", "1"),
    "P_pooled": (
        "pooled fraction inversions / stops of both directions (protocol: equals P; "
        "restart, bank: weighs the directions by their numbers of stops, not the paper's P)",
        "1",
    ),
    "inversions": ("inversions counted, both directions", "1"),
    "stops": ("stop-and-release operations counted, both directions", "1"),
    "P_ccw": ("P(inversion | CCW rotation before the stop)", "1"),
    "P_ccw_low": ("Wilson 95 % lower bound of P_ccw", "1"),
    "P_ccw_high": ("Wilson 95 % upper bound of P_ccw", "1"),
    "inversions_ccw": ("inversions from CCW rotation", "1"),
    "stops_ccw": ("stops from CCW rotation", "1"),
    "P_cw": ("P(inversion | CW rotation before the stop)", "1"),
    "P_cw_low": ("Wilson 95 % lower bound of P_cw", "1"),
    "P_cw_high": ("Wilson 95 % upper bound of P_cw", "1"),
    "inversions_cw": ("inversions from CW rotation", "1"),
    "stops_cw": ("stops from CW rotation", "1"),
    "pi_ccw": ("stationary fraction of CCW rotation of the two-state chain", "1"),
    "mean_abs_omega": ("mean |omega| just before the stops", "1/time"),
    "uncommitted": ("restarts without a committed direction at the release cap", "1"),
    "mean_commit_time": ("mean release time until |omega| >= commit_fraction |omega0|", "time"),
    "runs_done": ("runs with a result file", "1"),
    "runs_expected": ("runs of the sweep at this point", "1"),
}


def _point_statistics(sweep: Sweep, contents: Sequence[dict[str, Any]], expected: int) -> dict:
    kind = sweep.spec.estimator.kind
    counts = DirectionCounts()
    omegas: list[float] = []
    uncommitted = 0
    commit_times: list[float] = []
    if kind != "protocol":
        before = [c["result"]["direction_before"] for c in contents]
        after = [c["result"]["direction_after"] for c in contents]
        if contents:
            counts = restart_counts(before, after)
        for c in contents:
            res = c["result"]
            omegas.append(abs(res["omega_before"]))
            if res["committed"]:
                commit_times.append(res["t_commit"])
            else:
                uncommitted += 1
    else:
        for c in contents:
            res = c["result"]
            counts += DirectionCounts(
                Proportion(res["inversions_ccw"], res["n_ccw"]),
                Proportion(res["inversions_cw"], res["n_cw"]),
            )
            omegas.extend(abs(w) for w in res["omegas"][:-1])
    total = counts.total
    if kind != "protocol":
        chain = two_state_chain(counts)
        p, lo, hi, pi = chain.p, chain.low, chain.high, chain.pi_ccw
    else:
        p = total.p
        lo, hi = total.interval()
        a, b = counts.ccw.p, counts.cw.p
        pi = b / (a + b) if counts.ccw.n and counts.cw.n and a + b > 0 else math.nan
    out = {
        "P": p,
        "P_low": lo,
        "P_high": hi,
        "P_pooled": total.p,
        "inversions": total.k,
        "stops": total.n,
        "pi_ccw": pi,
        "mean_abs_omega": float(np.mean(omegas)) if omegas else math.nan,
        "uncommitted": uncommitted,
        "mean_commit_time": float(np.mean(commit_times)) if commit_times else math.nan,
        "runs_done": len(contents),
        "runs_expected": expected,
    }
    for name in ("ccw", "cw"):
        prop: Proportion = getattr(counts, name)
        low, high = prop.interval()
        out.update(
            {
                f"P_{name}": prop.p,
                f"P_{name}_low": low,
                f"P_{name}_high": high,
                f"inversions_{name}": prop.k,
                f"stops_{name}": prop.n,
            }
        )
    return out


def gather(sweep: Sweep, sweep_dir: str | Path) -> xr.Dataset:
    """Collect the run files of `sweep` from `sweep_dir` into a Dataset (no writing).

    Coordinates are the sweep axes (dimension = last part of the dotted key, the full
    key in the attribute ``config_key``); a sweep without axes gives scalar variables.
    """
    sweep_dir = Path(sweep_dir)
    keys = list(sweep.axes)
    dims = _dim_names(keys)
    by_point: dict[tuple[int, ...], list[Run]] = {}
    for run in sweep.runs():
        by_point.setdefault(run.point, []).append(run)
    shape = sweep.shape
    arrays = {name: np.full(shape, np.nan) for name in _VARIABLES}
    for index, runs in by_point.items():
        contents = []
        for run in runs:
            content = load_run(run_path(sweep_dir, run.key))
            if content is not None and content.get("key") == run.key:
                contents.append(content)
        stats = _point_statistics(sweep, contents, len(runs))
        for name, value in stats.items():
            arrays[name][index] = value
    coords = {}
    for key in keys:
        values = sweep.axes[key]
        if all(isinstance(v, bool) for v in values):
            values = [int(v) for v in values]
        coords[dims[key]] = xr.Variable(dims[key], values, attrs={"config_key": key})
    dim_list = [dims[k] for k in keys]
    data_vars = {}
    kind = sweep.spec.estimator.kind
    p_is = P_ESTIMATORS[_p_estimator(kind)]
    for name, (long_name, units) in _VARIABLES.items():
        if name in ("P", "P_low", "P_high"):
            long_name = f"{long_name} ({kind} estimator: {p_is})"
        arr = arrays[name]
        if name in ("inversions", "stops", "runs_done", "runs_expected", "uncommitted") or (
            name.startswith(("inversions_", "stops_"))
        ):
            arr = arr.astype(np.int64)
        data_vars[name] = xr.Variable(dim_list, arr, attrs={"long_name": long_name, "units": units})
    spec = sweep.spec
    grid = sweep.base.get("grid", {})
    attrs = {
        "sweep": spec.name,
        "description": spec.description,
        "estimator": spec.estimator.kind,
        "estimator_settings": json.dumps(spec.estimator.model_dump(mode="json")),
        "samples_per_point": spec.samples,
        "seed": spec.seed,
        "confidence": CONFIDENCE,
        "interval": (
            "protocol: Wilson score interval of inversions / M; restart, bank: two-state chain "
            "2 a b / (a + b) of the Bonferroni (97.5 %) Wilson bounds of a = P_ccw, b = P_cw"
        ),
        "base_config": json.dumps(sweep.base, sort_keys=True),
        "grid_dx": float(grid.get("dx", RotorConfig().grid.dx)),
        "grid_dt": float(grid.get("dt", RotorConfig().grid.dt)),
        "paper": "Koyano, Kitahata, Nakata, Gorecki, Chaos 30 (2020), Figs. 5, 7, 8, 9",
    }
    return xr.Dataset(data_vars, coords=coords, attrs=attrs)


def report(sweep_dir: str | Path, out: str | Path | None = None, echo: bool = True) -> xr.Dataset:
    """Gather a sweep directory into a Dataset, write it as NetCDF and print a table.

    Args:
        sweep_dir: directory written by :func:`run_sweep` (holds sweep.yaml and runs/).
        out: NetCDF path (default: SWEEP_DIR/report.nc); written atomically with the
            h5netcdf engine.
        echo: print the table (:func:`format_table`).
    """
    sweep_dir = Path(sweep_dir)
    sweep = Sweep.load(sweep_dir)
    ds = gather(sweep, sweep_dir)
    target = Path(out) if out is not None else sweep_dir / REPORT_FILE
    target.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=target.parent, prefix=f".{target.name}.", suffix=".part")
    os.close(fd)
    try:
        ds.to_netcdf(tmp, engine="h5netcdf")
        _publish(tmp, target)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    if echo:
        print(format_table(ds))
    return ds


def _p_estimator(kind: str) -> str:
    """The key of :data:`P_ESTIMATORS` for an estimator kind (bank: as restart)."""
    return "protocol" if kind == "protocol" else "restart"


TABLE_LEGENDS: dict[str, tuple[str, str]] = {
    "protocol": (
        "P=inv/M",
        "P=inv/M: inversions / stops of all protocol runs (the paper's estimator); "
        "inv|CCW, inv|CW: by the direction before the stop",
    ),
    "restart": (
        "P chain",
        "P chain: 2ab/(a+b), a = P(inv|CCW), b = P(inv|CW): the inversion fraction of M "
        "stops in a row (the paper's P); pooled: all stops together, not the paper's P",
    ),
}
"""Header of the P column and the legend line of :func:`format_table`, by estimator."""


def format_table(ds: xr.Dataset) -> str:
    """One row per point: axis values, P [95 % interval], conditionals, pooled, mean |omega|.

    The P column is named after its estimator (the chain value of the restart and bank
    estimators, inversions / M of the protocol one) and a legend line says what it is;
    the pooled fraction inversions / stops stands beside it.
    """
    dims = list(ds.sizes)
    rows = []
    p_header, legend = TABLE_LEGENDS[_p_estimator(str(ds.attrs.get("estimator", "")))]
    header = [*dims, p_header, "95% CI", "inv|CCW", "inv|CW", "pooled", "mean|omega|", "runs"]
    flat = ds.stack(point=dims) if dims else ds.expand_dims(point=[0])
    for i in range(flat.sizes["point"]):
        row = flat.isel(point=i)
        cells = [f"{row[d].item():.6g}" for d in dims]

        def fmt(name: str, row: xr.Dataset = row) -> str:
            value = float(row[name])
            return "nan" if math.isnan(value) else f"{value:.3f}"

        k, n = int(row["inversions"]), int(row["stops"])
        cells += [
            fmt("P"),
            f"[{fmt('P_low')}, {fmt('P_high')}]",
            f"{int(row['inversions_ccw'])}/{int(row['stops_ccw'])}",
            f"{int(row['inversions_cw'])}/{int(row['stops_cw'])}",
            f"{k}/{n} = {k / n:.3f}" if n else f"{k}/{n}",
            f"{float(row['mean_abs_omega']):.1f}",
            f"{int(row['runs_done'])}/{int(row['runs_expected'])}",
        ]
        rows.append(cells)
    widths = [max(len(h), *(len(r[k]) for r in rows)) for k, h in enumerate(header)]
    lines = [
        f"{ds.attrs.get('sweep', '')} ({ds.attrs.get('estimator', '')} estimator, "
        f"dx = {ds.attrs.get('grid_dx')}, dt = {ds.attrs.get('grid_dt')})",
        legend,
        "  ".join(h.rjust(w) for h, w in zip(header, widths, strict=True)),
    ]
    lines += ["  ".join(c.rjust(w) for c, w in zip(r, widths, strict=True)) for r in rows]
    return "\n".join(lines)
