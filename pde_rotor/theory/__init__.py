"""Reduced theories the simulations are checked against.

* :mod:`.ring` — the 1D limit of Eq. (eqc) for N point-like camphor boats on a ring: the
  speed of N evenly spaced boats, the Bloch modes of their spacing, the symmetric boat's
  onset of motion.
* :mod:`.ring_solve` — a direct spectral solve of the same 1D equations (moving point
  sources, overdamped boats) that checks :mod:`.ring`.
"""
