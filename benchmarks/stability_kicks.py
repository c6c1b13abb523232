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
With ``--coordinates`` the eigenvalues include the body's coordinate and the fit keeps two
slow modes (:func:`with_coordinate`).

Run: ``python benchmarks/stability_kicks.py [--dx 0.025] [--relax 6] [--decay 1e4] [--span 2]``
(one thread: OPENBLAS_NUM_THREADS=1 NUMBA_NUM_THREADS=1).
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np

from pde_rotor import RotorConfig
from pde_rotor.gallery.onsets import (
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


def config_of(name: str, dx: float, mu: float, t_end: float, relax: float) -> RotorConfig:
    """The config of system `name` at friction `mu` held for `relax`, ending at `t_end`."""
    if name == "free disk":
        return free_disk_config(dx, 1e-4, 4.0, 2e-3, mu, t_end, relax)
    return two_disk_rotor_config(dx, 1e-4, 3.0, 0.5, 1e-4, mu, t_end, relax)


COLUMNS = {"free disk": (0, 3), "two-disk rotor": (2, 5)}
"""The pose's coordinate and velocity of each system (x, U_x; phi, omega)."""


def with_coordinate(args: argparse.Namespace, name: str, factor: float) -> None:
    """A body with its coordinate: the linearisation with the coordinates (an absorbing
    dish pushes a displaced disk to the wall; the lattice turns a turned rotor) has a
    slow pair beside the field's fast modes; after the fast ones have fallen
    `--two-mode-decay` behind, a two-mode fit (Prony,
    :func:`pde_rotor.gallery.onsets.two_mode_rates`) of the kicked body's coordinate and
    velocity gives both, and log |velocity| alone a mixture of the pair."""
    start = time.process_time()
    mu = factor * SYSTEMS[name][0]
    data = config_of(name, args.dx, mu, 1.0, 0.5).model_dump(mode="json")
    spectrum = spectrum_at(data, KEY, mu, k=6, positions=True)
    lam = spectrum.leading
    start_t, end_t = gap_window(spectrum.eigenvalues, args.two_mode_decay, args.span, modes=2)
    window = (start_t, math.ceil(end_t / SAMPLE) * SAMPLE)
    times = np.arange(0.0, window[1] + 1e-9, SAMPLE)
    config = config_of(name, args.dx, mu, round(args.relax + window[1] + 0.1, 2), args.relax)
    kick = SYSTEMS[name][2]
    series = kicked_series(config, args.relax, COLUMNS[name][1], kick, times,
                           lambda pose: pose[list(COLUMNS[name])])  # fmt: skip
    keep = times >= window[0] - 1e-9
    rates = two_mode_rates(times[keep], series[keep])
    single, _ = fitted_rate(times, np.abs(series[:, 1]), window)
    print(
        f"{name} with its coordinate: mu = {factor:g} mu_c = {mu:.5f}: eigenvalues "
        f"{np.round(spectrum.eigenvalues.real[:5], 5)}; window [{window[0]:.2f}, "
        f"{window[1]:.2f}]: two-mode fit {np.round(rates.real, 5)}, leading eigenvalue "
        f"{lam.real:+.5f}: difference {rates[0].real - lam.real:+.2e} "
        f"({(rates[0].real - lam.real) / abs(lam.real):+.2%}); log |velocity| alone "
        f"{single:+.5f}; cpu {time.process_time() - start:.0f} s",
        flush=True,
    )


def main() -> None:
    """Print, per system and friction, lambda of the spectrum and of the kicked fits."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--dx", type=float, default=0.025)
    parser.add_argument("--relax", type=float, default=RELAX)
    parser.add_argument("--decay", type=float, default=1e4)
    parser.add_argument("--span", type=float, default=2.0)
    parser.add_argument("--systems", nargs="+", default=list(SYSTEMS), choices=list(SYSTEMS))
    parser.add_argument("--factors", type=float, nargs="+", default=list(FACTORS))
    parser.add_argument("--coordinates", action="store_true", help="fit the coordinate too")
    parser.add_argument("--two-mode-decay", type=float, default=1e6)
    args = parser.parse_args()
    if args.coordinates:
        for name in args.systems:
            for factor in args.factors:
                with_coordinate(args, name, factor)
        return
    for name in args.systems:
        mu_c, column, largest_kick, measure = SYSTEMS[name]
        for factor in args.factors:
            start = time.process_time()
            mu = factor * mu_c
            data = config_of(name, args.dx, mu, 1.0, 0.5).model_dump(mode="json")
            spectrum = spectrum_at(data, KEY, mu, k=6)
            lam = spectrum.leading
            start_t, end_t = gap_window(spectrum.eigenvalues, args.decay, args.span)
            window = (start_t, math.ceil(end_t / SAMPLE) * SAMPLE)
            kick = min(largest_kick, 1e-3 * math.exp(-max(lam.real, 0.0) * window[1]))
            times = np.arange(0.0, window[1] + 1e-9, SAMPLE)
            t_end = round(args.relax + window[1] + 0.1, 2)
            config = config_of(name, args.dx, mu, t_end, args.relax)
            values = kicked_series(config, args.relax, column, kick, times, measure)
            rate, error = fitted_rate(times, values, window)
            old, _ = fitted_rate(times, values, GALLERY_FIT)
            print(
                f"{name}: mu = {factor:g} mu_c = {mu:.5f}: eigenvalues "
                f"{np.round(spectrum.eigenvalues.real[:4], 4)}; window [{window[0]:.2f}, "
                f"{window[1]:.2f}], kick {kick:.1e}: fitted {rate:+.5f} +- {error:.1e}, "
                f"eigenvalue {lam.real:+.5f} {lam.imag:+.1e}i: difference {rate - lam.real:+.2e} "
                f"({(rate - lam.real) / abs(lam.real):+.2%}); fixed [0.5, 1.5]: {old:+.5f} "
                f"({(old - lam.real) / abs(lam.real):+.2%}); cpu "
                f"{time.process_time() - start:.0f} s",
                flush=True,
            )


if __name__ == "__main__":
    main()
