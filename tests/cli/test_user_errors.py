"""What a new user runs into: every mistake is one line, exit 2, before any compute.

Bad output paths, an unreachable scheduler, values outside the model's regime, records
that cannot fit, options that contradict each other; and the help a user reads.
"""

from __future__ import annotations

import time
from pathlib import Path

import pytest
import xarray as xr
import yaml
from typer.testing import CliRunner

from pde_rotor import __version__
from pde_rotor.cli.main import app
from pde_rotor.config import RotorConfig
from pde_rotor.sweep import execution
from pde_rotor.trackers import budget
from tests.cli.test_main import TINY_YAML

ROOT = Path(__file__).resolve().parents[2]
QUICK_SWEEP = ROOT / "configs" / "sweeps" / "fig5_quick.yaml"
TABLE = ROOT / "data" / "decision" / "dx40.nc"

runner = CliRunner()


def invoke(*args: object):
    return runner.invoke(app, [str(a) for a in args], catch_exceptions=False)


def one_line(result, *fragments: str) -> None:
    """Exit 2, a single ``error:`` line on stderr naming every fragment, no stdout noise."""
    assert result.exit_code == 2, (result.stdout, result.stderr)
    assert result.stderr.startswith("error: "), result.stderr
    assert result.stderr.count("\n") == 1, result.stderr
    assert "Traceback" not in result.output
    for fragment in fragments:
        assert fragment in result.stderr, (fragment, result.stderr)


@pytest.fixture
def a_file(tmp_path: Path) -> Path:
    path = tmp_path / "FILE"
    path.write_text("not a directory\n")
    return path


@pytest.fixture
def tiny_config(tmp_path: Path) -> Path:
    path = tmp_path / "tiny.yaml"
    path.write_text(TINY_YAML)
    return path


def entries(directory: Path) -> set[str]:
    return {p.name for p in directory.iterdir()}


def test_sweep_out_that_is_a_file_or_below_one_is_one_line(tmp_path, a_file):
    before = entries(tmp_path)
    one_line(invoke("sweep", QUICK_SWEEP, "--set", "samples=1", "--out", a_file), "FILE")
    one_line(invoke("sweep", QUICK_SWEEP, "--out", a_file / "sub"), "is a file")
    assert entries(tmp_path) == before


def test_outputs_where_nothing_can_be_created_are_one_line(tmp_path, a_file):
    """/proc refuses new entries even to root, where permission bits do not."""
    one_line(invoke("sweep", QUICK_SWEEP, "--out", "/proc/pde-rotor-x"), "/proc/pde-rotor-x")
    sweep_dir = ROOT / "data" / "sweeps" / "fig5"
    one_line(invoke("report", sweep_dir, "--out", "/proc/x/r.nc"), "/proc/x/r.nc")
    one_line(invoke("report", sweep_dir, "--out", a_file / "r.nc"), "is a file")
    one_line(invoke("report", sweep_dir, "--out", tmp_path), "is a directory")


def test_map_gallery_and_show_refuse_a_file_as_output_directory(tmp_path, a_file):
    before = entries(tmp_path)
    one_line(invoke("predict", "map", TABLE, "--sigma", "1.5e-7", "-o", a_file), "FILE")
    one_line(invoke("gallery", "--tiny", "--only", "fig1", "-o", a_file), "FILE")
    one_line(invoke("predict", "check", TABLE, ROOT / "data" / "fig5.nc", "--plot", a_file))
    assert entries(tmp_path) == before


def test_an_unreachable_scheduler_is_one_line_quickly_and_leaves_nothing(tmp_path, monkeypatch):
    monkeypatch.setattr(execution, "CONNECT_TIMEOUT", 1.0)
    out = tmp_path / "sweep"
    start = time.monotonic()
    result = invoke("sweep", QUICK_SWEEP, "--scheduler", "tcp://127.0.0.1:1", "--out", out)
    elapsed = time.monotonic() - start
    one_line(result, "tcp://127.0.0.1:1", "within 1 s", "check that")
    assert elapsed < 20
    assert not out.exists()


@pytest.mark.parametrize(
    ("key", "value", "named"),
    [
        ("camphor.supply", "1e308", "0 <= supply <= 1000"),
        ("rotor.inertia", "1e-12", "1e-08 <= inertia"),
        ("rotor.omega0", "1e9", "omega0 <= 10000"),
        ("protocol.cycles", "1000000000000", "cycles <= 100000"),
    ],
)
def test_values_far_outside_the_models_regime_are_refused_at_check(tiny_config, key, value, named):
    one_line(invoke("check", tiny_config, "--set", f"{key}={value}"), key, named)


def test_a_run_whose_records_cannot_fit_in_memory_is_refused_before_it_starts(
    tmp_path, tiny_config, monkeypatch
):
    config = RotorConfig.model_validate(yaml.safe_load(TINY_YAML))
    need = budget.estimate_budget(config).memory
    monkeypatch.setattr(budget, "available_memory", lambda: need - 1)
    out = tmp_path / "run"
    one_line(invoke("check", tiny_config), "of memory", "protocol.cycles")
    one_line(invoke("run", tiny_config, "--out", out), "of memory")
    assert not out.exists()
    monkeypatch.setattr(budget, "available_memory", lambda: need)
    assert invoke("check", tiny_config).exit_code == 0


def test_a_run_whose_files_cannot_fit_on_disk_is_refused_before_it_starts(
    tmp_path, tiny_config, monkeypatch
):
    config = RotorConfig.model_validate(yaml.safe_load(TINY_YAML))
    need = budget.estimate_budget(config, movie=True).disk
    assert need > budget.estimate_budget(config, movie=False).disk  # the movie counts
    monkeypatch.setattr(budget, "free_disk", lambda directory: need - 1)
    out = tmp_path / "run"
    one_line(invoke("run", tiny_config, "--out", out), "on disk", "--no-movie")
    assert not out.exists()


def test_budget_grows_with_the_protocol_and_the_recorded_fields():
    base = RotorConfig.model_validate(yaml.safe_load(TINY_YAML))
    longer = base.model_copy(
        update={"protocol": base.protocol.model_copy(update={"cycles": 20 * base.protocol.cycles})}
    )
    assert budget.estimate_budget(longer).memory > 5 * budget.estimate_budget(base).memory
    no_snap = base.model_copy(
        update={"output": base.output.model_copy(update={"snapshot_interval": None})}
    )
    assert budget.estimate_budget(no_snap).disk < budget.estimate_budget(base).disk


def test_divergence_names_the_parameters_furthest_from_the_papers(tiny_config, tmp_path):
    result = invoke(
        "run", tiny_config, "--out", tmp_path / "run", "-q",
        "--set", "rotor.omega0=1e4", "--set", "flow.drag=1e3",
    )  # fmt: skip
    assert result.exit_code == 1
    assert "likely cause: rotor.omega0 = 10000" in result.stderr
    assert "flow.drag = 1000" in result.stderr
    assert result.stderr.index("rotor.omega0") < result.stderr.index("flow.drag")  # furthest first


def test_far_from_paper_lists_only_what_differs_by_more_than_the_factor():
    assert RotorConfig().far_from_paper() == []
    config = RotorConfig.model_validate({"camphor": {"supply": 20.0, "evaporation": 5.0}})
    assert config.far_from_paper() == ["camphor.supply = 20, 20 times the paper's 1"]
    assert len(config.far_from_paper(factor=2.0)) == 2


def test_seed_and_backend_options_refuse_a_conflicting_set(tiny_config):
    one_line(
        invoke("run", tiny_config, "--seed", "3", "--set", "noise.seed=4"), "--seed 3", "noise.seed"
    )
    one_line(
        invoke("run", tiny_config, "--backend", "cpu", "--set", "solver.backend=gpu"),
        "solver.backend",
    )


def test_gallery_takes_one_size(tmp_path):
    one_line(invoke("gallery", "--quick", "--tiny", "-o", tmp_path / "g"), "--quick", "--tiny")
    assert not (tmp_path / "g").exists()


def test_run_and_sweep_refuse_a_directory_that_holds_something_else(tmp_path, tiny_config):
    other = tmp_path / "mine"
    other.mkdir()
    (other / "x.txt").write_text("keep me\n")
    one_line(invoke("run", tiny_config, "--out", other), "x.txt")
    one_line(invoke("sweep", QUICK_SWEEP, "--out", other), "x.txt", "no sweep.yaml")
    assert entries(other) == {"x.txt"}
    assert (other / "x.txt").read_text() == "keep me\n"


def test_help_names_what_options_take_not_python_types():
    commands = [
        [], ["run"], ["show"], ["check"], ["sweep"], ["report"], ["compact"], ["plot"], ["gallery"],
        ["predict"],
        ["predict", "measure"], ["predict", "point"], ["predict", "calibrate"],
        ["predict", "check"], ["predict", "map"],
    ]  # fmt: skip
    for command in commands:
        text = invoke(*command, "--help").stdout
        for python_type in ("<list[", "<int", "<float", "<str>", "<path>"):
            assert python_type not in text, (command, python_type)
    listing = invoke("predict", "--help").stdout
    assert "Draw the predicted Fig. 9 map." in listing
    run_help = invoke("run", "--help").stdout
    assert "the config's noise.seed" in run_help
    assert "the config's solver.backend" in run_help


def test_version():
    result = invoke("--version")
    assert result.exit_code == 0
    assert result.stdout.strip() == f"pde-rotor {__version__}"


def test_the_report_table_speaks_plainly_and_explains_its_terms(tmp_path):
    result = invoke("report", ROOT / "data" / "sweeps" / "fig7b", "--out", tmp_path / "r.nc")
    assert result.exit_code == 0, result.output
    lines = result.stdout.splitlines()
    header = next(line for line in lines if line.lstrip().startswith("t_stop"))
    assert header.split() == [
        "t_stop", "P", "95%", "interval", "from", "CCW", "from", "CW", "mean", "|omega|", "runs",
        "done",
    ]  # fmt: skip
    assert all(len(line) <= 100 for line in lines[: lines.index(header)])
    assert "chain" not in result.stdout and "pooled" not in result.stdout
    assert "--explain" in result.stdout
    explained = invoke("report", ROOT / "data" / "sweeps" / "fig7b", "--out", tmp_path / "r.nc",
                       "--explain").stdout  # fmt: skip
    for term in ("inverted", "from CCW / CW", "estimator", "Dw", "committed"):
        assert term in explained.split("report:", 1)[1], term


def test_a_time_step_that_does_not_divide_the_times_gets_one_that_does(tiny_config):
    result = invoke("check", tiny_config, "--set", "grid.dt=3.9e-4")
    one_line(result, "protocol.t_ini = 0.4", "grid.dt = 0.00025, which divides every time")
    fitting = float(result.stderr.split("grid.dt = ")[2].split(",")[0])
    assert invoke("check", tiny_config, "--set", f"grid.dt={fitting}").exit_code == 0


def test_a_bad_sweep_point_is_named_once(tmp_path):
    path = tmp_path / "s.yaml"
    path.write_text("name: s\nbase: coarse\naxes: {grid.dt: [0.1]}\nsamples: 2\nseed: 1\n")
    result = invoke("sweep", path, "--dry-run")
    one_line(result, "sweep point grid.dt = 0.1: above the explicit stability limit")
    assert result.stderr.count("grid.dt = 0.1") == 1


def test_a_sweep_without_axes_says_it_runs_the_base_config(tmp_path):
    path = tmp_path / "s.yaml"
    path.write_text("name: s\nbase: coarse\naxes: {}\nsamples: 2\nseed: 1\n")
    result = invoke("sweep", path, "--dry-run")
    assert result.exit_code == 0
    assert "1 point x 4 runs = 4 runs" in result.stdout
    assert "(no axes: every run is of the base config)" in result.stdout


def test_a_full_disk_mid_run_stops_with_one_line_and_keeps_what_was_written(
    tmp_path, tiny_config, monkeypatch
):
    """The time series is checkpointed as the run goes; when the disk fills up the run
    stops, says when and why in one line (exit 1), and the last checkpoint stays readable."""
    import errno

    from pde_rotor.trackers import timeseries

    written = timeseries.write_netcdf_atomic
    calls = []

    def fill_up(dataset, path):
        calls.append(path)
        if len(calls) >= 3:
            raise OSError(errno.ENOSPC, "No space left on device", str(path))
        written(dataset, path)

    monkeypatch.setattr(timeseries, "write_netcdf_atomic", fill_up)
    out = tmp_path / "run"
    result = invoke(
        "run", tiny_config, "--out", out, "-q", "--no-movie",
        "--set", "output.checkpoint_seconds=1e-6",
    )  # fmt: skip
    assert result.exit_code == 1
    assert result.stderr.count("\n") == 1 and "Traceback" not in result.output
    assert "run stopped after t = " in result.stderr
    assert "No space left on device" in result.stderr and str(out) in result.stderr
    with xr.open_dataset(out / "timeseries.nc", engine="h5netcdf") as ds:
        assert ds.sizes["time"] >= 1 and ds.attrs["status"] == "running"


def test_the_disk_budget_holds_every_file_and_the_rewritten_time_series_twice(
    tmp_path, tiny_config
):
    """timeseries.nc is rewritten as the run goes, the new copy beside the old one: the
    up-front disk check counts both, and every other file the run writes."""
    out = tmp_path / "run"
    no_fields = ("--no-movie", "--set", "output.snapshot_interval=null")
    assert invoke("run", tiny_config, "--out", out, "-q", *no_fields).exit_code == 0
    config = RotorConfig.model_validate(yaml.safe_load(TINY_YAML))
    config = config.model_copy(
        update={"output": config.output.model_copy(update={"snapshot_interval": None})}
    )
    sizes = {p.name: p.stat().st_size for p in out.iterdir()}
    assert {"timeseries.nc", "events.nc", "summary.png"} <= set(sizes)
    need = sum(sizes.values()) + sizes["timeseries.nc"]
    assert budget.estimate_budget(config, movie=False).disk >= need


def test_a_disk_that_fills_while_snapshots_are_written_keeps_them_readable(
    tmp_path, tiny_config, monkeypatch
):
    """HDF5 crashes the process when it closes a file whose write failed: no snapshot is
    written without room for it, and the reserve held since the start lets the file
    close with every snapshot so far, readable."""
    from pde.storage import FileStorage

    from pde_rotor.trackers import snapshots

    calls = []

    def filling(directory):
        calls.append(directory)
        return 1 << 40 if len(calls) < 3 else 0

    monkeypatch.setattr(snapshots, "free_disk", filling)
    out = tmp_path / "run"
    result = invoke("run", tiny_config, "--out", out, "-q", "--no-movie")
    assert result.exit_code == 1, result.output
    assert result.stderr.count("\n") == 1 and "Traceback" not in result.output
    assert "No space left on device (writing snapshots.h5.part)" in result.stderr
    assert sorted(p.name for p in out.iterdir()) == [
        "config.yaml", "events.csv", "events.nc", "run.log", "snapshots.h5", "timeseries.nc"
    ]  # fmt: skip
    storage = FileStorage(out / "snapshots.h5", write_mode="readonly")
    try:
        assert len(storage) == 2 and storage.times[1] == pytest.approx(0.4)
    finally:
        storage.close()
    with xr.open_dataset(out / "timeseries.nc", engine="h5netcdf") as ds:
        assert ds.attrs["status"] == "failed"


def test_a_full_disk_at_the_summary_is_one_line_and_keeps_the_records(
    tmp_path, tiny_config, monkeypatch
):
    import errno

    from pde_rotor.api import RunResult

    def full(self):
        raise OSError(errno.ENOSPC, "No space left on device", str(self.run_dir / "summary.png"))

    monkeypatch.setattr(RunResult, "write_summary", full)
    out = tmp_path / "run"
    result = invoke("run", tiny_config, "--out", out, "-q", "--no-movie")
    assert result.exit_code == 1, result.output
    assert result.stderr.count("\n") == 1 and "Traceback" not in result.output
    assert "No space left on device (writing summary.png)" in result.stderr
    assert RunResult.load(out).events.sizes["cycle"] == 2


def test_crossings_are_read_along_any_axis_rising_or_falling(tmp_path):
    """The noise of the 0.2 plateau, from the ensembles alone: P(3, 2e-5) rises with
    sigma, read along sigma as the crossing functions read it."""
    from pde_rotor.statistics.crossing import report_crossing
    from pde_rotor.sweep.stored import load_report

    store = ROOT / "data" / "sweeps" / "science_calibration"
    args = ("report", store, "--out", tmp_path / "r.nc", "--crossing", "0.2", "--along", "sigma")
    result = invoke(*args, "--rising")
    assert result.exit_code == 0, result.output
    ds = load_report(ROOT / "data" / "science_calibration.nc").squeeze()
    expected = report_crossing(ds, 0.2, x_dim="sigma", falling=False).describe("sigma")
    assert f"crossing (t_stop = 3): {expected}" in result.stdout
    falling = invoke(*args)  # read as falling, the curve starts below 0.2: "at sigma = 0"
    assert expected not in falling.stdout and "P = 0.2 at sigma = 0 [open" in falling.stdout
    one_line(invoke(*args[:-2], "--along", "dx"), "no dimension 'dx'")
