"""The sweep estimators, written once for every place a run is computed.

A run is computed either by a per-run task on a dask worker (:mod:`pde_rotor.sweep.tasks`)
or as a member of an ensemble batch (:mod:`pde_rotor.sweep.batch`); both take from here
what makes a stored run mean the same whichever computed it, over any ensemble backend
(:class:`pde_rotor.backends.base.EnsembleRunner`: the tasks call the estimators with the
CPU backend, the batches with theirs). One module per estimator:

* :mod:`.base`: what every estimator shares: the divergence check and the record of a
  run with its share of the wall time;
* :mod:`.protocol`: the paper's protocol, M stop-and-release cycles in one run;
* :mod:`.restart`: independent single stops: the spin-up and its steady states, the
  draw of the stop and the noise from the seeds, the step counts, the commit check of
  the release by the one inversion rule, the stored result;
* :mod:`.bank`: restarts whose noise-free stop is shared by every noise intensity: the
  noise-free approach computed once, the noise that starts at the end of the stop;
* :mod:`.releases`: the restart and bank estimators run as ensembles, each member read
  at the steps the rules above name;
* :mod:`.collective`: one bodies run per sample, its collective measures
  (:mod:`pde_rotor.collective`) recorded.
"""

from __future__ import annotations

from .bank import DelayedNoise, noise_free, run_distinct
from .base import check_finite, run_content, timed_contents
from .collective import Trajectory, collective_result, collective_runs, trajectory
from .protocol import protocol_result, protocol_runs, protocol_steps
from .releases import RECORD_BUDGET, restart_runs
from .restart import (
    WARM_MAX,
    Stop,
    Timing,
    check_spin_up,
    draw_stop,
    period_steps,
    release_outcome,
    restart_result,
    spin_up,
    stop_period,
    warm_states,
)

__all__ = [
    "RECORD_BUDGET",
    "WARM_MAX",
    "DelayedNoise",
    "Stop",
    "Timing",
    "Trajectory",
    "check_finite",
    "check_spin_up",
    "collective_result",
    "collective_runs",
    "draw_stop",
    "noise_free",
    "period_steps",
    "protocol_result",
    "protocol_runs",
    "protocol_steps",
    "release_outcome",
    "restart_result",
    "restart_runs",
    "run_content",
    "run_distinct",
    "spin_up",
    "stop_period",
    "timed_contents",
    "trajectory",
    "warm_states",
]
