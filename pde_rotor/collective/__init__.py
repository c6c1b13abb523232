"""Collective measures of many camphor bodies from their trajectories (numpy only).

The measures reduce the poses of K bodies at the record times to a few numbers per
record and per run; docs/collective.md defines each and its thresholds.

* :mod:`.ring`: bodies round a ring (boats in an annular channel): angular and arc speed,
  spacing spread, lattice and cluster order, gap mobility, and the mode (uniform,
  clusters, density wave, stop);
* :mod:`.dish`: free bodies in a circular dish: pair correlation g(r) with the dish's
  finite-size normalisation, mean speed, polar and rotational order.
"""

from __future__ import annotations

from .dish import (
    disk_pair_density,
    mean_speed,
    pair_correlation,
    pair_counts,
    polar_order,
    rotational_order,
)
from .ring import (
    MODES,
    NET_SPEED,
    STOP_SPEED,
    UNIFORM_SPREAD,
    WAVE_MOBILITY,
    angular_velocity,
    cluster_order,
    gap_mobility,
    gaps,
    lattice_order,
    ring_angles,
    ring_mode,
    spacing_spread,
)

__all__ = [
    "MODES",
    "NET_SPEED",
    "STOP_SPEED",
    "UNIFORM_SPREAD",
    "WAVE_MOBILITY",
    "angular_velocity",
    "cluster_order",
    "disk_pair_density",
    "gap_mobility",
    "gaps",
    "lattice_order",
    "mean_speed",
    "pair_correlation",
    "pair_counts",
    "polar_order",
    "ring_angles",
    "ring_mode",
    "rotational_order",
    "spacing_spread",
]
