"""Onsets of motion of camphor bodies: simulated growth rates against the linear stability.

Two bodies of docs/bodies.md, without flow (the limit the derivation takes) and with it
(what the flow changes), each held while its camphor relaxes to the rest state, then
released with a small kick; the growth rate lambda of its speed is fitted over [0.5, 1.5]
after the release (:mod:`pde_rotor.gallery.onsets`) and drawn against the friction mu,
beside the growth rate of the linear stability
(:func:`pde_rotor.theory.free_disk.free_disk_growth_rate`, ``rotor_growth_rate``) and its
critical friction mu_c, where lambda = 0:

* (a) a free camphor disk (no plate, radius 0.1, mass 2e-3): it starts to move below
  mu_c = 0.176 (the closed form in Bessel functions);
* (b) the two-disk rotor of Koyano et al. (PRE 96, 012609, 2017; configs/bodies/
  two_disk_rotor.yaml): two such disks at +-0.5 on a strip that does not touch the water,
  inertia 1e-4: it starts to turn below mu_c(0.5) = 0.138. Theirs (the abstract): a
  critical rotor size below which it does not rotate; in this model that size is the l
  where mu_c(l) falls to the rotor's friction (docs/bodies.md);
* (c) the free disk's steady speed below onset, U^2 against mu, beside the exact drive of
  the co-moving problem (:func:`pde_rotor.theory.free_disk.free_disk_steady_speed`) and the
  supercritical pitchfork's tangent U^2 = pi rho^2 (mu_c - mu) / |K3|.

Run: ``python gallery/bodies_onsets.py [--quick | --tiny]`` (full: the paper's grid
dx = 0.025; quick and tiny: dx = 0.05, tiny with two frictions).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from pathlib import Path

import numpy as np
from matplotlib.axes import Axes

from pde_rotor import RotorConfig
from pde_rotor.gallery.common import add_footer, new_figure, parse_args, save
from pde_rotor.gallery.onsets import (
    extrapolated_limit,
    free_disk_config,
    kick_growth_rate,
    kick_rotation_rate,
    released_speeds,
    two_disk_rotor_config,
)
from pde_rotor.theory import (
    CamphorDisk,
    free_disk_critical_friction,
    free_disk_cubic_coefficient,
    free_disk_growth_rate,
    free_disk_steady_speed,
    rotor_critical_friction,
    rotor_growth_rate,
)

NAME = "bodies_onsets"
RELAX, FIT = 6.0, (0.5, 1.5)
"""Held time before the kick, and the window of the fit after it (the tiny size: a tenth)."""
MASS, INERTIA, HALF_LENGTH = 2e-3, 1e-4, 0.5
FACTORS = (0.8, 0.9, 0.95, 1.05, 1.1, 1.2)
"""Frictions simulated, as multiples of each body's mu_c."""
SPEED_FRICTIONS, SPEED_DISH = (0.14, 0.15, 0.16), 8.0
"""Frictions of the free disk's steady speed, and the radius of the dish it crosses."""


def defined(theory: Callable[[float], float], mu: float) -> float:
    """The linear stability's growth rate at `mu`, nan where the mode decays faster than
    the sublimation (no isolated rate:
    :func:`pde_rotor.theory.two_disk_rotor.rotor_growth_rate`)."""
    try:
        return theory(mu)
    except ValueError:
        return float("nan")


def sign_change(mus: np.ndarray, rates: np.ndarray) -> float:
    """The friction where the simulated growth rate first changes sign, by linear
    interpolation between the two frictions around it (nan where it keeps its sign)."""
    crossing = np.nonzero(np.diff(np.sign(rates)))[0]
    if not crossing.size:
        return float("nan")
    i = crossing[0]
    return float(mus[i] - rates[i] * (mus[i + 1] - mus[i]) / (rates[i + 1] - rates[i]))


def draw_steady_speeds(
    ax: Axes,
    disk: CamphorDisk,
    dx: float,
    dt: float,
    frictions: Sequence[float],
    dish: float,
    curve_points: int,
) -> None:
    """(c) the free disk's steady speed below onset: U^2 simulated without and with flow
    against the exact drive's U*(mu)^2 and the pitchfork's tangent pi rho^2 (mu_c - mu)/|K3|.

    The disk is held 2 at one side of a dish of radius `dish`, released at the
    theory's speed towards the other side, and its speed read at 1/2, 3/4 and all of the
    time it takes to cross 0.9 of the dish; the steady speed is their Aitken limit. The
    exact curve is drawn at `curve_points` frictions (each a root of the drive).
    """
    mu_c = free_disk_critical_friction(disk)
    line = np.linspace(min(frictions) - 0.01, mu_c, curve_points)
    ax.plot(
        line,
        [free_disk_steady_speed(disk, mu) ** 2 for mu in line],
        color="tab:blue",
        label="exact co-moving drive U*(mu)^2",
    )
    slope = disk.area / abs(free_disk_cubic_coefficient(disk))
    ax.plot(
        line,
        slope * (mu_c - line),
        color="tab:blue",
        ls=":",
        label=f"supercritical tangent {slope:.1f} (mu_c - mu)",
    )
    exact = {mu: free_disk_steady_speed(disk, mu) for mu in frictions}
    for flow, style, label in ((False, "ko", "no flow"), (True, "rs", "with flow")):
        squares = []
        for mu in frictions:
            u_star = exact[mu]
            crossing = round(0.9 * 2 * (dish - 1.0) / u_star, 1)
            config = free_disk_config(
                dx, dt, dish, MASS, mu, 2.0 + crossing + 0.1, 2.0, flow, 1.0 - dish
            )
            speeds = released_speeds(config, 2.0, u_star, crossing * np.array([0.5, 0.75, 1.0]))
            steady = extrapolated_limit(speeds)
            squares.append(steady**2)
            print(
                f"{NAME}: (c) free disk, {label}: mu = {mu:g}: U = "
                f"{', '.join(f'{u:.4f}' for u in speeds)}; steady {steady:.4f}, "
                f"exact drive {u_star:.4f} ({steady / u_star - 1:+.1%})"
            )
        ax.plot(frictions, squares, style, mfc="none", label=f"simulated, {label}")
    ax.axvline(mu_c, color="tab:blue", ls="--", lw=1, label=f"mu_c = {mu_c:.4f}")
    ax.set(
        xlabel="friction mu",
        ylabel="steady speed squared U^2",
        title="(c) free disk: steady speed below onset",
    )
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)


def main(argv: Sequence[str] | None = None) -> list[Path]:
    """Simulate both bodies at frictions around their onsets and draw lambda(mu)."""
    args = parse_args(__doc__.splitlines()[0], argv)
    fid = args.fidelity
    dx, dt = (0.025, 1e-4) if fid.name == "full" else (0.05, 4e-4)
    factors = (0.9, 1.1) if fid.is_tiny else FACTORS
    disk = CamphorDisk.from_config(RotorConfig())
    smoothing = RotorConfig().geometry.smoothing
    fig = new_figure(16.0, 4.4)
    axes = fig.subplots(1, 3)
    relax, fit = (RELAX / 10, (FIT[0] / 10, FIT[1] / 10)) if fid.is_tiny else (RELAX, FIT)
    end = relax + fit[1] + 0.1
    panels = (
        (
            "(a) free camphor disk",
            free_disk_critical_friction(disk),
            lambda mu, flow: kick_growth_rate(
                free_disk_config(dx, dt, 4.0, MASS, mu, end, relax, flow), relax, 1e-4, fit
            ),
            lambda mu: free_disk_growth_rate(disk, mu, MASS),
        ),
        (
            f"(b) two-disk rotor, l = {HALF_LENGTH:g}",
            rotor_critical_friction(disk, HALF_LENGTH, smoothing),
            lambda mu, flow: kick_rotation_rate(
                two_disk_rotor_config(dx, dt, 3.0, HALF_LENGTH, INERTIA, mu, end, relax, flow),
                relax,
                1e-3,
                fit,
            ),
            lambda mu: rotor_growth_rate(disk, HALF_LENGTH, mu, INERTIA, smoothing),
        ),
    )
    for ax, (title, mu_c, simulate, theory) in zip(axes[:2], panels, strict=True):
        mus = mu_c * np.array(factors)
        line = np.linspace(mus[0], mus[-1], 4 if fid.is_tiny else 40)
        ax.plot(
            line, [defined(theory, mu) for mu in line], color="tab:blue", label="linear stability"
        )
        expected_rates = [defined(theory, mu) for mu in mus]
        for flow, style, label in ((False, "ko", "no flow"), (True, "rs", "with flow")):
            simulated = np.array([simulate(mu, flow) for mu in mus])
            found_mu = sign_change(mus, simulated)
            found = f", mu_c = {found_mu:.4f} ({found_mu / mu_c - 1:+.1%})"
            ax.plot(mus, simulated, style, mfc="none", label=f"simulated, {label}{found}")
            print(f"{NAME}: {title}: {label}: theory mu_c = {mu_c:.5f}, simulated{found}")
            for mu, lam, expected in zip(mus, simulated, expected_rates, strict=True):
                rates = f"lambda {lam:+.4f}, theory {expected:+.4f}"
                print(f"{NAME}: {title}: {label}: mu = {mu:.5f}: {rates}")
        ax.axhline(0, color="0.5", lw=0.7)
        ax.axvline(mu_c, color="tab:blue", ls="--", lw=1, label=f"mu_c = {mu_c:.4f}")
        ax.set(xlabel="friction mu", ylabel="growth rate lambda of the kick", title=title)
        ax.legend(fontsize=8)
        ax.grid(alpha=0.3)
    if fid.is_tiny:
        draw_steady_speeds(axes[2], disk, dx, dt, (0.15,), 2.5, 2)
    else:
        draw_steady_speeds(axes[2], disk, dx, dt, SPEED_FRICTIONS, SPEED_DISH, 12)
    add_footer(
        fig,
        f"pde_rotor, {fid.name} run of the gallery; dx = {dx:g}, dt = {dt:g}, delta = "
        f"{smoothing:g}, paper scheme, without and with the flow; held {relax:g}, kicked, "
        f"lambda fitted over {fit[0]:g} to {fit[1]:g} after the release",
    )
    return save(fig, args.out, NAME)


if __name__ == "__main__":
    main()
