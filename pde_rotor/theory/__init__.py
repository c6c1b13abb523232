"""The exact onsets of motion from linear stability: the theory the bodies are checked against.

Each system is the no-flow limit (v = 0) of Eq. (eqc) with the force and torque of the
surface tension gamma = gamma0 - k c, Eq. (surfacetension), on the floating part F of a
body (the sign of ``rotor.torque = "physical"``). docs/bodies.md derives every result;
nothing here steps time, and the layer imports only :mod:`pde_rotor.config`.

* :mod:`.disk`: the camphor disk, its dish wall, its rest state and its force per unit
  displacement Phi(lambda), shared by the next two;
* :mod:`.free_disk`: a free disk on an unbounded surface: the velocity response
  K(lambda), the critical friction, the growth rate, the exact drive of a translating
  disk, the pitchfork's cubic coefficient and the steady speed;
* :mod:`.dish`: a disk at the centre of a dish: the Hopf onset with a no-flux wall
  (Koyano, Suematsu & Kitahata, PRE 2019), the drift from an absorbing one;
* :mod:`.two_disk_rotor`: the two-disk rotor of Koyano et al. (PRE 2017): the torque
  response, the critical friction, the growth rate and the critical size;
* :mod:`.ring`: the 1D limit of Eq. (eqc) for N point-like camphor boats on a ring: the
  speed of N evenly spaced boats, the Bloch modes of their spacing, the symmetric boat's
  onset of motion;
* :mod:`.ring_solve`: a direct spectral solve of the same 1D equations (moving point
  sources, overdamped boats) that checks :mod:`.ring`.
* :mod:`.ring_channel`: strip boats narrower than a straight no-flux channel, the exact
  2D steady state of N boats moving together (Fourier-cosine modes), which tends to
  :mod:`.ring` as the boat spans the channel.

Units are the config's: lengths in sqrt(D/a) when D = a = 1, times in 1/a.
"""

from __future__ import annotations

from .dish import dish_drift_rate, dish_hopf_onset, dish_hopf_rate
from .disk import CamphorDisk, Wall, free_disk_displacement_force, rest_concentration
from .free_disk import (
    free_disk_critical_friction,
    free_disk_cubic_coefficient,
    free_disk_drive,
    free_disk_force_coefficient,
    free_disk_growth_rate,
    free_disk_smoothed_coefficients,
    free_disk_steady_speed,
)
from .two_disk_rotor import (
    RotorGrid,
    rotor_critical_friction,
    rotor_critical_half_length,
    rotor_friction_moment,
    rotor_grid,
    rotor_growth_rate,
    rotor_torque_coefficient,
)

__all__ = [
    "CamphorDisk",
    "RotorGrid",
    "Wall",
    "dish_drift_rate",
    "dish_hopf_onset",
    "dish_hopf_rate",
    "free_disk_critical_friction",
    "free_disk_cubic_coefficient",
    "free_disk_displacement_force",
    "free_disk_drive",
    "free_disk_force_coefficient",
    "free_disk_growth_rate",
    "free_disk_smoothed_coefficients",
    "free_disk_steady_speed",
    "rest_concentration",
    "rotor_critical_friction",
    "rotor_critical_half_length",
    "rotor_friction_moment",
    "rotor_grid",
    "rotor_growth_rate",
    "rotor_torque_coefficient",
]
