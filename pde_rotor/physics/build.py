"""The physics compiled for a target: :func:`make_physics` and its CPU build :data:`CPU`.

Each module of the package builds its functions in a ``make_*`` factory for a given
compiler; :func:`make_physics` calls them in the order of their dependencies (the
spline before the indicators and the tension integral, which read it, the tension
before the motion, whose area integrals read it) and bundles the
results by topic. :data:`CPU` is the build for numba's CPU target, inlined into the loops
of :mod:`pde_rotor.kernels`; :mod:`pde_rotor.kernels.cuda` builds the same source as
CUDA device functions.

numba caches each compiled loop on disk keyed by its own file, not by what it inlines:
importing this module first drops the package's caches if any compiled source changed
since they were made (:func:`pde_rotor.physics.cache.refresh_caches`), so that no loop
keeps an inlined old version.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import NamedTuple

import numba as nb

from .cache import refresh_caches
from .indicators import Indicators, make_indicators
from .motion import Motion, make_motion
from .rates import Rates, make_rates
from .spline import Spline, make_spline
from .tension import Tension, make_tension

refresh_caches(Path(__file__).resolve().parents[1])


class Physics(NamedTuple):
    """The compiled physics of one target, by topic (one field per module)."""

    spline: Spline
    indicators: Indicators
    rates: Rates
    tension: Tension
    motion: Motion


def make_physics(jit: Callable[[Callable], Callable]) -> Physics:
    """Compile every physics function with `jit` (numba ``njit`` or ``cuda.jit(device=True)``).

    Args:
        jit: decorator turning a scalar Python function into a compiled one that other
            compiled functions of the same target can call.

    Returns:
        The compiled functions by topic; each calls only functions of the same build.
    """
    spline = make_spline(jit)
    tension = make_tension(jit, spline)
    return Physics(
        spline=spline,
        indicators=make_indicators(jit, spline),
        rates=make_rates(jit),
        tension=tension,
        motion=make_motion(jit, tension),
    )


FASTMATH = {"contract", "arcp", "nsz"}
"""numba fastmath flags of the CPU kernels: contraction into FMAs, reciprocals, no signed
zeros; no reassociation, so sums keep their order (and CPU results their bits)."""


def cpu_jit(func: Callable) -> Callable:
    """numba njit for the CPU loops: inlined into the caller, fastmath without reassociation."""
    return nb.njit(cache=True, nogil=True, fastmath=FASTMATH, inline="always")(func)


CPU: Physics = make_physics(cpu_jit)
"""The physics compiled for the CPU."""
