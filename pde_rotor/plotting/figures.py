"""Figure helpers shared by the gallery: pyplot-free figures, footers, probability axes.

Everything draws on a :class:`matplotlib.figure.Figure` built without pyplot
(:func:`new_figure`) and is saved atomically (:func:`save_figure`).
"""

from __future__ import annotations

import logging
import textwrap
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr
from matplotlib.figure import Figure

from ..config import RotorConfig
from ..io.output import atomic_path
from ..statistics.crossing import partial_points
from ..statistics.proportions import wilson_interval

_logger = logging.getLogger(__name__)


FOOTER_FONTSIZE = 9.0
"""Font size of the fidelity footers: readable at 100 % (7 was not)."""


def grid_label(config: RotorConfig) -> str:
    """``dx = 0.05, dt = 0.0004, delta = 0.05, L = 3``."""
    g = config.grid
    return (
        f"dx = {g.dx:.4g}, dt = {g.dt:.3g}, \u03b4 = {config.geometry.smoothing:.4g}, "
        f"L = {g.domain_radius:g}"
    )


def count_range(values: Any) -> str:
    """``60`` if every value is 60, else ``40-60``."""
    low, high = int(np.min(values)), int(np.max(values))
    return f"{low}" if low == high else f"{low}-{high}"


def add_footer(fig: Figure, text: str, fontsize: float = FOOTER_FONTSIZE) -> None:
    """Write the fidelity footer at the bottom of `fig`, wrapped, with room reserved for it.

    Each line of `text` is a paragraph, wrapped to the figure width; the constrained layout
    keeps the axes above the footer.
    """
    width = max(40, int(fig.get_figwidth() * 72 / (0.55 * fontsize)))
    lines = [line for para in text.splitlines() for line in (textwrap.wrap(para, width) or [""])]
    height = (len(lines) * 1.25 * fontsize / 72 + 0.08) / fig.get_figheight()
    engine = fig.get_layout_engine()
    if engine is not None:
        engine.set(rect=(0, height, 1, 1 - height))
    fig.text(0.5, 0.005, "\n".join(lines), ha="center", va="bottom", fontsize=fontsize, color="0.3")


def save_figure(fig: Figure, out: Path, name: str, dpi: int = 110) -> list[Path]:
    """Write `fig` as out/name.png and out/name.pdf (atomically: temporary name, rename).

    Returns:
        The two paths.
    """
    paths = []
    for suffix in ("png", "pdf"):
        path = out / f"{name}.{suffix}"
        with atomic_path(path) as tmp:
            fig.savefig(tmp, format=suffix, dpi=dpi)
        paths.append(path)
        _logger.info("wrote %s", path)
    return paths


def new_figure(width: float, height: float) -> Figure:
    """A pyplot-free Figure with constrained layout and room for the footer."""
    fig = Figure(figsize=(width, height), layout="constrained")
    fig.get_layout_engine().set(rect=(0, 0.03, 1, 0.97))
    return fig


def errorbar_p(ax: Any, x: np.ndarray, ds: xr.Dataset, **kwargs: Any) -> None:
    """Plot P with its 95 % interval (P_low, P_high) as error bars against `x`; points
    whose runs are not all done (:func:`pde_rotor.statistics.crossing.partial_points`) are drawn
    hollow and labelled. Points not measured yet (P is NaN) are left out, so the line
    joins the measured points of a design that is run region by region."""
    p = np.asarray(ds["P"].values, dtype=float)
    measured = np.isfinite(p)
    x = np.asarray(x, dtype=float)[measured]
    p = p[measured]
    lo = np.asarray(ds["P_low"].values, dtype=float)[measured]
    hi = np.asarray(ds["P_high"].values, dtype=float)[measured]
    yerr = np.vstack([np.clip(p - lo, 0, None), np.clip(hi - p, 0, None)])
    lines = ax.errorbar(x, p, yerr=yerr, capsize=3, **kwargs)
    partial = partial_points(ds)[measured]
    if partial.any():
        color = lines[0].get_color()
        x_partial = x[partial]
        ax.plot(
            x_partial,
            p[partial],
            "o",
            mfc="white",
            mec=color,
            zorder=5,
            label="partial point (runs still to do)",
        )


def probability_axes(ax: Any, xlabel: str) -> None:
    """Axis styling shared by the probability figures."""
    ax.set_ylim(-0.05, 1.05)
    ax.set_xlabel(xlabel)
    ax.set_ylabel("inversion probability P")
    ax.axhline(0.5, color="0.6", lw=0.7, ls=":")
    ax.grid(alpha=0.3)


def draw_conditionals(ax: Any, x: np.ndarray, ds: xr.Dataset) -> None:
    """Faint P(inversion | CCW) and P(inversion | CW): the two directions of the chain."""
    for name, marker, label in (("P_ccw", "^", "from CCW"), ("P_cw", "v", "from CW")):
        if name in ds and np.isfinite(ds[name].values).any():
            ax.plot(
                x,
                ds[name].values,
                marker,
                ms=4,
                ls="none",
                alpha=0.45,
                color="0.35",
                label=f"P(inv | {label})",
            )


def wilson_text(k: int, n: int) -> str:
    """``k/n, 95 % CI [lo, hi]``."""
    lo, hi = wilson_interval(k, n)
    return f"{k}/{n}, 95 % CI [{lo:.2f}, {hi:.2f}]"
