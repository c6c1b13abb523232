"""Lattice torque of the contour-form torque with different interpolants of c.

The ``consistent`` scheme (:mod:`pde_rotor.model.schemes`) takes the torque of Eq. (torque) as
a contour integral whose nodes turn with the plate, so its lattice torque comes from how
c is interpolated between cell centres (and from the discrete c itself). This script
holds the steady c of a stopped symmetric plate (sparse solve, :mod:`pde_rotor.model.analysis`)
at `--angles` angles over one period pi/6 and evaluates the contour torque with:
a Catmull-Rom interpolant (``cr``, the scheme's first version), tensor-product Lagrange interpolants
on 4, 6 and 8 points (``lag4`` ...) and interpolating cubic and quintic splines
(scipy's RectBivariateSpline, ``spl3``, ``spl5``; the scheme now uses the cubic
one). It prints the rms and max lattice
torque of each. Evidence for the next lever of docs/model.md, "Schemes".

Run:  python benchmarks/contour_interpolants.py [--dx 0.05 0.025] [--angles 24]
"""

from __future__ import annotations

import argparse
from collections.abc import Callable

import numpy as np
from scipy.interpolate import RectBivariateSpline

from pde_rotor import RotorConfig
from pde_rotor.model.analysis import stopped_concentration
from pde_rotor.model.geometry import edge_normal_angles
from pde_rotor.model.pde import RotorPDE
from pde_rotor.model.schemes import Scheme

Interpolant = Callable[[np.ndarray, float, float, np.ndarray, np.ndarray], np.ndarray]


def catmull_rom(field: np.ndarray, x0: float, dx: float, x: np.ndarray, y: np.ndarray):
    """Bicubic Catmull-Rom (Keys' cubic convolution, a = -1/2): local, C^1, third order."""
    fx, fy = (x - x0) / dx, (y - x0) / dx
    i, j = np.floor(fx).astype(int), np.floor(fy).astype(int)

    def weights(t: np.ndarray) -> tuple[np.ndarray, ...]:
        t2, t3 = t * t, t * t * t
        return (
            -0.5 * t3 + t2 - 0.5 * t,
            1.5 * t3 - 2.5 * t2 + 1.0,
            -1.5 * t3 + 2.0 * t2 + 0.5 * t,
            0.5 * t3 - 0.5 * t2,
        )

    wx, wy = weights(fx - i), weights(fy - j)
    out = np.zeros(np.shape(x))
    for a in range(4):
        for b in range(4):
            out += wx[a] * wy[b] * field[i - 1 + a, j - 1 + b]
    return out


def lagrange(points: int) -> Interpolant:
    """Tensor-product Lagrange interpolant on `points` x `points` cells around (x, y)."""
    offsets = np.arange(points) - (points // 2 - 1)

    def weights(t: np.ndarray) -> list[np.ndarray]:
        out = []
        for a in offsets:
            w = np.ones_like(t)
            for b in offsets:
                if b != a:
                    w = w * (t - b) / (a - b)
            out.append(w)
        return out

    def interpolate(field: np.ndarray, x0: float, dx: float, x: np.ndarray, y: np.ndarray):
        fx, fy = (x - x0) / dx, (y - x0) / dx
        i, j = np.floor(fx).astype(int), np.floor(fy).astype(int)
        wx, wy = weights(fx - i), weights(fy - j)
        out = np.zeros_like(x)
        for ia, a in enumerate(offsets):
            for ib, b in enumerate(offsets):
                out += wx[ia] * wy[ib] * field[i + a, j + b]
        return out

    return interpolate


def contour_torque(
    c: np.ndarray, pde: RotorPDE, scheme: Scheme, phi: float, interpolate: Interpolant
) -> float:
    """The scheme's contour quadrature of int F r x grad c dA with a given interpolant."""
    s_nodes, s_weights = scheme.quad_s
    t_nodes, t_weights = scheme.quad_t
    h = pde.shape.apothem - pde.shape.smoothing * s_nodes
    half = h * scheme.tan_half
    t = half[:, None] * t_nodes[None, :]
    angles = edge_normal_angles(pde.shape.n_corners, phi)
    ex, ey = np.cos(angles)[:, None, None], np.sin(angles)[:, None, None]
    x = h[None, :, None] * ex - t[None] * ey
    y = h[None, :, None] * ey + t[None] * ex
    values = interpolate(c, float(pde.domain.coords[0]), pde.domain.dx, x, y)
    weights = s_weights[:, None] * t_weights[None, :] * half[:, None] * t
    return float(-np.sum(weights[None] * values)) * pde.config.camphor.tension_slope


def main() -> None:
    """Print the rms and max lattice torque of the contour form per interpolant and dx."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--dx", type=float, nargs="+", default=[0.05, 0.025])
    parser.add_argument("--angles", type=int, default=24, help="angles over one period pi/6")
    parser.add_argument("--band-nodes", type=int, default=6)
    parser.add_argument("--contour-nodes", type=int, default=64)
    args = parser.parse_args()
    phis = np.arange(args.angles) * (np.pi / 6) / args.angles
    names = ["cr", "lag4", "lag6", "lag8", "spl3", "spl5"]
    print(f"{'dx':>7} " + " ".join(f"{name + ' rms/max':>20}" for name in names))
    for dx in args.dx:
        numerics = {
            "scheme": "consistent",
            "band_nodes": args.band_nodes,
            "contour_nodes": args.contour_nodes,
        }
        cfg = RotorConfig.model_validate(
            {"grid": {"dx": dx}, "geometry": {"smoothing": max(dx, 0.025)}, "numerics": numerics}
        )
        pde = RotorPDE(cfg)
        coords = pde.domain.coords
        torques: dict[str, list[float]] = {name: [] for name in names}
        for phi in phis:
            c = stopped_concentration(pde, float(phi))
            splines = {k: RectBivariateSpline(coords, coords, c, kx=k, ky=k, s=0) for k in (3, 5)}
            interpolants: dict[str, Interpolant] = {
                "cr": catmull_rom,
                "lag4": lagrange(4),
                "lag6": lagrange(6),
                "lag8": lagrange(8),
                "spl3": lambda f, x0, h, x, y, s=splines[3]: s.ev(x, y),
                "spl5": lambda f, x0, h, x, y, s=splines[5]: s.ev(x, y),
            }
            for name in names:
                torques[name].append(contour_torque(c, pde, pde.scheme, phi, interpolants[name]))
        cells = []
        for name in names:
            values = np.array(torques[name])
            cells.append(f"{np.sqrt(np.mean(values**2)):9.2e}/{np.abs(values).max():9.2e}")
        print(f"{dx:7.4f} " + " ".join(f"{cell:>20}" for cell in cells), flush=True)


if __name__ == "__main__":
    main()
