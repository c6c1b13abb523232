"""Paper Fig. 9: the inversion probability P(t_stop, Delta) as a map.

Reads the report of the sweep ``fig9`` (axes t_stop and Delta; a stored one from data/ if
present, else configs/sweeps/fig9.yaml or fig9_quick.yaml through :mod:`pde_rotor.sweep`;
``--tiny``: a shrunken copy). (a) P with the paper's colours (red: high, blue: low,
grey-white near 0.5), each cell labelled with P; (b) the width of the 95 % interval of
each cell. The paper: high P (red) for short stops, the favourable direction (blue) for
long stops and large Delta, random (grey) for long stops and small Delta.

Run: ``python gallery/fig9_map.py [--quick | --tiny]``.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np
from _common import (
    add_footer,
    new_figure,
    parse_args,
    save,
)
from _sweeps import (
    ASYMMETRY_LABEL,
    STOP_LABEL,
    probability_footer,
    sweep_data,
)

NAME = "fig9_map"
SWEEP = "fig9"


def edges(values: np.ndarray) -> np.ndarray:
    """Cell edges around sorted axis values (midpoints; end cells symmetric)."""
    v = np.asarray(values, dtype=float)
    if v.size == 1:
        return np.array([v[0] - 0.5, v[0] + 0.5]) if v[0] == 0 else v[0] * np.array([0.5, 1.5])
    mid = 0.5 * (v[1:] + v[:-1])
    return np.concatenate([[v[0] - (mid[0] - v[0])], mid, [v[-1] + (v[-1] - mid[-1])]])


def main(argv: Sequence[str] | None = None) -> list[Path]:
    """Load or run the sweep, write Fig. 9 as PNG and PDF."""
    args = parse_args(__doc__.splitlines()[0], argv)
    data = sweep_data(SWEEP, args.fidelity, args.out)
    ds = data.report.transpose("asymmetry", "t_stop", ...)
    extra = [d for d in ds.dims if d not in ("asymmetry", "t_stop")]
    if extra:
        ds = ds.isel(dict.fromkeys(extra, 0))
    t_stop = ds["t_stop"].values
    delta = ds["asymmetry"].values
    # Delta is drawn on evenly spaced rows (its values need not be evenly spaced)
    rows = np.arange(delta.size)
    fig = new_figure(12.5, 5.2)
    ax_p, ax_w = fig.subplots(1, 2)
    p = ds["P"].values
    width = ds["P_high"].values - ds["P_low"].values
    mesh = ax_p.pcolormesh(
        edges(t_stop), edges(rows.astype(float)), p, cmap="coolwarm", vmin=0, vmax=1
    )
    fig.colorbar(mesh, ax=ax_p, label="inversion probability P")
    for i in rows:
        for j, t in enumerate(t_stop):
            if np.isfinite(p[i, j]):
                ax_p.text(t, i, f"{p[i, j]:.2f}", ha="center", va="center", fontsize=7)
            print(
                f"{NAME}: Delta = {delta[i]:g}, t_stop = {t:g}: P = {p[i, j]:.3f} "
                f"[{float(ds['P_low'].values[i, j]):.3f}, "
                f"{float(ds['P_high'].values[i, j]):.3f}] ({int(ds['stops'].values[i, j])} stops)"
            )
    mesh_w = ax_w.pcolormesh(
        edges(t_stop), edges(rows.astype(float)), width, cmap="Greys", vmin=0, vmax=1
    )
    fig.colorbar(mesh_w, ax=ax_w, label="width of the 95 % interval of P")
    for ax, title in (
        (ax_p, "(a) P(t_stop, \u0394); paper: red short stops, blue long stops and large \u0394"),
        (ax_w, "(b) uncertainty: P_high \u2212 P_low"),
    ):
        ax.set_yticks(rows, [f"{d:g}" for d in delta])
        ax.set_xlabel(STOP_LABEL)
        ax.set_ylabel(ASYMMETRY_LABEL)
        ax.set_title(title, fontsize=10)
    fig.suptitle("Fig. 9: inversion probability against t_stop and \u0394", fontsize=11)
    add_footer(fig, probability_footer(args.fidelity, data))
    return save(fig, args.out, NAME)


if __name__ == "__main__":
    main()
