"""The cubic spline of c, written once for the compiled targets.

The contour form of the tension integral (:mod:`.tension`) and the filtered tables of
the ``consistent`` scheme (:mod:`.indicators`) read a field between its cell centres
through its interpolating cubic spline: Unser's recursive B-spline prefilter, symmetric
under mirroring (:func:`spline_line` from its steps :func:`spline_reach`,
:func:`spline_coefficient`), the B-spline weights and taps
(:func:`bspline_weights`, :func:`spline_node`, :func:`spline_sum`; about the grid's
middle, mirror for mirror, :func:`mirror_node`) and the value at a point
(:func:`interpolate`). ``scipy.ndimage`` does the same outside compiled code
(:func:`pde_rotor.model.schemes.interpolate_spline`, the test oracle).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import NamedTuple

SPLINE_POLE = math.sqrt(3.0) - 2.0
"""Pole of the cubic B-spline prefilter (Unser, IEEE Signal Process. Mag. 1999)."""

SPLINE_GAIN = math.sqrt(3.0)
"""-6 z / (1 - z^2) for the pole z: the gain of the prefilter's partial fractions."""

SPLINE_MARGIN = 24
"""Cells the spline window extends beyond the contour's taps: |pole|^24 = 2e-14."""


class Spline(NamedTuple):
    """The compiled spline functions for one target (see the module docstring)."""

    spline_reach: Callable
    spline_coefficient: Callable
    spline_line: Callable
    bspline_weights: Callable
    spline_node: Callable
    mirror_node: Callable
    spline_sum: Callable
    interpolate: Callable


def make_spline(jit: Callable[[Callable], Callable]) -> Spline:
    """Compile the spline functions with `jit`.

    Args:
        jit: decorator turning a scalar Python function into a compiled one that other
            compiled functions of the same target can call (numba ``njit`` or
            ``cuda.jit(device=True)``, :func:`pde_rotor.physics.build.make_physics`).

    Returns:
        The compiled functions.
    """

    @jit
    def spline_reach(prev):
        """The pole's share z y of the previous output `y` of a recursion of the cubic
        B-spline prefilter (pole z = sqrt(3) - 2): a recursion's output is its sample
        plus this, y_k = s_k + z y_(k -/+ 1); the first output is the first sample."""
        return SPLINE_POLE * prev

    @jit
    def spline_coefficient(forward, backward, sample):
        """The B-spline coefficient sqrt(3) ((p_k + m_k) + s_k) of sample s_k from the
        reaches p_k of the forward recursion and m_k of the backward one
        (:func:`spline_reach`): the prefilter 6 / (q + 4 + 1/q) split into partial
        fractions, -6 z / (1 - z^2) (1 / (1 - z/q) + 1 / (1 - z q) - 1), where
        -6 z / (1 - z^2) = sqrt(3). p_k and m_k add first, so that the coefficient
        does not depend on the line's direction: a mirrored line has mirrored
        coefficients, bit for bit."""
        return SPLINE_GAIN * ((forward + backward) + sample)

    @jit
    def spline_line(src, so, dst, o, stride, count):
        """Cubic B-spline prefilter of `count` samples src[so + k stride] into the
        coefficients dst[o + k stride] (another place than the samples).

        Turns samples into the coefficients of the interpolating cubic spline (Unser's
        recursive filter as two independent recursions, :func:`spline_reach`, one from
        each end, joined by :func:`spline_coefficient`): the backward reaches m_k go to
        dst first, the forward pass then finishes each coefficient. The samples beyond
        both ends are taken as 0: a coefficient then errs by |z|^k = 0.268^k times the
        values k cells beyond the line's ends, so lines cut from a larger field need a
        margin. The same steps from either end make the filter commute with mirroring
        exactly. Written out because it runs inside the CUDA kernels, which cannot call
        scipy.ndimage's prefilter (``map_coordinates`` applies it in
        :func:`pde_rotor.model.schemes.interpolate_spline`;
        tests/model/test_schemes.py compares them). The CPU filters many lines at once
        with the same steps (:mod:`pde_rotor.kernels.spline`).
        """
        reach = 0.0
        for k in range(count - 1, -1, -1):
            dst[o + k * stride] = reach
            reach = spline_reach(src[so + k * stride] + reach)
        reach = 0.0
        for k in range(count):
            sample = src[so + k * stride]
            dst[o + k * stride] = spline_coefficient(reach, dst[o + k * stride], sample)
            reach = spline_reach(sample + reach)

    @jit
    def bspline_weights(t):
        """The 4 cubic B-spline weights of the nodes -1, 0, 1, 2 at t in [0, 1)."""
        u = 1.0 - t
        t2 = t * t
        return (
            u * u * u / 6.0,
            (t2 * (3.0 * t - 6.0) + 4.0) / 6.0,
            (t * (t * (3.0 - 3.0 * t) + 3.0) + 1.0) / 6.0,
            t2 * t / 6.0,
        )

    @jit
    def spline_node(x0, inv_dx, x):
        """(k, t): the node k = floor((x - x0) inv_dx) at or before the coordinate x on
        the nodes x0 + k / inv_dx, and the fraction t in [0, 1) of the way to the next;
        the cubic spline's taps along that axis are the nodes k - 1 .. k + 2, with the
        weights :func:`bspline_weights` of t."""
        f = (x - x0) * inv_dx
        # int(): numba-cuda types math.floor as float64, numba's CPU target as int64
        k = int(math.floor(f))  # noqa: RUF046
        return k, f - k

    @jit
    def mirror_node(n, d):
        """(first, step, t): the taps of the cubic spline along an axis of n nodes at the
        point d nodes from their middle (n - 1) / 2, read as mirror images of each other
        at d and -d.

        The point lies at |d| + 1/2 (n even) or |d| (n odd) past the node n // 2 - 1 or
        (n - 1) / 2; k is the node at or before it, t in [0, 1) the fraction of the way
        to the next. For d >= 0 the taps are the nodes k - 1 .. k + 2 (first k - 1,
        step +1) with the weights :func:`bspline_weights` of t, those of
        :func:`spline_node`; for d < 0 their mirror images n - 1 - (k - 1) ..
        n - 1 - (k + 2) (first n - k, step -1) with the same weights in the same order.
        A point and its mirror image thus do the same arithmetic on mirrored taps: on
        coefficients symmetric under i -> n - 1 - i their values agree bit for bit,
        whatever the rounding of t, the order of the sums or the fused multiply-adds.
        Where t = 0 a point at d < 0 reads one tap beyond spline_node's four, with
        weight 0.
        """
        g = abs(d) + 0.5 * (1 - n % 2)
        past = int(g)  # g >= 0: truncation is the floor
        k = (n - 1) // 2 + past
        if d >= 0.0:
            return k - 1, 1, g - past
        return n - k, -1, g - past

    @jit
    def spline_sum(coef, row, sx, sy, wx, wy):
        """sum_(a, b) wx_a wy_b coef[row + a sx + b sy], a, b = 0 .. 3: the 4 x 4 taps
        of a cubic spline from its first, `row`, the offsets `sx`, `sy` of the next node
        along x and y all of the caller's integer type (unsigned on the CPU: no index
        needs a negative-wraparound check), summed along y first; `wx`, `wy` the 4-tuples
        of weights (:func:`bspline_weights`)."""
        wx0, wx1, wx2, wx3 = wx
        wy0, wy1, wy2, wy3 = wy
        r1 = row + sy
        r2 = r1 + sy
        r3 = r2 + sy
        acc = wx0 * (wy0 * coef[row] + wy1 * coef[r1] + wy2 * coef[r2] + wy3 * coef[r3])
        row += sx
        r1 += sx
        r2 += sx
        r3 += sx
        acc += wx1 * (wy0 * coef[row] + wy1 * coef[r1] + wy2 * coef[r2] + wy3 * coef[r3])
        row += sx
        r1 += sx
        r2 += sx
        r3 += sx
        acc += wx2 * (wy0 * coef[row] + wy1 * coef[r1] + wy2 * coef[r2] + wy3 * coef[r3])
        row += sx
        r1 += sx
        r2 += sx
        r3 += sx
        acc += wx3 * (wy0 * coef[row] + wy1 * coef[r1] + wy2 * coef[r2] + wy3 * coef[r3])
        return acc

    @jit
    def interpolate(coef, o0, n, x0, inv_dx, x, y):
        """Cubic spline at (x, y) from the n x n B-spline coefficients at offset o0.

        x0 is the coordinate of cell 0's centre; the 4 x 4 taps (:func:`spline_node`,
        :func:`spline_sum`) must lie in the prefiltered window (:func:`spline_line`
        along both axes). Written out because it runs inside the compiled kernels, where
        ``scipy.ndimage.map_coordinates`` cannot be called.
        """
        i, tx = spline_node(x0, inv_dx, x)
        j, ty = spline_node(x0, inv_dx, y)
        row = o0 + (i - 1) * n + j - 1
        return spline_sum(coef, row, n, 1, bspline_weights(tx), bspline_weights(ty))

    return Spline(
        spline_reach=spline_reach,
        spline_coefficient=spline_coefficient,
        spline_line=spline_line,
        bspline_weights=bspline_weights,
        spline_node=spline_node,
        mirror_node=mirror_node,
        spline_sum=spline_sum,
        interpolate=interpolate,
    )
