"""Stop-and-release protocol of the paper's section "Model" (last part).

Stop m (m = 1..M) covers t in (t_ini + (m-1) T, t_ini + t_stop + (m-1) T] with
T = t_stop + t_release: phi is frozen at its value at the start of the stop and
dphi/dt = 0, while Eqs. (eqc) and (eqv) keep evolving (with the plate at rest in the
flow term). After the stop the rotor is released from omega = 0.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np
import pytest
from pde.trackers import CallbackTracker

from pde_rotor import RotorConfig, Simulation
from pde_rotor.config import ProtocolConfig
from pde_rotor.model.protocol import StopSchedule

SHORT_PROTOCOL: dict[str, Any] = {"t_ini": 0.5, "t_stop": 0.1, "t_release": 0.2, "cycles": 2}
"""Spin-up and two quick cycles at the coarse dt = 4e-4: 1250 + 2 x (250 + 500) steps."""


def in_stop_by_time(step: int, protocol: ProtocolConfig, dt: float) -> bool:
    """The paper's definition, in times: the step ((k dt, (k+1) dt]) lies in a stop interval.

    The step's midpoint avoids any ambiguity from round-off at the interval ends.
    """
    t_mid = (step + 0.5) * dt
    for m in range(1, protocol.cycles + 1):
        start = protocol.t_ini + (m - 1) * protocol.period
        if start < t_mid < start + protocol.t_stop:
            return True
    return False


def test_schedule_steps_follow_the_paper(small_config: Callable[..., RotorConfig]) -> None:
    """StopSchedule marks exactly the steps inside the paper's stop intervals.

    is_stopped is the compiled core's stopped_at, the rule the kernels apply. Also:
    cycle(step) counts the cycles (0 before the first stop, then 1..M, M after the
    end) and stop_times are t_ini + (m-1) T.
    """
    cfg = small_config({"protocol": SHORT_PROTOCOL})
    proto, dt = cfg.protocol, cfg.grid.dt
    schedule = StopSchedule.from_config(proto, dt)
    n_end = round(proto.t_end / dt)
    stopped = [schedule.is_stopped(k) for k in range(n_end + 300)]
    assert stopped == [in_stop_by_time(k, proto, dt) for k in range(n_end + 300)]
    assert sum(stopped) == proto.cycles * round(proto.t_stop / dt)
    np.testing.assert_allclose(
        schedule.stop_times(), proto.t_ini + proto.period * np.arange(proto.cycles), rtol=1e-12
    )
    for k in range(n_end + 300):
        t_mid = (k + 0.5) * dt
        expected = (
            0
            if t_mid < proto.t_ini
            else min(int((t_mid - proto.t_ini) // proto.period) + 1, proto.cycles)
        )
        assert schedule.cycle(k) == expected


def test_schedule_rejects_durations_off_the_time_grid() -> None:
    """Stop times must be whole multiples of dt: a stop of 0.5 dt more is refused."""
    dt = RotorConfig.model_validate({}).grid.dt
    proto = ProtocolConfig.model_validate({**SHORT_PROTOCOL, "t_stop": 0.1 + 0.5 * dt})
    with pytest.raises(ValueError, match="multiple of dt"):
        StopSchedule.from_config(proto, dt)


def test_rotor_frozen_during_stops_and_released_from_rest(
    small_config: Callable[..., RotorConfig],
) -> None:
    """Run the short protocol, recording every step through py-pde's tracker.

    During each stop: omega == 0 exactly, phi equals its value at the stop's start, the
    rotor reports ``stopped``; c keeps changing and the fluid's angular momentum
    int r x v dA decays faster than exp(-eta_b t) (Eq. (eqv): the plate under it is at
    rest and int r x lap v dA = L^2 v_theta'(L) < 0 for a co-rotating flow). The first
    step after a stop starts from omega = 0: phi does not move in it and omega becomes
    dt (T + friction) / I with the torques reported for that step, Eq. (eq_motion).
    """
    cfg = small_config({"protocol": SHORT_PROTOCOL})
    proto, dt = cfg.protocol, cfg.grid.dt
    sim = Simulation(cfg)
    x, y = sim.pde.cell_coordinates()
    rows: dict[int, tuple[float, ...]] = {}

    def record(state: Any, t: float) -> None:
        rotor = state.rotor
        spin = float(np.sum(x * state.data[2] - y * state.data[1]))
        rows[round(t / dt)] = (
            rotor.phi,
            rotor.omega,
            float(rotor.stopped),
            rotor.torque,
            rotor.friction,
            float(np.sum(state.data[0])),
            spin,
        )

    sim.run(proto.t_end, trackers=[CallbackTracker(record, interrupts=dt)])
    n_end = round(proto.t_end / dt)
    assert sorted(rows) == list(range(n_end + 1))
    phi, omega, stopped, torque, friction, mass, spin = np.array(
        [rows[k] for k in range(n_end + 1)]
    ).T
    schedule = StopSchedule.from_config(proto, dt)
    assert abs(omega[schedule.n_ini]) > 10 * cfg.rotor.omega0  # spun up before the first stop
    for m in range(proto.cycles):
        start = schedule.n_ini + m * schedule.n_period
        end = start + schedule.n_stop
        assert omega[start] != 0.0  # it was rotating when stopped
        assert abs(omega[start - 1] - omega[start]) > 0.0
        frozen = slice(start + 1, end + 1)  # states after the stopped steps
        assert np.all(omega[frozen] == 0.0)
        assert np.all(phi[frozen] == phi[start])
        assert np.all(stopped[frozen] == 1.0)
        assert stopped[start] == 0.0 and stopped[end + 1] == 0.0
        assert np.all(np.diff(mass[frozen]) != 0.0)  # camphor keeps evolving
        # the fluid's angular momentum only loses: bulk drag exp(-eta_b t), plus the drag
        # of the still plate and the viscous stress at |r| = L
        assert np.all(np.diff(np.abs(spin[start : end + 1])) < 0)
        bulk_decay = np.exp(-cfg.flow.bulk_drag * proto.t_stop)
        assert abs(spin[end]) < bulk_decay * abs(spin[start])
        # release: the first free step starts from omega = 0
        assert phi[end + 1] == phi[end]
        assert omega[end + 1] == pytest.approx(
            dt * (torque[end + 1] + friction[end + 1]) / cfg.rotor.inertia, rel=1e-12
        )
        assert omega[end + 2] != 0.0
