"""Kicked growth rates against the eigenvalues, the fit window chosen from the spectrum.

The configs of ``gallery/bodies_onsets.py`` (paper grid, no flow, paper scheme, delta =
0.025): a free disk (mass 2e-3, dish radius 4) and the two-disk rotor (l = 0.5, inertia
1e-4, dish radius 3), held for `--relax` (the gallery's 6), then kicked, at 0.8, 0.9,
0.95, 1.05, 1.1, 1.2 times the theory's mu_c (0.17635 and 0.13820). For each: the leading
eigenvalues of the same config (:func:`pde_rotor.stability.continuation.spectrum_at`), the
window that starts when the
next eigenvalue's mode has fallen behind the leading one by `--decay`
(:func:`pde_rotor.gallery.onsets.gap_window`), the kicked run sampled every 0.05 up to its
end, and lambda fitted over that window and over the gallery's fixed [0.5, 1.5]
(:func:`pde_rotor.gallery.onsets.fitted_rate`, with the fit's standard error). The kick is
small enough that the amplitude stays below 1e-3 of its unit up to the window's end.
With ``--positions`` the eigenvalues include the body's coordinate (the co-moving one is
printed beside); with ``--coordinates`` the fit keeps two slow modes and compares both
(:func:`with_coordinate`).

``--systems dish``: the disk of ``gallery/bodies_dish.py`` (mass 1e-4, no-flux dish of
radius 3) at 0.95, 0.98, 1.02, 1.05 times the theory's mu_c = 0.17809, where the leading
eigenvalues are a complex pair: the disk moved to x = kick and released, and
:func:`oscillation_fit` of e^{sigma t} (a cos omega t + b sin omega t) + c to (x, U_x)
from the time the next eigenvalue has fallen `--decay` behind, over `--periods` periods
(:func:`dish_kick`).

Run: ``python benchmarks/stability_kicks.py [--dx 0.025] [--relax 6] [--decay 1e4] [--span 2]
[--systems "free disk" "two-disk rotor" dish] [--positions | --coordinates [--offset 1e-4]]
[--periods 0.5] [--amplitude 1e-4]``
(one thread: OPENBLAS_NUM_THREADS=1 NUMBA_NUM_THREADS=1). The dish steps its cut cells
implicitly: about 15 s of CPU per time unit on the paper grid, against 1-2 s for the
absorbing dishes.
"""

from __future__ import annotations

import argparse
import math
import time
from dataclasses import dataclass

import numpy as np
from scipy.optimize import least_squares

from pde_rotor import RotorConfig
from pde_rotor.gallery.onsets import (
    disk_in_dish_config,
    fitted_rate,
    free_disk_config,
    gap_window,
    kicked_series,
    two_disk_rotor_config,
    two_mode_rates,
)
from pde_rotor.stability.continuation import spectrum_at

KEY = "bodies[0].motion.friction"
RELAX, GALLERY_FIT, SAMPLE = 6.0, (0.5, 1.5), 0.05
FACTORS = (0.8, 0.9, 0.95, 1.05, 1.1, 1.2)
SYSTEMS = {
    "free disk": (0.17635, 3, 1e-4, lambda pose: math.hypot(*pose[3:5])),
    "two-disk rotor": (0.13820, 5, 1e-3, lambda pose: abs(pose[5])),
}


def config_of(
    name: str,
    dx: float,
    mu: float,
    t_end: float,
    relax: float,
    dt: float = 1e-4,
    offset: float = 0.0,
) -> RotorConfig:
    """The config of system `name` at friction `mu` held for `relax`, ending at `t_end`
    (the free disk held at x = `offset`)."""
    if name == "free disk":
        return free_disk_config(dx, dt, 4.0, 2e-3, mu, t_end, relax, x=offset)
    return two_disk_rotor_config(dx, dt, 3.0, 0.5, 1e-4, mu, t_end, relax)


COLUMNS = {"free disk": (0, 3), "two-disk rotor": (2, 5)}
"""The pose's coordinate and velocity of each system (x, U_x; phi, omega)."""

DISH_MU_C, DISH_MASS, DISH_RADIUS = 0.17809, 1e-4, 3.0
"""The disk in a no-flux dish (``gallery/bodies_dish.py``): the sharp theory's mu_c
(:func:`pde_rotor.theory.dish.dish_hopf_onset`), the mass, the dish's radius."""
DISH_FACTORS = (0.95, 0.98, 1.02, 1.05)
"""Its frictions / mu_c: below 0.93 and above 1.08 the pair is real."""
DISH_AMPLITUDE = 1e-4
"""The kicked x is chosen so that |x| stays below this up to the window's end."""


@dataclass(frozen=True)
class Oscillation:
    """A damped or growing oscillation fitted to a kicked body.

    Attributes:
        rate: sigma + i omega.
        residual: the fit's rms residual over the rms of the series (columns scaled to 1).
        offset: the largest slow term (a constant per column) over its column's amplitude.
    """

    rate: complex
    residual: float
    offset: float


def oscillation_fit(times: np.ndarray, series: np.ndarray) -> Oscillation:
    """sigma + i omega of e^{sigma t} (a cos omega t + b sin omega t) + c fitted to each
    column of `series` at `times` (the same sigma, omega; a, b, c per column).

    Variable projection: for given (sigma, omega) the amplitudes are a linear least
    squares fit, and (sigma, omega) minimise what is left (scipy ``least_squares``),
    starting from Prony's order-2 estimate (:func:`pde_rotor.gallery.onsets.two_mode_rates`)
    on samples 1/20 of a period apart (closer samples make Prony ill-conditioned). Each
    column is scaled by its largest value (position and velocity differ in units). The
    constant c stands for any mode slower than the pair; where the kick excites none, it
    fits 0.
    """
    t = times - times[0]
    scaled = series / np.abs(series).max(axis=0)
    guess = two_mode_rates(t, scaled)
    omega = abs(guess[0].imag)
    if omega > 0:
        step = max(1, int(2 * math.pi / omega / 20 / (t[1] - t[0])))
        guess = two_mode_rates(t[::step], scaled[::step])
    lam = complex(guess[np.argmax(guess.imag)] if np.any(guess.imag > 0) else guess[0])

    def basis(p: np.ndarray) -> np.ndarray:
        grow = np.exp(p[0] * t)
        return np.stack([grow * np.cos(p[1] * t), grow * np.sin(p[1] * t), np.ones_like(t)], 1)

    def residuals(p: np.ndarray) -> np.ndarray:
        b = basis(p)
        amplitudes, *_ = np.linalg.lstsq(b, scaled, rcond=None)
        return (b @ amplitudes - scaled).ravel()

    best = least_squares(residuals, [lam.real, abs(lam.imag)], xtol=1e-14, ftol=1e-14)
    b = basis(best.x)
    amplitudes, *_ = np.linalg.lstsq(b, scaled, rcond=None)
    swing = np.abs(b[:, :2] @ amplitudes[:2]).max(axis=0)
    return Oscillation(
        rate=complex(best.x[0], best.x[1]),
        residual=float(np.sqrt(np.mean(best.fun**2) / np.mean(scaled**2))),
        offset=float(np.max(np.abs(amplitudes[2]) / swing)),
    )


@dataclass(frozen=True)
class DishKick:
    """The dish's leading pair against the kicked disk's fit.

    Attributes:
        eigenvalues: the leading eigenvalues with the disk's position.
        window: the fit's times after the kick.
        kick: the kicked x.
        fit: the oscillation fitted to (x, U_x) over the window.
        prony: Prony's order-2 rates over the window (every sample).
    """

    eigenvalues: np.ndarray
    window: tuple[float, float]
    kick: float
    fit: Oscillation
    prony: complex

    @property
    def pair(self) -> complex:
        """The leading eigenvalue with Im >= 0."""
        lam = complex(self.eigenvalues[0])
        return complex(lam.real, abs(lam.imag))


def dish_kick(
    dx: float,
    dt: float,
    radius: float,
    mu: float,
    relax: float,
    decay: float = 1e4,
    periods: float = 1.0,
    span: float = 2.0,
    amplitude: float = DISH_AMPLITUDE,
) -> DishKick:
    """The disk of ``gallery/bodies_dish.py`` at friction `mu` in a no-flux dish of
    `radius`: the leading eigenvalues with its position
    (:func:`pde_rotor.stability.continuation.spectrum_at`, ``positions=True``), and the
    disk held for `relax`, moved to x = kick (U = 0; the mirror y -> -y keeps it on the
    x axis) and released; (x, U_x) sampled every 0.05 and :func:`oscillation_fit` over
    a window that starts when the first faster eigenvalue's mode has fallen `decay`
    behind the pair (:func:`pde_rotor.gallery.onsets.gap_window`) and lasts `periods`
    periods 2 pi / omega of the pair (at least `span`); the kick keeps |x| below
    `amplitude` up to the window's end."""
    data = disk_in_dish_config(dx, dt, radius, DISH_MASS, mu, 1.0, 0.5).model_dump(mode="json")
    spectrum = spectrum_at(data, KEY, mu, k=8, positions=True)
    lam = complex(spectrum.leading)
    start_t, _ = gap_window(spectrum.eigenvalues, decay, 0.0)
    length = span if lam.imag == 0 else max(span, periods * 2 * math.pi / abs(lam.imag))
    window = (start_t, math.ceil((start_t + length) / SAMPLE) * SAMPLE)
    kick = amplitude * math.exp(-max(lam.real, 0.0) * window[1])
    times = np.arange(0.0, window[1] + 1e-9, SAMPLE)
    config = disk_in_dish_config(
        dx, dt, radius, DISH_MASS, mu, round(relax + window[1] + 0.1, 2), relax
    )
    series = kicked_series(config, relax, 0, kick, times, lambda pose: pose[[0, 3]])
    keep = times >= window[0] - 1e-9
    rates = two_mode_rates(times[keep], series[keep])
    return DishKick(
        eigenvalues=spectrum.eigenvalues,
        window=window,
        kick=kick,
        fit=oscillation_fit(times[keep], series[keep]),
        prony=complex(rates[np.argmax(rates.imag)]),
    )


def distinct(eigenvalues: np.ndarray, count: int = 4) -> np.ndarray:
    """The first `count` distinct eigenvalues with Im >= 0 (a pair and copies as one)."""
    out: list[complex] = []
    for lam in eigenvalues[eigenvalues.imag >= 0]:
        if all(abs(lam - other) > 1e-7 * max(abs(lam), 1.0) for other in out):
            out.append(complex(lam))
    return np.array(out[:count])


def dish(args: argparse.Namespace, factor: float) -> None:
    """Print the dish's Hopf pair and the kicked disk's fit at `factor` mu_c."""
    start = time.process_time()
    mu = factor * DISH_MU_C
    run = dish_kick(
        args.dx,
        args.dt,
        DISH_RADIUS,
        mu,
        args.relax,
        args.decay,
        args.periods,
        amplitude=args.amplitude,
    )
    lam, fit = run.pair, run.fit.rate
    euler = np.log(1 + args.dt * lam) / args.dt
    print(
        f"dish: mu = {factor:g} mu_c = {mu:.5f}: eigenvalues "
        f"{distinct(run.eigenvalues)}; window [{run.window[0]:.2f}, "
        f"{run.window[1]:.2f}], kick x = {run.kick:.1e}: fitted sigma {fit.real:+.5f}, "
        f"omega {fit.imag:.5f} (residual {run.fit.residual:.1e}, slow term "
        f"{run.fit.offset:.1e}; Prony {run.prony.real:+.5f}, {abs(run.prony.imag):.5f}); "
        f"eigenvalue {lam.real:+.5f} {lam.imag:+.5f}i (Euler {euler.real:+.5f}, "
        f"{euler.imag:.5f}): difference sigma {fit.real - lam.real:+.2e} "
        f"({(fit.real - lam.real) / abs(lam.real):+.2%}), omega {fit.imag - lam.imag:+.2e} "
        f"({(fit.imag - lam.imag) / lam.imag:+.2%}); cpu {time.process_time() - start:.0f} s",
        flush=True,
    )


def real_rates_fit(times: np.ndarray, series: np.ndarray, guess: np.ndarray) -> np.ndarray:
    """Real rates lambda_k of sum_k a_k e^{lambda_k t} fitted to each column of `series`
    at `times` (the same rates, amplitudes per column), by variable projection from
    `guess` (scipy ``least_squares``; columns scaled by their largest value), by
    decreasing rate."""
    t = times - times[0]
    scaled = series / np.abs(series).max(axis=0)

    def residuals(rates: np.ndarray) -> np.ndarray:
        basis = np.exp(np.outer(t, rates))
        amplitudes, *_ = np.linalg.lstsq(basis, scaled, rcond=None)
        return (basis @ amplitudes - scaled).ravel()

    best = least_squares(residuals, np.asarray(guess, dtype=float), xtol=1e-14, ftol=1e-14)
    return np.sort(best.x)[::-1]


def with_coordinate(args: argparse.Namespace, name: str, factor: float) -> None:
    """A body with its coordinate: the linearisation with the coordinates (an absorbing
    dish pushes a displaced disk to the wall; the lattice turns a turned rotor) has a
    slow pair beside the field's fast modes; after the fast ones have fallen
    `--two-mode-decay` behind, a two-mode fit (Prony,
    :func:`pde_rotor.gallery.onsets.two_mode_rates`, and :func:`real_rates_fit` from
    it) of the kicked body's coordinate and velocity gives both, and log |velocity|
    alone a mixture of the pair. The kick keeps the velocity below 1e-3 of its unit up
    to the window's end. With `--offset` the free disk is not kicked: it is held at
    x = offset e^{-lambda_+ t_end} (its camphor relaxes about it; lambda_+ the pair's
    growing member, t_end the window's end) and released at rest, which starts the slow
    member of the pair (the displaced disk with its own rest field) more than the fast
    one, and keeps the growing one below offset |lambda_- / lambda_+|."""
    start = time.process_time()
    mu = factor * SYSTEMS[name][0]
    data = config_of(name, args.dx, mu, 1.0, 0.5, args.dt).model_dump(mode="json")
    spectrum = spectrum_at(data, KEY, mu, k=6, positions=True)
    slow = distinct(spectrum.eigenvalues, 2)
    start_t, end_t = gap_window(spectrum.eigenvalues, args.two_mode_decay, args.span, modes=2)
    window = (start_t, math.ceil(end_t / SAMPLE) * SAMPLE)
    times = np.arange(0.0, window[1] + 1e-9, SAMPLE)
    t_end = round(args.relax + window[1] + 0.1, 2)
    growth = math.exp(-max(slow[0].real, 0.0) * window[1])
    kick = 0.0 if args.offset else min(SYSTEMS[name][2], 1e-3 * growth)
    offset = args.offset * growth
    config = config_of(name, args.dx, mu, t_end, args.relax, args.dt, offset)
    series = kicked_series(config, args.relax, COLUMNS[name][1], kick, times,
                           lambda pose: pose[list(COLUMNS[name])])  # fmt: skip
    keep = times >= window[0] - 1e-9
    prony = two_mode_rates(times[keep], series[keep])
    rates = real_rates_fit(times[keep], series[keep], prony.real)
    single, _ = fitted_rate(times, np.abs(series[:, 1]), window)
    differences = ", ".join(
        f"{fit - lam.real:+.2e} ({(fit - lam.real) / abs(lam.real):+.4%})"
        for fit, lam in zip(rates, slow, strict=True)
    )
    start_how = f"held at x = {offset:.1e}" if args.offset else f"kick {kick:.1e}"
    print(
        f"{name} with its coordinate: mu = {factor:g} mu_c = {mu:.5f}: eigenvalues "
        f"{np.round(spectrum.eigenvalues.real[:5], 6)}; window [{window[0]:.2f}, "
        f"{window[1]:.2f}], {start_how}: two-mode fit {np.round(rates, 6)} (Prony "
        f"{np.round(prony.real, 6)}), the pair {np.round(slow.real, 6)}: differences "
        f"{differences}; log |velocity| alone {single:+.5f}; cpu "
        f"{time.process_time() - start:.0f} s",
        flush=True,
    )


def one_mode(args: argparse.Namespace, name: str, factor: float) -> None:
    """The leading eigenvalue (with the coordinates if `--positions`) against log
    |velocity| fitted over the window after the next eigenvalue's mode has fallen
    `--decay` behind (and over the gallery's fixed [0.5, 1.5])."""
    mu_c, column, largest_kick, measure = SYSTEMS[name]
    start = time.process_time()
    mu = factor * mu_c
    data = config_of(name, args.dx, mu, 1.0, 0.5, args.dt).model_dump(mode="json")
    spectrum = spectrum_at(data, KEY, mu, k=6, positions=args.positions or None)
    lam = spectrum.leading
    comoving = ""
    if args.positions:
        lam0 = spectrum_at(data, KEY, mu, k=2, positions=False).leading
        comoving = f" (co-moving {lam0.real:+.6f})"
    start_t, end_t = gap_window(spectrum.eigenvalues, args.decay, args.span)
    window = (start_t, math.ceil(end_t / SAMPLE) * SAMPLE)
    kick = min(largest_kick, 1e-3 * math.exp(-max(lam.real, 0.0) * window[1]))
    times = np.arange(0.0, window[1] + 1e-9, SAMPLE)
    t_end = round(args.relax + window[1] + 0.1, 2)
    config = config_of(name, args.dx, mu, t_end, args.relax, args.dt)
    values = kicked_series(config, args.relax, column, kick, times, measure)
    rate, error = fitted_rate(times, values, window)
    old, _ = fitted_rate(times, values, GALLERY_FIT)
    euler = math.log1p(args.dt * lam.real) / args.dt
    print(
        f"{name}: mu = {factor:g} mu_c = {mu:.5f}: eigenvalues "
        f"{np.round(spectrum.eigenvalues.real[:4], 6)}; window [{window[0]:.2f}, "
        f"{window[1]:.2f}], kick {kick:.1e}: fitted {rate:+.6f} +- {error:.1e}, "
        f"eigenvalue {lam.real:+.6f} {lam.imag:+.1e}i{comoving}, Euler's "
        f"ln(1 + dt lambda)/dt {euler:+.6f}: difference {rate - lam.real:+.2e} "
        f"({(rate - lam.real) / abs(lam.real):+.2%}), to Euler's {rate - euler:+.2e}; "
        f"fixed [0.5, 1.5]: {old:+.5f} ({(old - lam.real) / abs(lam.real):+.2%}); cpu "
        f"{time.process_time() - start:.0f} s",
        flush=True,
    )


def main() -> None:
    """Print, per system and friction, lambda of the spectrum and of the kicked fits."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--dx", type=float, default=0.025)
    parser.add_argument("--dt", type=float, default=1e-4)
    parser.add_argument("--relax", type=float, default=RELAX)
    parser.add_argument("--decay", type=float, default=1e4)
    parser.add_argument("--span", type=float, default=2.0)
    systems = [*SYSTEMS, "dish"]
    parser.add_argument("--systems", nargs="+", default=list(SYSTEMS), choices=systems)
    parser.add_argument("--factors", type=float, nargs="+")
    parser.add_argument("--coordinates", action="store_true", help="fit the coordinate too")
    parser.add_argument("--positions", action="store_true", help="eigenvalues with them")
    parser.add_argument("--two-mode-decay", type=float, default=1e6)
    parser.add_argument("--offset", type=float, default=0.0, help="hold the free disk off")
    parser.add_argument("--periods", type=float, default=1.0, help="the dish's fit length")
    parser.add_argument("--amplitude", type=float, default=DISH_AMPLITUDE, help="dish's |x|")
    args = parser.parse_args()
    for name in args.systems:
        for factor in args.factors or (DISH_FACTORS if name == "dish" else FACTORS):
            if name == "dish":
                dish(args, factor)
            elif args.coordinates:
                with_coordinate(args, name, factor)
            else:
                one_mode(args, name, factor)


if __name__ == "__main__":
    main()
