"""Discretisation schemes of F, G and the torque: ``paper`` and ``consistent``.

The continuum model is invariant under rotations of the plate; a Cartesian grid is
not, and a stopped symmetric plate feels a spurious *lattice torque* of period pi/6 in
its angle (docs/model.md). Two schemes are offered (``numerics.scheme``):

``paper``
    F and G of the equations after Eq. (rj) sampled at the cell centres; the torque
    of Eq. (torque) in its area form, -k int F r x grad c dA, with central differences
    for grad c. The paper's "explicit method for the spatial derivative".

``consistent`` (default)
    * F and G through isotropic prefilters of width eps = kappa dx, sampled at the cell
      centres: the filtered fields turn rigidly with the plate and have almost no
      content near the grid's Nyquist wavenumber, where the 5-point Laplacian is
      anisotropic (:mod:`pde_rotor.model.filtering`). By default F goes through the Gaussian
      N_eps (``numerics.plate_filter_*``, kappa = 0.7), a change of the model of order
      dx^2, and G through the sharpened 2 N_eps - N_(sqrt2 eps)
      (``numerics.pill_filter_*``, kappa = 0.95), which keeps the pills' second moment,
      on which the asymmetry torque depends (docs/model.md, "Which kernel").
    * The torque in contour form. F depends on r only through h(r) = max_j r . e_j,
      whose level sets are regular N-gons, so integrating by parts and by level sets
      (coarea formula, |grad h| = 1)

          int F r x grad c dA = - int w(h) sum_j int c(h e_j + t tau_j) t dt dh,

      with w(h) dh = 1/2 sech^2(s) ds, s = (R cos(pi/N) - h) / delta, and
      t in [-h tan(pi/N), h tan(pi/N)] along edge j. The identity is exact for the
      smoothed model (no sharp-interface limit is taken), so both schemes converge to
      the same continuum torque. It is evaluated with a Gauss rule for the weight
      1/2 sech^2(s) (:func:`sech2_gauss`, ``numerics.band_nodes`` nodes) across the
      edge and Gauss-Legendre (``numerics.contour_nodes`` per edge) along it, with c
      from its interpolating cubic spline (:mod:`pde_rotor.physics`: ``spline_line``,
      ``interpolate``). Every quadrature node turns with the plate, so only the
      interpolation error of c, O(dx^4), and the lattice error of c itself still see
      the lattice; the torque integrates the model's own F (unfiltered), the field
      equations see F_eps and G_eps (docs/model.md, "Schemes").

The per-cell work of both schemes is in :mod:`pde_rotor.physics`; this module only builds
the numbers the kernels need (:func:`pde_rotor.kernels.records.make_record` packs them).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from functools import lru_cache

import numpy as np
from scipy.ndimage import map_coordinates

from ..config import CamphorConfig, RotorConfig
from ..physics.spline import SPLINE_MARGIN
from .filtering import FilterTables, make_tables
from .geometry import RotorShape


def surface_pressure(c: np.ndarray, camphor: CamphorConfig | None) -> np.ndarray:
    """Pi(c) / k = (gamma0 - gamma(c)) / k, the surface pressure per tension slope that
    the tension integrals read (numpy reference): c for the paper's linear law
    (`camphor` None, or its ``saturation`` None), c / (1 + c / c_sat) for the saturating
    one. It takes the camphor section whole, as the compiled ``surface_pressure`` takes
    the parameter record, so that a new scalar of the law is read here and nowhere else."""
    saturation = None if camphor is None else camphor.saturation
    if saturation is None:
        return c
    return c / (1.0 + c / saturation)


@lru_cache(maxsize=32)
def sech2_gauss(n_nodes: int) -> tuple[np.ndarray, np.ndarray]:
    """Gauss rule for int 1/2 sech^2(s) g(s) ds over the real line (total weight 1).

    Golub-Welsch on the recurrence coefficients from a discretised Stieltjes procedure
    (trapezoidal rule on [-S, S], which for this weight is exponentially accurate).

    Args:
        n_nodes: number of nodes M (exact for polynomials of degree <= 2M - 1).

    Returns:
        (nodes, weights), each of length M, nodes ascending and symmetric about 0.
    """
    half_width = 30.0 + 4.0 * n_nodes
    s = np.linspace(-half_width, half_width, 40_001)
    w = 0.5 / np.cosh(s) ** 2 * (s[1] - s[0])
    alpha = np.zeros(n_nodes)
    beta = np.zeros(n_nodes)
    p_prev = np.zeros_like(s)
    p = np.ones_like(s)
    norm_prev = 1.0
    for k in range(n_nodes):
        norm = np.sum(w * p * p)
        alpha[k] = np.sum(w * s * p * p) / norm
        beta[k] = norm / norm_prev if k > 0 else norm
        p_next = (s - alpha[k]) * p - (beta[k] if k > 0 else 0.0) * p_prev
        p_prev, p, norm_prev = p, p_next, norm
    jacobi = np.diag(alpha) + np.diag(np.sqrt(beta[1:]), 1) + np.diag(np.sqrt(beta[1:]), -1)
    nodes, vectors = np.linalg.eigh(jacobi)
    weights = vectors[0] ** 2  # the weight function has total mass 1
    nodes = 0.5 * (nodes - nodes[::-1])  # exact symmetry
    weights = 0.5 * (weights + weights[::-1])
    return nodes, weights


@dataclass(frozen=True)
class Scheme:
    """The numbers one run's kernels need to apply its scheme.

    Attributes:
        name: ``paper`` or ``consistent``.
        tables: the filtered F and G (:mod:`pde_rotor.model.filtering`), None for point values.
        contour: whether the torque is taken in contour form (else area form).
        quad_s: (2, M) nodes and weights across the edge (weight 1/2 sech^2).
        quad_t: (2, L) Gauss-Legendre nodes and weights on [-1, 1] along an edge.
        tan_half: tan(pi / N).
        window: cell range [lo, hi), along both axes, whose c is turned into cubic
            spline coefficients each step: the contour's 4 x 4 taps plus
            :data:`~pde_rotor.physics.spline.SPLINE_MARGIN` cells.
        taps: the cell range [lo, hi) within `window`, along both axes, of the contour's
            taps: the coefficients wanted (the window's margin only feeds the prefilter's
            recursions).
    """

    name: str
    tables: FilterTables | None
    contour: bool
    quad_s: np.ndarray
    quad_t: np.ndarray
    tan_half: float
    window: tuple[int, int]
    taps: tuple[int, int]

    @classmethod
    def from_config(cls, config: RotorConfig, shape: RotorShape) -> Scheme:
        """The scheme of a run configuration (``numerics`` section) for the rotor `shape`
        of its ``geometry`` (:attr:`pde_rotor.model.setup.Setup.shape`)."""
        num = config.numerics
        consistent = num.scheme == "consistent"
        n_cells = 2 * math.ceil(config.grid.domain_radius / config.grid.dx - 1e-9) + 2
        window = taps = (0, 0)
        tables = None
        if consistent:
            quad_s = np.stack(sech2_gauss(num.band_nodes))
            quad_t = np.stack(np.polynomial.legendre.leggauss(num.contour_nodes))
            geo = config.geometry
            apothem = geo.radius * math.cos(math.pi / geo.n_corners)
            reach = (apothem + geo.smoothing * np.abs(quad_s[0]).max()) / math.cos(
                math.pi / geo.n_corners
            )
            half = math.ceil(reach / config.grid.dx) + 2 + SPLINE_MARGIN
            window = (max(1, n_cells // 2 - half), min(n_cells - 1, n_cells // 2 + half))
            inner = half - SPLINE_MARGIN
            taps = (max(window[0], n_cells // 2 - inner), min(window[1], n_cells // 2 + inner))
            # F and G's profiles do not depend on Delta: one table for a sweep over it
            tables = make_tables(
                replace(shape, asymmetry=0.0),
                config.grid.dx,
                num.table_refinement,
                plate=(num.plate_filter_kernel, num.plate_filter_width),
                pill=(num.pill_filter_kernel, num.pill_filter_width),
            )
        else:
            quad_s = np.zeros((2, 1))
            quad_t = np.zeros((2, 1))
        return cls(
            name=num.scheme,
            tables=tables,
            contour=consistent,
            quad_s=np.ascontiguousarray(quad_s),
            quad_t=np.ascontiguousarray(quad_t),
            tan_half=math.tan(math.pi / config.geometry.n_corners),
            window=window,
            taps=taps,
        )

    def kernel_tables(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """(quad_s, quad_t, plate spline coefficients, edge profile, pill profile): the
        arrays the kernels take besides the parameter record; one-element dummies of the
        same type for point values."""
        if self.tables is None:
            return self.quad_s, self.quad_t, np.zeros(1), np.zeros(1), np.zeros(1)
        return self.quad_s, self.quad_t, self.tables.plate, self.tables.edge, self.tables.pill


def interpolate_spline(
    field: np.ndarray, x0: float, dx: float, x: np.ndarray, y: np.ndarray
) -> np.ndarray:
    """Interpolating cubic spline of a grid field at points (numpy/scipy reference).

    scipy's ``map_coordinates`` with its own prefilter over the whole grid and zero
    values beyond it (c = 0 on and outside the circle, so this is exact).

    Args:
        field: (n, n) values at the cell centres x0 + i dx (axis 0: x, axis 1: y).
        x0: coordinate of cell 0's centre.
        dx: grid spacing.
        x, y: points (same shape).
    """
    points = np.stack([(np.asarray(x) - x0) / dx, (np.asarray(y) - x0) / dx])
    return map_coordinates(field, points, order=3, mode="grid-constant", cval=0.0)


def contour_cross_grad(
    c: np.ndarray,
    x0: float,
    dx: float,
    scheme: Scheme,
    normal_angles: np.ndarray,
    apothem: float,
    smoothing: float,
    camphor: CamphorConfig | None = None,
) -> float:
    """int F r x grad P dA in the contour form of the ``consistent`` scheme (numpy reference),
    P = :func:`surface_pressure` of c (c itself for the linear law).

    Args:
        c: (n, n) concentration at the cell centres.
        x0: coordinate of cell 0's centre.
        dx: grid spacing.
        scheme: a scheme with ``contour`` set (its quadrature rules).
        normal_angles: angles of the edge normals e_j at the current phi.
        apothem: R cos(pi/N).
        smoothing: delta.
        camphor: the camphor section, its law of the surface tension (None: linear).
    """
    s_nodes, s_weights = scheme.quad_s
    t_nodes, t_weights = scheme.quad_t
    h = apothem - smoothing * s_nodes
    half = h * scheme.tan_half
    t = half[:, None] * t_nodes[None, :]
    ex = np.cos(normal_angles)[:, None, None]
    ey = np.sin(normal_angles)[:, None, None]
    x = h[None, :, None] * ex - t[None] * ey
    y = h[None, :, None] * ey + t[None] * ex
    values = surface_pressure(interpolate_spline(c, x0, dx, x, y), camphor)
    weights = s_weights[:, None] * t_weights[None, :] * half[:, None] * t
    return float(-np.sum(weights[None] * values))
