"""A camphor disk in a circular dish with a no-flux wall: from rest to rotation about the centre.

The free camphor disk of docs/bodies.md (no plate, radius 0.1, mass 1e-4, no flow) at the
centre of a dish of radius 3 whose wall holds the camphor in (``grid.wall: no_flux``, the
dish of Koyano, Suematsu & Kitahata, PRE 99, 022211 (2019); configs/bodies/disk_in_dish.yaml):

* (a), (b) held while its camphor relaxes to the rest state, kicked, and the pair of modes
  e^{lambda t} fitted to its position (:func:`pde_rotor.gallery.onsets.kick_hopf_rate`):
  the growth rate sigma and the frequency omega against the friction mu, beside the
  linear stability's Hopf pair (:func:`pde_rotor.theory.dish.dish_hopf_rate`) and its
  onset mu_c, omega_c (:func:`~pde_rotor.theory.dish.dish_hopf_onset`);
* (c), (d) below the onset, the disk moved to (1, 0) and pushed to U = (0, 1) at the
  release: it swings through the centre, then settles into rotation about the centre at a
  constant radius; the orbit, and its radius and angle against time. The disk is nearly
  overdamped (m / mu ~ 6e-4): the push itself is forgotten within two steps, and what
  breaks the mirror symmetry about the x axis is the 6e-4 it moves the disk across.
  (A kick along a line through the centre keeps it on that line by symmetry, and grows
  into motion back and forth through the centre; which wakes end in which motion, and
  the rotation's hysteresis above the onset: benchmarks/dish_branches.py,
  docs/bodies.md.)

Theirs (the 2019 abstract): "rotational motion is stably realized through the double-Hopf
bifurcation from the rest state"; only the abstract was available to us, their model's
parameters and numbers are not reproduced.

Run: ``python gallery/bodies_dish.py [--quick | --tiny]`` (full: the paper's grid dx =
0.025; quick: dx = 0.05; tiny: dx = 0.05 in a dish of radius 1.75, two frictions, shorter runs).
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np

from pde_rotor import RotorConfig
from pde_rotor.gallery.common import TINY_DOMAIN_RADIUS, add_footer, new_figure, parse_args, save
from pde_rotor.gallery.onsets import disk_in_dish_config, kick_hopf_rate, kick_orbit
from pde_rotor.theory import CamphorDisk, Wall, dish_hopf_onset, dish_hopf_rate

NAME = "bodies_dish"
MASS = 1e-4
RELAX, FIT = 6.0, (4.0, 24.0)
"""Held time before the kick, and the window of the fit after it."""
FACTORS = (0.92, 0.95, 0.98, 1.02)
"""Frictions simulated, as multiples of the theory's mu_c."""
ORBIT_FACTOR, ORBIT_START, ORBIT_TIME = 0.93, 1.0, 60.0
"""The run below the onset: friction / mu_c; the disk moved to (start, 0) and pushed to U =
(0, start) at the release (angular momentum about the centre); its length."""
THEIRS = (
    'Theirs (Koyano, Suematsu & Kitahata 2019, abstract): "rotational motion is stably '
    'realized through the double-Hopf bifurcation from the rest state"'
)


def theory_line(disk: CamphorDisk, wall: Wall, mus: np.ndarray) -> np.ndarray:
    """The Hopf pair's lambda at `mus` (nan + nan i where it cannot be followed, next to
    where the pair meets the real axis)."""
    out = np.full(mus.size, complex(np.nan, np.nan))
    for m, mu in enumerate(mus):
        try:
            out[m] = dish_hopf_rate(disk, wall, mu, MASS)
        except ValueError:
            continue
    return out


def main(argv: Sequence[str] | None = None) -> list[Path]:
    """Simulate the disk at frictions around the onset and below it, and draw both."""
    args = parse_args(__doc__.splitlines()[0], argv)
    fid = args.fidelity
    dx, dt = (0.025, 1e-4) if fid.name == "full" else (0.05, 4e-4)
    radius = TINY_DOMAIN_RADIUS if fid.is_tiny else 3.0
    factors = (0.9, 1.1) if fid.is_tiny else FACTORS
    relax, fit = (2.0, (1.0, 3.0)) if fid.is_tiny else (RELAX, FIT)
    orbit_time = 4.0 if fid.is_tiny else ORBIT_TIME
    disk = CamphorDisk.from_config(RotorConfig())
    wall = Wall(radius, "no_flux")
    mu_c, omega_c = dish_hopf_onset(disk, wall, MASS)
    mus = mu_c * np.array(factors)
    end = relax + fit[1] + 0.1
    simulated = np.array(
        [
            kick_hopf_rate(
                disk_in_dish_config(dx, dt, radius, MASS, mu, end, relax), relax, 1e-4, fit
            )
            for mu in mus
        ]
    )
    line = np.linspace(min(mus[0], 0.95 * mu_c), mus[-1], 60)
    theory = theory_line(disk, wall, line)
    crossing = np.nonzero(np.diff(np.sign(simulated.real)))[0]
    found = ""
    if crossing.size:
        i = crossing[0]
        weight = simulated[i].real / (simulated[i].real - simulated[i + 1].real)
        found_mu = mus[i] + weight * (mus[i + 1] - mus[i])
        found_omega = simulated[i].imag + weight * (simulated[i + 1].imag - simulated[i].imag)
        found = f"; simulated {found_mu:.4f}, {found_omega:.3f}"
    print(f"{NAME}: theory mu_c = {mu_c:.5f}, omega_c = {omega_c:.5f}{found}")
    for mu, lam in zip(mus, simulated, strict=True):
        expected = dish_hopf_rate(disk, wall, mu, MASS)
        print(
            f"{NAME}: mu = {mu:.5f}: sigma {lam.real:+.4f}, omega {lam.imag:.4f}; theory "
            f"{expected.real:+.4f}, {expected.imag:.4f}"
        )
    mu_orbit = ORBIT_FACTOR * mu_c
    times = np.arange(0.5, orbit_time + 1e-9, 0.5)
    config = disk_in_dish_config(dx, dt, radius, MASS, mu_orbit, relax + orbit_time + 0.1, relax)
    start = 0.4 if fid.is_tiny else ORBIT_START
    orbit = kick_orbit(config, relax, (0.0, start), times, (start, 0.0))
    r = np.hypot(orbit[:, 0], orbit[:, 1])
    angle = np.unwrap(np.arctan2(orbit[:, 1], orbit[:, 0]))
    late = (times >= times[-1] / 2) & np.isfinite(r)
    speed = np.polyfit(times[late], angle[late], 1)[0] if late.sum() > 1 else np.nan
    print(
        f"{NAME}: mu = {mu_orbit:.5f}: orbit radius over the second half "
        f"{np.nanmin(r[late]):.4f} to {np.nanmax(r[late]):.4f}, angular speed {speed:+.4f}"
    )

    fig = new_figure(11.0, 8.4)
    axes = fig.subplots(2, 2)
    ax = axes[0, 0]
    ax.plot(line, theory.real, color="tab:blue", label="linear stability (sharp disk)")
    ax.plot(mus, simulated.real, "ko", label=f"simulated, dx = {dx:g}")
    ax.axhline(0, color="0.5", lw=0.7)
    ax.axvline(mu_c, color="tab:blue", ls="--", lw=1, label=f"mu_c = {mu_c:.4f}{found}")
    ax.set(xlabel="friction mu", ylabel="growth rate sigma", title="(a) growth rate of a kick")
    ax = axes[0, 1]
    ax.plot(line, theory.imag, color="tab:blue", label="linear stability")
    ax.plot(mus, simulated.imag, "ko", label="simulated")
    ax.axvline(mu_c, color="tab:blue", ls="--", lw=1, label=f"omega_c = {omega_c:.4f}")
    ax.set(xlabel="friction mu", ylabel="frequency omega", title="(b) frequency of the orbit")
    ax = axes[1, 0]
    ax.plot(orbit[:, 0], orbit[:, 1], color="tab:red", lw=0.8)
    ax.plot(*orbit[np.flatnonzero(np.isfinite(r))[-1]], "o", color="tab:red")
    circle = np.linspace(0, 2 * np.pi, 200)
    ax.plot(radius * np.cos(circle), radius * np.sin(circle), color="0.3", lw=1.2)
    ax.set_aspect("equal")
    ax.set(
        xlabel="x",
        ylabel="y",
        title=f"(c) below the onset, mu = {ORBIT_FACTOR:g} mu_c: the orbit",
    )
    ax = axes[1, 1]
    ax.plot(times, r, color="tab:red", label="distance from the centre |X|")
    ax.set(xlabel="time after the kick", ylabel="|X|", title="(d) radius and angle of the orbit")
    twin = ax.twinx()
    twin.plot(times, angle / (2 * np.pi), color="tab:green", label="turns about the centre")
    twin.set_ylabel("angle / 2 pi")
    ax.legend(loc="upper left", fontsize=8)
    twin.legend(loc="lower right", fontsize=8)
    for ax in axes[0]:
        ax.legend(fontsize=8)
        ax.grid(alpha=0.3)
    fig.suptitle(THEIRS, fontsize=9, style="italic")
    add_footer(
        fig,
        f"pde_rotor, {fid.name} run of the gallery; no-flux dish L = {radius:g}, dx = {dx:g}, "
        f"dt = {dt:g}, delta = 0.025, no flow, paper scheme; disk rho = 0.1, m = {MASS:g}; "
        f"held {relax:g}, kicked, lambda fitted over {fit[0]:g} to {fit[1]:g} after the release",
    )
    return save(fig, args.out, NAME)


if __name__ == "__main__":
    main()
