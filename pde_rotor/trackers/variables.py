"""The variables of a run's records: timeseries.nc's and the events' columns.

Plain data, apart from the trackers that fill them, so that the disk budget
(:mod:`.budget`) is computed without importing py-pde or xarray.
"""

from __future__ import annotations

from ..units import OMEGA_UNITS, TIME_UNITS

TIMESERIES_VARIABLES: dict[str, dict[str, str]] = {
    "phi": {
        "long_name": "rotor angle phi",
        "units": "rad",
        "equation": "Eq. (eq_motion): dphi/dt = omega",
    },
    "omega": {
        "long_name": "angular velocity dphi/dt",
        "units": OMEGA_UNITS,
        "equation": "Eq. (eq_motion)",
    },
    "torque": {
        "long_name": "surface tension torque T (of the last step)",
        "units": "model units (k, D, a = 1)",
        "equation": "Eq. (torque)",
    },
    "friction": {
        "long_name": "friction torque -mu int F (|r|^2 omega - r x v) dA (of the last step)",
        "units": "model units (k, D, a = 1)",
        "equation": "Eq. (eq_motion)",
    },
    "camphor_total": {
        "long_name": "total camphor int c dA over the domain",
        "units": "model units",
        "equation": "Eq. (eqc)",
    },
    "stopped": {
        "long_name": "1 if the last step was in a stop phase (phi frozen, omega = 0)",
        "units": "1",
        "equation": "protocol (section Model)",
    },
    "cycle": {
        "long_name": "stop-and-release cycle m of the last step (0: before the first stop)",
        "units": "1",
        "equation": "protocol (section Model)",
    },
}
"""Variables of timeseries.nc with their attributes."""

EVENT_COLUMNS = (
    "cycle",
    "t_stop",
    "omega_before",
    "direction_before",
    "direction_after",
    "inverted",
    "committed",
    "time_to_commit",
    "omega_after",
)
"""Columns of events.csv / variables of events.nc (see module docstring)."""

EVENT_ATTRS: dict[str, dict[str, str]] = {
    "t_stop": {"long_name": "start time of the stop", "units": TIME_UNITS},
    "omega_before": {"long_name": "omega just before the stop", "units": OMEGA_UNITS},
    "direction_before": {"long_name": "sign of omega_before (+1: counterclockwise)"},
    "direction_after": {"long_name": "sign of omega at commit (0: not committed)"},
    "inverted": {"long_name": "committed and direction_after == -direction_before"},
    "committed": {"long_name": "|omega| reached commit_fraction |omega_before| after release"},
    "time_to_commit": {"long_name": "commit time minus release time", "units": TIME_UNITS},
    "omega_after": {
        "long_name": "omega at commit (or at the last sample of the release)",
        "units": OMEGA_UNITS,
    },
}
