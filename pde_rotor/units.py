"""Units of every output: the paper's dimensionless units (section "Model").

Lengths are in units of the camphor diffusion length sqrt(D/a), times in units of 1/a
(a: the evaporation rate of camphor); written as the ``units`` attribute of every
NetCDF variable and on every axis of the plots.
"""

from __future__ import annotations

TIME_UNITS = "1/a"
"""Unit of every time in the outputs: the paper's dimensionless time, in units of 1/a
(a: the evaporation rate of camphor)."""
OMEGA_UNITS = "rad\u00b7a"
"""Unit of the angular velocity omega: radians per time unit 1/a, written rad·a."""
LENGTH_UNITS = "sqrt(D/a)"
CONCENTRATION_UNITS = "s0/D"
"""Unit of the camphor surface concentration c: with lengths in sqrt(D/a), Eq. (eqc)
balances a c against the supply s0 / (pi rho^2), so c is an amount per area in units of
s0 / (a D/a) = s0/D."""
