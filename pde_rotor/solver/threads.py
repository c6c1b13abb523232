"""How many threads one run's time steps use (``solver.threads``).

The fused CPU step (:func:`pde_rotor.kernels.cpu.advance`) shares its rows, spline
columns and contour nodes among numba's threads and adds every sum over fixed parts in a
fixed order, so a run has the same bits on any number of threads. ``solver.threads:
null`` takes numba's thread count of the calling thread: every core the process may use
(numba's default, ``os.sched_getaffinity``, capped by ``NUMBA_NUM_THREADS``), or what the
caller set with ``numba.set_num_threads``, as a sweep's worker does (one thread each by
default, :func:`pde_rotor.sweep.tasks.execute_group`).
"""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager

import numba

from ..config import ConfigError


def resolve_threads(requested: int | None) -> int:
    """The threads a run uses: `requested` (``solver.threads``) or numba's thread count.

    Raises:
        ConfigError: `requested` exceeds the threads numba may start in this process (one
            line naming ``solver.threads``, before any step).
    """
    if requested is None:
        return numba.get_num_threads()
    limit = numba.config.NUMBA_NUM_THREADS
    if requested > limit:
        msg = (
            f"solver.threads = {requested}: numba starts at most {limit} threads in this "
            f"process (NUMBA_NUM_THREADS, by default the cores it may use); give 1 to "
            f"{limit}, or null for all of them"
        )
        raise ConfigError(msg)
    return requested


@contextmanager
def running_on(threads: int) -> Iterator[None]:
    """Let numba's parallel loops started in this block use `threads` threads (then
    restore the calling thread's count)."""
    previous = numba.get_num_threads()
    if threads == previous:
        yield
        return
    numba.set_num_threads(threads)
    try:
        yield
    finally:
        numba.set_num_threads(previous)
