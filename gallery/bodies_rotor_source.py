"""A camphor rotor beside a fixed camphor source: its angular velocity against its angle.

Gorecki, Koyano and Kitahata (arXiv:2505.06236, 2025; the follow-up arXiv:2602.11823) study
a camphor rotor perturbed by a camphor disk fixed on the water. Their abstracts state (theirs,
not measured here): a Hamiltonian model, whose Marangoni interaction is a potential, gives
results qualitatively different from the experiment; the reaction-diffusion description of
the camphor agrees better; the rotor's velocity depends on its position, with a pronounced
asymmetry between approaching and receding from the fixed disk.

This script puts the two-disk rotor of configs/bodies/two_disk_rotor.yaml (two camphor disks
at +-0.5 on a strip that does not touch the water, turning about the origin; friction 0.1,
below its onset 0.138, so that it turns slowly as experimental rotors do) beside one fixed
camphor disk at (1.8, 0), and records omega against the angle
theta of a pill measured from the direction of the source, at steady rotation: with the flow
of Eq. (eqv), without it (v = 0), and without the source. Where omega(theta) differs from
omega(-theta) the rotor is faster on one side of its pass than on the other: a potential
force of the source, depending on the distance alone, would give the same omega at the
same distance whichever way the pill moves. Printed and drawn: the mean omega, the range of
omega over a turn and the largest |omega(theta) - omega(-theta)| of each case.

Run: ``python gallery/bodies_rotor_source.py [--quick | --tiny]``.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from pde_rotor.config import load_config
from pde_rotor.gallery.common import (
    CONFIGS,
    add_footer,
    fidelity_label,
    new_figure,
    parse_args,
    save,
)
from pde_rotor.solver.simulation import Simulation
from pde_rotor.trackers.bodies import BodiesTracker

NAME = "bodies_rotor_source"
SOURCE = (1.8, 0.0)
"""The fixed disk's centre: its footprint (rho + 20 delta = 0.6) clear of the rotor's (1.1)."""
FRICTION = 0.1
"""The rotor's mu: below its onset mu_c(0.5) = 0.138 (docs/bodies.md), so it turns slowly
(an experimental rotor makes about a turn a second, not the 850 rad per time unit this rotor
reaches at the paper's mu = 1e-4, where the source barely modulates it)."""
BINS = 60
"""Bins of theta over half a turn (3 degrees each; the two-pill rotor repeats every pi)."""


def case_config(fid, flow: bool, source: bool, spin_up: float, record: float):
    """The two-disk rotor (and the source) for one case."""
    overrides = [
        "grid.domain_radius=3.5",
        "grid.domain_centre=[0.9, 0.0]",
        f"flow.enabled={'true' if flow else 'false'}",
        "noise.sigma=0",
        f"protocol.t_ini={spin_up + record!r}",
        "protocol.cycles=0",
        "bodies[0].start.omega=5.0",
        f"bodies[0].motion.friction={FRICTION!r}",
    ]
    if source:
        overrides += [
            "bodies[1].pills=[{x: 0.0, y: 0.0}]",
            "bodies[1].motion={kind: fixed}",
            f"bodies[1].start={{x: {SOURCE[0]}, y: {SOURCE[1]}}}",
            "bodies[1].name=source",
        ]
    if fid.name != "full":
        overrides += ["grid.dx=0.05", "grid.dt=0.0004"]
    return load_config(CONFIGS / "bodies" / "two_disk_rotor.yaml", overrides)


def omega_by_angle(config, spin_up: float, record: float) -> tuple[np.ndarray, np.ndarray, float]:
    """Run to steady rotation, then omega at every step over `record`, binned by the
    angle theta of a pill from the source direction (mod pi: the two pills are alike).

    Returns:
        the bin centres in [-pi/2, pi/2), the mean omega per bin, and the mean omega.
    """
    sim = Simulation(config)
    sim.run(spin_up)
    tracker = BodiesTracker(config, config.grid.dt)
    sim.run(spin_up + record, trackers=[tracker])
    data = tracker.to_dataset()
    keep = data["time"].values > spin_up
    phi = data["phi"].values[keep, 0]
    omegas = data["omega"].values[keep, 0]
    theta = np.angle(np.exp(1j * phi)) - math.atan2(SOURCE[1], SOURCE[0])
    thetas = (theta + math.pi / 2) % math.pi - math.pi / 2
    edges = np.linspace(-math.pi / 2, math.pi / 2, BINS + 1)
    index = np.clip(np.digitize(thetas, edges) - 1, 0, BINS - 1)
    means = np.array(
        [omegas[index == b].mean() if np.any(index == b) else np.nan for b in range(BINS)]
    )
    return 0.5 * (edges[1:] + edges[:-1]), means, float(omegas.mean())


def main(argv: Sequence[str] | None = None) -> list[Path]:
    """Run the three cases and draw omega(theta)."""
    args = parse_args(__doc__.splitlines()[0], argv)
    fid = args.fidelity
    spin_up, record = (0.3, 0.2) if fid.is_tiny else (6.0, 2.0)
    cases = {
        "source, flow": (True, True),
        "source, no flow": (False, True),
        "no source, flow": (True, False),
    }
    fig = new_figure(7.0, 4.6)
    ax = fig.subplots()
    config = None
    for label, (flow, source) in cases.items():
        config = case_config(fid, flow, source, spin_up, record)
        theta, omega, mean = omega_by_angle(config, spin_up, record)
        both = np.isfinite(omega) & np.isfinite(omega[::-1])  # bins a short run left empty
        differences = np.abs(omega - omega[::-1])[both]
        asymmetry = float(differences.max()) if differences.size else float("nan")
        spread = float(np.nanmax(omega) - np.nanmin(omega))
        print(
            f"{NAME}: {label}: mean omega {mean:.3f}, range over a turn {spread:.3f}, "
            f"largest |omega(theta) - omega(-theta)| {asymmetry:.3f}"
        )
        ax.plot(
            np.degrees(theta),
            omega,
            label=f"{label}: range {spread:.2f}, asymmetry {asymmetry:.2f}",
        )
    ax.axvline(0, color="0.5", lw=0.7)
    ax.set_xlabel("angle of a pill from the source's direction [degrees] (turning: left to right)")
    ax.set_ylabel("angular velocity omega")
    ax.set_title(
        f"two-disk rotor (l = 0.5, mu = {FRICTION:g}), a fixed camphor disk at distance 1.8\n"
        "theirs (Gorecki et al. 2025): the speed depends on the position,\n"
        "asymmetric between approach and retreat",
        fontsize=9,
    )
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    add_footer(fig, fidelity_label(fid, config, f"spin-up {spin_up:g}, recorded {record:g}"))
    return save(fig, args.out, NAME)


if __name__ == "__main__":
    main()
