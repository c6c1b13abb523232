"""The plan of a sweep: its points, runs, seeds and run keys (:class:`Sweep`, :class:`Run`)."""

from __future__ import annotations

import copy
import hashlib
import itertools
import json
from collections.abc import Iterable, Iterator, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from pydantic import ValidationError

from ..config import ConfigError, RotorConfig, parse_yaml, set_key
from ..statistics.proportions import CCW, CW
from .placement import CrowdError, CrowdSpec, place
from .spec import (
    CollectiveEstimator,
    RestartEstimator,
    SweepError,
    SweepSpec,
    apply_sweep_overrides,
    looks_like_run_config,
    read_base,
    spec_error,
    sweep_format,
    validate_point,
)

SCHEMA_VERSION = 2
"""Version of the run-file layout and run key; part of every key (2: bank stop angles
drawn at random, solver section not in the key)."""
SPEC_FILE = "sweep.yaml"
"""Copy of the sweep specification (base inlined) kept in the sweep directory."""
STOP_STREAM = 1
"""Seed stream (:func:`run_seed`) of the bank estimator's stop angles."""


@dataclass(frozen=True)
class Run:
    """One run of a sweep (picklable, sent to a worker).

    Attributes:
        point: index of the point along each axis.
        coords: the point's axis values by dotted key.
        sample: sample index at the point.
        direction: +1 (CCW) or -1 (CW) for restarts, 0 for protocol runs.
        config: resolved physics configuration (JSON mapping, noise.seed set; without
            the output and solver sections, which change no result).
        estimator: estimator settings (JSON mapping).
        key: hash of config, estimator, direction, sample and stop seed
            (:func:`run_key`); the key of its record in the store.
        stop_seed: seed of the stop angle shared by a bank group (bank estimator only):
            derived from the sweep seed, the point's coordinates without its ``noise``
            axes, the sample and the direction.
    """

    point: tuple[int, ...]
    coords: dict[str, Any]
    sample: int
    direction: int
    config: dict[str, Any]
    estimator: dict[str, Any]
    key: str
    stop_seed: int | None = None


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
        base = resolve_base(spec, root)
        if spec.crowd is None:
            validate_point(base, "base")
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
        return cls.from_spec(*read_spec(path, overrides))

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
        """Directions sampled per point: (CCW, CW) for restarts, (0,) for protocol and
        collective runs."""
        return (0,) if self.spec.estimator.kind in ("protocol", "collective") else (CCW, CW)

    def runs(self) -> list[Run]:
        """Every run of the sweep (validated, seeds derived, hashes computed)."""
        if self._runs is not None:
            return self._runs
        estimator = self.spec.estimator.model_dump(mode="json")
        bank = self.spec.estimator.kind == "bank"
        runs: list[Run] = []
        for index, coords in self.points():
            data = copy.deepcopy(self.base)
            where = ", ".join(f"{k} = {v}" for k, v in coords.items()) or "base"
            for key, value in coords.items():
                if not key.startswith("crowd."):
                    _set(data, key, value, where)
            crowd = self._crowd(coords, where)
            if crowd is None:
                config = validate_point(data, where)
            else:
                config = _with_crowd(data, crowd, 0, where)
            if self.spec.estimator.kind in ("restart", "bank"):
                _check_restart(config, self.spec.estimator, where)
            if isinstance(self.spec.estimator, CollectiveEstimator):
                _check_collective(config, self.spec.estimator, where)
            stop_coords = {k: v for k, v in coords.items() if not k.startswith("noise.")}
            for direction in self.directions():
                for sample in range(self.spec.samples):
                    seed = run_seed(self.spec.seed, coords, sample, direction)
                    if crowd is None:
                        resolved = config.model_copy(deep=True)
                    else:
                        resolved = _with_crowd(data, crowd, sample, where)
                    resolved.noise.seed = seed
                    cfg = resolved.physics()
                    stop_seed = (
                        run_seed(self.spec.seed, stop_coords, sample, direction, STOP_STREAM)
                        if bank
                        else None
                    )
                    key = run_key(cfg, estimator, direction, sample, stop_seed)
                    runs.append(
                        Run(index, coords, sample, direction, cfg, estimator, key, stop_seed)
                    )
        self._runs = runs
        return runs

    def _crowd(self, coords: Mapping[str, Any], where: str) -> CrowdSpec | None:
        """The sweep's crowd at a point (its ``crowd.*`` axes applied), or None."""
        if self.spec.crowd is None:
            return None
        data = self.spec.crowd.model_dump(mode="json")
        for key, value in coords.items():
            if key.startswith("crowd."):
                _set(data, key.removeprefix("crowd."), value, where)
        try:
            return CrowdSpec.model_validate(data)
        except ValidationError as err:
            raise SweepError(f"sweep point {where}: crowd.{spec_error(err)}") from None


def _with_crowd(data: dict[str, Any], crowd: CrowdSpec, sample: int, where: str) -> RotorConfig:
    """The config of one sample of a point: `data` with the crowd's bodies placed."""
    placed = copy.deepcopy(data)
    centre = placed.get("grid", {}).get("domain_centre", (0.0, 0.0))
    try:
        placed["bodies"] = place(crowd, (float(centre[0]), float(centre[1])), sample)
    except CrowdError as err:
        raise SweepError(f"sweep point {where}, sample {sample}: {err}") from None
    return validate_point(placed, f"{where}, sample {sample}")


def dim_names(keys: Sequence[str]) -> dict[str, str]:
    """Short dimension names: the last part of each dotted key unless two collide."""
    last = [k.rsplit(".", 1)[-1] for k in keys]
    return {
        k: (s if last.count(s) == 1 else k.replace(".", "_"))
        for k, s in zip(keys, last, strict=True)
    }


def read_spec(path: str | Path, overrides: Iterable[str] = ()) -> tuple[SweepSpec, Path]:
    """Read and validate a sweep YAML file's specification, without planning its runs.

    Args:
        path: the sweep file or directory (its sweep.yaml).
        overrides: ``KEY=VALUE`` changes of the file's keys (:func:`apply_sweep_overrides`).

    Returns:
        The specification and the directory a relative ``base`` file is read from.

    Raises:
        SweepError: one line naming the file and the problem.
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
    if looks_like_run_config(data):
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
        raise SweepError(f"{path}: {spec_error(err)}") from None
    return spec, path.parent


def resolve_base(spec: SweepSpec, root: Path | None = None) -> dict[str, Any]:
    """The base configuration mapping of `spec`: its base file or mapping, ``set`` applied."""
    base = read_base(spec.base, root) if isinstance(spec.base, str) else copy.deepcopy(spec.base)
    for key, value in spec.set.items():
        _set(base, key, value, "set")
    return base


def base_config(path: str | Path) -> RotorConfig:
    """The validated base configuration of a sweep file, without planning its runs (a
    paper-resolution map plans tens of thousands).

    Raises:
        SweepError: the file or its base is invalid.
    """
    spec, root = read_spec(path)
    return validate_point(resolve_base(spec, root), f"{path}: base")


def _set(data: dict[str, Any], key: str, value: Any, where: str) -> None:
    """:func:`~pde_rotor.config.set_key` with the error naming the point (or ``set``)."""
    try:
        set_key(data, key, value)
    except ConfigError as err:
        raise SweepError(f"{where}: {key}: {err}") from None


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


def _check_collective(config: RotorConfig, estimator: CollectiveEstimator, where: str) -> None:
    try:
        estimator.resolve(config)
    except ValueError as err:
        raise SweepError(f"{where}: {err}") from None
    dt = config.grid.dt
    value = estimator.record_interval
    if abs(round(value / dt) * dt - value) > 1e-9 * max(1.0, value):
        msg = (
            f"{where}: estimator.record_interval = {value:g} is not an integer multiple of "
            f"grid.dt = {dt:g}"
        )
        raise SweepError(msg)


def run_seed(
    sweep_seed: int, coords: Mapping[str, Any], sample: int, direction: int, stream: int = 0
) -> int:
    """Noise seed of one run: SeedSequence(sweep seed, coordinates, sample, direction).

    `stream` > 0 gives further independent seeds of the same run (:data:`STOP_STREAM`:
    the bank estimator's stop angle).

    The coordinates enter through the SHA-256 of their canonical JSON (keys sorted), so
    the seed of a run depends only on its own axis values, not on the order or number of
    other points; adding values to an axis leaves the seeds of existing points unchanged.
    """
    text = json.dumps(dict(coords), sort_keys=True, separators=(",", ":"), default=str)
    digest = hashlib.sha256(text.encode()).digest()
    words = np.frombuffer(digest, dtype=np.uint32).tolist()
    extra = [stream] if stream else []
    seq = np.random.SeedSequence([sweep_seed, *words, sample, direction + 1, *extra])
    return int(seq.generate_state(1, np.uint64)[0] >> np.uint64(1))


def run_key(
    config: Mapping[str, Any],
    estimator: Mapping[str, Any],
    direction: int,
    sample: int,
    stop_seed: int | None = None,
) -> str:
    """Hash naming a run's record: SHA-256 of its resolved config and estimator settings.

    Only what determines the result enters (the physics config, the estimator, the
    sample, its direction and stop seed): no path, machine, backend or scheduler, so
    runs committed on one machine are found by a sweep resumed on another.
    """
    payload = {
        "schema": SCHEMA_VERSION,
        "config": config,
        "estimator": estimator,
        "direction": direction,
        "sample": sample,
        "stop_seed": stop_seed,
    }
    text = json.dumps(payload, sort_keys=True, separators=(",", ":"))
    return hashlib.sha256(text.encode()).hexdigest()[:24]
