"""The ``rotor:`` section (the rotor's dynamics, Eq. (eq_motion)) and the ``noise:``
section (its torque noise, Eq. (noiseav)), with the calibrated noise intensities."""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import Field

from .bodies import BodyLoads
from .fields import (
    ANGLE_BOUND,
    OMEGA_BOUND,
    PAPER_FRICTION,
    PAPER_INERTIA,
    SCALE_BOUND,
    FiniteFloat,
    Int,
    NonNegativeFloat,
    PositiveFloat,
    _Section,
)
from .recorded import BuiltInto, NotRecorded

_INITIAL = NotRecorded("an initial condition: the rotor's state at t = 0")


class RotorKeys(_Section):
    """The rotor's own keys: its dynamics, Eq. (eq_motion), and initial condition (a base
    of :class:`RotorDynamicsConfig`, so that they come before the loads)."""

    inertia: PositiveFloat = Field(
        PAPER_INERTIA,
        ge=PAPER_INERTIA / SCALE_BOUND,
        le=PAPER_INERTIA * SCALE_BOUND,
        description="I: moment of inertia",
    )
    friction: NonNegativeFloat = Field(
        PAPER_FRICTION, le=PAPER_FRICTION * SCALE_BOUND, description="mu: friction constant"
    )
    phi0: Annotated[FiniteFloat, _INITIAL] = Field(
        1.0, ge=-ANGLE_BOUND, le=ANGLE_BOUND, description="phi(0): initial angle [rad]"
    )
    omega0: Annotated[FiniteFloat, _INITIAL] = Field(
        0.1, ge=-OMEGA_BOUND, le=OMEGA_BOUND, description="dphi/dt(0): initial angular velocity"
    )
    torque: Annotated[Literal["physical", "printed"], BuiltInto("torque_sign")] = Field(
        "physical",
        description=(
            "physical: T = -k int F r x grad c dA (contour integral of gamma n); "
            "printed: T = int_Omega r x (-grad gamma) dA as printed in Eq. (torque)"
        ),
    )


class RotorDynamicsConfig(BodyLoads, RotorKeys):
    """Rotor dynamics, Eq. (eq_motion), and its initial condition (:class:`RotorKeys`), and
    the external loads every body takes (:class:`~pde_rotor.config.bodies.BodyLoads`),
    handed to the rotor's body (:meth:`pde_rotor.config.RotorConfig.rotor_body`)."""


CALIBRATED_SIGMA = 1.5e-7
"""Noise intensity calibrated at the paper's resolution (dx = delta = 0.025, dt = 1e-4)
on the default scheme (``consistent``): Dw = (sigma/I)^2 = 2.25e-4.

With it the Delta = 2e-5 plateau at t_stop = 3 is the paper's 0.2 (Fig. 7b):
configs/sweeps/science_calibration.yaml measured P = 0.197 [0.108, 0.332] here, from
100 stops per direction at each of seven intensities (data/science_calibration.nc);
fitted with the decision model, the crossing lies at sigma = 1.49e-7, 95 % range
1.35e-7 to 1.62e-7 (docs/statistics.md). The paper-resolution configs
(configs/paper_fig*.yaml, pde_rotor/bases/paper.yaml) carry this value;
tests/config/test_config.py keeps them equal.
"""

PAPER_SCHEME_SIGMA = 2.0e-8
"""The intensity once calibrated on the ``paper`` scheme, whose lattice torque alone
gives the Delta = 2e-5 plateau 0.18 (so it calibrates the grid more than the noise;
docs/statistics.md). The stored paper-scheme reports (data/calibration.nc,
predictions.nc, predictions_no_flow.nc) hold it; the gallery draws them at it."""


PAPER_STEADY_OMEGA = 176.06
"""Steady angular velocity of the noise-free rotor at the paper's parameters and grid
(docs/model.md: 176.0626; the paper: "~176"): the scale of the rotation against which
:class:`RotorConfig` judges the noise."""


class NoiseConfig(_Section):
    """Torque noise xi(t) of Eq. (eq_motion), <xi(t) xi(s)> = 2 sigma^2 delta(t-s), Eq. (noiseav).

    Integrated by Euler-Maruyama, so results do not depend on dt. The paper's
    sigma = 0.1 taken literally destroys the rotation (docs/model.md); the default is
    no noise, and :data:`CALIBRATED_SIGMA` is the intensity calibrated to the paper.
    """

    sigma: Annotated[NonNegativeFloat, BuiltInto("kick")] = Field(
        0.0, description="sigma: torque noise intensity"
    )
    seed: Annotated[Int | None, NotRecorded("seeds the host's generator of the normals")] = Field(
        None, ge=0, description="seed of the numpy Generator (null: drawn and recorded per run)"
    )
