"""Paper Fig. 3: camphor concentration c and surface flow v of a steadily rotating rotor.

The symmetric rotor (Delta = 0) of configs/paper_fig4a.yaml spins up freely from the
paper's initial state (phi0 = 1, omega0 = 0.1: counter-clockwise) for the fidelity's
spin-up time without stops; then (a) c of Eq. (eqc) as a colour map with its colour bar
and (b) v of Eq. (eqv) as arrows with a scale arrow are drawn over the central square of
side 3, with the plate and pills at the current angle.

Run: ``python gallery/fig3_fields.py [--quick | --tiny]``.
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from pathlib import Path

import numpy as np
from matplotlib.patches import Circle, Polygon

from pde_rotor.gallery.common import (
    PAPER_CONFIG,
    add_footer,
    fidelity_label,
    new_figure,
    parse_args,
    save,
)
from pde_rotor.model.geometry import RotorShape, pill_centres
from pde_rotor.plotting.run import plate_corners
from pde_rotor.solver.simulation import Simulation
from pde_rotor.units import CONCENTRATION_UNITS, LENGTH_UNITS, OMEGA_UNITS, TIME_UNITS

NAME = "fig3_fields"
HALF_WIDTH = 1.5
"""Half the side of the square shown (the paper: a square of side 3)."""
ARROWS_ACROSS = 25
"""Flow arrows along one side of the square."""


def draw_rotor(ax, shape: RotorShape, phi: float, color: str) -> None:
    """Outline of the plate and the pills at angle phi."""
    ax.add_patch(
        Polygon(plate_corners(shape, phi), closed=True, fill=False, edgecolor=color, lw=1.2)
    )
    for centre in pill_centres(shape, phi):
        ax.add_patch(
            Circle(tuple(centre), shape.pill_radius, fill=False, edgecolor="orangered", lw=1.0)
        )


def main(argv: Sequence[str] | None = None) -> list[Path]:
    """Spin the rotor up, draw c and v, write Fig. 3 as PNG and PDF."""
    args = parse_args(__doc__.splitlines()[0], argv)
    fid = args.fidelity
    config = fid.config(PAPER_CONFIG, "protocol.cycles=0", f"protocol.t_ini={fid.spinup!r}")
    start = time.perf_counter()
    sim = Simulation(config)
    sim.run(fid.spinup)
    wall = time.perf_counter() - start
    omega, phi = sim.rotor.omega, sim.rotor.phi
    coords = sim.pde.domain.coords
    data = sim.state.data
    inside = np.nonzero(np.abs(coords) <= HALF_WIDTH + 1e-12)[0]
    sel = slice(int(inside[0]), int(inside[-1]) + 1)
    xs = coords[sel]
    c = data[0][sel, sel]
    vx, vy = data[1][sel, sel], data[2][sel, sel]
    h = 0.5 * (xs[1] - xs[0])
    extent = (xs[0] - h, xs[-1] + h, xs[0] - h, xs[-1] + h)
    shape = RotorShape.from_config(config.geometry)

    fig = new_figure(11.0, 5.9)
    ax_c, ax_v = fig.subplots(1, 2)
    image = ax_c.imshow(c.T, origin="lower", extent=extent, cmap="viridis", vmin=0.0)
    fig.colorbar(
        image,
        ax=ax_c,
        location="top",
        shrink=0.8,
        label=f"camphor surface concentration c [{CONCENTRATION_UNITS}]",
    )
    draw_rotor(ax_c, shape, phi, "white")
    ax_c.set_title("(a)", loc="left")

    stride = max(1, round(xs.size / ARROWS_ACROSS))
    idx = np.arange(stride // 2, xs.size, stride)
    ax_x, ax_y = np.meshgrid(xs[idx], xs[idx], indexing="ij")
    u, w = vx[np.ix_(idx, idx)], vy[np.ix_(idx, idx)]
    speed = np.hypot(vx, vy)
    v_max = float(speed.max())
    spacing = float(xs[idx[1]] - xs[idx[0]]) if idx.size > 1 else 1.0
    scale = v_max / (1.6 * spacing) if v_max > 0 else 1.0  # longest arrow: 1.6 spacings
    quiver = ax_v.quiver(
        ax_x, ax_y, u, w, angles="xy", scale_units="xy", scale=scale, width=0.003, color="k"
    )
    key = float(f"{0.5 * v_max:.1g}") if v_max > 0 else 1.0
    ax_v.quiverkey(quiver, 0.78, 1.03, key, f"|v| = {key:g}", labelpos="E", coordinates="axes")
    draw_rotor(ax_v, shape, phi, "tab:blue")
    ax_v.set_title("(b)", loc="left")
    for ax in (ax_c, ax_v):
        ax.set_xlim(extent[:2])
        ax.set_ylim(extent[2:])
        ax.set_aspect("equal")
        ax.set_xlabel(f"x [{LENGTH_UNITS}]")
        ax.set_ylabel(f"y [{LENGTH_UNITS}]")
    direction = "counter-clockwise" if omega > 0 else "clockwise"
    fig.suptitle(
        f"Fig. 3: steady {direction} rotation, \u0394 = {config.geometry.asymmetry:g}: "
        f"\u03c9 = {omega:.2f} {OMEGA_UNITS} at t = {sim.t:g} {TIME_UNITS};\nmax c = "
        f"{float(c.max()):.3f}, "
        f"max |v| = {v_max:.2f}",
        fontsize=11,
    )
    add_footer(
        fig,
        fidelity_label(
            fid, config, f"{PAPER_CONFIG.name}, free rotation to t = {fid.spinup:g} ({wall:.0f} s)"
        ),
    )
    return save(fig, args.out, NAME)


if __name__ == "__main__":
    main()
