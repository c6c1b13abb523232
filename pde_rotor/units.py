"""Units of every output: the paper's dimensionless units (section "Model").

Lengths are in units of the camphor diffusion length sqrt(D/a), times in units of 1/a
(a: the evaporation rate of camphor); written as the ``units`` attribute of every
NetCDF variable and on every axis of the plots.
"""

from __future__ import annotations

TIME_UNITS = "1/a"
"""Unit of every time in the outputs: the paper's dimensionless time, in units of 1/a
(a: the evaporation rate of camphor)."""
OMEGA_UNITS = f"rad per {TIME_UNITS}"
"""Unit of the angular velocity omega."""
LENGTH_UNITS = "sqrt(D/a)"
