"""``pde-rotor predict``: the reduced decision model (measure a table, map, point, calibrate).

Registered on the main typer app by :func:`register` (called from :mod:`pde_rotor.cli.main`).
``measure`` runs the noise-free stops and releases of :mod:`pde_rotor.decision.runs`
(minutes); ``map``, ``point`` and ``calibrate`` only read the table (seconds). Exit
codes: 0 success, 2 bad input (one line ``error: ...``).
"""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from ..paper import PLATEAU, PLATEAU_ASYMMETRY, PLATEAU_STOP
from .common import SetOption, fail, output_dir, output_file


def _diffusion(dw: float | None, sigma: float | None, inertia: float) -> float:
    """Dw from --dw or --sigma (exactly one)."""
    from ..decision.table import diffusion_of

    if (dw is None) == (sigma is None):
        fail("give the noise as exactly one of --dw (angular-velocity diffusion) or --sigma")
    if dw is not None:
        if dw < 0:
            fail(f"--dw {dw:g}: must be >= 0")
        return dw
    if sigma < 0:
        fail(f"--sigma {sigma:g}: must be >= 0")
    return diffusion_of(sigma, inertia)


def table_footer(table, path: Path) -> str:
    """Fidelity line of a map: the table, its grid and scheme, lambda and the angles."""
    from ..config import RotorConfig
    from ..plotting.figures import grid_label

    config = RotorConfig.model_validate_json(table.attrs["config"])
    return (
        f"decision model, table {path.name}: {grid_label(config)}, scheme "
        f"{config.numerics.scheme}, flow {'on' if config.flow.enabled else 'off'}, "
        f"{table.torque.shape[1]} stop angles per direction, lambda = {table.growth_rate:.4g}"
    )


def _table(path: Path):
    from ..decision.table import load_table

    if not path.is_file():
        fail(f"{path}: no such decision table (pde-rotor predict measure writes one)")
    try:
        return load_table(path)
    except (OSError, KeyError, ValueError) as err:
        fail(f"{path}: not a decision table ({err})")


def _reports(paths: list[Path], label: str) -> list:
    """The sweep reports at `paths`, read as the gallery reads them (P by the current
    rule, :func:`pde_rotor.sweep.stored.load_report`); a missing file fails naming it."""
    from ..sweep.stored import load_report

    for path in paths:
        if not path.is_file():
            fail(f"{label}{path}: no such report")
    return [load_report(path) for path in paths]


def _sweep_outcomes(table, sweep_dirs: list[Path]) -> list:
    """The releases of `sweep_dirs` that match the table (grid, smoothing, flow,
    scheme), run by run: a sweep along dx gives the runs of the table's dx, and says
    how many it leaves out. Refused with one line where no run of a sweep matches or
    a sweep holds no restart or bank runs."""
    from ..decision.check import mismatch
    from ..decision.fit import sweep_outcomes
    from ..sweep import SweepError

    outcomes = []
    for path in sweep_dirs:
        if not (path / "sweep.yaml").is_file():
            fail(f"--sweep {path}: holds no sweep.yaml (not a sweep directory)")
        verdicts: list[str | None] = []

        def accept(config, verdicts=verdicts) -> bool:
            verdicts.append(mismatch(table, config))
            return verdicts[-1] is None

        try:
            found = sweep_outcomes(path, accept)
        except (SweepError, ValueError) as err:
            fail(f"--sweep {path}: {verdicts[0] if verdicts and all(verdicts) else err}")
        problems = [v for v in verdicts if v]
        if problems:
            typer.echo(f"--sweep {path}: {len(problems)} runs left out ({problems[0]})")
        outcomes += found
    return outcomes


def _stored_groups(data: Path | None, flow: str, scheme: str | None) -> tuple[list, list[str]]:
    """Every stored ensemble under `data` (default: the repository's data/) with the
    table under DATA/decision that predicts it, grouped by table, and one line per
    report (or grid of one) that no table predicts. `flow`: on, off or all; `scheme`:
    the ensembles' numerics.scheme (None: all)."""
    import xarray as xr

    from ..decision.check import is_ensemble, report_config, stored_matches
    from ..gallery.common import DATA
    from ..sweep.stored import load_report

    data = data or DATA
    if not (data / "decision").is_dir():
        fail(f"--data {data}: holds no decision/ folder of tables")
    reports = []
    for path in sorted(data.glob("*.nc")):
        try:
            ds = load_report(path)
        except (OSError, ValueError, KeyError) as err:
            fail(f"{path}: not a readable report ({err})")
        if not isinstance(ds, xr.Dataset) or not is_ensemble(ds):
            continue
        fixed = report_config(ds)
        enabled = fixed.get("flow", {}).get("enabled", True)
        if (flow == "all" or enabled == (flow == "on")) and scheme in (
            None,
            fixed["numerics"]["scheme"],
        ):
            reports.append((path, ds))
    if not reports:
        fail(
            f"--data {data}: no stored restart or bank report with the flow {flow}"
            + (f" and scheme {scheme}" if scheme else "")
        )
    pairs, left_out = stored_matches(reports, data / "decision")
    if not pairs:
        fail(
            f"--data {data}: no table under {data / 'decision'} predicts any report ({left_out[0]})"
        )
    groups: dict[Path, tuple] = {}
    for _, ds, table_path, table in pairs:
        groups.setdefault(table_path, (table_path, table, []))[2].append(ds)
    return list(groups.values()), left_out


def _print_check(result, min_q: float, draws: int | None, seed: int | None) -> None:
    """The headline tests, every point and the interval counts of `result` (`draws` and
    `seed` of the bootstrap: None for :data:`pde_rotor.decision.goodness.DRAWS`, SEED)."""
    from ..decision.goodness import DRAWS, SEED, goodness_of_fit

    try:
        fit = goodness_of_fit(
            result,
            min_q=min_q,
            draws=DRAWS if draws is None else draws,
            seed=SEED if seed is None else seed,
        )
    except ValueError:
        fit = None  # protocol reports: intervals only
    for line in fit.describe() if fit is not None else []:
        typer.echo(line)
    for row in result.rows:
        typer.echo(
            f"{row['sweep']}: t_stop = {row['t_stop']:g}, Delta = {row['asymmetry']:g}, "
            f"sigma = {row['sigma']:g}: {row['column']} = {row['measured']:.3f} "
            f"[{row['low']:.3f}, {row['high']:.3f}], model {row['predicted']:.3f}"
            + ("" if row["inside"] else "  (outside)")
        )
    worst = result.largest_deviation()

    def share(column: str | None = None) -> str:
        value = result.coverage(column)
        return "n/a" if value != value else f"{value:.2f}"

    typer.echo(
        f"coverage: P {share('P')}, P(inv|CCW) {share('P_ccw')}, "
        f"P(inv|CW) {share('P_cw')}, all {share()} of "
        f"{len(result.rows)} intervals; largest deviation "
        f"{worst['predicted'] - worst['measured']:+.3f} ({worst['column']} at t_stop = "
        f"{worst['t_stop']:g}, Delta = {worst['asymmetry']:g}, sigma = {worst['sigma']:g})"
    )
    conditionals = [r for r in result.rows if r["column"] != "P"]
    open_ = [r for r in conditionals if 0.02 <= r["predicted"] <= 0.98]
    typer.echo(
        f"independent intervals (the conditionals; P is made of them): "
        f"{sum(r['inside'] for r in conditionals)} of {len(conditionals)} hold the model, "
        f"{sum(r['inside'] for r in open_)} of the {len(open_)} where it predicts "
        "between 0.02 and 0.98"
    )


DwOption = Annotated[
    float | None,
    typer.Option("--dw", metavar="DW", help="Angular-velocity diffusion Dw = (sigma/I)^2."),
]
SigmaOption = Annotated[
    float | None, typer.Option("--sigma", metavar="SIGMA", help="Noise sigma of the config.")
]
TableArgument = Annotated[
    Path, typer.Argument(metavar="TABLE", help="Decision table (NetCDF of predict measure).")
]


def register(app: typer.Typer) -> None:
    """Add the ``predict`` command group to `app`."""
    predict = typer.Typer(
        help="Reduced decision model: P(t_stop, Delta, Dw) from noise-free runs.",
        no_args_is_help=True,
        rich_markup_mode=None,
    )
    app.add_typer(predict, name="predict", short_help="The reduced decision model of a release.")

    @predict.command("measure", short_help="Measure a decision table (noise-free runs).")
    def measure_command(
        config: Annotated[
            Path,
            typer.Argument(
                metavar="CONFIG", help="YAML config file, or a shipped sweep base (paper, coarse)."
            ),
        ],
        out: Annotated[
            Path, typer.Option("--out", "-o", metavar="FILE.nc", help="Table to write (.nc).")
        ],
        set_: SetOption = None,
        angles: Annotated[
            int, typer.Option(min=1, metavar="N", help="Stop angles per direction.")
        ] = 8,
        t_max: Annotated[
            float, typer.Option(min=0.1, metavar="T", help="Longest stop predicted.")
        ] = 3.5,
        check: Annotated[
            list[float] | None,
            typer.Option(metavar="T", help="Stop durations of check releases (repeatable)."),
        ] = None,
    ) -> None:
        """Measure a decision table: noise-free stop curves and the release response."""
        from ..config import ConfigError, load_config
        from ..decision.runs import measure_table, table_steps
        from ..sweep.cost import format_duration, step_seconds
        from ..sweep.spec import shipped_base, shipped_bases

        if not config.exists() and str(config) in shipped_bases():
            config = shipped_base(str(config))
        try:
            cfg = load_config(config, set_ or [])
        except ConfigError as err:
            fail(str(err))
        if cfg.geometry.asymmetry == 0:
            fail(
                "geometry.asymmetry = 0: measure at a nonzero reference Delta "
                "(e.g. --set geometry.asymmetry=1e-4) so the table predicts every Delta"
            )
        output_file(out)
        checks = sorted(check or [])
        if checks and (checks[0] <= 0 or checks[-1] > t_max):
            fail(f"--check values must lie in (0, t_max = {t_max:g}]")
        n = table_steps(cfg, angles, t_max, len(checks))
        typer.echo(f"{n:,} steps, about {format_duration(n * step_seconds(cfg))} on one core")
        table = measure_table(cfg, angles, t_max, checks=checks, progress=typer.echo)
        out.parent.mkdir(parents=True, exist_ok=True)
        table.save(out)
        typer.echo(
            f"lambda = {table.growth_rate:.4g} (by direction "
            f"{', '.join(f'{r:.4g}' for r in table.attrs['growth_rate_by_direction'])}), "
            f"C = {table.response:.3g}; wrote {out}"
        )

    @predict.command("point", short_help="Predicted P at given t_stop and Delta.")
    def point_command(
        table_path: TableArgument,
        t_stop: Annotated[
            list[float],
            typer.Option(
                "--t-stop", metavar="T", help="Stop duration; repeatable (--t-stop 1 --t-stop 1.5)."
            ),
        ],
        asymmetry: Annotated[
            list[float] | None,
            typer.Option(
                "--asymmetry",
                metavar="DELTA",
                help="Delta; repeatable (--asymmetry 0 --asymmetry 2e-5); every t_stop is "
                "printed at every Delta [default: 0].",
            ),
        ] = None,
        dw: DwOption = None,
        sigma: SigmaOption = None,
    ) -> None:
        """Print the predicted P(inv | CCW), P(inv | CW) and P at the given points."""
        table = _table(table_path)
        diffusion = _diffusion(dw, sigma, table.inertia)
        for t in t_stop:
            if not 0 <= t <= table.t_max:
                fail(f"--t-stop {t:g}: outside the table's [0, {table.t_max:g}]")
        for delta in asymmetry or [0.0]:
            for t in t_stop:
                a, b = table.conditionals(t, delta, diffusion)
                p = table.probability(t, delta, diffusion)
                typer.echo(
                    f"t_stop = {t:g}, Delta = {delta:g}, Dw = {diffusion:.3g}: P(inv|CCW) = "
                    f"{float(a):.3f}, P(inv|CW) = {float(b):.3f}, P = {float(p):.3f}"
                )

    @predict.command("calibrate", short_help="The noise at which P reaches a target.")
    def calibrate_command(
        table_path: TableArgument,
        target: Annotated[
            float, typer.Option(metavar="P", help="P to reach (default: the experiment's plateau).")
        ] = PLATEAU,
        t_stop: Annotated[
            float, typer.Option("--t-stop", metavar="T", help="Stop duration of P.")
        ] = PLATEAU_STOP,
        asymmetry: Annotated[
            float, typer.Option("--asymmetry", metavar="DELTA", help="Delta of P.")
        ] = PLATEAU_ASYMMETRY,
        sweep: Annotated[
            list[Path] | None,
            typer.Option(
                metavar="SWEEP_DIR",
                help="Fit the noise scale to the releases of these restart or bank sweeps "
                "and calibrate from the ensemble, with a 95 % range (repeatable).",
                show_default=False,
            ),
        ] = None,
    ) -> None:
        """The noise (Dw and sigma) at which P(t_stop, Delta) is `target`: the model's, and
        with --sweep the ensemble's (the model's noise scale fitted to its releases)."""
        from ..decision.table import sigma_of

        table = _table(table_path)
        outcomes = _sweep_outcomes(table, sweep or [])
        try:
            dw = table.calibrate(target, t_stop, asymmetry, (1e-9, 1e2))
        except ValueError as err:
            fail(str(err))
        typer.echo(
            f"P(t_stop = {t_stop:g}, Delta = {asymmetry:g}) = {target:g} at Dw = {dw:.4g} "
            f"(sigma = {sigma_of(dw, table.inertia):.4g})"
        )
        if not outcomes:
            return
        from ..decision.fit import fit_noise

        try:
            fit = fit_noise(table, outcomes, target, t_stop, asymmetry)
        except ValueError as err:
            fail(str(err))
        k_lo, k_hi = fit.scale_range
        d_lo, d_hi = fit.diffusion_range
        typer.echo(
            f"ensemble ({fit.stops} stops, {fit.groups} noisy counts): behaves as the model "
            f"at kappa Dw, kappa = {fit.scale:.3g} [{k_lo:.3g}, {k_hi:.3g}] (95 %, bootstrap "
            f"over stops)\ncalibrated: Dw = {fit.diffusion:.3g} [{d_lo:.3g}, {d_hi:.3g}], "
            f"sigma = {sigma_of(fit.diffusion, table.inertia):.3g} "
            f"[{sigma_of(d_lo, table.inertia):.3g}, {sigma_of(d_hi, table.inertia):.3g}]"
        )

    @predict.command("check", short_help="The model against stored sweep reports.")
    def check_command(
        paths: Annotated[
            list[Path] | None,
            typer.Argument(
                metavar="[TABLE REPORT...]",
                help="A decision table and the sweep reports (NetCDF) to test against it "
                "[default: every stored ensemble under --data, each with the table under "
                "DATA/decision that holds its physics].",
                show_default=False,
            ),
        ] = None,
        data: Annotated[
            Path | None,
            typer.Option(
                metavar="DIR",
                help="Where the stored reports (DIR/*.nc) and tables (DIR/decision/*.nc) "
                "are found without TABLE [default: the repository's data/].",
                show_default=False,
            ),
        ] = None,
        flow: Annotated[
            str,
            typer.Option(
                metavar="on|off|all",
                help="Without TABLE: the ensembles with the flow on, off, or all.",
            ),
        ] = "on",
        scheme: Annotated[
            str | None,
            typer.Option(
                metavar="SCHEME",
                help="Without TABLE: only the ensembles of this numerics.scheme "
                "[default: every scheme, each against its own table].",
                show_default=False,
            ),
        ] = None,
        min_q: Annotated[
            float,
            typer.Option(
                "--min-q",
                metavar="Q",
                help="Smallest q = min(p, 1 - p) of the combined X2 and G2 (0: every "
                "conditional with q > 0).",
            ),
        ] = 0.0,
        draws: Annotated[
            int | None,
            typer.Option(
                metavar="N",
                help="Parametric-bootstrap draws of the simulated null [default: 10000].",
                show_default=False,
            ),
        ] = None,
        seed: Annotated[
            int | None,
            typer.Option(
                metavar="S", help="Seed of the bootstrap [default: 0].", show_default=False
            ),
        ] = None,
        plot: Annotated[
            Path | None,
            typer.Option(
                metavar="DIR",
                help="Also draw the master curve P(+1) against x into this directory.",
            ),
        ] = None,
    ) -> None:
        """Test the model against every conditional of stored sweep reports.

        First the headline: every conditional P(inv | direction) by an exact binomial
        test, with the count that fails at 5 % against its null; Pearson's X2 and G2
        combined, with p-values from a parametric bootstrap of the model; and a
        calibration table of the stops that went the less likely way, observed against
        expected with 95 % binomial ranges, by bins of its predicted probability. Then
        every point, and the interval counts. Without TABLE, every stored ensemble
        (with the flow on, by default) against the table of its physics.
        """
        from ..decision.check import Comparison, compare, master_points

        if flow not in ("on", "off", "all"):
            fail(f"--flow {flow!r}: must be on, off or all")
        if not 0 <= min_q < 0.5:
            fail(f"--min-q {min_q:g}: must lie in [0, 0.5)")
        if draws is not None and draws < 1:
            fail(f"--draws {draws}: must be >= 1")
        for name, value in (("--data", data), ("--scheme", scheme)):
            if paths and value is not None:
                fail(f"{name}: give it without TABLE (it selects the stored reports)")
        if plot is not None:
            output_dir(plot, "--plot")
        if paths:
            if len(paths) < 2:
                fail(f"{paths[0]}: give the reports to check after the table")
            table_path = paths[0]
            table = _table(table_path)
            reports = _reports(paths[1:], "")
            try:
                result = compare(table, reports)
            except ValueError as err:
                fail(str(err))
            groups = [(table_path, table, reports)]
        else:
            groups, left_out = _stored_groups(data, flow, scheme)
            for line in left_out:
                typer.echo(f"left out: {line}")
            try:
                result = Comparison([row for _, t, r in groups for row in compare(t, r).rows])
            except ValueError as err:
                fail(str(err))
            for path, _, reports in groups:
                typer.echo(
                    f"table {path.name}: "
                    + ", ".join(sorted({ds.attrs.get("sweep", "?") for ds in reports}))
                )
        _print_check(result, min_q, draws, seed)
        if plot is not None:
            plot.mkdir(parents=True, exist_ok=True)
            from ..decision.map import draw_master

            for table_path, table, reports in groups:
                points = master_points(table, reports)
                name = "master_curve" if len(groups) == 1 else f"master_curve_{table_path.stem}"
                paths_out = draw_master(points, plot, name, footer=table_footer(table, table_path))
                typer.echo(
                    f"master curve: {len(points)} conditionals ({table_path.name}); wrote "
                    + ", ".join(map(str, paths_out))
                )

    @predict.command("map", short_help="Draw the predicted Fig. 9 map.")
    def map_command(
        table_path: TableArgument,
        dw: DwOption = None,
        sigma: SigmaOption = None,
        out: Annotated[
            Path | None,
            typer.Option(
                "--out", "-o", metavar="DIR", help="Output directory [default: the current one]."
            ),
        ] = None,
        report: Annotated[
            list[Path] | None,
            typer.Option(
                metavar="REPORT.nc",
                help="Sweep report (NetCDF) whose points are drawn on the map (repeatable).",
            ),
        ] = None,
        t_stop_max: Annotated[float, typer.Option(metavar="T", help="Longest stop drawn.")] = 3.5,
        asymmetry_max: Annotated[
            float, typer.Option(metavar="DELTA", help="Largest Delta drawn.")
        ] = 1e-4,
        resolution: Annotated[
            int, typer.Option(min=2, metavar="N", help="Points along t_stop.")
        ] = 160,
    ) -> None:
        """Draw the Fig. 9 map P(t_stop, Delta) predicted at one noise intensity."""
        from ..decision.map import draw_map, ensemble_points
        from ..decision.table import sigma_of

        table = _table(table_path)
        diffusion = _diffusion(dw, sigma, table.inertia)
        if t_stop_max > table.t_max:
            fail(f"--t-stop-max {t_stop_max:g}: beyond the table's {table.t_max:g}")
        reports = _reports(report or [], "--report ")
        try:
            points = ensemble_points(table, reports, sigma_of(diffusion, table.inertia))
        except ValueError as err:
            fail(str(err))
        out = output_dir(out or Path.cwd())
        out.mkdir(parents=True, exist_ok=True)
        paths, _ = draw_map(
            table,
            diffusion,
            out,
            t_range=(0.25, t_stop_max),
            asymmetry_max=asymmetry_max,
            resolution=(resolution, max(2, resolution // 2)),
            points=points,
            footer=table_footer(table, table_path),
        )
        typer.echo("wrote " + ", ".join(str(p) for p in paths))
