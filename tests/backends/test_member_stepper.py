"""One run path: a run advanced by an ensemble backend between the Controller's interrupts.

``pde-rotor run --backend gpu`` runs a configuration as an ensemble of one member
(:func:`pde_rotor.backends.member_stepper`) under the same py-pde Controller and
trackers as the CPU solver; driven by the CPU ensemble backend, it must write exactly
what the fused CPU solver writes (tests/backends/test_gpu.py runs the GPU backend in
numba's CUDA simulator).
"""

from __future__ import annotations

import numpy as np
import pytest
from pde.storage import MemoryStorage

from pde_rotor import trackers as tr
from pde_rotor.backends import member_stepper
from pde_rotor.config import RotorConfig
from pde_rotor.solver.rotor import SimulationDivergedError
from pde_rotor.solver.simulation import Simulation
from tests.conftest import DIVERGING

TINY = {
    "grid": {"dx": 0.05, "dt": 4e-4, "domain_radius": 1.75},
    "geometry": {"smoothing": 0.05, "asymmetry": 0.05},
    "protocol": {"t_ini": 0.4, "t_stop": 0.2, "t_release": 0.4, "cycles": 2},
    "noise": {"seed": 0, "sigma": 0.01},
}


def run_with_trackers(config: RotorConfig, ensemble: bool):
    """Time series (0.02), events (0.01) and field snapshots (0.3) of one run."""
    sim = Simulation(config, stepper=member_stepper("cpu")) if ensemble else Simulation(config)
    ts = tr.TimeSeriesTracker(sim.config, 0.02)
    ev = tr.InversionTracker(sim.config, 0.01, 0.5)
    storage = MemoryStorage()
    snaps = storage.tracker(interrupts=[0.0, 0.3, 0.6, 1.2])
    sim.run(trackers=[ts, ev, snaps])
    return sim, ts, ev, storage


def test_ensemble_driven_run_writes_what_the_solver_run_writes():
    config = RotorConfig.model_validate(TINY)
    ref = run_with_trackers(config, ensemble=False)
    got = run_with_trackers(config, ensemble=True)
    ts_ref, ts_got = ref[1].to_dataset(), got[1].to_dataset()
    assert ts_got.sizes == ts_ref.sizes
    for name in ts_ref.data_vars:
        np.testing.assert_array_equal(ts_got[name], ts_ref[name], err_msg=name)
    ev_ref, ev_got = ref[2].to_dataset(), got[2].to_dataset()
    for name in ev_ref.data_vars:
        np.testing.assert_array_equal(ev_got[name], ev_ref[name], err_msg=name)
    assert ev_ref["inverted"].values.any() and not ev_ref["inverted"].values.all()
    np.testing.assert_array_equal(got[3].times, ref[3].times)
    for a, b in zip(got[3], ref[3], strict=True):
        np.testing.assert_array_equal(a.data, b.data)
    np.testing.assert_array_equal(got[0].state.data, ref[0].state.data)
    assert got[0].t == pytest.approx(config.protocol.t_end)


def test_divergence_raises_after_the_samples_before_it():
    """A flow beyond the advection limit: the run stops, the samples before it are kept."""
    config = RotorConfig.model_validate({**TINY, **DIVERGING})
    sim = Simulation(config, stepper=member_stepper("cpu"))
    ts = tr.TimeSeriesTracker(sim.config, 0.02)
    with pytest.raises(SimulationDivergedError, match=r"diverged at t = .* cpu backend"):
        sim.run(trackers=[ts])
    times = np.asarray(ts.rows["time"])
    assert times.size >= 1 and times[-1] <= sim.t
    assert np.isfinite(ts.rows["omega"]).all()
    assert sim.t < config.protocol.t_end
