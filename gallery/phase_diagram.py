"""The critical stop across noise: the (t_stop, Dw) phase diagram with the measured crossings.

The decision model (docs/decision.md, ``data/decision/dx40.nc``: the paper's grid, the
default scheme) gives P(t_stop, Delta, Dw) everywhere; its contours P = 0.95 (where the fall
starts) and P = 0.75 (halfway from 1 to 0.5) are drawn against Dw = (sigma/I)^2 for the
symmetric rotor (Delta = 0) and for Delta = 2e-5, beside the law t_c = tau ln(A / max(|beta_asym|,
sqrt(lambda Dw))) of the memory's decay (``DecisionTable.critical_stop``). The markers are the
crossings measured on the ensembles, both readings with their 95 % intervals (straight lines
between the points; :mod:`pde_rotor.statistics.crossing`): Fig. 5 and Fig. 7(b) at the
calibrated sigma = 1.5e-7 (``data/fig5.nc``, ``data/fig7b.nc``) and the sweep ``noise_law`` at
sigma = 0.75e-7 and 3e-7 (``data/noise_law.nc``; crossings only where its complete points
bracket them). Nothing is fitted to the markers.

Run: ``python gallery/phase_diagram.py [--quick | --tiny]`` (every fidelity reads the stored
reports).
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np
import xarray as xr

from pde_rotor.decision.table import diffusion_of, load_table
from pde_rotor.gallery.common import DATA, add_footer, new_figure, parse_args, save
from pde_rotor.gallery.sweeps import STOP_LABEL
from pde_rotor.statistics.crossing import DECAY_LEVEL, DECAY_START_LEVEL, report_crossing

NAME = "phase_diagram"
TABLE = DATA / "decision" / "dx40.nc"
REPORTS = {
    0.0: [("fig5.nc", None)],
    2e-5: [("fig7b.nc", None)],
}
"""Reports of one curve P(t_stop) at the calibrated noise, by Delta."""
NOISE_LAW = DATA / "noise_law.nc"
"""The sweep over (Delta, t_stop, sigma) at half and twice the calibrated noise."""
LEVELS = {
    DECAY_START_LEVEL: ("s", "fall starts, P = 0.95"),
    DECAY_LEVEL: ("D", "halfway, P = 0.75"),
}


def curves(asymmetry: float) -> list[tuple[float, xr.Dataset]]:
    """(sigma, P(t_stop) curve) of every stored report at `asymmetry`."""
    out = []
    for name, _ in REPORTS.get(asymmetry, []):
        with xr.open_dataset(DATA / name, engine="h5netcdf") as ds:
            ds = ds.load()
        sigma = float(np.atleast_1d(ds["sigma"].values)[0]) if "sigma" in ds.coords else 1.5e-7
        out.append((sigma, ds.squeeze(drop=True)))
    if NOISE_LAW.exists():
        with xr.open_dataset(NOISE_LAW, engine="h5netcdf") as ds:
            ds = ds.load()
        if asymmetry in ds["asymmetry"].values:
            for sigma in ds["sigma"].values:
                curve = ds.sel(asymmetry=asymmetry, sigma=sigma).squeeze(drop=True)
                out.append((float(sigma), curve))
    return out


def complete(curve: xr.Dataset) -> xr.Dataset:
    """The points whose runs are all done (partial points left out)."""
    done = np.isfinite(curve["P"].values)
    if "runs_done" in curve and "runs_total" in curve:
        done &= curve["runs_done"].values >= curve["runs_total"].values
    return curve.isel(t_stop=np.nonzero(done)[0])


def main(argv: Sequence[str] | None = None) -> list[Path]:
    """Draw the model's contours, the law and the measured crossings for Delta = 0, 2e-5."""
    args = parse_args(__doc__.splitlines()[0], argv)
    table = load_table(TABLE)
    t = np.linspace(0.3, table.t_max, 200)
    dws = np.logspace(-5, -2, 60)
    fig = new_figure(11.0, 4.8)
    axes = fig.subplots(1, 2, sharey=True)
    for ax, asymmetry in zip(axes, (0.0, 2e-5), strict=True):
        grid = np.array([table.probability(t, asymmetry, dw) for dw in dws])
        contour = ax.contour(t, dws, grid, levels=sorted(LEVELS), colors="tab:blue")
        ax.clabel(contour, fmt="P = %.2f", fontsize=8)
        law = [table.critical_stop(asymmetry, dw) for dw in dws]
        ax.plot(law, dws, color="tab:orange", ls="--", label="law: beta_mem(t_c) = max(...)")
        for sigma, curve in curves(asymmetry):
            dw = diffusion_of(sigma, table.inertia)
            points = complete(curve)
            for level, (marker, label) in LEVELS.items():
                try:
                    found = report_crossing(points, level)
                except ValueError:
                    continue
                if found.value is None:
                    continue
                low = found.low if found.low is not None else np.nan
                high = found.high if found.high is not None else np.nan
                print(
                    f"{NAME}: Delta = {asymmetry:g}, sigma = {sigma:g} (Dw = {dw:.3g}): "
                    f"{found.describe()}"
                )
                ax.errorbar(
                    [found.value],
                    [dw],
                    xerr=[[found.value - low], [high - found.value]],
                    fmt=marker,
                    color="k",
                    ms=6,
                    capsize=3,
                    label=label,
                )
        handles, labels = ax.get_legend_handles_labels()
        unique = dict(zip(labels, handles, strict=True))
        ax.legend(unique.values(), unique.keys(), fontsize=8, loc="upper right")
        ax.set_yscale("log")
        ax.set_xlabel(STOP_LABEL)
        ax.set_title(f"\u0394 = {asymmetry:g}: model contours, measured crossings", fontsize=10)
        ax.grid(alpha=0.3)
    axes[0].set_ylabel("noise Dw = (\u03c3/I)\u00b2")
    fig.suptitle(
        "The critical stop across noise: P = 0.95 and 0.75 of the decision model "
        "(lines) and of the ensembles (markers, 95 % intervals)",
        fontsize=11,
    )
    add_footer(
        fig,
        f"pde_rotor, {args.fidelity.name} run of the gallery (stored reports); model "
        f"{TABLE.name}: dx = 0.025, default scheme, lambda = {table.growth_rate:.3g}, release "
        f"amplitude r = {table.amplitude_scale:.3f}; ensembles: fig5.nc, fig7b.nc (sigma = "
        "1.5e-7), noise_law.nc (0.75e-7, 3e-7), bank or restart estimator",
    )
    return save(fig, args.out, NAME)


if __name__ == "__main__":
    main()
