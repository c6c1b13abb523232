"""A rigid rotor as an ensemble backend: the estimators' reading, without a PDE.

Every member turns at the constant angular velocity it starts with (phi = omega t, stops
and noise ignored), so every number the estimators read follows from the step counts
alone. Records are taken as the backends take them: at the first step, then at every
multiple of the record interval. The runner records its calls (members, steps, noise).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np

from pde_rotor.backends.ensemble import EnsembleResult, EnsembleState
from pde_rotor.config import RotorConfig
from pde_rotor.model.setup import Setup, as_setup
from pde_rotor.sweep import Sweep, SweepSpec


class RigidRotor:
    """An :class:`~pde_rotor.backends.base.EnsembleRunner` of rotors that never slow."""

    def __init__(self) -> None:
        self.calls: list[dict[str, Any]] = []

    def __call__(
        self,
        members: Sequence[Setup | RotorConfig],
        t_end: float,
        *,
        record_interval: float,
        initial: EnsembleState | None = None,
        rngs: Sequence[Any] | None = None,
    ) -> EnsembleResult:
        setups = tuple(as_setup(member) for member in members)
        configs = [setup.config for setup in setups]
        dt = configs[0].grid.dt
        if initial is None:
            omega = np.array([c.rotor.omega0 for c in configs])
            rotor = np.zeros((len(configs), 5))
            rotor[:, 1] = omega
            initial = EnsembleState(np.zeros((len(configs), 3, 2, 2)), rotor, 0)
        end, every = round(t_end / dt), round(record_interval / dt)
        first = (initial.step // every + 1) * every  # the backends' record steps
        steps = np.concatenate([[initial.step], np.arange(first, end + 1, every)])
        omega = initial.rotor[:, 1:2]
        phi = initial.rotor[:, :1] + omega * (steps - initial.step) * dt
        shape = (len(configs), steps.size)
        rotor = initial.rotor.copy()
        rotor[:, 0] = phi[:, -1]
        self.calls.append({"members": len(configs), "steps": end - initial.step, "rngs": rngs})
        return EnsembleResult(
            setups=setups,
            t=steps * dt,
            phi=phi,
            omega=np.broadcast_to(omega, shape).copy(),
            torque=np.zeros(shape),
            friction=np.zeros(shape),
            stopped=np.zeros(shape, dtype=bool),
            camphor_total=np.zeros(shape),
            diverged_at=np.full(len(configs), math.nan),
            state=EnsembleState(initial.data, rotor, end),
            backend="rigid",
            wall_seconds=0.0,
        )


def rigid_sweep(kind: str, **changes: Any) -> Sweep:
    """Two asymmetries x 2 samples on the coarse grid (nothing here steps a PDE): t_ini,
    t_stop, t_release, the warmup and the check interval are 125, 50, 125, 250 and 25
    steps of dt = 4e-4."""
    data = {
        "name": "rigid",
        "base": {
            "grid": {"dx": 0.05, "dt": 4e-4},
            "protocol": {"t_ini": 0.05, "t_stop": 0.02, "t_release": 0.05, "cycles": 2},
        },
        "axes": {"geometry.asymmetry": [0.0, 1e-4]},
        "estimator": {"kind": kind, "warmup": 0.1, "check_interval": 0.01},
        "samples": 2,
        "seed": 5,
        **changes,
    }
    if kind == "protocol":
        data["estimator"] = {"kind": "protocol"}
    return Sweep.from_spec(SweepSpec.model_validate(data))
