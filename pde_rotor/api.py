"""Run one configuration with all trackers and collect the results: :func:`run` -> RunResult.

This is what ``pde-rotor run`` calls; it is equally usable from Python::

    import pde_rotor
    result = pde_rotor.run("configs/quickstart.yaml", out="runs/quick")
    result.timeseries.omega.plot()
    print(result.inversion_probability)

Without ``out`` nothing is written: the time series and events are returned in memory
(no snapshots, no movie).
"""

from __future__ import annotations

import logging
import math
import secrets
import time
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from datetime import datetime, timezone
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
import xarray as xr

from ._version import versions
from .backends import backend_for, device_name, member_stepper
from .config import ConfigError, RotorConfig, dump_config, load_config, validate_config
from .io.output import (
    RunDirectory,
    atomic_path,
    detach_log,
    write_netcdf_atomic,
    write_text_atomic,
)
from .units import LENGTH_UNITS, TIME_UNITS

if TYPE_CHECKING:
    from .model.setup import Setup

_logger = logging.getLogger(__name__)

PAPER = (
    "Koyano, Kitahata, Nakata, Gorecki: On a simple model that explains inversion of a "
    "self-propelled rotor under periodic stop-and-release operations, Chaos 30 (2020)"
)


def with_seed(config: RotorConfig) -> RotorConfig:
    """The config with ``noise.seed`` set: a fresh random seed if it is null."""
    if config.noise.seed is not None:
        return config
    noise = config.noise.model_copy(update={"seed": secrets.randbits(32)})
    return config.model_copy(update={"noise": noise})


def as_config(config: RotorConfig | Mapping[str, Any] | str | Path) -> RotorConfig:
    """Accept a RotorConfig, a nested mapping, or a YAML file path."""
    if isinstance(config, RotorConfig):
        return config
    if isinstance(config, (str, Path)):
        return load_config(config)
    return validate_config(config)


@dataclass
class RunResult:
    """Everything a run produced.

    Attributes:
        config: the resolved configuration (seed filled in).
        timeseries: Dataset over ``time``: phi, omega, torque, friction, camphor_total,
            stopped, cycle (see :data:`pde_rotor.trackers.TIMESERIES_VARIABLES`).
        events: Dataset over ``cycle``: one row per stop-and-release cycle.
        status: "completed", "diverged", "interrupted" or "failed".
        message: why the run ended.
        run_dir: the run directory (None for an in-memory run).
        wall_time: seconds the run took.
        backend: compute backend that ran it ("cpu" or "gpu"; ``solver.backend``
            resolved by :func:`pde_rotor.backends.resolve_backend`).
    """

    config: RotorConfig
    timeseries: xr.Dataset
    events: xr.Dataset
    status: str = "completed"
    message: str = ""
    run_dir: Path | None = None
    wall_time: float = math.nan
    backend: str = "cpu"
    files: dict[str, Path] = field(default_factory=dict)

    @property
    def ok(self) -> bool:
        """Whether the run reached the end of the protocol."""
        return self.status == "completed"

    @property
    def inversion_probability(self) -> float:
        """Inversions divided by the recorded cycles (the paper's definition)."""
        n = self.events.sizes.get("cycle", 0)
        if n == 0:
            return math.nan
        return float(self.events["inverted"].values.mean())

    @classmethod
    def load(cls, run_dir: str | Path) -> RunResult:
        """Read a run directory written by :func:`run` (config, time series, events).

        Raises:
            ConfigError: the directory or one of its files is missing or unreadable.
        """
        run = RunDirectory(run_dir)
        if not run.path.is_dir():
            msg = f"run directory {str(run.path)!r} not found"
            raise ConfigError(msg)
        config = load_config(run.config)
        if not run.timeseries.exists():
            msg = (
                f"{run.timeseries} not found (a running run writes it every "
                f"{config.output.checkpoint_seconds:g} s)"
            )
            raise ConfigError(msg)
        with xr.open_dataset(run.timeseries, engine="h5netcdf") as ds:
            ts = ds.load()
        if run.events_nc.exists():
            with xr.open_dataset(run.events_nc, engine="h5netcdf") as ds:
                events = ds.load()
        else:  # still running: the rows written so far
            events = _events_from_csv(run.events_csv, config.output.commit_fraction)
        return cls(
            config=config,
            timeseries=ts,
            events=events,
            status=str(ts.attrs.get("status", "completed")),
            message=str(ts.attrs.get("message", "")),
            run_dir=run.path,
            backend=str(ts.attrs.get("backend", "cpu")),
            files={name: run / name for name in RunDirectory.FILES if (run / name).exists()},
        )

    def snapshot(self, index: int = -1):
        """One stored field snapshot (:class:`pde_rotor.plotting.run.Snapshot`), or None."""
        from pde.storage import FileStorage

        from .plotting.run import Snapshot

        if self.run_dir is None:
            return None
        path = RunDirectory(self.run_dir).snapshots
        if not path.exists():
            return None
        storage = FileStorage(path, write_mode="readonly")
        try:
            if len(storage) == 0:
                return None
            state = storage[index]
            phis = storage.info.get("rotor_phi", [])
            k = index % len(storage)
            phi = float(phis[k]) if k < len(phis) else self.config.rotor.phi0
            return Snapshot(
                t=float(storage.times[k]),
                data=np.array(state.data),
                phi=phi,
                coords=np.asarray(state.grid.axes_coords[0]),
            )
        finally:
            storage.close()

    def summary_figure(self):
        """The ``pde-rotor show`` figure of this run (a matplotlib Figure)."""
        from .plotting.run import summary_figure

        return summary_figure(self.config, self.timeseries, self.events, self.snapshot())

    def write_summary(self) -> Path | None:
        """Save :meth:`summary_figure` as summary.png in the run directory (atomically)."""
        if self.run_dir is None:
            return None
        path = RunDirectory(self.run_dir).summary
        fig = self.summary_figure()
        with atomic_path(path) as tmp:
            fig.savefig(tmp, format="png", dpi=110)
        self.files["summary.png"] = path
        return path


def run(
    config: RotorConfig | Mapping[str, Any] | str | Path,
    out: str | Path | None = None,
    *,
    movie: bool | None = None,
    progress: bool | None = None,
    overwrite: bool = False,
    check: bool = True,
    overrides: Iterable[str] = (),
) -> RunResult:
    """Run one configuration with the trackers of :mod:`pde_rotor.trackers`.

    Args:
        config: RotorConfig, nested mapping, or path of a YAML config.
        out: run directory to write (see :mod:`pde_rotor.io.output`); None: in memory only.
        movie: override ``output.movie`` (only with `out`).
        progress: override ``output.progress``.
        overwrite: replace the files of an earlier run in `out`.
        check: raise SimulationDivergedError when the run diverges (after writing
            everything recorded up to then); False: return a result with status
            "diverged".
        overrides: ``key.path=value`` strings applied to the config first.

    Returns:
        The :class:`RunResult`.

    Raises:
        ConfigError: invalid configuration (before anything is compiled).
        pde_rotor.backends.BackendError: solver.backend is "gpu" and no GPU is usable.
        ConfigError: also when the records would not fit in memory or on disk.
        OutputError: `out` holds an earlier run and not `overwrite`.
        SimulationDivergedError: the state became NaN/Inf and `check` is True.
        RunError: anything else stopped the run (the original error is its cause).
    """
    cfg = as_config(config)
    overrides = list(overrides)
    if overrides:
        from .config import apply_overrides

        cfg = validate_config(apply_overrides(cfg.model_dump(mode="json"), overrides))
    output_update: dict[str, Any] = {}
    if movie is not None:
        output_update["movie"] = bool(movie)
    if progress is not None:
        output_update["progress"] = bool(progress)
    if output_update:
        cfg = cfg.model_copy(update={"output": cfg.output.model_copy(update=output_update)})
    cfg = with_seed(cfg)
    backend = backend_for(cfg)
    from .model.setup import Setup

    setup = Setup(cfg)  # the config made into the model's objects, once for the whole run
    if cfg.bodies is not None:
        return _run_bodies(setup, out, backend, overwrite=overwrite, check=check)
    device = device_name(backend)
    from . import trackers as tr

    tr.check_budget(cfg, out, cfg.output.movie and out is not None)
    run_dir = RunDirectory.create(out, overwrite=overwrite) if out is not None else None

    from .solver.rotor import SimulationDivergedError
    from .solver.simulation import Simulation

    vers = versions()
    provenance = {
        "pde_rotor_version": vers["pde_rotor"],
        "py_pde_version": vers["py-pde"],
        "numba_version": vers["numba"],
        "config_hash": cfg.config_hash(),
        "seed": cfg.noise.seed,
        "backend": backend,
        "device": device,
        "created": datetime.now(timezone.utc).isoformat(timespec="seconds"),
        "paper": PAPER,
    }
    attrs = {
        "title": "camphor rotor under stop-and-release operations",
        "source": f"pde_rotor {vers['pde_rotor']} (py-pde {vers['py-pde']})",
        "references": PAPER,
        "config_hash": provenance["config_hash"],
        "seed": int(cfg.noise.seed),
        "backend": backend,
        "device": device,
        "config": dump_config(cfg),
        "units": (
            f"lengths in {LENGTH_UNITS}, times in {TIME_UNITS} (the paper's dimensionless units)"
        ),
    }
    log_handler = None
    if run_dir is not None:
        write_text_atomic(run_dir.config, dump_config(cfg, provenance))
        log_handler = run_dir.attach_log()
    try:
        _logger.info(
            "run %s: config hash %s, seed %s, backend %s (%s), t_end %g, dx %g, dt %g",
            run_dir.path if run_dir else "(in memory)",
            provenance["config_hash"],
            cfg.noise.seed,
            backend,
            device,
            cfg.protocol.t_end,
            cfg.grid.dx,
            cfg.grid.dt,
        )
        _logger.info("versions: %s", ", ".join(f"{k} {v}" for k, v in vers.items()))
        # one run path: py-pde's Controller and the same trackers on every backend;
        # on the GPU the run is an ensemble of one member between the interrupts
        sim = (
            Simulation(setup, stepper=member_stepper(backend))
            if backend == "gpu"
            else Simulation(setup)
        )
        out_cfg = cfg.output
        ts_tracker = tr.TimeSeriesTracker(
            setup,
            out_cfg.timeseries_interval,
            run_dir.timeseries if run_dir else None,
            checkpoint_seconds=out_cfg.checkpoint_seconds,
            attrs=attrs,
        )
        ev_tracker = tr.InversionTracker(
            setup,
            out_cfg.event_interval,
            out_cfg.commit_fraction,
            run_dir.events_csv if run_dir else None,
            run_dir.events_nc if run_dir else None,
            attrs=attrs,
        )
        trackers: list[Any] = [ts_tracker, ev_tracker]
        if run_dir is not None and out_cfg.snapshot_interval is not None:
            info = {k: v for k, v in attrs.items() if isinstance(v, (str, int, float))}
            trackers.append(
                tr.SnapshotTracker(setup, run_dir.snapshots, out_cfg.snapshot_interval, info)
            )
        if run_dir is not None and out_cfg.movie:
            trackers.append(
                tr.MovieTracker(
                    setup,
                    run_dir.movie,
                    out_cfg.movie_interval,
                    fps=out_cfg.movie_fps,
                    dpi=out_cfg.movie_dpi,
                    half_width=out_cfg.movie_view,
                )
            )
        if out_cfg.progress:
            trackers.append(tr.ProgressBarTracker(setup))

        start = time.perf_counter()
        error: BaseException | None = None
        try:
            sim.run(trackers=trackers)
        except SimulationDivergedError as err:
            error = err
            _finalize_after_error(trackers, "diverged", str(err), ts_tracker)
        except BaseException as err:
            error = err
            _finalize_after_error(trackers, "failed", f"{type(err).__name__}: {err}", ts_tracker)
        wall = time.perf_counter() - start
        status = ts_tracker.status or {"status": "failed", "message": "trackers not finalized"}
        result = RunResult(
            config=cfg,
            timeseries=ts_tracker.to_dataset(status),
            events=ev_tracker.to_dataset(status),
            status=status["status"],
            message=status["message"],
            run_dir=run_dir.path if run_dir else None,
            wall_time=wall,
            backend=backend,
        )
        steps = int(sim.solver.info.get("steps", 0))
        _logger.info(
            "run %s after %.1f s wall time (%d steps, %.3g ms/step): %s; inversions %d/%d",
            result.status,
            wall,
            steps,
            1e3 * wall / max(steps, 1),
            result.message,
            int(result.events["inverted"].values.sum()),
            result.events.sizes.get("cycle", 0),
        )
        if run_dir is not None:
            result.files = {
                name: run_dir / name for name in RunDirectory.FILES if (run_dir / name).exists()
            }
            if error is None or isinstance(error, SimulationDivergedError):
                try:
                    result.write_summary()
                except OSError as err:  # a full disk: the records are kept, say so
                    _logger.error("writing summary.png failed: %s", err)
                    error = err
        if error is not None and (check or not isinstance(error, SimulationDivergedError)):
            if isinstance(error, SimulationDivergedError) or not isinstance(error, Exception):
                raise error
            t_last = ts_tracker.rows["time"][-1] if ts_tracker.rows["time"] else 0.0
            kept = f"; what was recorded before is in {run_dir.path}" if run_dir else ""
            msg = f"run stopped after t = {t_last:g}: {_describe(error)}{kept}"
            raise RunError(msg) from error
        return result
    finally:
        if log_handler is not None:
            detach_log(log_handler)


def _run_bodies(
    setup: Setup, out: str | Path | None, backend: str, *, overwrite: bool, check: bool
) -> RunResult:
    """:func:`run` for a config with ``bodies:``: bodies.nc, the events of every body
    with stops, config.yaml, run.log, summary.png and (``output.movie``) movie.mp4
    (:mod:`pde_rotor.plotting.bodies`).

    The result's ``timeseries`` is bodies.nc (time, body), its ``events`` the stops of
    every body with a protocol. A body at the dish's edge or at another body ends the
    run with status "stopped" and the message naming it; what was recorded is kept. On
    the GPU (`backend` "gpu") the bodies advance on
    :func:`pde_rotor.backends.gpu_bodies.gpu_bodies_stepper` under the same Controller
    and trackers. `setup` is the run's (:class:`~pde_rotor.model.setup.Setup`).
    """
    cfg = setup.config
    from .plotting.bodies import bodies_summary
    from .solver.bodies import BodyContactError
    from .solver.rotor import SimulationDivergedError
    from .solver.simulation import Simulation
    from .trackers.bodies import BodiesLogTracker, BodiesMovieTracker, BodiesTracker
    from .trackers.progress import ProgressBarTracker

    run_dir = RunDirectory.create(out, overwrite=overwrite) if out is not None else None
    attrs = {
        "title": "camphor bodies on one surface",
        "source": f"pde_rotor {versions()['pde_rotor']}",
        "references": PAPER,
        "config_hash": cfg.config_hash(),
        "backend": backend,
        "device": device_name(backend),
        "config": dump_config(cfg),
    }
    log_handler = None
    if run_dir is not None:
        write_text_atomic(run_dir.config, dump_config(cfg))
        log_handler = run_dir.attach_log()
    try:
        grid = cfg.grid
        _logger.info(
            "bodies run %s: config hash %s, %d bodies (%s), scheme %s, t_end %g, dx %g, dt %g",
            run_dir.path if run_dir else "(in memory)",
            attrs["config_hash"],
            len(cfg.bodies),
            ", ".join(b.name for b in setup.bodies),
            cfg.numerics.scheme,
            cfg.protocol.t_end,
            grid.dx,
            grid.dt,
        )
        if backend == "gpu":
            from .backends.gpu_bodies import gpu_bodies_stepper

            sim = Simulation(setup, stepper=gpu_bodies_stepper)
        else:
            sim = Simulation(setup)
        tracker = BodiesTracker(
            setup,
            cfg.output.timeseries_interval,
            run_dir / "bodies.nc" if run_dir else None,
            checkpoint_seconds=cfg.output.checkpoint_seconds,
            attrs=attrs,
        )
        out_cfg = cfg.output
        trackers: list[Any] = [tracker, BodiesLogTracker(setup, out_cfg.timeseries_interval)]
        if out_cfg.progress:
            trackers.append(ProgressBarTracker(setup))
        if run_dir is not None and out_cfg.movie:
            trackers.append(
                BodiesMovieTracker(
                    setup, run_dir.movie, out_cfg.movie_interval, fps=out_cfg.movie_fps,
                    dpi=out_cfg.movie_dpi,
                )
            )  # fmt: skip
        start = time.perf_counter()
        error: BaseException | None = None
        status, message = "completed", ""
        try:
            sim.run(trackers=trackers)
        except (BodyContactError, SimulationDivergedError) as err:
            error = err
            status = "stopped" if isinstance(err, BodyContactError) else "diverged"
            message = str(err)
            _logger.error("%s", message)
            t_last = tracker.times[-1] if tracker.times else 0.0
            info = {"controller": {"status": status, "stop_reason": message, "t_final": t_last}}
            for each in trackers:
                each.finalize(info=info)
        result = RunResult(
            config=cfg,
            timeseries=tracker.to_dataset(tracker.status),
            events=tracker.events(cfg.output.commit_fraction),
            status=status,
            message=message or (tracker.status or {}).get("message", ""),
            run_dir=run_dir.path if run_dir else None,
            wall_time=time.perf_counter() - start,
            backend=backend,
        )
        said = f": {result.message}" if result.message else ""
        _logger.info("bodies run %s after %.1f s%s", status, result.wall_time, said)
        if run_dir is not None:
            write_netcdf_atomic(result.events, run_dir / "events.nc")
            fig = bodies_summary(result.timeseries, cfg, setup.bodies)
            with atomic_path(run_dir.summary) as tmp:
                fig.savefig(tmp, format="png", dpi=110)
            names = ("config.yaml", "bodies.nc", "events.nc", "summary.png", "movie.mp4", "run.log")
            result.files = {n: run_dir / n for n in names if (run_dir / n).exists()}
        if error is not None and check and isinstance(error, SimulationDivergedError):
            raise error
        return result
    finally:
        if log_handler is not None:
            detach_log(log_handler)


class RunError(RuntimeError):
    """A run stopped by something other than the physics (a full disk, a failing writer);
    ``str(err)`` is one line saying when, why and where the records before it are."""


def _describe(error: Exception) -> str:
    """One line for what stopped a run: ``No space left on device (writing events.nc)``."""
    if isinstance(error, OSError) and error.strerror:
        where = f" (writing {Path(error.filename).name})" if error.filename else ""
        return f"{error.strerror}{where}"
    return f"{type(error).__name__}: {error}".splitlines()[0]


def _events_from_csv(path: Path, commit_fraction: float) -> xr.Dataset:
    """Events Dataset from the rows of events.csv (empty if the file does not exist)."""
    import csv

    from .trackers import EVENT_COLUMNS

    rows: list[dict[str, str]] = []
    if path.exists():
        with path.open(newline="", encoding="utf-8") as fh:
            rows = list(csv.DictReader(fh))
    flags = ("inverted", "committed")
    ints = ("cycle", "direction_before", "direction_after")
    data: dict[str, Any] = {}
    for name in EVENT_COLUMNS:
        values = [r[name] for r in rows]
        if name in flags:
            data[name] = np.array([v == "true" for v in values], dtype=bool)
        elif name in ints:
            data[name] = np.array([int(v) for v in values], dtype=np.int64)
        else:
            data[name] = np.array([float(v) for v in values], dtype=np.float64)
    cycle = data.pop("cycle")
    return xr.Dataset(
        {name: ("cycle", values) for name, values in data.items()},
        coords={"cycle": cycle},
        attrs={"commit_fraction": commit_fraction, "status": "running"},
    )


def _finalize_after_error(trackers: list[Any], status: str, message: str, ts_tracker: Any) -> None:
    """py-pde's Controller does not finalize trackers when the stepper raises: do it here."""
    _logger.error("%s", message)
    t_final = ts_tracker.rows["time"][-1] if ts_tracker.rows["time"] else 0.0
    info = {
        "controller": {
            "successful": False,
            "status": status,
            "stop_reason": message,
            "t_final": t_final,
        }
    }
    for tracker in trackers:
        try:
            tracker.finalize(info=info)
        except Exception:  # keep finalizing the others
            _logger.exception("finalizing %s failed", type(tracker).__name__)
