"""Paper Fig. 1: the rotor geometry, drawn from the model's own F and G.

(a) The hexagonal plate as the smoothed plate indicator F(r, phi) (grey), the camphor pills
as the contour G = 1/2 of the pill indicator (white disks), the pill centres R_j and the
edge normals e_j of Eq. (ejt0). (b) One corner magnified: F shows the tanh edge of width
delta, the pill (G = 1/2) sits at distance R_c, Eq. (rc), from the centre, turned by the
shift Delta from the line to the corner (Delta magnified so that it can be seen); the
point A at distance R - rho / cos(pi / N) is where a pill would touch both sides of the
corner, and p = |A| - R_c. All shapes come from :func:`pde_rotor.model.geometry.plate_indicator`,
:func:`pde_rotor.model.geometry.pill_indicator`, :func:`pde_rotor.model.geometry.pill_centres` and
:func:`pde_rotor.model.geometry.edge_normal_angles`; the pills are at the corners (Erratum 2 of
docs/model.md).

Run: ``python gallery/fig1_geometry.py [--quick | --tiny]`` (no time stepping; the
fidelity only sets the smoothing width delta).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence
from pathlib import Path

import numpy as np
from matplotlib.colors import LinearSegmentedColormap

from pde_rotor.gallery.common import (
    CONFIGS,
    add_footer,
    fidelity_label,
    new_figure,
    parse_args,
    save,
)
from pde_rotor.model.geometry import (
    RotorShape,
    edge_normal_angles,
    pill_centres,
    pill_indicator,
    plate_indicator,
)
from pde_rotor.units import LENGTH_UNITS

NAME = "fig1_geometry"
CONFIG = CONFIGS / "paper_fig6a.yaml"
"""The asymmetric rotor of the paper (Delta = 1e-4)."""
PLATE_CMAP = LinearSegmentedColormap.from_list("plate", ["white", "0.5"])
"""F = 0 white, F = 1 mid grey (so that the white pills and black contours stand out)."""
DELTA_DRAWN = 0.15
"""Shift Delta [rad] used to draw panel (b): the model's 1e-4 would be invisible."""


def main(argv: Sequence[str] | None = None) -> list[Path]:
    """Draw Fig. 1 and write it as PNG and PDF."""
    args = parse_args(__doc__.splitlines()[0], argv)
    config = args.fidelity.config(CONFIG)
    shape = RotorShape.from_config(config.geometry)
    phi = 0.0
    n = shape.n_corners

    fig = new_figure(11.0, 5.4)
    ax_a, ax_b = fig.subplots(1, 2, width_ratios=[1, 1.15])

    # (a) the whole rotor
    lim = shape.radius * 1.5
    xs = np.linspace(-lim, lim, 701)
    x, y = np.meshgrid(xs, xs, indexing="xy")
    F = plate_indicator(x, y, shape, phi)
    G = pill_indicator(x, y, shape, phi)
    ax_a.imshow(F, origin="lower", extent=(-lim, lim, -lim, lim), cmap=PLATE_CMAP, vmin=0, vmax=1)
    ax_a.contour(xs, xs, F, levels=[0.5], colors="k", linewidths=1.2)
    ax_a.contourf(xs, xs, G, levels=[0.5, 2.0], colors="white")
    ax_a.contour(xs, xs, G, levels=[0.5], colors="k", linewidths=0.8)
    centres = pill_centres(shape, phi)
    ax_a.plot(centres[:, 0], centres[:, 1], "k.", ms=3)
    for j, a in enumerate(edge_normal_angles(n, phi), start=1):
        base = shape.apothem * np.array([math.cos(a), math.sin(a)])
        tip = 0.14 * np.array([math.cos(a), math.sin(a)])
        ax_a.annotate(
            "",
            xy=base + tip,
            xytext=base,
            arrowprops={"arrowstyle": "-|>", "color": "tab:blue", "lw": 1.4},
        )
        ax_a.text(*(base + 1.45 * tip), f"$e_{j}$", color="tab:blue", ha="center", va="center")
    ax_a.plot([0], [0], "k+", ms=8)
    ax_a.set_xlim(-lim, lim)
    ax_a.set_ylim(-lim, lim)
    ax_a.set_aspect("equal")
    ax_a.set_title(
        f"(a) plate F (grey; F = 1/2 black), pills G = 1/2 (white),\n"
        f"edge normals $e_j$; N = {n}, R = {shape.radius:g}, \u03c1 = {shape.pill_radius:g}, "
        f"\u03c6 = {phi:g}",
        fontsize=9,
    )
    ax_a.set_xlabel(f"x [{LENGTH_UNITS}]")
    ax_a.set_ylabel(f"y [{LENGTH_UNITS}]")

    # (b) the corner j = N (angle phi) magnified, with Delta exaggerated
    drawn = dataclasses.replace(shape, asymmetry=DELTA_DRAWN)
    x0, x1, y0, y1 = 0.18, 0.56, -0.1, 0.17
    bx = np.linspace(x0, x1, 761)
    by = np.linspace(y0, y1, 541)
    X, Y = np.meshgrid(bx, by, indexing="xy")
    Fb = plate_indicator(X, Y, drawn, phi)
    Gb = pill_indicator(X, Y, drawn, phi)
    image = ax_b.imshow(
        Fb, origin="lower", extent=(x0, x1, y0, y1), cmap=PLATE_CMAP, vmin=0.0, vmax=1.0
    )
    fig.colorbar(image, ax=ax_b, label="plate indicator F", shrink=0.7, ticks=[0, 0.5, 1])
    ax_b.contour(bx, by, Fb, levels=[0.5], colors="k", linewidths=1.0)
    ax_b.contour(bx, by, Gb, levels=[0.5], colors="tab:red", linewidths=1.4)
    corner_angle = phi  # pill j = N sits at phi + 2 pi N / N + Delta
    centre = pill_centres(drawn, phi)[-1]
    r_a = shape.radius - shape.pill_radius / math.cos(math.pi / n)
    unit = np.array([math.cos(corner_angle), math.sin(corner_angle)])
    ax_b.plot([0, shape.radius], [0, 0], color="0.35", ls="--", lw=0.9)
    ax_b.plot([0, centre[0]], [0, centre[1]], color="tab:red", lw=1.0)
    ax_b.plot(*centre, "o", color="tab:red", ms=4)
    ax_b.annotate("$R_j$", centre, xytext=(6, 6), textcoords="offset points", color="tab:red")
    point_a = r_a * unit
    ax_b.plot(*point_a, "ko", ms=4)
    ax_b.annotate("A", point_a, xytext=(4, -12), textcoords="offset points")
    r_c = shape.pill_distance
    ax_b.plot(*(r_c * unit), "k|", ms=10)
    ax_b.annotate(
        "",
        xy=point_a + np.array([0, -0.045]),
        xytext=r_c * unit + np.array([0, -0.045]),
        arrowprops={"arrowstyle": "<->", "lw": 0.9},
    )
    ax_b.text((r_a + r_c) / 2, -0.04, "p", ha="center", va="bottom")
    ax_b.annotate(
        "",
        xy=r_c * unit + np.array([0, -0.08]),
        xytext=(x0, -0.08),
        arrowprops={"arrowstyle": "->", "lw": 0.9},
    )
    ax_b.text(
        x0 + 0.005,
        -0.075,
        f"$R_c$ = R \u2212 \u03c1/cos(\u03c0/N) \u2212 p = {r_c:.4f} (from the centre)",
        fontsize=8,
        va="bottom",
    )
    arc = np.linspace(0, DELTA_DRAWN, 30)
    ax_b.plot(0.26 * np.cos(arc), 0.26 * np.sin(arc), color="tab:red", lw=1.0)
    ax_b.text(0.265, 0.5 * 0.26 * DELTA_DRAWN, "\u0394", color="tab:red", va="center", fontsize=11)
    ax_b.set_xlim(x0, x1)
    ax_b.set_ylim(y0, y1)
    ax_b.set_aspect("equal")
    magnification = DELTA_DRAWN / config.geometry.asymmetry if config.geometry.asymmetry else 0
    ax_b.set_title(
        f"(b) one corner: \u0394 drawn as {DELTA_DRAWN:g} rad "
        f"(model: {config.geometry.asymmetry:g}, magnified \u00d7{magnification:.0f}),\n"
        f"tanh edges of width \u03b4 = {shape.smoothing:g}; red: pill G = 1/2",
        fontsize=9,
    )
    ax_b.set_xlabel(f"x [{LENGTH_UNITS}]")
    ax_b.set_ylabel(f"y [{LENGTH_UNITS}]")
    fig.suptitle(
        "Fig. 1: hexagonal rotor from the model's F and G (pills at the corners)", fontsize=11
    )
    add_footer(
        fig,
        fidelity_label(args.fidelity, config, f"{CONFIG.name}; geometry only", None),
    )
    return save(fig, args.out, NAME)


if __name__ == "__main__":
    main()
