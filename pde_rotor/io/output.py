"""Run directory layout and atomic file writing.

A run directory holds (names in :class:`RunDirectory`):

* ``config.yaml``: the fully resolved configuration with a provenance block (package
  versions, seed, config hash); ``pde-rotor run RUN_DIR/config.yaml`` repeats the run;
* ``timeseries.nc``: t, phi, omega, torque, friction, total camphor (xarray / NetCDF);
* ``bodies.nc``: with ``bodies:``, every body's pose, velocities and forces over (time, body);
* ``events.csv`` (appended row by row as the run goes) and ``events.nc``: one row per
  stop-and-release cycle;
* ``snapshots.h5``: fields c and v (py-pde FileStorage);
* ``movie.mp4``, ``summary.png`` and ``run.log``.

Every file except the two append-only streams (events.csv, run.log) is written under
the temporary name ``NAME.part`` in the same directory and renamed with
:func:`os.replace` when complete, so a file with its final name is always complete. An
interrupted run leaves ``*.part`` files, which never look finished. While snapshots are
written, ``.snapshots.h5.reserve`` holds the disk that closing them needs
(:class:`pde_rotor.trackers.SnapshotTracker`).
"""

from __future__ import annotations

import csv
import io
import logging
import os
import tempfile
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from datetime import datetime
from pathlib import Path
from typing import IO, TYPE_CHECKING, Any

if TYPE_CHECKING:
    import xarray as xr

PART_SUFFIX = ".part"
"""Suffix of files being written; they are renamed to their final name when complete."""


class OutputError(OSError):
    """A run directory cannot be used; ``str(err)`` is one readable line."""


def _reason(err: OSError) -> str:
    """The readable part of an OSError ("Permission denied", "No space left on device")."""
    return err.strerror or str(err)


def _nearest_file(path: Path) -> Path:
    """The first of `path` and its ancestors that exists (a file where a directory is needed)."""
    while not path.exists() and path != path.parent:
        path = path.parent
    return path


def check_output_dir(path: str | Path, option: str = "--out") -> Path:
    """Refuse, in one line, a directory that cannot be created and written to.

    The check creates what is missing and a probe file, then removes them again, so it
    holds for root too (permission bits do not stop root, /proc or a read-only mount
    do) and a refused command leaves nothing behind. It runs before any compute.

    Args:
        path: the directory a command will create (with its parents) and write into.
        option: the command-line option that named it, for the message.

    Returns:
        `path` as a Path.

    Raises:
        OutputError: the path or one of its ancestors is a file, or the directory
            cannot be created or written to (the reason is named).
    """
    path = Path(path)
    missing = []
    existing = path.absolute()
    while not existing.exists() and existing != existing.parent:
        missing.append(existing)
        existing = existing.parent
    if not existing.is_dir():
        what = "it is a file" if not missing else f"{str(existing)!r} is a file"
        msg = f"{option} {str(path)!r} must be a directory, but {what}"
        raise OutputError(msg)
    created: list[Path] = []
    try:
        for directory in reversed(missing):
            directory.mkdir()
            created.append(directory)
        fd, probe = tempfile.mkstemp(dir=path, prefix=".pde-rotor-probe-")
        os.close(fd)
        os.unlink(probe)
    except OSError as err:
        msg = f"{option} {str(path)!r}: cannot create or write there ({_reason(err)})"
        raise OutputError(msg) from None
    finally:
        for directory in reversed(created):
            directory.rmdir()
    return path


def check_output_file(path: str | Path, option: str = "--out") -> Path:
    """Refuse, in one line, a file path that cannot be written (see :func:`check_output_dir`).

    Raises:
        OutputError: the path is a directory, or its directory cannot be created or
            written to.
    """
    path = Path(path)
    if path.is_dir():
        msg = f"{option} {str(path)!r} is a directory; give a file name"
        raise OutputError(msg)
    try:
        check_output_dir(path.parent, option=option)
    except OutputError as err:
        msg = f"{option} {str(path)!r}: {str(err).split(': ', 1)[-1]}"
        if "must be a directory" in str(err):
            parent = _nearest_file(path.parent)
            msg = f"{option} {str(path)!r}: {str(parent)!r} is a file, not a directory"
        raise OutputError(msg) from None
    return path


def part_path(path: str | Path) -> Path:
    """Temporary name used while `path` is written (same directory, so rename is atomic)."""
    path = Path(path)
    return path.with_name(path.name + PART_SUFFIX)


def _fsync(path: Path) -> None:
    """Flush a closed file's data to disk before it is renamed."""
    fd = os.open(path, os.O_RDONLY)
    try:
        os.fsync(fd)
    finally:
        os.close(fd)


def commit(tmp: str | Path, path: str | Path) -> None:
    """Rename the finished temporary file `tmp` to `path` atomically."""
    _fsync(Path(tmp))
    os.replace(tmp, path)


@contextmanager
def atomic_path(path: str | Path) -> Iterator[Path]:
    """Yield a temporary path; rename it to `path` if the block succeeds, else delete it.

    Example:
        >>> with atomic_path(run / "timeseries.nc") as tmp:  # doctest: +SKIP
        ...     dataset.to_netcdf(tmp)
    """
    path = Path(path)
    tmp = part_path(path)
    try:
        yield tmp
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise
    commit(tmp, path)


def write_text_atomic(path: str | Path, text: str) -> None:
    """Write `text` to `path` atomically (UTF-8)."""
    with atomic_path(path) as tmp:
        tmp.write_text(text, encoding="utf-8")


def write_netcdf_atomic(dataset: xr.Dataset, path: str | Path) -> None:
    """Write an xarray Dataset as NetCDF-4 (h5netcdf engine) atomically.

    The file is built in memory and written with plain file I/O: HDF5 never writes to
    the disk itself. An HDF5 file whose write fails (a full disk) cannot be closed, and
    the next file HDF5 opens under the same name then crashes the process
    (segmentation fault); written this way a full disk is one ``OSError``
    (``ENOSPC``), after which every later write works or fails cleanly.

    Raises:
        OSError: the file cannot be written (nothing is left under its name or its
            ``.part`` name; an earlier complete file stays as it was).
    """
    data = dataset.to_netcdf(engine="h5netcdf")
    try:
        with atomic_path(path) as tmp, tmp.open("wb") as fh:
            fh.write(data)
    except OSError as err:
        raise OSError(err.errno, err.strerror or str(err), str(path)) from err


class AppendOnlyCSV:
    """CSV file written row by row; every row is flushed to disk when it is added.

    A crash keeps the header and every complete row written so far; a row that cannot
    be written whole (a full disk) is taken back, so the file never ends in half a row.
    """

    def __init__(self, path: str | Path, columns: Sequence[str]):
        """
        Args:
            path: file to create (truncated if present).
            columns: column names written as the header.
        """
        self.path = Path(path)
        self.columns = list(columns)
        self._file: IO[bytes] | None = self.path.open("wb", buffering=0)
        self._write(self.columns)

    def append(self, row: dict[str, Any]) -> None:
        """Write one row (keys: the columns) and flush it to disk.

        Raises:
            OSError: the row cannot be written (the file keeps the rows before it).
        """
        if self._file is None:
            msg = f"{self.path} is closed"
            raise ValueError(msg)
        self._write([_csv_value(row[name]) for name in self.columns])

    def _write(self, values: Sequence[str]) -> None:
        assert self._file is not None
        text = io.StringIO()
        csv.writer(text).writerow(values)
        data = text.getvalue().encode("utf-8")
        end = self._file.tell()
        try:
            view = memoryview(data)
            while view:
                view = view[self._file.write(view) :]
            os.fsync(self._file.fileno())
        except OSError as err:
            os.ftruncate(self._file.fileno(), end)
            self._file.seek(end)
            raise OSError(err.errno, err.strerror or str(err), str(self.path)) from err

    def close(self) -> None:
        """Close the file (idempotent)."""
        if self._file is not None:
            self._file.close()
            self._file = None


def _csv_value(value: Any) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        return repr(value)
    return str(value)


class RunDirectory:
    """The files of one run (see module docstring)."""

    FILES = (
        "config.yaml",
        "timeseries.nc",
        "bodies.nc",
        "events.csv",
        "events.nc",
        "snapshots.h5",
        "movie.mp4",
        "summary.png",
        "run.log",
    )

    def __init__(self, path: str | Path):
        """
        Args:
            path: the directory (not created; see :meth:`create`).
        """
        self.path = Path(path)

    @classmethod
    def create(cls, path: str | Path, *, overwrite: bool = False) -> RunDirectory:
        """Create the directory; refuse one that already holds run files.

        Args:
            path: directory to create.
            overwrite: delete the run files (and their ``.part`` files) of an earlier
                run there instead of refusing.

        Raises:
            OutputError: the path is a file, holds files but no run (somebody else's
                directory), or holds an earlier run and not `overwrite`. Files of the
                user's beside an earlier run (notes) are kept.
        """
        run = cls(path)
        if run.path.exists() and not run.path.is_dir():
            msg = f"output path {str(run.path)!r} is a file, not a directory"
            raise OutputError(msg)
        others = sorted(
            p.name
            for p in (run.path.iterdir() if run.path.is_dir() else ())
            if not p.name.startswith(".")
            and p.name not in cls.FILES
            and p.name not in {part_path(name).name for name in cls.FILES}
        )
        present = [name for name in cls.FILES if (run.path / name).exists()]
        present += [name for name in cls.FILES if part_path(run.path / name).exists()]
        if others and not present:
            msg = (
                f"output directory {str(run.path)!r} holds {others[0]} and no run: choose a "
                "new or empty directory"
            )
            raise OutputError(msg)
        if present and not overwrite:
            msg = (
                f"output directory {str(run.path)!r} already holds a run ({present[0]}); "
                "choose another --out or pass --overwrite"
            )
            raise OutputError(msg)
        try:
            run.path.mkdir(parents=True, exist_ok=True)
        except OSError as err:
            msg = f"cannot create output directory {str(run.path)!r}: {err.strerror}"
            raise OutputError(msg) from None
        for name in cls.FILES:
            (run.path / name).unlink(missing_ok=True)
            part_path(run.path / name).unlink(missing_ok=True)
            (run.path / f".{name}.reserve").unlink(missing_ok=True)
        return run

    @staticmethod
    def default_path(config_path: str | Path | None, root: str | Path = "runs") -> Path:
        """``runs/<config name>-<YYYYmmdd-HHMMSS>``, the CLI's default output directory."""
        stem = Path(config_path).stem if config_path else "run"
        if stem == "config":
            stem = Path(config_path).parent.name or "run"
        stamp = datetime.now().strftime("%Y%m%d-%H%M%S")
        return Path(root) / f"{stem}-{stamp}"

    def __truediv__(self, name: str) -> Path:
        return self.path / name

    @property
    def config(self) -> Path:
        """config.yaml: resolved configuration with provenance."""
        return self.path / "config.yaml"

    @property
    def timeseries(self) -> Path:
        """timeseries.nc: rotor time series."""
        return self.path / "timeseries.nc"

    @property
    def events_csv(self) -> Path:
        """events.csv: inversion events, appended as the run goes."""
        return self.path / "events.csv"

    @property
    def events_nc(self) -> Path:
        """events.nc: inversion events as a Dataset over cycles."""
        return self.path / "events.nc"

    @property
    def snapshots(self) -> Path:
        """snapshots.h5: py-pde FileStorage of the fields [c, v]."""
        return self.path / "snapshots.h5"

    @property
    def movie(self) -> Path:
        """movie.mp4."""
        return self.path / "movie.mp4"

    @property
    def summary(self) -> Path:
        """summary.png: figure written by ``pde-rotor show``."""
        return self.path / "summary.png"

    @property
    def log(self) -> Path:
        """run.log."""
        return self.path / "run.log"

    def attach_log(self, loggers: Sequence[str] = ("pde_rotor", "pde")) -> logging.Handler:
        """Send INFO and above of the named loggers to run.log; returns the handler.

        Detach it with :func:`detach_log` when the run ends.
        """
        handler = _RunLogHandler(self.log, mode="a", encoding="utf-8")
        handler.setLevel(logging.INFO)
        handler.setFormatter(
            logging.Formatter("%(asctime)s %(levelname)s %(name)s: %(message)s", "%H:%M:%S")
        )
        saved = {}
        for name in loggers:
            logger = logging.getLogger(name)
            logger.addHandler(handler)
            saved[name] = logger.level
            if logger.getEffectiveLevel() > logging.INFO:
                logger.setLevel(logging.INFO)
        handler.saved_levels = saved  # type: ignore[attr-defined]
        return handler


class _RunLogHandler(logging.FileHandler):
    """run.log's handler: a write that fails (a full disk) ends the log quietly.

    logging's default prints a traceback to stderr for every record it cannot write; on
    a full disk that buried the one line saying why the run stopped. The lines written
    before stay in run.log.
    """

    failed = False

    def emit(self, record: logging.LogRecord) -> None:
        if not self.failed:
            super().emit(record)

    def handleError(self, record: logging.LogRecord) -> None:  # noqa: N802
        self.failed = True
        try:
            self.close()
        except OSError:  # the buffered rest cannot be written either
            self.stream = None  # type: ignore[assignment]


def detach_log(handler: logging.Handler, loggers: Sequence[str] = ("pde_rotor", "pde")) -> None:
    """Remove a handler added by :meth:`RunDirectory.attach_log` and close it."""
    saved = getattr(handler, "saved_levels", {})
    for name in loggers:
        logger = logging.getLogger(name)
        logger.removeHandler(handler)
        if name in saved:
            logger.setLevel(saved[name])
    handler.close()
