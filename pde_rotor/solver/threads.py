"""How many threads one run's time steps use (``solver.threads``).

The fused CPU step (:func:`pde_rotor.kernels.cpu.advance`) shares its rows, spline
columns and contour nodes among numba's threads and adds every sum over fixed parts in a
fixed order, so a run has the same bits on any number of threads. The threads meet
once or twice a step; where another process keeps one of their cores busy, each meeting
waits for a thread the system has not scheduled, and two threads step 3 to 50 times
slower than one (docs/numerics.md, "Threads"). So ``solver.threads: null`` takes every
core the process may use that no other process is running on when the run starts
(:func:`free_cores`), at most numba's thread count of the calling thread: numba's
default is the cores the process may use (``os.sched_getaffinity``, capped by
``NUMBA_NUM_THREADS``), and a sweep's worker sets it to its runs' threads (one by default,
:func:`pde_rotor.sweep.tasks.execute_group`).
"""

from __future__ import annotations

import math
import os
import time
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

from ..config import ConfigError

LOADAVG = Path("/proc/loadavg")
"""Linux's load file: its fourth field is running / existing tasks (threads) right now."""
SAMPLES = 5
"""Readings of :data:`LOADAVG` per decision on the threads, 1 ms apart; the fewest
running tasks counts (a process that only wakes for a moment is not taken for one that
keeps a core busy)."""


def usable_cores() -> int:
    """CPU cores this process may run on (all cores where affinity is unknown)."""
    affinity = getattr(os, "sched_getaffinity", None)
    return len(affinity(0)) if affinity is not None else os.cpu_count() or 1


def other_tasks(samples: int = SAMPLES, pause: float = 1e-3) -> list[int] | None:
    """Tasks of other processes running now, per reading of :data:`LOADAVG` (the reading
    process itself is one of its running tasks), `pause` seconds apart; None where the
    file cannot be read (not Linux)."""
    counts = []
    for k in range(samples):
        if k:
            time.sleep(pause)
        try:
            counts.append(int(LOADAVG.read_text().split()[3].split("/")[0]) - 1)
        except (OSError, IndexError, ValueError):
            return None
    return counts


def free_cores() -> int:
    """The usable cores minus the tasks of other processes running now (at least 1), the
    fewest of :data:`SAMPLES` readings (:func:`other_tasks`); all usable cores where they
    cannot be read."""
    cores = usable_cores()
    others = other_tasks()
    if others is None:
        return cores
    return max(1, min(cores, cores - min(others)))


def other_load(samples: int = 50, pause: float = 0.01) -> float:
    """The cores other processes keep busy now: the mean of `samples` readings of their
    running tasks over half a second (:func:`other_tasks`); where they cannot be read, the
    1-minute load average (which also counts this process's own recent work)."""
    others = other_tasks(samples, pause)
    if others is None:
        return os.getloadavg()[0] if hasattr(os, "getloadavg") else 0.0
    return sum(others) / len(others)


FRESH_SECONDS = 2.0
"""How long a reading of the free cores serves the runs that start after it: code that
runs many short runs one after the other (the estimators' commitment checks) reads
:data:`LOADAVG` once every two seconds, not once a run."""
_last_reading = [-math.inf, 1]
"""When :func:`free_cores` was last read for :func:`resolve_threads`, and what it gave."""


def recent_free_cores() -> int:
    """:func:`free_cores`, read again only when the last reading is older than
    :data:`FRESH_SECONDS`."""
    now = time.monotonic()
    if now - _last_reading[0] > FRESH_SECONDS:
        _last_reading[:] = [now, free_cores()]
    return int(_last_reading[1])


def resolve_threads(requested: int | None) -> int:
    """The threads a run uses: `requested` (``solver.threads``), or for None the free
    cores (:func:`recent_free_cores`), at most numba's thread count of the calling thread.

    Raises:
        ConfigError: `requested` exceeds the threads numba may start in this process (one
            line naming ``solver.threads``, before any step).
    """
    import numba

    if requested is None:
        allowed = numba.get_num_threads()
        return 1 if allowed == 1 else min(allowed, recent_free_cores())
    limit = numba.config.NUMBA_NUM_THREADS
    if requested > limit:
        msg = (
            f"solver.threads = {requested}: numba starts at most {limit} threads in this "
            f"process (NUMBA_NUM_THREADS, by default the cores it may use); give 1 to "
            f"{limit}, or null for the free ones"
        )
        raise ConfigError(msg)
    return requested


@contextmanager
def running_on(threads: int) -> Iterator[None]:
    """Let numba's parallel loops started in this block use `threads` threads (then
    restore the calling thread's count)."""
    import numba

    previous = numba.get_num_threads()
    if threads == previous:
        yield
        return
    numba.set_num_threads(threads)
    try:
        yield
    finally:
        numba.set_num_threads(previous)
