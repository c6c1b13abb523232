"""A direct solve of the 1D ring model of :mod:`.ring`: Fourier modes and moving point sources.

The field is the truncated Fourier series c(x) = sum_{|n| <= K} c_n e^{i k_n x}, k_n = 2 pi n / L,
of Eq. (eqc)'s 1D limit c_t = D c_xx - a c + s0 sum_i delta(x - X_i - sigma). Over a step h
during which each source moves at a constant speed u_i from x_i to x_i + u_i h, each mode is
advanced exactly:

    c_n(t + h) = e^{-g h} c_n(t) + (s0 / L) sum_i [e^{-i k x_i(t+h)} - e^{-g h} e^{-i k x_i(t)}]
                 / (g - i k u_i),                  g = D k^2 + a,

so a state moving at constant speed is stepped without time error. The boats,
mu dX_i/dt = k [c(rear) - c(front)], take Heun's predictor-corrector step (second order).

The field has a kink at each source, so its truncated series errs by O(1/K) at a source
(where a rear source's own boat reads it) and its slope by O(1/(K y)) at a distance y from
one, rippling with K: the spacing modes' rates, small differences of such slopes, would
converge erratically. The modes above K relax at D k^2 + a - i k u ~ D k^2, quasi-statically,
so their missing part is added back to c at each boat end: per source at distance y,

    T(y) = (s0 / (L D)) sum_{|n| > K} e^{i k_n y} / k_n^2
         = s0 (L / (2 D)) B(y / L) - (2 s0 / (L D)) sum_{n=1}^{K} cos(k_n y) / k_n^2,

with B(x) = x^2 - x + 1/6 at the fractional part of x (the Bernoulli polynomial's Fourier
series). What remains is O(K^-2) in c and in its slope.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .ring import RingBoats


@dataclass(frozen=True)
class RingRun:
    """The record of a direct solve.

    Attributes:
        times: the recorded times.
        positions: (times, N) the boats' centres, unwrapped (not taken modulo L).
        velocities: (times, N) their speeds dX/dt.
    """

    times: np.ndarray
    positions: np.ndarray
    velocities: np.ndarray


class RingSolver:
    """The 1D field in K Fourier modes and N overdamped boats, stepped as the module says.

    Args:
        boats: the system (its count, lengths, friction, drive, D, a, source).
        modes: K, the highest Fourier index kept.
        positions: the boats' initial centres (N values).
    """

    def __init__(self, boats: RingBoats, modes: int, positions: np.ndarray) -> None:
        self.boats = boats
        self.k = 2 * math.pi * np.arange(modes + 1) / boats.ring_length
        self.decay = boats.diffusion * self.k**2 + boats.evaporation
        self.coef = np.zeros(modes + 1, dtype=complex)
        self.positions = np.asarray(positions, dtype=float).copy()
        if self.positions.shape != (boats.count,):
            raise ValueError(f"positions: need {boats.count} values, got {self.positions.shape}")
        self.time = 0.0
        self.weights = 2 / (boats.ring_length * boats.diffusion * self.k[1:] ** 2)

    def tail(self, points: np.ndarray, sources: np.ndarray) -> np.ndarray:
        """T summed over the sources at each point: the quasi-static part of the modes above K.

        The kept modes' part factorises, sum_j cos(k (x - s_j)) = Re e^{i k x} sum_j e^{-i k s_j},
        so the cost is that of evaluating the series, not of every pair.
        """
        b = self.boats
        points, sources = np.asarray(points, dtype=float), np.asarray(sources, dtype=float)
        x = np.mod((points[:, None] - sources[None, :]) / b.ring_length, 1.0)
        whole = (b.ring_length / (2 * b.diffusion) * (x * x - x + 1 / 6)).sum(axis=1)
        spectrum = np.exp(-1j * np.outer(sources, self.k[1:])).sum(axis=0) * self.weights
        kept = (np.exp(1j * np.outer(points, self.k[1:])) @ spectrum).real
        return whole - kept

    def field(self, x: np.ndarray) -> np.ndarray:
        """c at the points x (the series summed, per unit supply)."""
        phases = np.exp(1j * np.outer(np.asarray(x, dtype=float), self.k))
        return self.coef[0].real + 2 * (phases[:, 1:] @ self.coef[1:]).real

    def forces(self, positions: np.ndarray) -> np.ndarray:
        """k s0 [c(rear) - c(front)] on each boat at the given centres (the current field)."""
        half = 0.5 * self.boats.boat_length
        points = np.concatenate([positions - half, positions + half])
        ends = self.field(points) + self.tail(points, positions + self.boats.source_offset)
        n = self.boats.count
        return self.boats.drive * (ends[:n] - ends[n:])

    def _advanced(self, start: np.ndarray, end: np.ndarray, step: float) -> np.ndarray:
        """The modes after `step` with each source moving uniformly from `start` to `end`."""
        b = self.boats
        speed = (end - start) / step
        damp = np.exp(-self.decay * step)
        a0 = np.exp(-1j * np.outer(start + b.source_offset, self.k))
        a1 = np.exp(-1j * np.outer(end + b.source_offset, self.k))
        source = (a1 - damp * a0) / (self.decay - 1j * np.outer(speed, self.k))
        return damp * self.coef + source.sum(axis=0) / b.ring_length

    def step(self, step: float) -> np.ndarray:
        """One Heun step of the boats with the exact field update; returns the mean velocity."""
        mu = self.boats.friction
        v0 = self.forces(self.positions) / mu
        trial = self.positions + step * v0
        saved = self.coef
        self.coef = self._advanced(self.positions, trial, step)
        v1 = self.forces(trial) / mu
        self.coef = saved
        new = self.positions + 0.5 * step * (v0 + v1)
        self.coef = self._advanced(self.positions, new, step)
        self.positions = new
        self.time += step
        return 0.5 * (v0 + v1)

    def run(self, duration: float, step: float, every: int = 1) -> RingRun:
        """Step for `duration` and record every `every`-th step.

        Args:
            duration: time to run.
            step: h.
            every: record interval in steps.

        Returns:
            The record, starting with the state before the first step.
        """
        count = round(duration / step)
        times, positions, velocities = (
            [self.time],
            [self.positions.copy()],
            [self.forces(self.positions) / self.boats.friction],
        )
        for i in range(1, count + 1):
            v = self.step(step)
            if i % every == 0:
                times.append(self.time)
                positions.append(self.positions.copy())
                velocities.append(v)
        return RingRun(np.array(times), np.array(positions), np.array(velocities))


def mode_amplitudes(run: RingRun, spacing: float) -> np.ndarray:
    """The discrete Fourier modes of the boats' displacements from even spacing.

    Args:
        run: a record.
        spacing: d = L / N.

    Returns:
        (times, N) complex: sum_i (X_i - i d) e^{-2 pi i m i / N}; m = 0 is N times the mean
        displacement, m != 0 the spacing modes (independent of a common shift).
    """
    n = run.positions.shape[1]
    return np.fft.fft(run.positions - spacing * np.arange(n), axis=1)


def fitted_rate(times: np.ndarray, amplitude: np.ndarray) -> complex:
    """lambda of amplitude ~ e^{lambda t}: least-squares slopes of log|A| and of its phase."""
    real = np.polyfit(times, np.log(np.abs(amplitude)), 1)[0]
    imag = np.polyfit(times, np.unwrap(np.angle(amplitude)), 1)[0]
    return complex(real, imag)
