"""The critical stop across noise: the (t_stop, Dw) phase diagram with the measured crossings.

The decision model (docs/decision.md, ``data/decision/dx40.nc``: the paper's grid, the
default scheme) gives P(t_stop, Delta, Dw) everywhere; its contours P = 0.95 (where the fall
starts) and P = 0.75 are drawn against Dw = (sigma/I)^2 for the symmetric rotor (Delta = 0,
the decay of Fig. 5), Delta = 2e-5 (the fall of Fig. 7(b)) and Delta = 1e-4 (the onset of
Fig. 7(a)), beside the law t_c = tau ln(A / max(|beta_asym|, sqrt(lambda Dw))) of the
memory's decay (``DecisionTable.critical_stop``). The markers are the crossings measured on
the ensembles, both readings with their 95 % intervals (straight lines between the points;
:mod:`pde_rotor.statistics.crossing`): Figs. 5, 7(b) and 7(a) at the calibrated sigma =
1.5e-7, the sweep ``noise_law`` at sigma = 0.75e-7 and 3e-7 (``data/noise_law.nc``) and the
Delta = 1e-4 onset at 3e-7 (``data/noise_law_onset.nc``); crossings only where complete
points bracket them. Nothing is fitted to the markers.

Run: ``python gallery/phase_diagram.py [--quick | --tiny]`` (every fidelity reads the stored
reports).
"""

from __future__ import annotations

import json
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
REPORTS = ("fig5.nc", "fig7b.nc", "fig7a.nc", "noise_law.nc", "noise_law_onset.nc")
"""Stored reports of P(t_stop): Figs. 5, 7(b) and 7(a) at the calibrated noise, the sweep
over (Delta, t_stop, sigma) at half and twice it, and the Delta = 1e-4 onset at twice it
(those not yet reported are left out)."""
ASYMMETRIES = (0.0, 2e-5, 1e-4)
"""The panels' Delta: the symmetric decay, the fall of Fig. 7(b), the onset of Fig. 7(a)."""
LEVELS = {
    DECAY_START_LEVEL: ("s", "fall starts, P = 0.95"),
    DECAY_LEVEL: ("D", "halfway, P = 0.75"),
}


def stored_curves() -> list[tuple[float, float, xr.Dataset]]:
    """(Delta, sigma, P(t_stop) curve) of every stored report: one per (asymmetry, sigma)
    of its axes, the values its base config sets where it has no such axis."""
    out = []
    for name in REPORTS:
        if not (DATA / name).exists():
            continue
        with xr.open_dataset(DATA / name, engine="h5netcdf") as ds:
            ds = ds.load()
        base = json.loads(ds.attrs["base_config"])
        asymmetries = ds["asymmetry"].values if "asymmetry" in ds.dims else [None]
        sigmas = ds["sigma"].values if "sigma" in ds.dims else [None]
        for asymmetry in asymmetries:
            for sigma in sigmas:
                where = {
                    k: v for k, v in (("asymmetry", asymmetry), ("sigma", sigma)) if v is not None
                }
                curve = ds.sel(where).squeeze(drop=True) if where else ds
                delta = base["geometry"]["asymmetry"] if asymmetry is None else asymmetry
                noise = base["noise"]["sigma"] if sigma is None else sigma
                out.append((float(delta), float(noise), curve))
    return out


def complete(curve: xr.Dataset) -> xr.Dataset:
    """The points whose runs are all done (partial points left out)."""
    done = np.isfinite(curve["P"].values)
    if "runs_done" in curve and "runs_expected" in curve:
        done &= curve["runs_done"].values >= curve["runs_expected"].values
    return curve.isel(t_stop=np.nonzero(done)[0])


def main(argv: Sequence[str] | None = None) -> list[Path]:
    """Draw the model's contours, the law and the measured crossings for each Delta."""
    args = parse_args(__doc__.splitlines()[0], argv)
    table = load_table(TABLE)
    t = np.linspace(0.3, table.t_max, 200)
    dws = np.logspace(-5, -2, 60)
    stored = stored_curves()
    fig = new_figure(15.0, 4.8)
    axes = fig.subplots(1, len(ASYMMETRIES), sharey=True)
    for ax, asymmetry in zip(axes, ASYMMETRIES, strict=True):
        grid = np.array([table.probability(t, asymmetry, dw) for dw in dws])
        contour = ax.contour(t, dws, grid, levels=sorted(LEVELS), colors="tab:blue")
        ax.clabel(contour, fmt="P = %.2f", fontsize=8)
        law = [table.critical_stop(asymmetry, dw) for dw in dws]
        ax.plot(law, dws, color="tab:orange", ls="--", label="law: beta_mem(t_c) = max(...)")
        for delta, sigma, curve in stored:
            if delta != asymmetry:
                continue
            dw = diffusion_of(sigma, table.inertia)
            points = complete(curve)
            for level, (marker, label) in LEVELS.items():
                try:
                    found = report_crossing(points, level)
                except ValueError:
                    continue
                if found.value is None:
                    continue
                first = points.isel(t_stop=int(np.argmin(points["t_stop"].values)))
                if float(first["P"]) < level:  # crossed before the first point: censored
                    print(
                        f"{NAME}: Delta = {asymmetry:g}, sigma = {sigma:g}: P < {level:g} already "
                        f"at the first point, t_stop = {found.value:g} (not drawn)"
                    )
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
        f"amplitude r = {table.amplitude_scale:.3f}; ensembles: fig5.nc, fig7b.nc, fig7a.nc "
        "(sigma = 1.5e-7), noise_law.nc (0.75e-7, 3e-7), noise_law_onset.nc (3e-7), bank or "
        "restart estimator",
    )
    return save(fig, args.out, NAME)


if __name__ == "__main__":
    main()
