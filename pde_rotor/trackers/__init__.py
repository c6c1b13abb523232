"""py-pde trackers that watch a rotor run: progress, time series, inversion events, fields, movie.

py-pde's :class:`~pde.solvers.Controller` calls every tracker at the times its
``interrupts`` ask for, before advancing the state further (see pde/trackers/base.py).
The fused solver advances whole steps of dt, so every interrupt time used here is an
integer number of steps; the trackers that record the rotor ask in addition for the
start and the end of every stop phase (:meth:`StopSchedule.stop_times`), so that the
angular velocity just before each stop is sampled exactly.

Every tracker reads what it records from the state py-pde hands it: the fields c and v
and ``state.rotor`` (:class:`~pde_rotor.model.pde.RotorFields`), which holds phi, omega
(Eq. (eq_motion)) and the torque T (Eq. (torque)) and friction torque of the last step.
Its constructor takes the run's setup (:class:`~pde_rotor.model.setup.Setup`) or its
configuration, whose stop schedule sets its sampling times.

What the records of a run need in memory and on disk is estimated, and a run that
cannot fit refused, by :mod:`.budget`. One module per tracker; this package hands them
on under one name, as py-pde's ``pde.trackers`` does.

* :mod:`.base`: the base of the rotor trackers (interrupts in whole steps, run status);
* :mod:`.progress`: a tqdm bar with an ETA that leaves the compile time out;
* :mod:`.timeseries`: phi, omega, torques and total camphor in timeseries.nc;
* :mod:`.events`: one row per stop-and-release cycle, inverted or not;
* :mod:`.snapshots`: the fields c and v in a py-pde HDF5 FileStorage;
* :mod:`.movie`: the movie of c, v and the rotor, into an mp4;
* :mod:`.bodies`: every body's pose, velocities and forces in bodies.nc, and the stops of
  each body with a protocol classified;
* :mod:`.budget`: the memory and disk the records need, checked before a run;
* :mod:`.variables`: the variables of timeseries.nc and the columns of the events.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from .._lazy import lazy_exports

if TYPE_CHECKING:
    from .budget import Budget, check_budget, estimate_budget
    from .events import InversionEvent, InversionTracker
    from .movie import MovieTracker
    from .progress import ProgressBarTracker
    from .snapshots import SnapshotTracker
    from .timeseries import TimeSeriesTracker
    from .variables import EVENT_ATTRS, EVENT_COLUMNS, TIMESERIES_VARIABLES

__all__ = [
    "EVENT_ATTRS",
    "EVENT_COLUMNS",
    "TIMESERIES_VARIABLES",
    "Budget",
    "InversionEvent",
    "InversionTracker",
    "MovieTracker",
    "ProgressBarTracker",
    "SnapshotTracker",
    "TimeSeriesTracker",
    "check_budget",
    "estimate_budget",
]

__getattr__, __dir__ = lazy_exports(__name__)
