"""What a run's records need, in memory and on disk, estimated before the run starts.

The trackers hold their sampling times (and the time series they fill) in memory and
write the time series, the events, the field snapshots and the movie to disk. A config
that asks for more than the machine has (a typo such as ``protocol.cycles:
1000000000000``) would otherwise start, then fail deep inside numpy with a traceback;
:func:`check_budget` refuses it in one line, naming the keys that set the size, before
anything is compiled or written.
"""

from __future__ import annotations

import os
import shutil
from dataclasses import dataclass
from pathlib import Path

from ..config import ConfigError, RotorConfig
from .variables import EVENT_COLUMNS, TIMESERIES_VARIABLES

BYTES_PER_MOVIE_FRAME = 60_000
"""Disk taken by one H.264 frame of the movie at the default size (generous: the
quickstart's 215 frames take about 4 MB)."""
SNAPSHOT_FIELDS = 3
"""Components written per snapshot: c, v_x and v_y."""
NETCDF_BYTES = 24_000
"""Disk taken by an empty NetCDF-4 file (header and HDF5 metadata; the quickstart's
events.nc of three rows takes 18 kB)."""
SUMMARY_BYTES = 300_000
"""Disk taken by summary.png (the quickstart's takes 174 kB)."""
TEXT_BYTES = 64_000
"""config.yaml and run.log (a few kB each)."""
SNAPSHOT_RESERVE_BYTES = 1 << 20
"""Disk kept free for closing snapshots.h5 (HDF5 metadata and its 1 MiB chunk cache)."""


def snapshot_bytes(config: RotorConfig) -> int:
    """Bytes of one snapshot of the fields c, v_x, v_y (float64 on every cell)."""
    cells = (2 * config.grid.domain_radius / config.grid.dx + 1) ** 2
    return int(8 * SNAPSHOT_FIELDS * cells)


def snapshot_reserve(config: RotorConfig) -> int:
    """Disk that a run with snapshots holds in reserve until snapshots.h5 is closed.

    HDF5 cannot close a file whose last write failed, and the process then crashes; the
    snapshot tracker therefore keeps this much disk allocated (the chunk cache and two
    snapshots) and frees it just before it closes the file.
    """
    return SNAPSHOT_RESERVE_BYTES + 2 * snapshot_bytes(config)


@dataclass(frozen=True)
class Budget:
    """Estimated size of a run's records.

    Attributes:
        samples: time-series samples (every ``output.timeseries_interval`` and the two
            ends of every stop).
        memory: bytes held in memory while the run goes.
        disk: bytes written into the run directory.
    """

    samples: int
    memory: int
    disk: int


def estimate_budget(config: RotorConfig, movie: bool | None = None) -> Budget:
    """Estimate the memory and disk that the records of `config` take.

    Args:
        config: the run configuration.
        movie: whether a movie is rendered (default: ``output.movie``).
    """
    p, out = config.protocol, config.output
    t_end = p.t_end
    samples = int(t_end / out.timeseries_interval) + 2 * p.cycles + 2
    # int64 sampling steps and float64 values of every variable, in memory and on disk
    series = 8 * samples * (1 + len(TIMESERIES_VARIABLES))
    events = 8 * p.cycles * len(EVENT_COLUMNS) * 2  # events.csv and events.nc
    # timeseries.nc is rewritten as the run goes: the new copy is complete before the
    # old one is replaced, so both lie on the disk at once
    disk = 2 * (series + NETCDF_BYTES) + events + NETCDF_BYTES + SUMMARY_BYTES + TEXT_BYTES
    if out.snapshot_interval is not None:
        disk += int(snapshot_bytes(config) * (t_end / out.snapshot_interval + 1))
        disk += snapshot_reserve(config)
    if config.output.movie if movie is None else movie:
        disk += int(BYTES_PER_MOVIE_FRAME * (t_end / out.movie_interval + 1))
    return Budget(samples, series + events, disk)


def available_memory() -> int:
    """Bytes of memory available to a new allocation (the whole memory where unknown)."""
    try:
        return os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
    except (ValueError, OSError, AttributeError):
        return 1 << 62


def free_disk(directory: str | Path) -> int:
    """Free bytes on the file system that holds `directory` (or its nearest ancestor)."""
    path = Path(directory).absolute()
    while not path.exists() and path != path.parent:
        path = path.parent
    return shutil.disk_usage(path).free


def format_bytes(n: float) -> str:
    """``7.28 TiB``."""
    for unit in ("B", "KiB", "MiB", "GiB", "TiB", "PiB"):
        if abs(n) < 1024 or unit == "PiB":
            return f"{n:.3g} {unit}"
        n /= 1024
    raise AssertionError("unreachable")


def check_budget(
    config: RotorConfig, directory: str | Path | None = None, movie: bool | None = None
) -> Budget:
    """Refuse, in one line, a run whose records cannot fit in memory or on disk.

    Args:
        config: the run configuration.
        directory: the run directory (None: an in-memory run, no disk check).
        movie: whether a movie is rendered (default: ``output.movie``).

    Returns:
        The estimate.

    Raises:
        ConfigError: the records would need more memory than is available, or more
            disk than is free where `directory` lies.
    """
    budget = estimate_budget(config, movie)
    p = config.protocol
    what = (
        f"protocol.cycles = {p.cycles}, t_end = {p.t_end:g}: {budget.samples:,} time-series samples"
    )
    memory = available_memory()
    if budget.memory > memory:
        msg = (
            f"{what} need {format_bytes(budget.memory)} of memory, {format_bytes(memory)} "
            "are available (shorten the protocol or raise output.timeseries_interval)"
        )
        raise ConfigError(msg)
    if directory is not None:
        free = free_disk(directory)
        if budget.disk > free:
            msg = (
                f"the run's files need about {format_bytes(budget.disk)} on disk, "
                f"{format_bytes(free)} are free at {directory} ({what}; shorten the "
                "protocol, raise output.snapshot_interval or movie_interval, or --no-movie)"
            )
            raise ConfigError(msg)
    return budget
