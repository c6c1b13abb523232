"""An independent radial finite-volume solve of Eq. (eqc) around a camphor disk, in the lab
frame: the oracle of the closed forms of :mod:`pde_rotor.theory.disk` and
:mod:`pde_rotor.theory.free_disk`."""

from __future__ import annotations

import math

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import spsolve

from pde_rotor.theory.disk import CamphorDisk, Wall


def radial_lab_frame(
    disk: CamphorDisk, smoothing: float, spacing: float, lam: complex, wall: Wall
) -> tuple[np.ndarray, np.ndarray, complex]:
    """Radial finite volumes of the rest state and the displaced disk, in the lab frame.

    Cells of width `spacing` fill [0, L]; the wall sits on the last face. F = G is the
    tanh indicator of width `smoothing` (0: a step, rho on a face). Displacing the disk by
    X along x adds -(X . grad F)(a c0 + S) to Eq. (eqc), so the cos(theta) mode h of the
    field obeys (D L_1 - a (1 - F) - lambda) h = F' (a c0 + S), and the force per unit
    displacement is k pi int F' (h + c0') r dr (docs/bodies.md, "Dish").

    Returns:
        (cell centres, c0, Phi(lambda)).
    """
    n = round(wall.radius / spacing)
    r = (np.arange(n) + 0.5) * spacing
    faces = np.arange(n + 1) * spacing
    if smoothing == 0:
        indicator, slope = (r < disk.radius).astype(float), None
    else:
        edge = np.tanh((disk.radius - r) / smoothing)
        indicator, slope = 0.5 * (1 + edge), -(1 - edge**2) / (2 * smoothing)
    inner = faces[:-1] / (r * spacing**2)
    outer = faces[1:] / (r * spacing**2)

    def operator(order: int, rate: complex) -> sp.csc_matrix:
        main = -inner - outer - order**2 / r**2
        main[-1] += outer[-1] if wall.condition == "no_flux" else -outer[-1]
        lap = sp.diags([inner[1:], main, outer[:-1]], [-1, 0, 1])
        sink = disk.evaporation * (1 - indicator) + rate
        return (disk.diffusion * lap.tocsc() - sp.diags(sink)).tocsc()

    rest = spsolve(operator(0, 0.0), -disk.source * indicator).real
    if slope is None:
        return r, rest, math.nan
    drive = slope * (disk.evaporation * rest + disk.source)
    mode = spsolve(operator(1, complex(lam)), drive.astype(complex))
    force = disk.tension_slope * math.pi * np.sum(slope * (mode + np.gradient(rest, r)) * r)
    return r, rest, complex(force * spacing)
