"""The noise intensity from an ensemble: the decision model's one noise scale, fitted.

The noise is calibrated so that the Fig. 7(b) plateau (P at t_stop = 3,
Δ = 2e-5; the paper's long-run inversion fraction and the experiment's 0.2) is
reached. The decision model (:mod:`pde_rotor.decision.table`) predicts the conditionals
P(inv | CCW) and P(inv | CW) at every sigma from noise-free quantities alone. An
ensemble at several sigma measures them, and the two are joined by one number, κ:
the ensemble behaves as the model at the diffusion κ Dw, Dw = (sigma/I)². κ = 1 is
the model exact; κ absorbs what the linear escape leaves out (the finite kick
response, the nonlinear end of the release). κ is fitted by maximum likelihood over
the binomial counts of every (point, direction), and the calibrated diffusion is the
model's crossing divided by κ.

Its 95 % range comes from a bootstrap over stops, not from the binomial likelihood:
the bank estimator releases each stop at every sigma, so its counts at different
sigma share their stops (the stop angle and its lattice torque). The stop (its
direction and sample index) is the unit that is resampled, within each direction
(``scipy.stats.bootstrap`` with one sample of stops per direction, percentile range).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from scipy import optimize, stats

from ..paper import PLATEAU, PLATEAU_ASYMMETRY, PLATEAU_STOP
from .table import DIRECTIONS, DecisionTable, diffusion_of, escape_probability

LOG_SCALES = np.linspace(math.log(1e-3), math.log(1e3), 121)
"""log κ searched, 1e-3 to 1e3: the best of these 121 points (12 % apart) and its
neighbours bracket the likelihood's maximum for Brent's method (the likelihood is flat
where every P is 0, 1 or 1/2, which a bounded search over the whole range can stop on)."""
SCALE_TOLERANCE = 1e-6
"""Absolute tolerance of the maximum in log κ (a relative 1e-6 in κ)."""

RESAMPLES = 1000
"""Bootstrap resamples of the stops behind the 95 % range."""


@dataclass(frozen=True)
class Outcome:
    """One release of an ensemble: where, from which direction, whether it inverted."""

    t_stop: float
    asymmetry: float
    sigma: float
    direction: int
    sample: int
    inverted: bool


def sweep_outcomes(
    sweep_dir: str | Path, accept: Callable[[Mapping[str, Any]], bool] | None = None
) -> list[Outcome]:
    """Every finished release of a restart or bank sweep directory.

    Args:
        sweep_dir: the sweep's store.
        accept: keeps a run where it returns True for the run's full config (the runs of
            one grid of a sweep that compares grids); all runs where None.

    Raises:
        ValueError: the sweep uses the paper protocol (its cycles have no fixed
            direction before the stop), or no accepted run has finished.
    """
    from ..sweep.estimates import inverted
    from ..sweep.plan import Sweep
    from ..sweep.store import read_runs

    sweep = Sweep.load(sweep_dir)
    if sweep.spec.estimator.kind == "protocol":
        msg = f"{sweep_dir}: a protocol sweep; the noise fit needs restart or bank runs"
        raise ValueError(msg)
    stored = read_runs(sweep_dir)
    outcomes = []
    for run in sweep.runs():
        if accept is not None and not accept(run.config):
            continue
        content = stored.get(run.key)
        if content is None:
            continue
        outcomes.append(
            Outcome(
                t_stop=float(run.config["protocol"]["t_stop"]),
                asymmetry=float(run.config["geometry"]["asymmetry"]),
                sigma=float(run.config["noise"]["sigma"]),
                direction=run.direction,
                sample=run.sample,
                inverted=inverted(content),
            )
        )
    if not outcomes:
        msg = f"{sweep_dir}: no finished runs"
        raise ValueError(msg)
    return outcomes


@dataclass(frozen=True)
class NoiseFit:
    """κ and the calibrated diffusion with their 95 % ranges (bootstrap over stops).

    Attributes:
        scale: κ, the ensemble behaves as the model at κ Dw.
        scale_range: its 95 % range.
        model_diffusion: the model's Dw at which P reaches the target.
        stops: independent stops (direction, sample) behind the fit.
        groups: (point, direction) counts fitted (noise-free ones carry no κ).
    """

    scale: float
    scale_range: tuple[float, float]
    model_diffusion: float
    stops: int
    groups: int

    @property
    def diffusion(self) -> float:
        """The calibrated Dw: the model's crossing divided by κ."""
        return self.model_diffusion / self.scale

    @property
    def diffusion_range(self) -> tuple[float, float]:
        """95 % range of the calibrated Dw."""
        return (
            self.model_diffusion / self.scale_range[1],
            self.model_diffusion / self.scale_range[0],
        )


def _model_inversion(
    table: DecisionTable, groups: Sequence[tuple[float, float, float, int]]
) -> Callable[[float], np.ndarray]:
    """P(inversion) of each (t_stop, Δ, sigma, direction) group as a function of κ."""
    scaled, positive = [], []
    for t_stop, asymmetry, sigma, direction in groups:
        beta = table.release_bias(t_stop, asymmetry)[DIRECTIONS.index(direction)]
        # Φ(β / sqrt(λ κ Dw)): the escape of β / sqrt(Dw) at the diffusion κ
        scaled.append(beta / math.sqrt(diffusion_of(sigma, table.inertia)))
        positive.append(direction > 0)
    scaled_bias, inverts_from_positive = np.array(scaled), np.array(positive)

    def inversion(scale: float) -> np.ndarray:
        p = np.mean(escape_probability(scaled_bias, table.growth_rate, scale), axis=1)
        return np.where(inverts_from_positive, 1.0 - p, p)

    return inversion


def _log_likelihoods(p: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """log P and log (1 - P), clipped at 1e-12 so that a count against a certainty
    costs a finite amount."""
    return np.log(np.clip(p, 1e-12, 1.0)), np.log(np.clip(1.0 - p, 1e-12, 1.0))


def _best_scale(
    model: Callable[[float], np.ndarray], grid: np.ndarray, k: np.ndarray, n: np.ndarray
) -> float:
    """κ of the largest binomial log likelihood of counts k of n (one per group).

    The best point of :data:`LOG_SCALES` brackets the maximum (`grid`: log P and
    log (1 - P) of the model there, shape (2, groups, points)); bounded Brent's method
    (``scipy.optimize.minimize_scalar``) refines it in log κ.
    """
    log_p, log_q = grid
    best = int(np.argmax(k @ log_p + (n - k) @ log_q))
    bracket = LOG_SCALES[[max(best - 1, 0), min(best + 1, LOG_SCALES.size - 1)]]

    def negative(log_scale: float) -> float:
        log_p, log_q = _log_likelihoods(model(math.exp(log_scale)))
        return -float(k @ log_p + (n - k) @ log_q)

    found = optimize.minimize_scalar(
        negative, bounds=tuple(bracket), method="bounded", options={"xatol": SCALE_TOLERANCE}
    )
    return math.exp(found.x)


def fit_noise(
    table: DecisionTable,
    outcomes: Sequence[Outcome],
    target: float = PLATEAU,
    t_stop: float = PLATEAU_STOP,
    asymmetry: float = PLATEAU_ASYMMETRY,
    resamples: int = RESAMPLES,
    seed: int = 0,
) -> NoiseFit:
    """Fit κ to the releases and calibrate Dw so that P(t_stop, Δ) = `target`.

    Raises:
        ValueError: no release with noise (κ is then undetermined), or the model's P
            never reaches `target` (see :meth:`DecisionTable.calibrate`).
    """
    groups = sorted(
        {(o.t_stop, o.asymmetry, o.sigma, o.direction) for o in outcomes if o.sigma > 0}
    )
    if not groups:
        msg = "no release with noise (sigma > 0): the noise scale is undetermined"
        raise ValueError(msg)
    column = {g: i for i, g in enumerate(groups)}
    units = sorted({(o.direction, o.sample) for o in outcomes})
    row = {u: i for i, u in enumerate(units)}
    hits = np.zeros((len(units), len(groups)))
    tries = np.zeros((len(units), len(groups)))
    for o in outcomes:
        g = column.get((o.t_stop, o.asymmetry, o.sigma, o.direction))
        if g is not None:
            hits[row[o.direction, o.sample], g] += o.inverted
            tries[row[o.direction, o.sample], g] += 1
    model = _model_inversion(table, groups)
    grid = np.stack([_log_likelihoods(model(math.exp(x))) for x in LOG_SCALES], axis=-1)

    strata = [np.array([row[u] for u in units if u[0] == d]) for d in DIRECTIONS]
    # a direction of one stop resamples to itself (scipy needs two or more to resample)
    fixed = [s for s in strata if s.size == 1]
    resampled = [s for s in strata if s.size > 1]

    def best(*picked: np.ndarray) -> float:
        pick = np.concatenate([*picked, *fixed])
        return _best_scale(model, grid, hits[pick].sum(axis=0), tries[pick].sum(axis=0))

    scale = best(*resampled)
    low = high = scale
    if resampled:
        boot = stats.bootstrap(
            resampled,
            best,
            n_resamples=resamples,
            vectorized=False,
            confidence_level=0.95,
            method="percentile",
            random_state=np.random.default_rng(seed),
        )
        low, high = boot.confidence_interval
    model_dw = table.calibrate(target, t_stop, asymmetry, (1e-9, 1e2))
    return NoiseFit(scale, (float(low), float(high)), model_dw, len(units), len(groups))
