"""The two-disk rotor's angular velocity against its size: omega(l), its maximum, its critical size.

Koyano, Gryciuk, Skrobanska, Malecki, Sumino, Kitahata & Gorecki, PRE 96, 012609 (2017):
two camphor disks at the ends of an arm that does not touch the water. Theirs (the
abstract; the full text was not at hand): "For large l the angular velocity decreases for
increasing l. At a specific value of l the angular velocity reaches its maximum and, for
short l it rapidly decreases. [...] The model also predicts that there is a critical rotor
size below which it does not rotate."

This model (configs/bodies/two_disk_rotor_size.yaml: disks of radius 0.1, friction
mu = 0.15, dish radius l + 3, paper scheme), without flow (the limit the theory takes) and
with it: each l starts at omega = 1 and turns for 24 time units; its steady omega is the
Aitken limit of omega at 12, 18 and 24 (:func:`pde_rotor.gallery.onsets.extrapolated_limit`;
near the onset the approach is slow). Drawn beside:

* the critical half-length l_c of the rest state's linear stability, where mu_c(l) falls
  to mu (:func:`pde_rotor.theory.two_disk_rotor.rotor_critical_half_length`, at the grid's delta);
* the far-apart limit omega = U*(mu) / l, each disk running at the free disk's steady
  speed (:func:`pde_rotor.theory.free_disk.free_disk_steady_speed`, sharp disks, no flow).

The simulated critical size is where omega^2, linear in l near a supercritical onset,
reaches zero (a straight line through the three smallest l that turn).

Run: ``python gallery/bodies_rotor_size.py [--quick | --tiny]`` (full: the paper's grid,
about 30 minutes of one core; quick: dx = 0.05; tiny: two sizes, short runs).
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np

from pde_rotor.gallery.common import CONFIGS, add_footer, new_figure, parse_args, save
from pde_rotor.gallery.onsets import extrapolated_limit, rotation_samples, sized_rotor
from pde_rotor.theory import (
    CamphorDisk,
    free_disk_steady_speed,
    rotor_critical_half_length,
)

NAME = "bodies_rotor_size"
CONFIG = CONFIGS / "bodies" / "two_disk_rotor_size.yaml"
MARGIN = 3.0
"""Dish radius minus l: three diffusion lengths between the disks and the absorbing rim."""
HALF_LENGTHS = {
    "full": (0.64, 0.66, 0.7, 0.75, 0.8, 0.9, 1.0, 1.1, 1.25, 1.5, 1.75, 2.0, 2.5),
    "quick": (0.7, 0.75, 0.8, 0.9, 1.0, 1.2, 1.5, 2.0, 2.5),
    "tiny": (0.8, 1.2),
}
SAMPLES = {"full": (12.0, 18.0, 24.0), "quick": (12.0, 18.0, 24.0), "tiny": (0.5, 0.75, 1.0)}
"""Times at which omega is read; the steady omega is their Aitken limit."""


def critical_size(half_lengths: np.ndarray, omegas: np.ndarray) -> float:
    """Where omega^2 of the three smallest turning rotors, a straight line in l, reaches
    zero (nan with fewer than three)."""
    turning = omegas > 0
    if turning.sum() < 3:
        return float("nan")
    l3, w3 = half_lengths[turning][:3], omegas[turning][:3]
    slope, intercept = np.polyfit(l3, w3**2, 1)
    return float(-intercept / slope)


def main(argv: Sequence[str] | None = None) -> list[Path]:
    """Run the rotor over its size with and without flow and draw omega(l)."""
    args = parse_args(__doc__.splitlines()[0], argv)
    fid = args.fidelity
    sizes = np.array(HALF_LENGTHS[fid.name])
    margin = 1.5 if fid.is_tiny else MARGIN
    base = fid.config(CONFIG, f"grid.domain_radius={float(sizes.max()) + margin}")
    body = base.body_list()[0]
    mu, smoothing, dx = body.motion.friction, base.geometry.smoothing, base.grid.dx
    disk = CamphorDisk.from_config(base)
    l_c = rotor_critical_half_length(disk, mu, smoothing)
    u_star = free_disk_steady_speed(disk, mu)
    print(f"{NAME}: mu = {mu:g}, delta = {smoothing:g}: linear stability l_c = {l_c:.4f}")
    print(f"{NAME}: free disk steady speed U* = {u_star:.4f} (the far-apart limit omega l)")
    fig = new_figure(11.0, 4.4)
    ax_omega, ax_speed = fig.subplots(1, 2)
    for flow, marker, label in ((False, "o", "no flow"), (True, "s", "with flow")):
        limits = []
        for half_length in sizes:
            config = sized_rotor(base, half_length, half_length + margin, flow={"enabled": flow})
            omega = rotation_samples(config, np.array(SAMPLES[fid.name]))
            limits.append(extrapolated_limit(omega))
            print(
                f"{NAME}: {label}: l = {half_length:g}: omega = "
                + ", ".join(f"{w:.4f}" for w in omega)
                + f" at t = {', '.join(f'{t:g}' for t in SAMPLES[fid.name])}; "
                f"steady {limits[-1]:.4f}"
            )
        steady = np.array(limits)
        found = critical_size(sizes, steady)
        peak = sizes[np.argmax(steady)]
        print(
            f"{NAME}: {label}: largest omega {steady.max():.4f} at l = {peak:g}; "
            f"simulated l_c = {found:.4f} ({found / l_c - 1:+.1%} from the linear stability)"
        )
        ax_omega.plot(sizes, steady, marker=marker, ls="-", label=f"{label}, l_c = {found:.3f}")
        ax_speed.plot(sizes, steady * sizes, marker=marker, ls="-", label=label)
    far = np.linspace(max(1.0, sizes[0]), sizes[-1], 40)
    ax_omega.plot(far, u_star / far, color="0.4", ls=":", label="far apart: U*(mu) / l")
    ax_speed.axhline(u_star, color="0.4", ls=":", label=f"U*(mu) = {u_star:.3f}")
    for ax in (ax_omega, ax_speed):
        ax.axvline(l_c, color="tab:blue", ls="--", lw=1, label=f"linear stability l_c = {l_c:.3f}")
        ax.set_xlabel("half-length l (disk centre to axis)")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    ax_omega.set(ylabel="steady angular velocity omega", title="(a) omega(l)")
    ax_speed.set(ylabel="disk speed omega l", title="(b) each disk's speed")
    ax_omega.text(
        0.98,
        0.04,
        "Koyano et al. 2017 (abstract, theirs): omega falls with l for large l,\n"
        "peaks, drops fast for short l; a critical size below which it does not turn",
        transform=ax_omega.transAxes,
        ha="right",
        fontsize=7,
        color="0.3",
    )
    add_footer(
        fig,
        f"pde_rotor, {fid.name} run of the gallery; dx = {dx:g}, dt = {base.grid.dt:g}, "
        f"delta = {smoothing:g}, mu = {mu:g}, I = {body.motion.inertia:g}, dish radius "
        f"l + {margin:g}, paper scheme; steady omega: Aitken limit of omega at "
        f"t = {', '.join(f'{t:g}' for t in SAMPLES[fid.name])}",
    )
    return save(fig, args.out, NAME)


if __name__ == "__main__":
    main()
