"""Crowds of camphor bodies: boats in a ring channel and free disks in a dish, from the
committed collective sweeps (docs/collective.md).

* ring (configs/sweeps/crowd_ring.yaml, data/sweeps/crowd_ring): (a) the boats' mean
  |arc speed| against their number N, per friction and flow, with the runs of the same
  sweep on the paper scheme (configs/sweeps/crowd_ring_paper.yaml, crosses) beside them;
  (b) the spacing spread std(gaps) / mean(gaps) against time for each N (solid) and the
  cluster order (dashed); (f) the mode of each run (uniform, clusters, density wave, stop)
  against N; while the consistent store holds no run yet, the panels show the paper
  scheme's;
* symmetric boats (configs/sweeps/crowd_ring_symmetric.yaml,
  data/sweeps/crowd_ring_symmetric: the camphor at the boat's centre): (g), (h) the mode
  of each run (stop, oscillation, uniform, ...) over friction and N, flow off and on;
  (i) the mean |arc speed| (solid) and the mean signed arc speed's size (dashed, the
  speed round the ring) against the friction for each N, flow off: where the two part,
  the boats rock about their places;
* their density waves and coexisting states (configs/sweeps/crowd_ring_waves.yaml,
  data/sweeps/crowd_ring_waves: N = 8 ... 16, friction 0.0125 apart, flow off, each point
  from rest and from a sailing start): (j), (k) the modes from each start, (l) the speeds
  from rest (solid, dashed) and from the sailing start (dotted: the mean |arc speed|);
* dish (configs/sweeps/crowd_dish.yaml, data/sweeps/crowd_dish): (c) the disks' mean
  speed against time, per friction and flow, to the end of each run (a run ends where two
  footprints meet or one reaches the wall: there is no contact force yet); (d) their pair
  correlation g(r), normalised by the pair distances of uncorrelated centres in the dish;
  (e) polar (solid) and rotational (dashed) order against time.

A panel whose store is not committed says so. Run: ``python gallery/bodies_crowd.py
[--quick | --tiny]``: full and quick read the committed stores (nothing is computed);
tiny runs two tiny sweeps of free disks here, in a ring channel (whose report also stands
in for the symmetric boats') and in a dish (seconds), and draws them (the CI check that
the page draws).
"""

from __future__ import annotations

import tempfile
from collections.abc import Sequence
from pathlib import Path

import xarray as xr
from matplotlib.axes import Axes

from pde_rotor.gallery.common import add_footer, new_figure, parse_args, save
from pde_rotor.sweep import Sweep, SweepSpec, gather
from pde_rotor.sweep.store import DEFAULT_ROOT, RunLog, prepare
from pde_rotor.sweep.tasks import execute_group

NAME = "bodies_crowd"
STORES = {
    "ring": DEFAULT_ROOT / "crowd_ring",
    "dish": DEFAULT_ROOT / "crowd_dish",
    "ring_paper": DEFAULT_ROOT / "crowd_ring_paper",
    "ring_symmetric": DEFAULT_ROOT / "crowd_ring_symmetric",
    "ring_waves": DEFAULT_ROOT / "crowd_ring_waves",
}
GROUPS = {
    "enabled = 0": "flow off",
    "enabled = 1": "flow on",
    "speed = 0.01": "from rest",
    "speed = 0.5": "sailing start",
}
"""Titles of the groups of runs that a symmetric store's other axis (flow or start speed)
makes."""
DISK = {
    "plate": {"shape": "none"},
    "pills": [{"radius": 0.1}],
    "motion": {"kind": "free", "mass": 1.0e-4, "inertia": 5.0e-7, "friction": 0.25},
}
TINY_GRID = {"dx": 0.04, "dt": 2.0e-4}


def tiny_sweeps() -> dict[str, dict]:
    """Two tiny collective sweeps of free disks, in a ring channel 1 < r < 2.4 and in a
    no-flux dish of radius 2: the page's drawing checked on the cheapest crowd (boats on
    their track are checked by tests/solver/test_track.py and the committed stores)."""
    common = {
        "geometry": {"smoothing": 0.02},
        "numerics": {"scheme": "paper"},
        "protocol": {"t_ini": 0.1, "cycles": 0},
        "output": {"progress": False},
    }
    annulus = {"shape": "annulus", "inner_radius": 1.0, "outer_radius": 2.4}
    ring = {
        "name": "tiny_ring",
        "base": common | {"grid": TINY_GRID | {"domain_radius": 2.4, "vessel": annulus}},
        "crowd": {"count": 2, "body": DISK, "placement": {"kind": "ring", "radius": 1.7}},
        "axes": {"crowd.count": [1, 2, 3], "crowd.body.motion.friction": [0.2, 0.25]},
        "estimator": {"kind": "collective", "record_interval": 0.02},
        "samples": 1,
        "seed": 1,
    }
    dish = {
        "name": "tiny_dish",
        "base": common | {"grid": TINY_GRID | {"domain_radius": 2.0, "wall": "no_flux"}},
        "crowd": {
            "count": 3,
            "body": DISK,
            "placement": {"kind": "scatter", "radius": 1.0, "min_distance": 1.05},
        },
        "axes": {"crowd.body.motion.friction": [0.2, 0.25]},
        "estimator": {"kind": "collective", "record_interval": 0.02, "bins": 6},
        "samples": 1,
        "seed": 1,
    }
    return {"ring": ring, "dish": dish}


def run_here(spec: dict, sweep_dir: Path) -> xr.Dataset:
    """Compute a (tiny) collective sweep in this process, store it and gather its report."""
    sweep = Sweep.from_spec(SweepSpec.model_validate(spec))
    prepare(sweep, sweep_dir)
    with RunLog(sweep_dir) as log:
        for run in sweep.runs():
            for content in execute_group([run]):
                log.append(content)
    return gather(sweep, sweep_dir)


def stored(path: Path) -> xr.Dataset | None:
    """The report of the committed store at `path` (None where there is none)."""
    if not (path / "sweep.yaml").is_file():
        return None
    return gather(Sweep.load(path), path)


def lines(ds: xr.Dataset, keep: Sequence[str]) -> list[tuple[str, xr.Dataset]]:
    """(label, the dataset at one value of every axis but `keep` and the samples)."""
    others = [d for d in ds["runs_done"].dims if d not in keep]
    if not others:
        return [("", ds)]
    flat = ds.stack(line=others)
    result = []
    for i in range(flat.sizes["line"]):
        one = flat.isel(line=i)
        label = ", ".join(f"{d} = {one[d].item():g}" for d in others)
        result.append((label, one))
    return result


def missing(ax: Axes, what: str) -> None:
    ax.text(0.5, 0.5, what, ha="center", va="center", transform=ax.transAxes, fontsize=9)
    ax.set_xticks([])
    ax.set_yticks([])


def draw_ring(
    ds: xr.Dataset | None, paper: xr.Dataset | None, axes: Sequence[Axes], scheme: str
) -> None:
    """Panels (a), (b) and (f) of the ring store `ds` (on `scheme`), with the paper
    scheme's runs `paper` in (a)."""
    speed_ax, spread_ax, mode_ax = axes
    if ds is None:
        for ax in axes:
            missing(ax, f"no run in {STORES['ring']} yet")
        return
    count = "count" if "count" in ds.dims else ds["runs_done"].dims[0]
    for label, one in lines(ds, [count]):
        speed = one["abs_arc_speed"].mean("sample")
        speed_ax.plot(one[count], speed, "o-", label=label or None)
    for label, one in lines(paper, [count]) if paper is not None else []:
        speed = one["abs_arc_speed"].mean("sample")
        if bool(speed.notnull().any()):
            speed_ax.plot(one[count], speed, "x", ms=7, label=f"paper scheme: {label}")
    speed_ax.set(
        xlabel="boats N", ylabel="mean |arc speed|", title=f"(a) speed against N ({scheme})"
    )
    first = lines(ds, [count])[0][1]
    for n in first[count].values:
        one = first.sel({count: n}).mean("sample")
        if not bool(one["spacing_spread"].notnull().any()):
            continue  # not computed yet
        (line,) = spread_ax.plot(one["time"], one["spacing_spread"], label=f"N = {n}")
        spread_ax.plot(one["time"], one["cluster_order"], "--", color=line.get_color())
    spread_ax.set(
        xlabel="time",
        ylabel="spacing spread (solid), cluster order (dashed)",
        title="(b) spacing against time",
    )
    modes = ds.attrs["modes"].split(", ")
    labels = []
    for row, (label, one) in enumerate(lines(ds, [count])):
        labels.append(label or "all")
        for n in one[count].values:
            for code in one["mode"].sel({count: n}).values:
                if code >= 0:
                    mode_ax.plot(n, row, "s", ms=9, color=f"C{code}")
    for code, mode in enumerate(modes):
        mode_ax.plot([], [], "s", color=f"C{code}", label=mode)
    mode_ax.set_yticks(range(len(labels)), labels, fontsize=7)
    mode_ax.set(xlabel="boats N", title="(f) mode of each run (docs/collective.md)")
    mode_ax.legend(fontsize=7)
    if speed_ax.get_legend_handles_labels()[0]:
        speed_ax.legend(fontsize=7)
    spread_ax.legend(fontsize=7, ncol=2)


def draw_symmetric(
    ds: xr.Dataset | None, axes: Sequence[Axes], what: str, store: str, letters: str = "ghi"
) -> None:
    """Panels (g), (h) and (i) (`letters`) of a ring store `ds` swept in count and
    friction (`what`: its bodies; `store`: its name): the modes over both per value of the
    other axis (the flow, or the start speed), and the mean |arc speed| and the mean
    signed arc speed's size against the friction, of the first group; of the second, its
    mean |arc speed| (dotted)."""
    if ds is None or "friction" not in ds.dims:
        for ax in axes:
            missing(ax, f"no store {STORES[store]} yet")
        return
    modes = ds.attrs["modes"].split(", ")
    groups = [(GROUPS.get(label, label), one) for label, one in lines(ds, ["count", "friction"])]
    frictions = ds["friction"].values
    for ax, (label, one), letter in zip(axes[:2], groups, letters, strict=False):
        for n in one["count"].values:
            for mu in one["friction"].values:
                code = int(one["mode"].sel(count=n, friction=mu).values.flat[0])
                if code >= 0:
                    ax.plot(mu, n, "s", ms=9, color=f"C{code}")
        for code, mode in enumerate(modes):
            ax.plot([], [], "s", color=f"C{code}", label=mode)
        ax.set(xlabel="friction mu", ylabel="boats N", title=f"({letter}) {what}: {label}")
        ax.set_xlim(frictions.min() - 0.03, frictions.max() + 0.03)
        ax.set_ylim(0, 1.25 * max(one["count"].values) + 1)  # room for the legend
        ax.legend(fontsize=7, ncol=3, loc="upper center")
    for ax in axes[len(groups) : 2]:
        missing(ax, "one group of runs only")
    speed_ax = axes[2]
    first_label, first = groups[0]
    sailing = groups[1][1] if len(groups) > 1 and groups[1][0] == "sailing start" else None
    for n in first["count"].values:
        one = first.sel(count=n).mean("sample")
        if not bool(one["abs_arc_speed"].notnull().any()):
            continue  # not computed yet
        (line,) = speed_ax.plot(one["friction"], one["abs_arc_speed"], "o-", label=f"N = {n}")
        speed_ax.plot(one["friction"], abs(one["mean_arc_speed"]), "x--", color=line.get_color())
        if sailing is not None:
            other = sailing.sel(count=n).mean("sample")
            speed_ax.plot(other["friction"], other["abs_arc_speed"], ":", color=line.get_color())
    ylabel = "<|arc speed|> (solid), |<arc speed>| (dashed)"
    if sailing is not None:
        ylabel += ";\nsailing start <|arc speed|> (dotted)"
    speed_ax.set(
        xlabel="friction mu",
        ylabel=ylabel,
        yscale="log",
        title=f"({letters[2]}) {what}, {first_label}: speeds",
    )
    speed_ax.legend(fontsize=7, ncol=2)


def draw_dish(ds: xr.Dataset | None, axes: Sequence[Axes]) -> None:
    """Panels (c), (d) and (e) of the dish store `ds`."""
    speed_ax, g_ax, order_ax = axes
    if ds is None:
        for ax in axes:
            missing(ax, f"no store {STORES['dish']}")
        return
    for label, one in lines(ds, []):
        runs = one.mean("sample")
        (line,) = speed_ax.plot(runs["time"], runs["mean_speed"], label=label)
        colour = line.get_color()
        g_ax.plot(runs["r"], one["g"], "o-", ms=3, color=colour, label=label)
        order_ax.plot(runs["time"], runs["polar_order"], color=colour, label=label)
        order_ax.plot(runs["time"], runs["rotational_order"], "--", color=colour)
    speed_ax.set(xlabel="time", ylabel="mean speed <|U|>", title="(c) speed against time")
    g_ax.axhline(1, color="0.5", lw=0.7)
    g_ax.set(xlabel="r", ylabel="g(r)", title="(d) pair correlation (after settle)")
    order_ax.set(
        xlabel="time",
        ylabel="polar (solid), rotational (dashed)",
        title="(e) order against time",
    )
    for ax in axes:
        ax.legend(fontsize=7)


def main(argv: Sequence[str] | None = None) -> list[Path]:
    """Draw the crowd stores (tiny: two tiny sweeps computed here)."""
    args = parse_args(__doc__.splitlines()[0], argv)
    fid = args.fidelity
    if fid.is_tiny:
        with tempfile.TemporaryDirectory() as tmp:
            specs = tiny_sweeps()
            reports = {kind: run_here(spec, Path(tmp) / kind) for kind, spec in specs.items()}
        reports["ring_symmetric"] = reports["ring_waves"] = reports["ring"]
        source = "tiny sweeps of free disks computed here (not boats)"
    else:
        reports = {kind: stored(path) for kind, path in STORES.items()}
        source = "committed stores " + ", ".join(str(p) for p in STORES.values())
    ring, paper, scheme = reports["ring"], reports.get("ring_paper"), "consistent scheme"
    if ring is None or int(ring["runs_done"].sum()) == 0:
        ring, paper, scheme = paper, None, "paper scheme"
    fig = new_figure(15.0, 16.8)
    axes = fig.subplots(4, 3)
    draw_ring(ring, paper, axes[0], "free disks" if fid.is_tiny else scheme)
    draw_dish(reports["dish"], axes[1])
    what = "free disks" if fid.is_tiny else "symmetric boats"
    draw_symmetric(reports["ring_symmetric"], axes[2], what, "ring_symmetric")
    draw_symmetric(reports["ring_waves"], axes[3], what, "ring_waves", "jkl")
    for ax in axes.flat:
        ax.grid(alpha=0.3)
    for kind, ds in reports.items():
        if ds is not None:
            done, expected = int(ds["runs_done"].sum()), int(ds["runs_expected"].sum())
            ended = int((ds["ended_early"] == 1).sum())
            print(f"{NAME}: {kind}: {done} of {expected} runs, {ended} ended early")
    add_footer(
        fig,
        f"pde_rotor, {fid.name} fidelity; {source}; collective measures of docs/collective.md",
    )
    return save(fig, args.out, NAME)


if __name__ == "__main__":
    main()
