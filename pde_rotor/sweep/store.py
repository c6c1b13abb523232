"""The store of a sweep: append-only logs of finished runs, read in one pass.

A sweep directory holds ``sweep.yaml`` (the specification, base inlined), ``runs/``
with the finished runs and ``report.nc``. A finished run is one *record*: a compact JSON
object on one line (run key, point coordinates, sample, direction, result, wall time,
backend). A run key is a hash of what determines the run's result
(:func:`pde_rotor.sweep.plan.run_key`), never of a path, a machine or the scheduler, so
the directory can be committed to the repository (the default is
``data/sweeps/<name>``) and a sweep resumed from a clone on another machine recomputes
nothing that is stored.

* **Writing** (:class:`RunLog`): every process that stores runs appends them to a log
  of its own, ``runs/<host>-<pid>-<random>.jsonl``, created on its first record. Each
  record is one ``os.write`` of one line, then ``os.fsync``: a crash loses at most the
  record being written, left behind as a torn last line. A write that fails (disk
  full, read-only) is undone and raises one :class:`StoreError` line; the records
  written before stay readable.
* **One writer per directory** (:func:`lock`): :func:`~pde_rotor.sweep.run_sweep` and
  :func:`compact` hold an exclusive advisory lock (``fcntl.flock``) on
  ``<sweep_dir>/.lock``, which records the holder's pid and host; a second process is
  refused with one :class:`StoreBusyError` line and leaves nothing behind. The lock dies
  with its process, so a killed sweep never blocks the next one.
* **Reading** (:func:`read_runs`): one pass over every ``runs/*.jsonl`` and the legacy
  ``runs/<key>.json`` files (one per run, as earlier versions stored them), giving a
  dict run key -> record. A line that is not a complete record (a torn last line
  without its newline, a corrupt line) is skipped with one warning naming the file and
  line: a run stored only there counts as not finished and is recomputed. A listed
  file that vanishes meanwhile (merged by a compaction) makes the reader list the
  files again. A key stored twice counts once: the record whose canonical JSON sorts
  first is kept, with one warning where the two results differ.
* **Compaction** (:func:`compact`, ``pde-rotor compact``): the logs and legacy files
  are merged into one ``runs/runs.jsonl`` sorted by key (duplicates and torn lines
  dropped), written atomically (temporary file, fsync, rename), after which the merged
  files are removed. Compacting again changes nothing; a compaction cut short leaves
  the merged files beside ``runs.jsonl``, which the reader deduplicates.

Commit a store compacted (a handful of files). Sessions that compute shares of one sweep
commit their own logs (distinct names, so merges do not conflict); ``runs.jsonl``
changed on two branches merges with git's ``union`` driver (``data/.gitattributes``):
the reader deduplicates the lines of both sides.
"""

from __future__ import annotations

import errno
import fcntl
import json
import logging
import os
import re
import secrets
import socket
from collections.abc import Iterator, Mapping
from contextlib import contextmanager, suppress
from dataclasses import dataclass, field
from pathlib import Path
from types import TracebackType
from typing import Any

import yaml

from ..io.output import write_text_atomic
from .plan import SPEC_FILE, Sweep
from .spec import SweepError

RUNS_DIR = "runs"
"""Sub-directory of a sweep directory holding the logs of finished runs."""
COMPACT_FILE = "runs.jsonl"
"""The log :func:`compact` writes in RUNS_DIR: every stored run, sorted by key."""
LOCK_FILE = ".lock"
"""File of a sweep directory locked by the process writing to it (:func:`lock`)."""
REPORT_FILE = "report.nc"
"""NetCDF file written by :func:`pde_rotor.sweep.reporting.report`."""
DEFAULT_ROOT = Path("data") / "sweeps"
"""Sweep directories default to data/sweeps/<name of the sweep file>: in the repository,
so that committed results travel with a clone and a sweep resumes from them."""

_logger = logging.getLogger(__name__)
_SHOWN_LINES = 5
"""Line numbers named in one warning about a file's unreadable lines."""
_ATTEMPTS = 3
"""Readings of a store's listing when its files vanish while they are read."""


class StoreError(SweepError):
    """A sweep directory's store cannot be read, written or locked; ``str(err)`` is one
    line."""


class StoreBusyError(StoreError):
    """Another process holds the lock of a sweep directory (:func:`lock`)."""


def _line(content: Mapping[str, Any]) -> str:
    """A record as it is stored: compact JSON on one line."""
    return json.dumps(content, separators=(",", ":"), allow_nan=True) + "\n"


def _canonical(value: Any) -> str:
    return json.dumps(value, sort_keys=True, separators=(",", ":"), allow_nan=True)


def _fsync_dir(path: Path) -> None:
    """Make the creation, renaming or removal of entries of directory `path` durable."""
    fd = os.open(path, os.O_RDONLY)
    try:
        os.fsync(fd)
    finally:
        os.close(fd)


class RunLog:
    """This process's append-only log of finished runs in a sweep directory.

    The file, ``runs/<host>-<pid>-<random>.jsonl``, is created on the first
    :meth:`append`; a log that is never appended to leaves nothing behind.

    Example:
        >>> with RunLog(sweep_dir) as log:  # doctest: +SKIP
        ...     log.append(content)
    """

    def __init__(self, sweep_dir: str | Path) -> None:
        """
        Args:
            sweep_dir: the sweep directory (its runs/ sub-directory must exist).
        """
        host = re.sub(r"[^A-Za-z0-9.-]", "_", socket.gethostname()) or "host"
        name = f"{host}-{os.getpid()}-{secrets.token_hex(4)}.jsonl"
        self.path = Path(sweep_dir) / RUNS_DIR / name
        self.records = 0
        self._fd: int | None = None

    def append(self, content: Mapping[str, Any]) -> None:
        """Store one finished run: its record in one write, flushed to disk.

        Raises:
            StoreError: the record cannot be written (no space, read-only, no
                directory); nothing of it is left in the log, and the records appended
                before are kept.
        """
        data = _line(content).encode("utf-8")
        start = None
        try:
            if self._fd is None:
                flags = os.O_WRONLY | os.O_CREAT | os.O_EXCL | os.O_APPEND | os.O_CLOEXEC
                self._fd = os.open(self.path, flags, 0o644)
                _fsync_dir(self.path.parent)
            start = os.fstat(self._fd).st_size
            if os.write(self._fd, data) != len(data):
                raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
            os.fsync(self._fd)
        except OSError as err:
            if self._fd is not None and start is not None:
                with suppress(OSError):  # the reader skips a torn line anyway
                    os.ftruncate(self._fd, start)  # no torn line before the next record
            msg = (
                f"cannot store a finished run in {self.path}: {err.strerror or err}; the "
                f"{self.records} runs stored before by this process are kept: make room "
                "(or make the directory writable) and rerun to resume"
            )
            raise StoreError(msg) from err
        self.records += 1

    def close(self) -> None:
        """Close the log file (idempotent)."""
        if self._fd is not None:
            os.close(self._fd)
            self._fd = None

    def __enter__(self) -> RunLog:
        return self

    def __exit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        self.close()


@dataclass
class _Scan:
    """What one pass over a store found."""

    records: dict[str, dict[str, Any]] = field(default_factory=dict)
    where: dict[str, str] = field(default_factory=dict)  # key -> file:line of the record
    sources: list[Path] = field(default_factory=list)  # files read
    dropped: int = 0  # unreadable lines and files

    def add(self, content: dict[str, Any], where: str) -> None:
        key = content["key"]
        kept = self.records.get(key)
        if kept is None:
            self.records[key], self.where[key] = content, where
            return
        if _canonical(kept.get("result")) != _canonical(content.get("result")):
            _logger.warning(
                "run %s is stored twice with different results (%s and %s); the record "
                "of %s is kept",
                key,
                self.where[key],
                where,
                where if _canonical(content) < _canonical(kept) else self.where[key],
            )
        if _canonical(content) < _canonical(kept):
            self.records[key], self.where[key] = content, where


def _record(text: bytes) -> dict[str, Any] | None:
    """The record on a line or in a legacy file; None if it is not one."""
    try:
        content = json.loads(text)
    except ValueError:
        return None
    if not isinstance(content, dict) or not isinstance(content.get("key"), str):
        return None
    return content


def _files(runs_dir: Path) -> list[tuple[Path, bytes]]:
    """Every file of a store with its bytes: legacy run files first, then logs, by name.

    A file that vanishes meanwhile was merged by a compaction, which renames runs.jsonl
    into place before it removes what it merged: the listing is then read again.
    """
    for _ in range(_ATTEMPTS):
        paths = [*sorted(runs_dir.glob("*.json")), *sorted(runs_dir.glob("*.jsonl"))]
        try:
            return [(path, path.read_bytes()) for path in paths]
        except FileNotFoundError:
            continue
        except OSError as err:
            msg = f"cannot read {err.filename}: {err.strerror or err}"
            raise StoreError(msg) from err
    msg = f"cannot read {runs_dir}: its files vanish while they are read"
    raise StoreError(msg)


def _scan_log(path: Path, data: bytes, scan: _Scan) -> None:
    lines = data.split(b"\n")
    torn = lines.pop()  # b"" where the file ends with its newline
    bad = []
    for number, line in enumerate(lines, start=1):
        if not line.strip():
            continue
        content = _record(line)
        if content is None:
            bad.append(number)
        else:
            scan.add(content, f"{path}:{number}")
    if torn.strip():
        bad.append(len(lines) + 1)
    if bad:
        scan.dropped += len(bad)
        more = f" and {len(bad) - _SHOWN_LINES} more" if len(bad) > _SHOWN_LINES else ""
        shown = ", ".join(map(str, bad[:_SHOWN_LINES]))
        _logger.warning(
            "%s: line%s %s%s: not a complete run record (torn or corrupt), ignored: a run "
            "stored only there is recomputed",
            path,
            "s" if len(bad) > 1 else "",
            shown,
            more,
        )


def _scan_legacy(path: Path, data: bytes, scan: _Scan) -> None:
    content = _record(data)
    if content is None or content["key"] != path.stem:
        scan.dropped += 1
        _logger.warning("%s: not a complete run file, ignored: its run is recomputed", path)
    else:
        scan.add(content, str(path))


def _scan(sweep_dir: str | Path) -> _Scan:
    """Read every record of a store (:func:`_files`)."""
    runs_dir = Path(sweep_dir) / RUNS_DIR
    scan = _Scan()
    if not runs_dir.is_dir():
        return scan
    for path, data in _files(runs_dir):
        scan.sources.append(path)
        if path.suffix == ".json":
            _scan_legacy(path, data, scan)
        else:
            _scan_log(path, data, scan)
    return scan


def read_runs(sweep_dir: str | Path) -> dict[str, dict[str, Any]]:
    """Every finished run stored in a sweep directory, by run key (see module docstring).

    A directory without runs/ (or none at all) holds no runs.

    Raises:
        StoreError: a file of the store cannot be read.
    """
    return _scan(sweep_dir).records


@dataclass
class Compaction:
    """What :func:`compact` did.

    Attributes:
        runs: runs stored in the compacted log.
        merged: files merged into it (logs, legacy run files and the previous
            compacted log).
        dropped: unreadable lines and files left out (their runs are recomputed).
        path: the compacted log.
    """

    runs: int
    merged: int
    dropped: int
    path: Path


def compact(sweep_dir: str | Path) -> Compaction:
    """Merge the logs and legacy run files of a sweep directory into runs/runs.jsonl.

    One record per run key, sorted by key; the file is written atomically, then the
    files merged into it are removed. Holds :func:`lock` meanwhile.

    Raises:
        StoreBusyError: a sweep is writing to the directory.
        StoreError: the directory is no sweep directory, or cannot be written.
    """
    sweep_dir = Path(sweep_dir)
    runs_dir = sweep_dir / RUNS_DIR
    if not runs_dir.is_dir():
        msg = f"{sweep_dir} holds no {RUNS_DIR}/ directory (not a sweep directory)"
        raise StoreError(msg)
    target = runs_dir / COMPACT_FILE
    with lock(sweep_dir):
        scan = _scan(sweep_dir)
        text = "".join(_line(scan.records[key]) for key in sorted(scan.records))
        try:
            if scan.sources != [target] or target.read_text(encoding="utf-8") != text:
                write_text_atomic(target, text)
                _fsync_dir(runs_dir)
                for path in scan.sources:
                    if path != target:
                        path.unlink()
                _fsync_dir(runs_dir)
        except OSError as err:
            msg = f"cannot compact {runs_dir}: {err.strerror or err}; nothing stored is lost"
            raise StoreError(msg) from err
    return Compaction(len(scan.records), len(scan.sources), scan.dropped, target)


def _busy(path: Path, holder: str) -> StoreBusyError:
    """The one line that refuses a locked sweep directory, naming its holder."""
    msg = (
        f"{path.parent} is busy: a sweep ({holder or 'pid unknown'}) is writing to "
        "it; wait for it to finish or stop it, then rerun"
    )
    return StoreBusyError(msg)


def check_not_busy(sweep_dir: str | Path) -> None:
    """Refuse at once a sweep directory that another process is writing to (:func:`lock`).

    Creates and changes nothing: the CLI asks before it reads the sweep file or prints
    anything, so a second sweep on one directory stops in a fraction of a second.
    :func:`lock` still decides (a sweep that starts in between is refused there).

    Raises:
        StoreBusyError: another process holds the lock (one line naming the holder).
    """
    path = Path(sweep_dir) / LOCK_FILE
    try:
        fd = os.open(path, os.O_RDONLY | os.O_CLOEXEC)
    except OSError:  # no lock file (or no directory): nobody holds it
        return
    try:
        fcntl.flock(fd, fcntl.LOCK_SH | fcntl.LOCK_NB)
    except BlockingIOError:
        raise _busy(path, os.read(fd, 256).decode("utf-8", "replace").strip()) from None
    finally:
        os.close(fd)


def _acquire(path: Path) -> int:
    """Open the lock file `path` and lock it; its descriptor.

    Raises:
        StoreBusyError: another process holds it (the message names the holder).
        OSError: it cannot be created or locked.
    """
    while True:
        fd = os.open(path, os.O_RDWR | os.O_CREAT | os.O_CLOEXEC, 0o644)
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            current = os.stat(path).st_ino == os.fstat(fd).st_ino
        except BlockingIOError:
            holder = os.read(fd, 256).decode("utf-8", "replace").strip()
            os.close(fd)
            raise _busy(path, holder) from None
        except FileNotFoundError:
            current = False
        except OSError:
            os.close(fd)
            raise
        if current:  # not a file that its previous holder removed after this one opened it
            return fd
        os.close(fd)


@contextmanager
def lock(sweep_dir: str | Path) -> Iterator[Path]:
    """Hold the exclusive lock of a sweep directory (created if missing); yields it.

    The lock file records ``pid PID on host HOST``; it is removed when the lock is
    released.

    Raises:
        StoreBusyError: another process holds it (one line: the directory, the holder, what
            to do); nothing is changed.
        StoreError: the directory cannot be created or locked (e.g. read-only).
    """
    sweep_dir = Path(sweep_dir)
    path = sweep_dir / LOCK_FILE
    try:
        sweep_dir.mkdir(parents=True, exist_ok=True)
        fd = _acquire(path)
    except OSError as err:
        msg = f"cannot lock {sweep_dir}: {err.strerror or err}"
        raise StoreError(msg) from err
    try:
        os.ftruncate(fd, 0)
        os.write(fd, f"pid {os.getpid()} on host {socket.gethostname()}\n".encode())
        yield path
    finally:
        path.unlink(missing_ok=True)  # while still held: a later locker opens a new file
        os.close(fd)


def holds(design: Sweep, sweep: Sweep) -> bool:
    """Whether every run of `sweep` is a run of `design` (same run keys: a subset of its
    axis values or samples, everything else equal)."""
    keys = {run.key for run in design.runs()}
    return all(run.key in keys for run in sweep.runs())


def prepare(sweep: Sweep, sweep_dir: str | Path) -> Path:
    """Create the sweep directory and record the design (base inlined) in its sweep.yaml.

    A design already recorded there that holds every run of `sweep` (:func:`holds`) is
    kept: a run of a subset (``--set axes.KEY=[...]``) adds runs to the directory without
    narrowing its design, so the directory's report and a resume from a clone still
    cover the whole design. Any other sweep (or an unreadable sweep.yaml) replaces it.

    Raises:
        StoreError: the directory cannot be created or written.
    """
    sweep_dir = Path(sweep_dir)
    spec_path = sweep_dir / SPEC_FILE
    try:
        (sweep_dir / RUNS_DIR).mkdir(parents=True, exist_ok=True)
        if spec_path.is_file():
            try:
                if holds(Sweep.load(spec_path), sweep):
                    return sweep_dir
            except SweepError:
                pass  # a record that no longer loads is replaced by this sweep's
        text = yaml.safe_dump(sweep.spec.model_dump(mode="json"), sort_keys=False)
        write_text_atomic(spec_path, text)
    except OSError as err:
        msg = f"cannot write the sweep directory {sweep_dir}: {err.strerror or err}"
        raise StoreError(msg) from err
    return sweep_dir
