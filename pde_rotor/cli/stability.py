"""``pde-rotor stability``: the rest state, the leading eigenvalues and the onset of a config.

Without ``--param``: the rest state's camphor balance, the leading eigenvalues of the
linearisation with their residuals, and a picture of each leading mode. With ``--param
KEY --from A --to B --points N``: the leading eigenvalues along the key, every critical
value where the real part crosses 0 (brentq, ``--rtol``) with its kind (pitchfork or
Hopf and its frequency), a plot and a NetCDF of the branch. Bad input (config, key,
range, output directory) is one line ``error: ...`` and exit 2, before any compute
(:mod:`pde_rotor.stability`; docs/stability.md).
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Annotated

import numpy as np
import typer

from ..config import ConfigError, apply_overrides, read_config_data
from .common import SetOption, fail, output_dir


def _describe(value: complex) -> str:
    from ..stability import is_real

    if is_real(value):
        return f"{value.real:+.6g} (real)"
    return f"{value.real:+.6g} {value.imag:+.6g}i (pair, frequency {abs(value.imag):.6g})"


def register(app: typer.Typer) -> None:
    """Add ``pde-rotor stability`` to `app`."""

    @app.command(short_help="Rest state, leading eigenvalues and onsets of a config.")
    def stability(
        config: Annotated[
            Path, typer.Argument(metavar="CONFIG", help="YAML config file (see configs/).")
        ],
        set_: SetOption = None,
        param: Annotated[
            str | None,
            typer.Option(
                "--param",
                metavar="KEY",
                help=(
                    "Config key to follow, e.g. rotor.friction; [*] sets it in every entry "
                    "of a list, e.g. bodies[*].motion.friction."
                ),
            ),
        ] = None,
        start: Annotated[
            float | None, typer.Option("--from", help="First value of --param.")
        ] = None,
        stop: Annotated[float | None, typer.Option("--to", help="Last value of --param.")] = None,
        points: Annotated[int, typer.Option("--points", help="Values of --param.")] = 10,
        log: Annotated[
            bool, typer.Option("--log", help="Space the values of --param geometrically.")
        ] = False,
        k: Annotated[int, typer.Option("--k", help="Eigenvalues per point.")] = 4,
        rtol: Annotated[
            float, typer.Option("--rtol", help="Relative tolerance of a critical value.")
        ] = 1e-6,
        positions: Annotated[
            bool | None,
            typer.Option(
                "--positions/--comoving",
                help=(
                    "Bodies' coordinates as unknowns [default: behind a no-flux wall only; "
                    "track bodies about a round vessel's centre: their relative ones]."
                ),
                show_default=False,
            ),
        ] = None,
        out: Annotated[
            Path | None,
            typer.Option("--out", "-o", metavar="DIR", help="Directory of the figures and NetCDF."),
        ] = None,
    ) -> None:
        """Linear stability of CONFIG's rest state (docs/stability.md)."""
        try:
            data = apply_overrides(read_config_data(config), set_ or [])
        except ConfigError as err:
            fail(str(err))
        from ..config import validate_config

        try:
            base = validate_config(data)
        except ConfigError as err:
            fail(str(err))
        if k < 1:
            fail(f"--k {k}: at least 1 eigenvalue")
        if not 0 < rtol < 1:
            fail(f"--rtol {rtol:g}: allowed 0 < rtol < 1")
        values = None
        if param is not None:
            if start is None or stop is None:
                fail(f"--param {param}: give its range with --from A --to B")
            if start == stop:
                fail(f"--from {start:g} --to {stop:g}: an empty range")
            if points < 2:
                fail(f"--points {points}: a branch needs at least 2 values")
            if log and (start <= 0 or stop <= 0):
                fail(f"--log with --from {start:g} --to {stop:g}: both ends must be > 0")
            values = np.geomspace(start, stop, points) if log else np.linspace(start, stop, points)
            from ..stability.continuation import config_at

            try:
                for value in (start, stop):
                    config_at(data, param, value)
            except ConfigError as err:
                fail(str(err))
        elif start is not None or stop is not None:
            fail("--from/--to without --param: name the key to follow")
        target = output_dir(out or Path(f"stability-{config.stem}"))
        if values is None:
            _spectrum(base, k, positions, target)
        else:
            _branch(data, param, values, k, rtol, positions, target)


def _spectrum(config, k: int, positions: bool | None, target: Path) -> None:
    from ..stability import DiscreteModel, leading_modes, linearise
    from ..stability.plots import plot_mode

    model = DiscreteModel(config)
    lin = linearise(model, positions=positions)
    rest = lin.rest
    typer.echo(
        f"rest state: supply {rest.supply:.6g} = sublimation {rest.sublimation:.6g} + wall "
        f"outflow {rest.wall_outflow:.6g}; max c0 {rest.c.max():.6g}"
    )
    labels = [d.label for d in model.dofs]
    typer.echo(
        "at rest, released: accelerations "
        + ", ".join(
            f"{name} {a:+.3g}" for name, a in zip(labels, lin.rest_acceleration, strict=True)
        )
    )
    typer.echo(
        f"unknowns: {lin.n_fields} field values, {lin.small.shape[0]} mechanical ({lin.frame_name})"
    )
    if lin.n_dofs:
        typer.echo(
            "stiffness K = d(acceleration)/dq at rest: "
            + np.array2string(lin.stiffness, precision=4)
        )
    spectrum = leading_modes(lin, k=k)
    typer.echo(f"shift sigma = {spectrum.shift:.6g}")
    for j, (value, residual) in enumerate(
        zip(spectrum.eigenvalues, spectrum.residuals, strict=True)
    ):
        typer.echo(f"lambda_{j} = {_describe(complex(value))}  residual {residual:.1e}")
    target.mkdir(parents=True, exist_ok=True)
    shown = 0
    for j, value in enumerate(spectrum.eigenvalues):
        if value.imag < 0 or shown == 2:
            continue
        path = plot_mode(lin, spectrum, j, target / f"mode{j}.png")
        typer.echo(f"wrote {path}")
        shown += 1
    summary = {
        "eigenvalues": [[float(v.real), float(v.imag)] for v in spectrum.eigenvalues],
        "residuals": spectrum.residuals.tolist(),
        "shift": spectrum.shift,
        "supply": rest.supply,
        "sublimation": rest.sublimation,
        "wall_outflow": rest.wall_outflow,
    }
    (target / "spectrum.json").write_text(json.dumps(summary, indent=1))
    typer.echo(f"wrote {target / 'spectrum.json'}")


def _branch(data, key, values, k, rtol, positions, target: Path) -> None:
    from tqdm.auto import tqdm

    from ..config import validate_config
    from ..stability import follow
    from ..stability.plots import plot_branch

    def progress(items):
        return tqdm(items, desc=f"{key}", unit="point")

    branch = follow(data, key, values, k=k, positions=positions, rtol=rtol, progress=progress)
    for value, lam in zip(branch.values, branch.leading, strict=True):
        typer.echo(f"{key} = {value:.6g}: leading lambda {_describe(complex(lam))}")
    if not branch.crossings:
        typer.echo("no crossing of Re lambda = 0 in the range")
    for cross in branch.crossings:
        extra = f", frequency {cross.frequency:.6g}" if cross.kind == "hopf" else ""
        typer.echo(
            f"critical {key} = {cross.value:.8g} +- {cross.tolerance:.1e}: {cross.kind}{extra} "
            f"({cross.direction} as {key} grows)"
        )
    target.mkdir(parents=True, exist_ok=True)
    dataset = branch.to_dataset(validate_config(data))
    dataset.to_netcdf(target / "branch.nc")
    typer.echo(f"wrote {target / 'branch.nc'}")
    path = plot_branch(branch, target / "branch.png", title=key)
    typer.echo(f"wrote {path}")
