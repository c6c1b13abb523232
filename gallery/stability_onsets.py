"""Onsets of motion from the linearised discrete model: growth rates against friction.

The leading eigenvalue of the linearisation about the rest state
(:mod:`pde_rotor.stability`, docs/stability.md) against the friction mu, without and with
the flow, and the critical friction where its real part crosses 0 (brentq), beside the
exact theory of :mod:`pde_rotor.theory` (no flow):

* (a) a free camphor disk (radius 0.1, mass 2e-3) in an absorbing dish of radius 3: a
  pitchfork; theory m lambda = K(lambda) - mu pi rho^2 (sharp disk), mu_c = 0.1764;
* (b) the two-disk rotor (l = 0.5, inertia 1e-4): a pitchfork; theory
  ``rotor_growth_rate`` at delta = 0.025, mu_c = 0.1382;
* (c) a free disk (mass 1e-4) in a no-flux dish of radius 3: a Hopf pair; theory
  ``dish_hopf_rate`` (sharp), mu_c = 0.1781, omega_c = 0.274; real and imaginary parts;
* (d) the paper's rotor (default scheme): its growth rate against rotor.friction, and its
  own onset friction, the mu below which the plate at rest starts to turn.

Run: ``python gallery/stability_onsets.py [--quick | --tiny]`` (full: the paper's grid
dx = 0.025; quick: dx = 0.05; tiny: dx = 0.05 in dishes of radius 1.75, a branch's two ends
only).
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from pde_rotor.config import read_config_data
from pde_rotor.gallery.common import add_footer, new_figure, parse_args, save
from pde_rotor.stability import Branch, follow
from pde_rotor.theory import (
    CamphorDisk,
    Wall,
    dish_hopf_rate,
    free_disk_growth_rate,
    rotor_growth_rate,
)

NAME = "stability_onsets"
KEY = "bodies[0].motion.friction"
DELTA = 0.025
DISK = CamphorDisk(1.0, 1.0, 1.0, 1.0, 0.1)


def body_data(kind: str, dx: float, flow: bool, radius: float) -> dict[str, Any]:
    """The config of one outside system on grid `dx` in a dish of `radius` (paper scheme,
    delta = 0.025)."""
    grid: dict[str, Any] = {"domain_radius": radius, "dx": dx, "dt": 1e-4}
    if kind == "free":
        data = read_config_data("configs/bodies/free_disk.yaml")
        data["bodies"][0]["motion"].update({"mass": 2e-3, "inertia": 1e-5})
    elif kind == "rotor":
        data = read_config_data("configs/bodies/two_disk_rotor.yaml")
        data["bodies"][0]["motion"] = {"kind": "fixed_axis", "inertia": 1e-4}
    else:
        data = read_config_data("configs/bodies/disk_in_dish.yaml")
        data["bodies"][0]["start"] = {"x": 0.0, "y": 0.0}
        grid["wall"] = "no_flux"
    data.update(grid=grid, flow={"enabled": flow}, geometry={"smoothing": DELTA})
    return data


def theory(kind: str, mu: float, radius: float) -> complex:
    """The exact growth rate of theory/ in a dish of `radius` (nan where it has none)."""
    try:
        if kind == "free":
            return free_disk_growth_rate(DISK, mu, 2e-3)
        if kind == "rotor":
            return rotor_growth_rate(DISK, 0.5, mu, 1e-4, DELTA)
        return dish_hopf_rate(DISK, Wall(radius, "no_flux"), mu, 1e-4)
    except ValueError:
        return complex(np.nan, np.nan)


def describe(branch: Branch) -> str:
    """The branch's crossings in words."""
    parts = []
    for cross in branch.crossings:
        text = f"mu_c = {cross.value:.5g} ({cross.kind}"
        text += f", omega = {cross.frequency:.4f})" if cross.kind == "hopf" else ")"
        parts.append(text)
    return "; ".join(parts) or "no crossing"


def main(argv: Sequence[str] | None = None) -> list[Path]:
    """Compute every branch and draw them."""
    args = parse_args(__doc__.splitlines()[0], argv)
    fid = args.fidelity
    dx = 0.025 if fid.name == "full" else 0.05
    points = 2 if fid.is_tiny else 7
    rtol = 5e-2 if fid.is_tiny else 1e-5
    radius = 1.75 if fid.is_tiny else 3.0
    fig = new_figure(16.0, 9.0)
    axes = fig.subplots(2, 2).ravel()
    panels = (
        ("free", "(a) free camphor disk", (0.14, 0.2)),
        ("rotor", "(b) two-disk rotor, l = 0.5", (0.11, 0.16)),
        ("dish", "(c) disk in a no-flux dish", (0.15, 0.2)),
    )
    for ax, (kind, title, (lo, hi)) in zip(axes[:3], panels, strict=True):
        mus = np.linspace(lo, hi, points)
        line = np.linspace(lo, hi, 2 if fid.is_tiny else 30)
        exact = np.array([theory(kind, mu, radius) for mu in line])
        ax.plot(line, exact.real, color="tab:blue", label="exact theory, Re lambda")
        if kind == "dish":
            ax.plot(line, exact.imag, color="tab:blue", ls=":", label="exact theory, Im lambda")
        for flow, style, label in ((False, "ko-", "no flow"), (True, "rs-", "with flow")):
            branch = follow(body_data(kind, dx, flow, radius), KEY, mus, k=6, rtol=rtol)
            lam = branch.leading
            ax.plot(mus, lam.real, style, mfc="none", label=f"{label}: {describe(branch)}")
            if kind == "dish":
                ax.plot(mus, np.abs(lam.imag), style[:2] + "--", mfc="none", lw=0.8)
            print(f"{NAME}: {title}, {label}: {describe(branch)}")
            for mu, value in zip(mus, lam, strict=True):
                print(f"{NAME}: {title}, {label}: mu = {mu:.4f}: lambda = {value:.5f}")
        ax.axhline(0, color="0.5", lw=0.7)
        ax.set(xlabel="friction mu", ylabel="leading eigenvalue lambda", title=title)
        ax.legend(fontsize=8)
        ax.grid(alpha=0.3)
    ax = axes[3]
    frictions = np.geomspace(1e-4, 1e-2, points)
    for flow, style, label in ((False, "ko-", "no flow"), (True, "rs-", "with flow")):
        data = {"grid": {"dx": dx, "dt": 1e-4}, "flow": {"enabled": flow}}
        if fid.is_tiny:
            data["grid"]["domain_radius"] = radius
        branch = follow(data, "rotor.friction", frictions, k=3, rtol=rtol)
        ax.semilogx(frictions, branch.leading.real, style, mfc="none",
                    label=f"{label}: {describe(branch)}")  # fmt: skip
        print(f"{NAME}: paper rotor, {label}: {describe(branch)}")
        for mu, value in zip(frictions, branch.leading, strict=True):
            print(f"{NAME}: paper rotor, {label}: mu = {mu:.3g}: lambda = {value:.5f}")
    ax.axhline(0, color="0.5", lw=0.7)
    ax.axvline(1e-4, color="tab:green", ls="--", lw=1, label="the paper's mu = 1e-4")
    ax.set(
        xlabel="rotor.friction mu",
        ylabel="leading eigenvalue lambda",
        title="(d) the paper's rotor released from rest: its own onset friction",
    )
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    add_footer(
        fig,
        f"pde_rotor, {fid.name} run of the gallery; dx = {dx:g}, dish radius {radius:g}, "
        f"delta = {DELTA:g} (a-c, paper scheme), the paper's rotor on the default scheme; "
        "eigenvalues of the linearised "
        f"discrete model (scipy shift-invert Arnoldi), critical values by brentq (rtol {rtol:g})",
    )
    return save(fig, args.out, NAME)


if __name__ == "__main__":
    main()
