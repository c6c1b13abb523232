"""Onsets of motion of camphor bodies: simulated growth rates against the linear stability.

Two bodies of docs/bodies.md, without flow (the limit the derivation takes) and with it (what
the flow changes), each held while its
camphor relaxes to the rest state, then released with a small kick; the growth rate lambda of
its speed is fitted over [0.5, 1.5] after the release (:mod:`pde_rotor.gallery.onsets`) and
drawn against the friction mu, beside the growth rate of the linear stability
(:func:`pde_rotor.model.onsets.free_disk_growth_rate`, ``rotor_growth_rate``) and its
critical friction mu_c, where lambda = 0:

* (a) a free camphor disk (no plate, radius 0.1, mass 2e-3): it starts to move below
  mu_c = 0.176 (the closed form in Bessel functions);
* (b) the two-disk rotor of Koyano et al. (PRE 96, 012609, 2017; configs/bodies/
  two_disk_rotor.yaml): two such disks at +-0.5 on a strip that does not touch the water,
  inertia 1e-4: it starts to turn below mu_c(0.5) = 0.138. Theirs (the abstract): a
  critical rotor size below which it does not rotate; in this model that size is the l
  where mu_c(l) falls to the rotor's friction (docs/bodies.md).

Run: ``python gallery/bodies_onsets.py [--quick | --tiny]`` (full: the paper's grid
dx = 0.025; quick and tiny: dx = 0.05, tiny with two frictions).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from pathlib import Path

import numpy as np

from pde_rotor import RotorConfig
from pde_rotor.gallery.common import add_footer, new_figure, parse_args, save
from pde_rotor.gallery.onsets import (
    free_disk_config,
    kick_growth_rate,
    kick_rotation_rate,
    two_disk_rotor_config,
)
from pde_rotor.model.onsets import (
    CamphorDisk,
    free_disk_critical_friction,
    free_disk_growth_rate,
    rotor_critical_friction,
    rotor_growth_rate,
)

NAME = "bodies_onsets"
RELAX, FIT = 6.0, (0.5, 1.5)
"""Held time before the kick, and the window of the fit after it."""
MASS, INERTIA, HALF_LENGTH = 2e-3, 1e-4, 0.5
FACTORS = (0.8, 0.9, 0.95, 1.05, 1.1, 1.2)
"""Frictions simulated, as multiples of each body's mu_c."""


def defined(theory: Callable[[float], float], mu: float) -> float:
    """The linear stability's growth rate at `mu`, nan where the mode decays faster than
    the sublimation (no isolated rate: :func:`pde_rotor.model.onsets.rotor_growth_rate`)."""
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


def main(argv: Sequence[str] | None = None) -> list[Path]:
    """Simulate both bodies at frictions around their onsets and draw lambda(mu)."""
    args = parse_args(__doc__.splitlines()[0], argv)
    fid = args.fidelity
    dx, dt = (0.025, 1e-4) if fid.name == "full" else (0.05, 4e-4)
    factors = (0.9, 1.1) if fid.is_tiny else FACTORS
    disk = CamphorDisk.from_config(RotorConfig())
    smoothing = RotorConfig().geometry.smoothing
    fig = new_figure(11.0, 4.4)
    axes = fig.subplots(1, 2)
    end = RELAX + FIT[1] + 0.1
    panels = (
        (
            "(a) free camphor disk",
            free_disk_critical_friction(disk),
            lambda mu, flow: kick_growth_rate(
                free_disk_config(dx, dt, 4.0, MASS, mu, end, RELAX, flow), RELAX, 1e-4, FIT
            ),
            lambda mu: free_disk_growth_rate(disk, mu, MASS),
        ),
        (
            f"(b) two-disk rotor, l = {HALF_LENGTH:g}",
            rotor_critical_friction(disk, HALF_LENGTH, smoothing),
            lambda mu, flow: kick_rotation_rate(
                two_disk_rotor_config(dx, dt, 3.0, HALF_LENGTH, INERTIA, mu, end, RELAX, flow),
                RELAX,
                1e-3,
                FIT,
            ),
            lambda mu: rotor_growth_rate(disk, HALF_LENGTH, mu, INERTIA, smoothing),
        ),
    )
    for ax, (title, mu_c, simulate, theory) in zip(axes, panels, strict=True):
        mus = mu_c * np.array(factors)
        line = np.linspace(mus[0], mus[-1], 40)
        ax.plot(
            line, [defined(theory, mu) for mu in line], color="tab:blue", label="linear stability"
        )
        for flow, style, label in ((False, "ko", "no flow"), (True, "rs", "with flow")):
            simulated = np.array([simulate(mu, flow) for mu in mus])
            found_mu = sign_change(mus, simulated)
            found = f", mu_c = {found_mu:.4f} ({found_mu / mu_c - 1:+.1%})"
            ax.plot(mus, simulated, style, mfc="none", label=f"simulated, {label}{found}")
            print(f"{NAME}: {title}: {label}: theory mu_c = {mu_c:.5f}, simulated{found}")
            for mu, lam in zip(mus, simulated, strict=True):
                expected = defined(theory, mu)
                rates = f"lambda {lam:+.4f}, theory {expected:+.4f}"
                print(f"{NAME}: {title}: {label}: mu = {mu:.5f}: {rates}")
        ax.axhline(0, color="0.5", lw=0.7)
        ax.axvline(mu_c, color="tab:blue", ls="--", lw=1, label=f"mu_c = {mu_c:.4f}")
        ax.set(xlabel="friction mu", ylabel="growth rate lambda of the kick", title=title)
        ax.legend(fontsize=8)
        ax.grid(alpha=0.3)
    add_footer(
        fig,
        f"pde_rotor, {fid.name} run of the gallery; dx = {dx:g}, dt = {dt:g}, delta = "
        f"{smoothing:g}, paper scheme, without and with the flow; held {RELAX:g}, kicked, "
        f"lambda fitted over {FIT[0]:g} to {FIT[1]:g} after the release",
    )
    return save(fig, args.out, NAME)


if __name__ == "__main__":
    main()
