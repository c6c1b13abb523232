"""Where a sweep's runs are computed: dask.distributed on CPUs, or ensemble batches on a GPU.

:func:`run_sweep` is the one seam: it locks the sweep directory, reads the finished runs
from the store, picks the backend (:func:`sweep_backend`) and hands the unfinished runs
to dask tasks (:func:`.tasks.execute_group`) or to ensemble batches
(:func:`.batch.execute_batch`), appending each result to its log in the store
(:class:`.store.RunLog`) as it arrives.
"""

from __future__ import annotations

import signal
import threading
from collections.abc import Callable, Iterable, Sequence
from concurrent.futures import Future
from dataclasses import dataclass
from functools import partial
from pathlib import Path
from typing import Any

from ..backends import resolve_backend, run_ensemble
from ..solver.threads import usable_cores
from .batch import EnsembleRunner, batches, execute_batch
from .plan import Run, Sweep
from .spec import SweepError
from .store import RunLog, lock, prepare, read_runs
from .tasks import execute_group, stop_group, warm_group


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


def local_workers(workers: int | None, threads: int = 1) -> int:
    """The worker processes of a LocalCluster whose runs use `threads` threads each:
    `workers`, by default as many as the usable cores hold.

    Raises:
        SweepError: workers x threads exceed the usable cores (one line, what to give).
    """
    cores = usable_cores()
    n = workers or max(1, cores // threads)
    if n * threads > cores:
        fix = (
            f"--workers {cores // threads} with --threads {threads}"
            if threads <= cores
            else f"--threads {cores}"
        )
        msg = (
            f"--workers {n} x --threads {threads} = {n * threads} threads exceed the "
            f"{cores} usable cores of this machine: give at most {fix}"
        )
        raise SweepError(msg)
    return n


CONNECT_TIMEOUT = 5.0
"""Seconds to wait for a dask scheduler to answer before giving up (dask's default is 30)."""


def connect(scheduler: str, timeout: float | None = None) -> Any:
    """A dask Client on the running scheduler at `scheduler`.

    Args:
        scheduler: its address, e.g. ``tcp://node:8786``.
        timeout: seconds to wait for it (default: :data:`CONNECT_TIMEOUT`).

    Raises:
        SweepError: the scheduler did not answer within `timeout` seconds (one line
            naming the address and what to check).
    """
    from distributed import Client

    timeout = CONNECT_TIMEOUT if timeout is None else timeout
    try:
        return Client(scheduler, timeout=timeout)
    except (OSError, TimeoutError, ValueError) as err:
        reason = str(err).split("\n", 1)[0]
        msg = (
            f"--scheduler {scheduler}: no dask scheduler answered within {timeout:g} s "
            f"({reason}); check that `dask scheduler` runs there and that its port is "
            "reachable from this machine"
        )
        raise SweepError(msg) from None


def check_scheduler(scheduler: str, timeout: float | None = None) -> None:
    """Connect to `scheduler` and close again: the check a command makes before any compute.

    Raises:
        SweepError: as :func:`connect`.
    """
    connect(scheduler, timeout).close()


def _start_client(scheduler: str | None, workers: int | None, threads: int) -> tuple[Any, Any]:
    """A dask Client on the given scheduler, or on a new LocalCluster of processes
    (:func:`local_workers`)."""
    from distributed import Client, LocalCluster

    if scheduler:
        return connect(scheduler), None
    n = local_workers(workers, threads)
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


def sweep_backend(sweep: Sweep) -> str:
    """Where the runs of `sweep` are computed: ``cpu`` or ``gpu``.

    ``solver.backend`` of the base config, resolved on this machine
    (:func:`pde_rotor.backends.resolve_backend`).

    Raises:
        SweepError: ``gpu`` is requested but there is no usable GPU (one line, before
            anything runs).
    """
    try:
        return resolve_backend(sweep.base.get("solver", {}).get("backend", "cpu"))
    except RuntimeError as err:
        raise SweepError(f"base: solver.backend: {err}") from None


def run_sweep(
    sweep: Sweep | str | Path,
    sweep_dir: str | Path,
    *,
    scheduler: str | None = None,
    workers: int | None = None,
    threads: int = 1,
    progress: bool = True,
    ensemble: EnsembleRunner | None = None,
    batch_size: int = 256,
) -> SweepOutcome:
    """Run every unfinished run of a sweep and store its result.

    The one seam between the sweep and the compute backends: on the CPU the runs are
    tasks on dask.distributed (groups of :func:`.tasks.stop_group`); on the GPU
    (:func:`sweep_backend`) they go to the ensemble backend in batches of `batch_size`
    members (:func:`.batch.execute_batch`), computed in this process.

    Args:
        sweep: a :class:`Sweep` or the path of a sweep YAML file.
        sweep_dir: directory of the results (created; reused to resume).
        scheduler: address of a running dask scheduler (e.g. of a dask-jobqueue
            SLURMCluster); None starts a LocalCluster of worker processes.
        workers: number of LocalCluster workers (default: the usable CPU cores over
            `threads`).
        threads: threads of each worker's runs (their ``solver.threads``,
            :func:`.tasks.execute_group`); workers x threads may not exceed the usable
            cores (:func:`local_workers`).
        progress: show a tqdm bar counting finished runs.
        ensemble: the batch runner (``run_ensemble`` of a backend); given, it computes
            the runs whatever ``solver.backend`` says (default: the GPU backend when
            :func:`sweep_backend` is ``gpu``, else dask).
        batch_size: members per ensemble batch.

    Returns:
        Counts of skipped, computed and failed runs. Runs that raised are not stored
        and are retried by the next call.

    Raises:
        SweepError: workers x threads exceed the usable cores (before anything runs).
        StoreBusyError: another process is running a sweep in `sweep_dir` (one line, before
            anything runs or is written).
        StoreError: the store cannot be written (the runs stored so far are kept).
    """
    if not isinstance(sweep, Sweep):
        sweep = Sweep.load(sweep)
    if ensemble is None and sweep_backend(sweep) == "gpu":
        ensemble = partial(run_ensemble, backend="gpu")
    if ensemble is None and not scheduler:
        workers = local_workers(workers, threads)
    with lock(sweep_dir):
        sweep_dir = prepare(sweep, sweep_dir)
        runs = sweep.runs()
        stored = read_runs(sweep_dir)
        todo = in_order([run for run in runs if run.key not in stored])
        if ensemble is not None:
            groups = batches(todo, batch_size)
            submit = _in_process(partial(execute_batch, ensemble=ensemble))
        else:
            by_stop: dict[str, list[Run]] = {}
            for run in todo:
                by_stop.setdefault(stop_group(run), []).append(run)
            groups = list(by_stop.values())
            submit = None
        outcome = SweepOutcome(len(runs), len(runs) - len(todo), 0, [], sweep_dir)
        if todo:
            with RunLog(sweep_dir) as log:
                _compute(sweep, groups, outcome, log, submit, scheduler, workers, threads, progress)
    return outcome


def in_order(runs: Sequence[Run]) -> list[Run]:
    """`runs` in the order they are submitted.

    Runs sharing spin-ups (:func:`.tasks.warm_group`) are grouped together, so that workers
    reuse their warm states (two per group, one per direction). Within a group the order is
    by point and sample, and the directions alternate. A sweep that is stopped part way
    therefore holds about as many stops from CCW as from CW at each point it reached, and
    the chain estimate 2ab/(a+b) of its report is defined there.
    """
    return sorted(runs, key=lambda r: (warm_group(r), r.point, r.sample, r.direction))


Task = Callable[[Sequence[Run]], list[dict[str, Any]]]


def _in_process(task: Task) -> Callable[[list[Run]], Future]:
    """Submit `task` by calling it here (a GPU batch is one process's work)."""

    def submit(group: list[Run]) -> Future:
        future: Future = Future()
        try:
            future.set_result(task(group))
        except Exception as err:
            future.set_exception(err)
        return future

    return submit


def _compute(
    sweep: Sweep,
    groups: list[list[Run]],
    outcome: SweepOutcome,
    log: RunLog,
    submit: Callable[[list[Run]], Future] | None,
    scheduler: str | None,
    workers: int | None,
    threads: int,
    progress: bool,
) -> None:
    """Compute `groups` (dask tasks, or `submit` in this process) and append each result
    to `log`."""
    from ..trackers.progress import tqdm

    bar = tqdm(
        total=outcome.total,
        initial=outcome.skipped,
        unit="run",
        desc=sweep.spec.name,
        disable=not progress,
        dynamic_ncols=True,
    )
    client = cluster = None
    try:
        if submit is None:
            from distributed import as_completed

            client, cluster = _start_client(scheduler, workers, threads)
            futures = [
                client.submit(execute_group, group, threads, key=f"runs-{group[0].key}")
                for group in groups
            ]
            by_key = {f.key: g for f, g in zip(futures, groups, strict=True)}
            done: Iterable[tuple[list[Run], Any]] = (
                (by_key[f.key], f) for f in as_completed(futures)
            )
        else:
            done = ((group, submit(group)) for group in groups)
        for group, future in done:
            try:
                contents = future.result()
            except Exception as err:
                outcome.failed.extend((run.key, f"{type(err).__name__}: {err}") for run in group)
                bar.set_postfix(failed=len(outcome.failed))
                continue
            finally:
                if hasattr(future, "release"):
                    future.release()
            for content in contents:
                log.append(content)
            outcome.computed += len(group)
            bar.update(len(group))
    finally:
        bar.close()
        if client is not None:
            client.close()
        if cluster is not None:
            cluster.close()
