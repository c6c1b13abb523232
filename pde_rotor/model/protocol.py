"""Stop-and-release schedule of the paper's section "Model" (last part).

The first stop starts at t_ini; stop m (m = 1..M) lasts from t_ini + (m-1) T to
t_ini + t_stop + (m-1) T with T = t_stop + t_release. During a stop phi is frozen and
dphi/dt = 0; c and v keep evolving. Times are handled as integer step counts so that
the schedule does not drift with floating point round-off; the rule itself is the
compiled physics' ``stopped_at`` (:mod:`pde_rotor.physics.motion`), which the kernels call.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..config import ProtocolConfig
from ..physics.build import CPU

_stopped_at = CPU.motion.stopped_at


@dataclass(frozen=True)
class StopSchedule:
    """The protocol in units of time steps.

    Attributes:
        dt: time step.
        n_ini: steps before the first stop.
        n_stop: steps of one stop.
        n_period: steps of one stop-and-release cycle.
        cycles: M, number of cycles.
    """

    dt: float
    n_ini: int
    n_stop: int
    n_period: int
    cycles: int

    @classmethod
    def from_config(cls, protocol: ProtocolConfig, dt: float) -> StopSchedule:
        """Convert times to step counts (they must be multiples of dt, see config)."""
        return cls(
            dt=dt,
            n_ini=steps_of(protocol.t_ini, dt),
            n_stop=steps_of(protocol.t_stop, dt),
            n_period=steps_of(protocol.t_stop + protocol.t_release, dt),
            cycles=protocol.cycles,
        )

    def is_stopped(self, step: int) -> bool:
        """Whether step `step` (advancing t = step dt by dt) lies in a stop phase."""
        return bool(_stopped_at(step, self.n_ini, self.n_stop, self.n_period, self.cycles))

    def cycle(self, step: int) -> int:
        """Cycle number m (1..M) that `step` belongs to, 0 before the first stop."""
        rel = step - self.n_ini
        if rel < 0:
            return 0
        return min(rel // self.n_period + 1, self.cycles)

    def stop_steps(self) -> np.ndarray:
        """Start steps of the M stops."""
        return self.n_ini + self.n_period * np.arange(self.cycles, dtype=np.int64)

    def sample_steps(self, every: int, n_end: int) -> np.ndarray:
        """Multiples of `every` in [0, n_end], n_end, and the start and end of every stop.

        The steps at which the rotor trackers sample a run (and the inversion rule checks
        a release, :mod:`pde_rotor.statistics.inversion`), increasing and unique.
        """
        starts = self.stop_steps()
        steps = [
            np.arange(0, n_end + 1, max(1, every), dtype=np.int64),
            np.array([n_end], dtype=np.int64),
            starts,
            starts + self.n_stop,
        ]
        all_steps = np.unique(np.concatenate(steps))
        return all_steps[all_steps <= n_end]

    def stop_times(self) -> np.ndarray:
        """Start times of the M stops."""
        return (self.n_ini + self.n_period * np.arange(self.cycles)) * self.dt


def steps_of(duration: float, dt: float) -> int:
    """Number of steps of `duration`, which must be an integer multiple of dt."""
    steps = round(duration / dt)
    if abs(steps * dt - duration) > 1e-9 * max(1.0, duration):
        msg = f"duration {duration:g} is not an integer multiple of dt = {dt:g}"
        raise ValueError(msg)
    return steps
