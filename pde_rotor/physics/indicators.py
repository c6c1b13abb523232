"""The smoothed indicators F and G of a plate and its pills, written once.

The equations after Eq. (rj) of Koyano et al. (Chaos 2020): the plate's F as a function
of its gauge, the pills' G, point values (scheme ``paper``) and after the isotropic
Gaussian prefilter (scheme ``consistent``, from the tables of
:mod:`pde_rotor.model.filtering`):

* the rotor's table :func:`rotor_table`: edge normals e_j, Eq. (ejt0) rotated by phi, and
  pill centres R_j = R_c e(phi + 2 pi j / N + Delta), Eq. (rc) with the pills at the
  corners (erratum of Eq. (rj), see :mod:`pde_rotor.model.geometry`);
* the tanh as a branch-free :func:`logistic` of a polynomial :func:`vector_expm1`, so
  that the CPU's row loops compute four cells at a time (SIMD);
* the geometry: the gauge h(r) = max_j r . e_j (:func:`projection`, :func:`farther`,
  :func:`gauge_step`, :func:`gauge`, a body's :func:`polygon_gauge`, a strip's
  :func:`strip_gauge`), the frame of the nearest edge (:func:`tangential`,
  :func:`nearer_edge`, :func:`near_corner`), the pills' reach (:func:`pill_reach`,
  :func:`filtered_pill_reach`) and a body's footprint on a row (:func:`footprint_chord`);
* point values: :func:`plate_profile`, :func:`pill_term`, the cells :func:`plate_cell`,
  :func:`pill_cell` and a body's plate :func:`body_plate_cell`;
* filtered: :func:`filtered_edge`, :func:`corner_taps`, :func:`corner_sum`,
  :func:`filtered_corner`, :func:`filtered_plate`, :func:`filtered_pill_term` (from
  :func:`profile_place` and :func:`profile_value`),
  :func:`filtered_pills`, a strip's :func:`filtered_strip`.

The GPU calls the cell functions once per cell; the CPU's row loops
(:mod:`pde_rotor.kernels.indicators`, :mod:`pde_rotor.kernels.bodies`) call the terms
in loops over a row's cells.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import NamedTuple

from ..config import X_SATURATION
from .spline import Spline

PLATE_NONE, PLATE_POLYGON, PLATE_DISK, PLATE_STRIP = 0, 1, 2, 3
"""Plate shapes in the body record (:mod:`pde_rotor.kernels.records`, ``BODY``)."""


class PolygonFilter(NamedTuple):
    """A regular polygon plate's F_eps of the scheme ``consistent``
    (:func:`make_indicators` ``filtered_plate``), bundled in the compiled loops from the
    parameter record (the rotor) or a body's record: N, the apothem, tan(pi/N), the
    crease width and the corner table's end (``near_corner``); the edge profile, its
    first abscissa and inverse step (``filtered_edge``); the 2-D corner table, its
    size, first abscissa and inverse step (``filtered_corner``)."""

    n_corners: int
    apothem: float
    tan_half: float
    crease: float
    corner_end: float
    edge: object
    edge_u0: float
    edge_inv: float
    plate: object
    table_n: int
    table_x0: float
    table_inv: float


class Indicators(NamedTuple):
    """The compiled indicator functions for one target (see the module docstring)."""

    vector_expm1: Callable
    logistic: Callable
    rotor_table: Callable
    projection: Callable
    farther: Callable
    gauge_step: Callable
    gauge: Callable
    tangential: Callable
    nearer_edge: Callable
    near_corner: Callable
    pill_reach: Callable
    filtered_pill_reach: Callable
    footprint_chord: Callable
    plate_profile: Callable
    pill_term: Callable
    plate_cell: Callable
    pill_cell: Callable
    filtered_edge: Callable
    corner_taps: Callable
    corner_sum: Callable
    filtered_corner: Callable
    filtered_plate: Callable
    profile_place: Callable
    profile_value: Callable
    filtered_pill_term: Callable
    filtered_pills: Callable
    polygon_gauge: Callable
    strip_gauge: Callable
    filtered_strip: Callable
    body_plate_cell: Callable


def make_indicators(jit: Callable[[Callable], Callable], spline: Spline) -> Indicators:
    """Compile the indicator functions with `jit`.

    Args:
        jit: decorator turning a scalar Python function into a compiled one that other
            compiled functions of the same target can call (numba ``njit`` or
            ``cuda.jit(device=True)``, :func:`pde_rotor.physics.build.make_physics`).
        spline: the spline functions compiled with the same `jit`.

    Returns:
        The compiled functions.
    """
    spline_node = spline.spline_node
    bspline_weights = spline.bspline_weights
    spline_sum = spline.spline_sum

    @jit
    def vector_expm1(x: float) -> float:
        """exp(x) - 1 for 0 <= x <= 2 X_SATURATION in multiplications and additions only.

        The Taylor polynomial of degree 15 of expm1(x / 64) (remainder below 5e-17), then
        six doublings of the argument, (1 + q)^2 - 1 = q (2 + q), which keep the relative
        accuracy (2e-14 over the range, tests/physics/test_indicators.py; squaring
        exp(x / 64) itself would lose 64 ulp). libm's exp is a call that stops LLVM from
        vectorising a loop; this is not, so the CPU loops over a row of cells run it four
        cells at a time.
        """
        r = x * (1.0 / 64.0)
        p = 1.0 / 1307674368000.0
        p = p * r + 1.0 / 87178291200.0
        p = p * r + 1.0 / 6227020800.0
        p = p * r + 1.0 / 479001600.0
        p = p * r + 1.0 / 39916800.0
        p = p * r + 1.0 / 3628800.0
        p = p * r + 1.0 / 362880.0
        p = p * r + 1.0 / 40320.0
        p = p * r + 1.0 / 5040.0
        p = p * r + 1.0 / 720.0
        p = p * r + 1.0 / 120.0
        p = p * r + 1.0 / 24.0
        p = p * r + 1.0 / 6.0
        p = p * r + 0.5
        p = p * r + 1.0
        q = p * r
        q = q * (2.0 + q)
        q = q * (2.0 + q)
        q = q * (2.0 + q)
        q = q * (2.0 + q)
        q = q * (2.0 + q)
        return q * (2.0 + q)

    @jit
    def logistic(arg: float) -> float:
        """1/2 (1 + tanh(arg)) = 1 / (1 + exp(-2 arg)), arg clipped to +-X_SATURATION
        (where it is 1 exactly, or 4.2e-18), written with E = exp(2 |arg|) >= 1 as
        E / (E + 1) or 1 / (E + 1): branch-free, so vectorisable, and within 1 ulp of 1.
        ``scipy.special.expit(2 arg)`` outside compiled code; the kernels cannot call it."""
        arg = arg if arg < X_SATURATION else X_SATURATION
        arg = arg if arg > -X_SATURATION else -X_SATURATION
        big = 1.0 + vector_expm1(2.0 * abs(arg))
        return (big if arg >= 0.0 else 1.0) / (big + 1.0)

    @jit
    def rotor_table(phi, n_corners, r_c, asym, tab):
        """Fill tab (4, >= N): edge normals (cos, sin), pill centres (x, y) at angle phi."""
        for k in range(n_corners):
            a_edge = phi + 2.0 * math.pi * (k + 0.5) / n_corners
            tab[0, k] = math.cos(a_edge)
            tab[1, k] = math.sin(a_edge)
            a_pill = phi + 2.0 * math.pi * (k + 1) / n_corners + asym
            tab[2, k] = r_c * math.cos(a_pill)
            tab[3, k] = r_c * math.sin(a_pill)

    @jit
    def projection(x, y, ex, ey):
        """r . e_j, the distance of (x, y) along the edge normal e_j = (ex, ey)."""
        return x * ex + y * ey

    @jit
    def farther(p, h):
        """Whether p = r . e_j exceeds h: strict, so that the first of equal edges wins."""
        return p > h

    @jit
    def gauge_step(h, x, y, ex, ey):
        """max(h, r . e_j): one edge's step of the gauge h(r) = max_j r . e_j (branch-free)."""
        p = projection(x, y, ex, ey)
        return p if farther(p, h) else h

    @jit
    def gauge(x, y, tab, n_corners):
        """h(r) = max_j r . e_j: the plate's level sets h = const are regular N-gons."""
        h = projection(x, y, tab[0, 0], tab[1, 0])
        for k in range(1, n_corners):
            h = gauge_step(h, x, y, tab[0, k], tab[1, k])
        return h

    @jit
    def tangential(x, y, ex, ey):
        """r . tau_j, tau_j = e_j = (ex, ey) turned by +pi/2: the position along edge j."""
        return y * ex - x * ey

    @jit
    def nearer_edge(h, q, x, y, ex, ey):
        """(h, q) of (x, y) in the frame of the nearer of the edge so far (h = r . e,
        q = r . tau) and edge (ex, ey): the new edge where r . e_j > h (so the first of
        equal edges wins; branch-free)."""
        p = projection(x, y, ex, ey)
        nearer = farther(p, h)
        return (p if nearer else h), (tangential(x, y, ex, ey) if nearer else q)

    @jit
    def near_corner(h, q, tan_half, crease, corner_end):
        """Whether (h, q) (frame of the nearest edge) lies within the crease width of a
        corner bisector, h tan(pi/N) - |q| <= crease, and short of the table's end
        h < `corner_end` (beyond, F_eps is below 1e-13: :mod:`pde_rotor.model.filtering`,
        ``corner_end``), where F_eps needs the 2-D table."""
        return (h * tan_half - abs(q) <= crease) & (h < corner_end)

    @jit
    def footprint_chord(coords, j0, j1, rx, y_k, reach):
        """[ja, jb): the columns of [j0, j1) of a row, rx from X_k, within a body's
        footprint |r - X_k| < reach (the chord of the disk, scanned in from both ends of
        the footprint's box); every compiled drawing and the bodies' field update call it,
        so that they agree on each cell."""
        limit = reach * reach
        ja = j0
        while ja < j1:
            ry = coords[ja] - y_k
            if rx * rx + ry * ry < limit:
                break
            ja += 1
        jb = j1
        while jb > ja:
            ry = coords[jb - 1] - y_k
            if rx * rx + ry * ry < limit:
                break
            jb -= 1
        return ja, jb

    @jit
    def pill_reach(rho, inv_delta):
        """rho + X_SATURATION delta: beyond, a pill's term of G is below 4.3e-18."""
        return rho + X_SATURATION / inv_delta

    @jit
    def filtered_pill_reach(profile, inv_step):
        """The end of the filtered pill profile (spacing 1 / inv_step): beyond, G_eps's
        term is 0."""
        return (profile.size - 1) / inv_step

    @jit
    def plate_profile(h, apothem, inv_delta):
        """F as a function of the gauge h(r): 1/2 [1 + tanh((R cos(pi/N) - h) / delta)]."""
        return logistic((apothem - h) * inv_delta)

    @jit
    def pill_term(dx, dy, rho, inv_delta):
        """One pill's share of G at the offset (dx, dy) from its centre:
        1/2 [1 + tanh((rho - |(dx, dy)|) / delta)]."""
        return logistic((rho - math.sqrt(dx * dx + dy * dy)) * inv_delta)

    @jit
    def plate_cell(x, y, tab, n_corners, apothem, inv_delta):
        """F at the cell centre (x, y) (scheme ``paper``)."""
        return plate_profile(gauge(x, y, tab, n_corners), apothem, inv_delta)

    @jit
    def pill_cell(x, y, tab, n_corners, rho, inv_delta):
        """G at the cell centre (x, y) (scheme ``paper``): the sum over the pills within
        rho + X_SATURATION delta, in order (beyond, a pill's term is below 4.3e-18)."""
        reach = pill_reach(rho, inv_delta)
        g = 0.0
        for k in range(n_corners):
            dx = x - tab[2, k]
            dy = y - tab[3, k]
            if dx * dx + dy * dy < reach * reach:
                g += pill_term(dx, dy, rho, inv_delta)
        return g

    @jit
    def filtered_edge(h, apothem, edge, e_u0, e_inv):
        """F_eps = f_eps(apothem - h) away from the corners, from the 1-D edge profile
        `edge` (first node e_u0, 1 / spacing e_inv, linear): 0 before its first node, 1
        beyond its last (branch-free: the index is clipped, the value selected)."""
        last = edge.size - 1
        u = (apothem - h - e_u0) * e_inv
        i = min(max(int(u), 0), last - 1)
        value = edge[i] + (u - i) * (edge[i + 1] - edge[i])
        value = value if u > 0.0 else 0.0
        return value if u < last else 1.0

    @jit
    def corner_taps(h, q, t_n, t_x0, t_inv):
        """Where the cubic spline of the 2-D plate table (see :func:`filtered_corner`)
        takes its taps at (h, q): (inside, row, tx, ty), `inside` whether its 4 x 4 taps
        lie in the table, `row` the offset of the first (:func:`spline_sum`), tx, ty the
        fractions of :func:`spline_node` along h and q. Where the taps leave the table,
        those of a node inside instead (branch-free: the point is selected, so that the
        CPU computes many cells at once)."""
        fx = (h - t_x0) * t_inv
        fy = (q - t_x0) * t_inv
        inside = (fx >= 1.0) & (fy >= 1.0) & (fx < t_n - 2.0) & (fy < t_n - 2.0)
        node = t_x0 + 2.0 / t_inv
        i, tx = spline_node(t_x0, t_inv, h if inside else node)
        j, ty = spline_node(t_x0, t_inv, q if inside else node)
        return inside, (i - 1) * t_n + j - 1, tx, ty

    @jit
    def corner_sum(plate, row, sx, sy, tx, ty):
        """The cubic spline of the 2-D `plate` table from its taps (:func:`corner_taps`;
        `row`, `sx` = t_n and `sy` = 1 of the caller's integer type, as for
        :func:`spline_sum`)."""
        return spline_sum(plate, row, sx, sy, bspline_weights(tx), bspline_weights(ty))

    @jit
    def filtered_corner(h, q, plate, t_n, t_x0, t_inv):
        """F_eps near the corner bisectors, at (h, q) in the frame of the nearest edge:
        the cubic spline of the 2-D `plate` table (t_n x t_n coefficients on the nodes
        t_x0 + k / t_inv, edge 0's normal along +x), 0 where its taps leave the table
        (:func:`corner_taps`, :func:`corner_sum`)."""
        inside, row, tx, ty = corner_taps(h, q, t_n, t_x0, t_inv)
        if not inside:
            return 0.0
        return corner_sum(plate, row, t_n, 1, tx, ty)

    @jit
    def filtered_plate(x, y, tab, polygon):
        """F_eps of the cell centred at (x, y) (``consistent``, :mod:`pde_rotor.model.filtering`)
        of the plate `polygon` (:class:`PolygonFilter`), its edge normals `tab`.

        The point is written in the frame of its nearest edge j (the one maximising
        r . e_j; the first of equals, :func:`nearer_edge`): h = r . e_j, q = r . tau_j,
        tau_j = e_j turned by +pi/2. Where h tan(pi/N) - |q| > `crease` (more than
        crease cos(pi/N) from the corner bisectors) or h >= `corner_end` (beyond the
        corners, :func:`near_corner`) F_eps comes from :func:`filtered_edge`, closer
        from :func:`filtered_corner`. Either way F_eps has
        the hexagon's symmetry exactly.
        """
        n_corners, apothem, tan_half, crease, corner_end, edge = polygon[0:6]
        e_u0, e_inv, plate, t_n, t_x0, t_inv = polygon[6:12]
        h = projection(x, y, tab[0, 0], tab[1, 0])
        q = tangential(x, y, tab[0, 0], tab[1, 0])
        for k in range(1, n_corners):
            h, q = nearer_edge(h, q, x, y, tab[0, k], tab[1, k])
        if near_corner(h, q, tan_half, crease, corner_end):
            return filtered_corner(h, q, plate, t_n, t_x0, t_inv)
        return filtered_edge(h, apothem, edge, e_u0, e_inv)

    @jit
    def profile_place(dx, dy, last, inv_step):
        """Where a radial profile of `last` + 1 nodes (spacing 1 / inv_step) is read at
        the offset (dx, dy) from its centre: (i, t, inside), the node i at or before the
        distance (clipped to last - 1), the fraction t of the way to the next, and
        whether the distance is short of the last node (:func:`profile_value`)."""
        u = math.sqrt(dx * dx + dy * dy) * inv_step
        i = min(int(u), last - 1)
        return i, u - i, u < last

    @jit
    def profile_value(profile, i, t, inside):
        """The radial `profile` interpolated linearly at the place (i, t, inside) of
        :func:`profile_place`, 0 where not `inside` (branch-free: the value selected)."""
        value = profile[i] + t * (profile[i + 1] - profile[i])
        return value if inside else 0.0

    @jit
    def filtered_pill_term(dx, dy, profile, inv_step):
        """One pill's share of G_eps at the offset (dx, dy) from its centre: the radial
        profile `profile` (spacing 1 / inv_step) interpolated linearly, 0 beyond its end
        (:func:`profile_place`, :func:`profile_value`)."""
        i, t, inside = profile_place(dx, dy, profile.size - 1, inv_step)
        return profile_value(profile, i, t, inside)

    @jit
    def filtered_pills(x, y, tab, n_corners, profile, inv_step):
        """G_eps of the cell centred at (x, y): sum_j g_eps(|r - R_j|) over the pills
        within the profile's reach, in order (beyond, a term is 0)."""
        reach = filtered_pill_reach(profile, inv_step)
        g = 0.0
        for k in range(n_corners):
            dx = x - tab[2, k]
            dy = y - tab[3, k]
            if dx * dx + dy * dy < reach * reach:
                g += filtered_pill_term(dx, dy, profile, inv_step)
        return g

    @jit
    def polygon_gauge(rx, ry, normals, n_corners):
        """h = max_j (r - X) . e_j over the edge normals `normals` (2, >= N), lab frame."""
        h = projection(rx, ry, normals[0, 0], normals[1, 0])
        for j in range(1, n_corners):
            h = gauge_step(h, rx, ry, normals[0, j], normals[1, j])
        return h

    @jit
    def strip_gauge(rx, ry, ex, ey, half_length, half_width):
        """max(|r . e| - L/2, |r . tau| - W/2): a rectangle's gauge, e the body's x axis.

        Its level set 0 is the strip's outline and it grows by the distance from the
        nearer edge, like the polygon's max over edges h - R cos(pi/N).
        """
        along = abs(projection(rx, ry, ex, ey)) - half_length
        across = abs(ey * rx - ex * ry) - half_width
        return along if along > across else across

    @jit
    def filtered_strip(rx, ry, ex, ey, plate, rows, columns, t_x0, t_inv):
        """F_eps of a strip plate at r = X + (rx, ry) (``consistent``,
        :func:`pde_rotor.model.filtering.strip_table`), e = (ex, ey) its x axis: the cubic
        spline of the quadrant table `plate` (rows x columns coefficients on the nodes
        t_x0 + k / t_inv, x' along the rows) at (|x'|, |y'|), so that F_eps has the
        rectangle's two mirror symmetries exactly; 0 where the taps leave the table
        (beyond, F_eps is below 1e-17). t_x0 < 0: the taps of a point on an axis lie in
        the table's mirrored nodes."""
        along = abs(projection(rx, ry, ex, ey))
        across = abs(tangential(rx, ry, ex, ey))
        fx = (along - t_x0) * t_inv
        fy = (across - t_x0) * t_inv
        if not (fx < rows - 2.0 and fy < columns - 2.0):
            return 0.0
        i, tx = spline_node(t_x0, t_inv, along)
        j, ty = spline_node(t_x0, t_inv, across)
        return corner_sum(plate, (i - 1) * columns + j - 1, columns, 1, tx, ty)

    @jit
    def body_plate_cell(rx, ry, plate, normals, n_corners, size_a, size_b, inv_delta):
        """F_k at r = X_k + (rx, ry) for the plate kind `plate` (``paper`` scheme point value).

        polygon: 1/2 [1 + tanh((a - h) / delta)], h the polygon gauge, a = `size_a` the
        apothem; disk: the same with h = |r - X| and a the radius; strip:
        1/2 [1 + tanh(-h / delta)], h the strip gauge with `size_a`, `size_b` the half
        length and half width. A body without a plate has the pills' own indicator for F
        (the sum of ``pill_term`` over them, :mod:`pde_rotor.kernels.bodies`).
        """
        if plate == PLATE_POLYGON:
            return logistic((size_a - polygon_gauge(rx, ry, normals, n_corners)) * inv_delta)
        if plate == PLATE_DISK:
            return pill_term(rx, ry, size_a, inv_delta)
        if plate == PLATE_STRIP:
            h = strip_gauge(rx, ry, normals[0, 0], normals[1, 0], size_a, size_b)
            return logistic(-h * inv_delta)
        return 0.0

    return Indicators(
        vector_expm1=vector_expm1,
        logistic=logistic,
        rotor_table=rotor_table,
        projection=projection,
        farther=farther,
        gauge_step=gauge_step,
        gauge=gauge,
        tangential=tangential,
        nearer_edge=nearer_edge,
        near_corner=near_corner,
        pill_reach=pill_reach,
        filtered_pill_reach=filtered_pill_reach,
        footprint_chord=footprint_chord,
        plate_profile=plate_profile,
        pill_term=pill_term,
        plate_cell=plate_cell,
        pill_cell=pill_cell,
        filtered_edge=filtered_edge,
        corner_taps=corner_taps,
        corner_sum=corner_sum,
        filtered_corner=filtered_corner,
        filtered_plate=filtered_plate,
        profile_place=profile_place,
        profile_value=profile_value,
        filtered_pill_term=filtered_pill_term,
        filtered_pills=filtered_pills,
        polygon_gauge=polygon_gauge,
        strip_gauge=strip_gauge,
        filtered_strip=filtered_strip,
        body_plate_cell=body_plate_cell,
    )
