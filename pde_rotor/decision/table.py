"""Reduced decision model of a release: P(t_stop, Delta, Dw) without ensembles.

At the end of a stop the plate sits in an unstable rest state. Linearised about it,
Eq. (eq_motion) reads I dω/dt = (torque of the fields, a linear response to ω) + T(t)
+ I sqrt(2 Dw) ξ, where T(t) is the torque the fields would exert if the plate stayed at
rest (the stop continued: :attr:`DecisionTable.torque`) and Dw = (sigma/I)² the
angular-velocity diffusion of the noise. With one unstable mode of growth rate λ, the
response to a kick grows as h(t) → C e^{λt}, so

    ω(t) e^{-λt} → C [β/λ + sqrt(2 Dw) ∫ e^{-λs} dW(s)],
    β = (λ/I) ∫_0^∞ e^{-λs} T(t_stop + s) ds,

and the direction after the release is sign(β + noise) with

    P(direction = +1) = Φ(β / sqrt(λ Dw))        (C cancels).

β is the Laplace-weighted torque at release: the memory torque of the flow (opposite to
the rotation before the stop, decaying with t_stop, Figs. 5, 7), the asymmetry torque
∝ Δ (Eq. (def_asym)) and the lattice torque of the stop angle. The conditional inversion
probabilities of the two directions, averaged over the stop angles of the table, give the
paper's P as the sweep estimators do (:mod:`pde_rotor.sweep.estimates`): pooled at
Δ = 0, the two-state chain 2ab/(a + b) otherwise. The table is measured noise-free by
:mod:`pde_rotor.decision.runs`; everything here is arithmetic on it.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr
from scipy.optimize import brentq
from scipy.special import ndtr

from ..io.output import write_netcdf_atomic

DIRECTIONS = (1, -1)
"""Direction before the stop of the table's first axis: CCW, CW."""

TAIL = 0.6
"""Time after a stop over which the Laplace weight e^{-λs} is integrated (λ ≈ 14:
e^{-λ TAIL} ≈ 2e-4); beyond it the torque is held at its last value."""

DATASET_SCALARS = ("asymmetry", "growth_rate", "response", "inertia")
"""The table's scalars, stored as attributes of its Dataset."""


@dataclass(frozen=True)
class DecisionTable:
    """Noise-free stop curves and release response of one configuration.

    Attributes:
        time: time since the start of the stop, (n_t,), uniform spacing.
        torque: torque on the stopped plate, (2, n_angles, n_t), direction before the
            stop CCW then CW (:data:`DIRECTIONS`), stops spread over one period 2π/N.
        asymmetry: Δ of the measured stop curves (Δ_ref).
        growth_rate: λ, growth rate of ω at release (from kicked releases).
        response: C, the kick response h(t) e^{-λt} at late times (validation only).
        inertia: I.
        attrs: provenance (config, grid, scheme, fit windows, checks).
    """

    time: np.ndarray
    torque: np.ndarray
    asymmetry: float
    growth_rate: float
    response: float
    inertia: float
    attrs: dict[str, Any] = field(default_factory=dict)

    @property
    def t_max(self) -> float:
        """Longest stop the table predicts (its stop curves run TAIL longer)."""
        return round(float(self.time[-1]) - TAIL, 9)

    def asymmetry_torque(self) -> np.ndarray:
        """T_asym(t) at Δ_ref: the torque averaged over both directions and all angles.

        The memory torque is odd in the direction and the lattice torque averages out
        over a period of stop angles, so the mean is the asymmetry's torque (∝ Δ).
        """
        return self.torque.mean(axis=(0, 1))

    def memory_torque(self) -> np.ndarray:
        """T_mem(t): the torque against the rotation before the stop, angle-averaged.

        Positive values oppose the former rotation (they drive an inversion).
        """
        odd = 0.5 * (self.torque[0] - self.torque[1]).mean(axis=0)
        return -odd

    def torque_at(self, asymmetry: float) -> np.ndarray:
        """Stop curves at another Δ: the asymmetry torque rescaled, memory and lattice kept.

        Returns:
            (2, n_angles, n_t).
        """
        if asymmetry == self.asymmetry:
            return self.torque
        if self.asymmetry == 0:
            msg = "the table was measured at asymmetry 0: it cannot scale to another Δ"
            raise ValueError(msg)
        scale = (asymmetry - self.asymmetry) / self.asymmetry
        return self.torque + scale * self.asymmetry_torque()

    def bias(self, t_stop: np.ndarray | float, asymmetry: float) -> np.ndarray:
        """β(t_stop) = (λ/I) ∫ e^{-λs} T(t_stop + s) ds of every direction and angle.

        Args:
            t_stop: stop durations in [0, t_max], any shape S.
            asymmetry: Δ.

        Returns:
            (2, n_angles, *S), in units of angular acceleration.
        """
        t_stop = np.asarray(t_stop, dtype=float)
        if np.any(t_stop < 0) or np.any(t_stop > self.t_max + 1e-12):
            msg = f"t_stop outside the table's range [0, {self.t_max:g}]"
            raise ValueError(msg)
        lam = self.growth_rate
        h = float(self.time[1] - self.time[0])
        s = np.arange(0.0, TAIL + 0.5 * h, 0.5 * h)
        weight = np.exp(-lam * s) * lam / self.inertia
        weight[[0, -1]] *= 0.5
        weight *= s[1] - s[0]
        tail = np.exp(-lam * s[-1]) / self.inertia
        curves = self.torque_at(asymmetry)
        times = t_stop.reshape(-1)[:, None] + s[None, :]
        out = np.empty((*curves.shape[:2], times.shape[0]))
        for d in range(curves.shape[0]):
            for k in range(curves.shape[1]):
                values = np.interp(times, self.time, curves[d, k])
                out[d, k] = values @ weight + tail * values[:, -1]
        return out.reshape(curves.shape[:2] + t_stop.shape)

    @property
    def amplitude_scale(self) -> float:
        """r: the release amplitude the check releases measured over the model's C β/λ.

        The least-squares ratio sum m p / sum p^2 over the check releases of both
        directions (m: lim ω e^{-λt} of a noise-free release after the check's stop, p:
        C β/λ; :func:`pde_rotor.decision.runs.measure_table`), 1 for a table without
        checks. The linear model takes the bias of the whole release from the torque the
        fields would exert on a plate *held* at rest; the released plate moves, and its
        deterministic amplitude comes out a few per cent smaller (docs/decision.md,
        "The release amplitude"). r is measured on the table's own noise-free releases;
        no ensemble enters it.
        """
        measured, predicted = [], []
        for name in ("ccw", "cw"):
            m = np.asarray(self.attrs.get(f"check_amplitude_{name}", []), dtype=float)
            p = np.asarray(self.attrs.get(f"check_predicted_{name}", []), dtype=float)
            keep = np.isfinite(m) & np.isfinite(p)
            measured.append(m[keep])
            predicted.append(p[keep])
        m, p = np.concatenate(measured), np.concatenate(predicted)
        if m.size == 0 or not np.any(p):
            return 1.0
        return float(np.dot(m, p) / np.dot(p, p))

    def release_bias(self, t_stop: np.ndarray | float, asymmetry: float) -> np.ndarray:
        """r β: the bias the release acts on, :meth:`bias` times :attr:`amplitude_scale`."""
        return self.amplitude_scale * self.bias(t_stop, asymmetry)

    def conditionals(
        self, t_stop: np.ndarray | float, asymmetry: float, diffusion: float
    ) -> tuple[np.ndarray, np.ndarray]:
        """P(inversion | CCW) and P(inversion | CW), averaged over the stop angles.

        Args:
            t_stop: stop durations, any shape S.
            asymmetry: Δ.
            diffusion: Dw = (sigma/I)², the angular-velocity diffusion of the noise.

        Returns:
            a, b of shape S.
        """
        beta = self.release_bias(t_stop, asymmetry)
        positive = escape_probability(beta, self.growth_rate, diffusion)
        return (1.0 - positive[0]).mean(axis=0), positive[1].mean(axis=0)

    def probability(
        self, t_stop: np.ndarray | float, asymmetry: float, diffusion: float
    ) -> np.ndarray:
        """The paper's P: pooled (a + b)/2 at Δ = 0, else the chain value 2ab/(a + b)."""
        a, b = self.conditionals(t_stop, asymmetry, diffusion)
        if asymmetry == 0:
            return 0.5 * (a + b)
        total = a + b
        return np.divide(2 * a * b, total, out=np.zeros_like(total), where=total > 0)

    def critical_stop(self, asymmetry: float, diffusion: float) -> float:
        """t_c: where the memory bias falls to the larger of the asymmetry and noise scales.

        β_mem(t_c) = max(|β_asym(Δ)|, sqrt(λ Dw)), with the angle-averaged β of the table
        (nan if the memory bias never falls that far within the table).
        """
        t = self.time[self.time <= self.t_max]
        beta = self.release_bias(t, asymmetry)
        memory = 0.5 * (beta[1] - beta[0]).mean(axis=0)
        asym = np.abs(0.5 * (beta[0] + beta[1]).mean(axis=0))
        scale = np.maximum(asym, np.sqrt(self.growth_rate * diffusion))
        below = np.nonzero(memory <= scale)[0]
        if below.size == 0 or below[0] == 0:
            return float("nan") if below.size == 0 else float(t[0])
        i = below[0]
        g0, g1 = memory[i - 1] - scale[i - 1], memory[i] - scale[i]
        return float(t[i - 1] + (t[i] - t[i - 1]) * g0 / (g0 - g1))

    def calibrate(
        self, target: float, t_stop: float, asymmetry: float, bracket: tuple[float, float]
    ) -> float:
        """The Dw at which P(t_stop, Δ) equals `target` (Brent's method in log Dw).

        Raises:
            ValueError: `target` is not between P at the two ends of `bracket`.
        """

        def excess(log_dw: float) -> float:
            return float(self.probability(t_stop, asymmetry, np.exp(log_dw))) - target

        lo, hi = np.log(bracket[0]), np.log(bracket[1])
        f_lo, f_hi = excess(lo), excess(hi)
        if f_lo * f_hi > 0:
            msg = (
                f"P = {target:g} is not reached for Dw in [{bracket[0]:g}, {bracket[1]:g}] "
                f"(P = {f_lo + target:.3g} ... {f_hi + target:.3g})"
            )
            raise ValueError(msg)
        return float(np.exp(brentq(excess, lo, hi, xtol=1e-12)))

    def to_dataset(self) -> xr.Dataset:
        """The table as a Dataset (:func:`load_table` reads it back)."""
        return xr.Dataset(
            {"torque": (("direction", "angle", "time"), self.torque)},
            coords={
                "direction": list(DIRECTIONS),
                "angle": np.arange(self.torque.shape[1]),
                "time": self.time,
            },
            attrs={
                **self.attrs,
                "asymmetry": self.asymmetry,
                "growth_rate": self.growth_rate,
                "response": self.response,
                "inertia": self.inertia,
            },
        )

    def save(self, path: str | Path) -> None:
        """Write the table as NetCDF (atomically)."""
        write_netcdf_atomic(self.to_dataset(), path)


def load_table(path: str | Path) -> DecisionTable:
    """Read a table written by :meth:`DecisionTable.save`."""
    with xr.open_dataset(path, engine="h5netcdf") as ds:
        ds = ds.load()
    attrs = dict(ds.attrs)
    values = {name: float(attrs.pop(name)) for name in DATASET_SCALARS}
    return DecisionTable(
        time=ds["time"].values,
        torque=ds["torque"].values,
        asymmetry=values["asymmetry"],
        growth_rate=values["growth_rate"],
        response=values["response"],
        inertia=values["inertia"],
        attrs=attrs,
    )


def escape_probability(
    bias: np.ndarray | float, growth_rate: float, diffusion: float
) -> np.ndarray:
    """P(direction after the release = +1) = Φ(β / sqrt(λ Dw)) (linear escape).

    Args:
        bias: β, the Laplace-weighted torque per inertia at release.
        growth_rate: λ.
        diffusion: Dw = (sigma/I)² (0: the sign of β decides; 1/2 at β = 0).
    """
    bias = np.asarray(bias, dtype=float)
    if diffusion < 0:
        msg = f"diffusion Dw = {diffusion:g} must be >= 0"
        raise ValueError(msg)
    if diffusion == 0:
        return 0.5 * (1.0 + np.sign(bias))
    return ndtr(bias / np.sqrt(growth_rate * diffusion))


def diffusion_of(sigma: float, inertia: float) -> float:
    """Dw = (sigma/I)² of the project's noise (each moving step adds sqrt(2 dt) sigma/I N(0, 1))."""
    return (sigma / inertia) ** 2


def sigma_of(diffusion: float, inertia: float) -> float:
    """The sigma of a diffusion Dw: I sqrt(Dw)."""
    return inertia * float(np.sqrt(diffusion))
