"""The compiled step behind the no-flux dish wall against the numpy reference, and its
conservation of camphor; the compiled solve of the implicit clusters against a dense
solve."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pde_rotor import RotorConfig
from pde_rotor.config.vessel import AnnulusVessel, RectangleVessel
from pde_rotor.kernels.wall import implicit_clusters
from pde_rotor.model.clusters import cluster_matrices, implicit_factors
from pde_rotor.model.surface import SurfacePDE
from pde_rotor.model.vessel import make_vessel_cells
from pde_rotor.solver.simulation import Simulation

from .test_vessel import seeded

BODIES = [
    {
        "name": "hexagon",
        "plate": {"shape": "polygon", "n_corners": 6, "radius": 0.5},
        "pills": [{"x": 0.3, "y": 0.05}, {"x": -0.2, "y": -0.2, "radius": 0.08, "supply": 2.0}],
        "motion": {"kind": "fixed_axis"},
        "start": {"x": -1.6, "y": 1.0, "angle": 0.4, "omega": 3.0},
    },
    {
        "name": "strip",
        "plate": {"shape": "strip", "length": 0.8, "width": 0.3},
        "pills": [{"x": 0.3, "y": 0.0, "radius": 0.06}, {"x": -0.3, "y": 0.0, "radius": 0.06}],
        "motion": {"kind": "free", "mass": 3e-5, "friction": 1e-4},
        "start": {"x": 1.4, "y": -1.2, "angle": 0.7, "omega": 2.0, "velocity": [-0.2, 0.1]},
    },
]
"""A turning hexagon and a free strip, well inside a dish of radius 4."""


def walled(bodies: list[dict] = BODIES, **sections: dict) -> Simulation:
    """A coarse no-flux dish of radius 4 (dx = 0.1, 82^2 cells) with :data:`BODIES`, c and
    v smooth and nonzero up to the wall (v only where the cell centre lies inside)."""
    config = RotorConfig.model_validate(
        {
            "grid": {"domain_radius": 4.0, "dx": 0.1, "dt": 1e-3, "wall": "no_flux"},
            "geometry": {"smoothing": 0.05},
            "numerics": {"scheme": "paper"},
            "protocol": {"t_ini": 1.0, "cycles": 0},
            "bodies": bodies,
            **sections,
        }
    )
    sim = seeded(Simulation(config))
    if not config.flow.enabled:
        sim.state.data[1:] = 0.0
    return sim


@pytest.mark.parametrize("flow", [True, False])
def test_walled_step_equals_numpy_reference(flow: bool) -> None:
    """One compiled step gives the numpy step of c behind the wall
    (:meth:`SurfacePDE.camphor_step`: cut-cell fluxes, the stiff cells' faces implicit) on
    every cell, the cut cells and those beyond the circle included, and the numpy rate of
    v, Eq. (eqv); away from the stiff cells c moves at the numpy rate of Eq. (eqc)."""
    sim = walled(flow={"enabled": flow})
    pde: SurfacePDE = sim.pde
    before = sim.state.copy()
    dt = sim.config.grid.dt
    expected = pde.camphor_step(before, dt)
    rate = pde.evolution_rate(before).data
    sim.run(dt)
    after = sim.state.data
    assert np.abs(after[0] - expected).max() <= 1e-12 * np.abs(expected).max()
    computed = (after - before.data) / dt
    assert np.abs(computed[1:] - rate[1:]).max() <= 1e-9 * np.abs(rate).max()
    cells = pde.domain.cut_cells
    near_stiff = cells.stiff.copy()
    for axis in (0, 1):
        near_stiff |= np.roll(cells.stiff, 1, axis) | np.roll(cells.stiff, -1, axis)
    explicit = cells.mask & ~near_stiff
    assert np.abs(computed[0] - rate[0])[explicit].max() <= 1e-9 * np.abs(rate).max()
    assert np.abs(computed[0][cells.mask & ~pde.domain.interior_mask]).max() > 0
    assert np.all(after[:, ~cells.mask] == 0.0)


def test_walled_step_conserves_camphor_with_moving_bodies_and_flow() -> None:
    """With no sublimation and no supply, the camphor in the dish (sum of kappa c dA)
    stays what it was while the bodies turn and move and the flow advects it."""
    dry = [{**b, "pills": [{**p, "supply": 0.0} for p in b["pills"]]} for b in BODIES]
    dry[1]["motion"] = {
        "kind": "free",
        "mass": 1e-2,
        "friction": 1e-4,
    }  # drifts with its start velocity
    sim = walled(dry, camphor={"evaporation": 0.0})
    domain = sim.pde.domain
    start = domain.camphor_total(sim.state.data[0])
    sim.run(0.2)
    assert np.abs(sim.state.data[1:]).max() > 0.01
    assert abs(domain.camphor_total(sim.state.data[0]) / start - 1) < 1e-12


@pytest.mark.parametrize(
    ("vessel", "dx"),
    [
        (AnnulusVessel(shape="annulus", inner_radius=0.8, outer_radius=0.97), 0.037),
        (RectangleVessel(shape="rectangle", half_widths=(0.93, 0.61)), 0.1),  # one ring
    ],
)
def test_implicit_clusters_solve_each_cluster_as_a_dense_solve(vessel, dx: float) -> None:
    """The compiled forward and back substitution by the clusters' sparse factors gives
    each cluster's dense solve A c' = rhs (numpy's LU of the matrix itself) to round-off,
    keeps sum kappa c' = sum rhs (the camphor), and writes no cell outside the clusters
    (the numpy step's c' there is the explicit part's)."""
    n = 2 * math.ceil(1.0 / dx - 1e-9) + 2
    cells = make_vessel_cells((np.arange(n) + 0.5) * dx - n * dx / 2, vessel)
    coefficient = 0.2
    index, _, factor = implicit_factors(cells, coefficient)
    rhs = np.random.default_rng(3).random(n * n) * cells.mask.reshape(-1)
    nxt = np.full(n * n, -1.0)
    implicit_clusters(nxt, rhs.copy(), index, factor)
    kappa = cells.volume.reshape(-1)
    for members, matrix in cluster_matrices(cells, coefficient):
        expected = np.linalg.solve(matrix, rhs[members])
        assert np.abs(nxt[members] - expected).max() <= 1e-14 * np.abs(expected).max()
        total = np.dot(kappa[members], nxt[members])
        assert abs(total - rhs[members].sum()) <= 1e-15 * members.size * np.abs(rhs).max()
    outside = np.ones(n * n, dtype=bool)
    outside[index[:, 0]] = False
    assert np.all(nxt[outside] == -1.0)
