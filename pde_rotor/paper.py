"""The values that Koyano, Kitahata, Nakata and Gorecki (Chaos 30, 2020) state in words
about their inversion probabilities: one home for the targets of the noise calibration,
the gallery's reference marks and the benchmarks. The paper gives no tables; each
constant quotes the sentence it comes from (section "Results", Figs. 5, 7 and 8).
"""

from __future__ import annotations

DECAY_STOP = 1.4
"""Fig. 5 (Delta = 0): "It decayed around t_stop ≃ 1.4 and converged to 0.5"."""

ONSET_STOP = 1.0
"""Fig. 7(a) (Delta = 1e-4): "It started to decay around t_stop ≃ 1 and converged to 0"."""

ONSET_ASYMMETRY = 1e-4
"""Delta of Fig. 7(a) and of the asymmetric time series, Fig. 6."""

PLATEAU = 0.2
"""The experiment's long-stop inversion probability ("converged to the finite value
around 0.2"), which the paper's Fig. 7(b) at Delta = 2e-5 "looks similar to"."""

PLATEAU_ASYMMETRY = 2e-5
"""Delta of Fig. 7(b), whose long stops give the plateau :data:`PLATEAU`."""

PLATEAU_STOP = 3.0
"""t_stop of Fig. 7(c), "a long stop phase": where the plateau is read."""

NO_FLOW_FAVOURED = 0.8
"""Fig. 8 (no flow), Delta = 2e-5: "the favorable rotational direction is selected with
probability 0.8 after a forced stop"."""
