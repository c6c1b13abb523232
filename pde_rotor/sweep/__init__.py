"""Parameter sweeps of inversion statistics: resumable, reproducible, movable.

A sweep is a YAML file (:class:`SweepSpec`)::

    name: fig5_quick
    base: coarse                    # a shipped base (coarse, paper), a config file
                                    # (relative to this file) or an inline mapping
    set: {noise.sigma: 2.0e-6}      # optional dotted-key overrides of the base
    axes:                           # any dotted config key: a list or a range
      protocol.t_stop: {start: 0.5, stop: 3.0, step: 0.5}
      geometry.asymmetry: [0.0, 2.0e-5, 1.0e-4]
    estimator: {kind: restart}      # or {kind: bank}, {kind: protocol} (M cycles per run),
                                    # or {kind: collective} (a bodies run's collective measures)
    samples: 40                     # restart: stops per direction; protocol: runs per point
    seed: 20200501

Every combination of axis values is a *point*; every point has ``samples`` *runs* (the
restart estimator: ``samples`` runs from CCW and ``samples`` from CW rotation). A run is
fully described by its resolved configuration, whose ``noise.seed`` is derived with
numpy's SeedSequence from (sweep seed, the point's coordinate values, sample index,
direction): results depend neither on the scheduling order nor on the number of workers.

One module per job:

* :mod:`.spec`: the sweep file's schema, shipped bases, ``--set`` overrides;
* :mod:`.placement`: a crowd of N copies of one body, placed on a ring or scattered in a
  dish (the ``crowd`` section, whose ``count`` an axis may vary);
* :mod:`.plan`: points, runs, seeds and run keys (:class:`Sweep`, :class:`Run`);
* :mod:`.estimators`: the protocol, restart and bank estimators, one module each, written
  once over the ensemble interface for both the dask tasks and the GPU batches;
* :mod:`.tasks`: a group of runs on a dask worker (with its spin-up cache);
* :mod:`.batch`: runs in batches on an ensemble backend (GPU);
* :mod:`.store`: the append-only run logs of a sweep directory (default
  data/sweeps/<name>), their one-pass reader, compaction and lock;
* :mod:`.execution`: :func:`run_sweep`, the seam between dask on CPUs and GPU batches;
* :mod:`.estimates`, :mod:`.reporting`: the statistics of a point and the report;
  :mod:`.collective_report`: the report of a collective sweep (measures against time);
* :mod:`.stored`: stored reports read back (points, curves, the same physics);
* :mod:`.plot`: the figure of any report (``pde-rotor plot``);
* :mod:`.cost`: estimated wall time of a run or a sweep.

Estimators (see :mod:`pde_rotor.statistics.proportions` and docs/statistics.md):

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
  at most release_cap (default protocol.t_release).
* ``bank``: restarts whose stop is shared by every noise intensity. The noise acts only
  on the moving rotor, so the end-of-stop state depends on the stop angle, the
  direction and the noise-free configuration alone; runs that differ only in their
  ``noise`` section (a ``noise.sigma`` axis) form one group (:func:`stop_group`),
  submitted as one task: the stop is computed once, noise-free, at a stop angle drawn
  uniformly over the period for this sample, direction and point, and each run is
  released from it with its own noise. The noise values are then a paired design,
  compared in the report by McNemar's exact test.

* ``collective``: one run of a bodies config per sample from rest to t_end, the bodies'
  poses recorded every ``record_interval`` and reduced to collective measures
  (:mod:`pde_rotor.collective`, docs/collective.md): ring (speed, spacing spread, cluster
  order, mode) or dish (g(r), speed, polar and rotational order).

P is the pooled fraction inversions / stops where Delta = 0 and the two-state chain
value 2ab/(a+b) where Delta != 0 (:mod:`.estimates`).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from .._lazy import lazy_exports

if TYPE_CHECKING:
    from .estimates import CHAIN, P_DEFINITIONS, POOLED, mcnemar_p, point_statistics
    from .execution import (
        SweepOutcome,
        check_scheduler,
        local_workers,
        run_sweep,
        sweep_backend,
        usable_cores,
    )
    from .plan import SCHEMA_VERSION, SPEC_FILE, Run, Sweep, base_config, run_key, run_seed
    from .reporting import format_table, gather, report
    from .spec import (
        BASES_DIR,
        SWEEP_KEYS,
        BankEstimator,
        ProtocolEstimator,
        RangeSpec,
        RestartEstimator,
        SweepError,
        SweepSpec,
        apply_sweep_overrides,
        shipped_base,
        shipped_bases,
        sweep_format,
    )
    from .store import (
        COMPACT_FILE,
        DEFAULT_ROOT,
        REPORT_FILE,
        RUNS_DIR,
        Compaction,
        RunLog,
        StoreBusyError,
        StoreError,
        compact,
        lock,
        read_runs,
    )
    from .tasks import (
        execute,
        execute_group,
        stop_group,
        warm_key,
        warm_state,
    )

__all__ = [
    "BASES_DIR",
    "CHAIN",
    "COMPACT_FILE",
    "DEFAULT_ROOT",
    "POOLED",
    "P_DEFINITIONS",
    "REPORT_FILE",
    "RUNS_DIR",
    "SCHEMA_VERSION",
    "SPEC_FILE",
    "SWEEP_KEYS",
    "BankEstimator",
    "Compaction",
    "ProtocolEstimator",
    "RangeSpec",
    "RestartEstimator",
    "Run",
    "RunLog",
    "StoreBusyError",
    "StoreError",
    "Sweep",
    "SweepError",
    "SweepOutcome",
    "SweepSpec",
    "apply_sweep_overrides",
    "base_config",
    "check_scheduler",
    "compact",
    "execute",
    "execute_group",
    "format_table",
    "gather",
    "local_workers",
    "lock",
    "mcnemar_p",
    "point_statistics",
    "read_runs",
    "report",
    "run_key",
    "run_seed",
    "run_sweep",
    "shipped_base",
    "shipped_bases",
    "stop_group",
    "sweep_backend",
    "sweep_format",
    "usable_cores",
    "warm_key",
    "warm_state",
]

__getattr__, __dir__ = lazy_exports(__name__)
