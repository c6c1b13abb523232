"""Leading eigenvalues: residuals, symmetry, the growth of the paper's rotor, the onsets."""

from __future__ import annotations

import numpy as np
import pytest

from pde_rotor.config import RotorConfig
from pde_rotor.stability import DiscreteModel, is_real, leading_modes, linearise
from pde_rotor.theory import CamphorDisk, Wall, dish_hopf_onset
from tests.stability.conftest import disk_data


def test_the_paper_rotor_at_rest_is_unstable_to_turning(rotor_config: RotorConfig) -> None:
    lin = linearise(DiscreteModel(rotor_config))
    spectrum = leading_modes(lin, k=4)
    lam = spectrum.leading
    assert is_real(lam) and lam.real > 0
    assert spectrum.residuals.max() < 1e-8
    # the mode turns the plate: its angular velocity is a real multiple of the mode
    mode = lin.split(spectrum.vectors[:, 0], lam)
    assert abs(mode["dp"][0]) > 0
    # every other eigenvalue found decays
    assert all(value.real < 0 for value in spectrum.eigenvalues[1:])
    # the eigenvector grows under J as lambda says
    x = spectrum.vectors[:, 0]
    assert np.linalg.norm(lin.matvec(x) - lam * x) < 1e-8 * abs(lam)


def test_free_disk_translation_modes_are_degenerate_in_x_and_y() -> None:
    data = disk_data("absorbing", radius=3.0)
    data["bodies"][0]["motion"]["friction"] = 0.15
    lin = linearise(DiscreteModel(RotorConfig.model_validate(data)))
    spectrum = leading_modes(lin, k=4)
    first, second = spectrum.eigenvalues[:2]
    assert first.real > 0
    assert first == pytest.approx(second, rel=1e-8)


def test_disk_in_a_no_flux_dish_oscillates_hopf_pair() -> None:
    """Koyano, Suematsu & Kitahata's dish: the leading pair is complex, at the theory's
    frequency within the coarse grid's error."""
    data = disk_data("no_flux", radius=3.0, mass=1e-4)
    data["bodies"][0]["motion"]["friction"] = 0.165
    lin = linearise(DiscreteModel(RotorConfig.model_validate(data)))
    assert lin.positions
    spectrum = leading_modes(lin, k=6)
    lam = spectrum.leading
    assert not is_real(lam)
    _, omega_c = dish_hopf_onset(CamphorDisk(1.0, 1.0, 1.0, 1.0, 0.1), Wall(3.0, "no_flux"), 1e-4)
    assert abs(lam.imag) == pytest.approx(omega_c, rel=0.15)
    assert spectrum.residuals[:4].max() < 1e-8  # the two pairs (x and y)
