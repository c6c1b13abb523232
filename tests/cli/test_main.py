"""The pde-rotor CLI end to end: a tiny run, every output file, bad inputs, divergence."""

from __future__ import annotations

import csv
import math
import subprocess
import sys
import types
from pathlib import Path

import imageio_ffmpeg
import numpy as np
import pytest
import xarray as xr
import yaml
from pde.storage import FileStorage
from typer.testing import CliRunner

import pde_rotor
from pde_rotor import api, backends
from pde_rotor.cli.main import app
from pde_rotor.config import load_config
from pde_rotor.io.output import PART_SUFFIX, OutputError, RunDirectory
from pde_rotor.solver.rotor import FusedStepper, SimulationDivergedError
from pde_rotor.trackers import EVENT_COLUMNS, TIMESERIES_VARIABLES
from tests.config.test_config import BAD_INPUTS, COARSE_YAML
from tests.conftest import DIVERGING

TINY_YAML = """\
geometry: {smoothing: 0.05}
grid: {dx: 0.05, dt: 4.0e-4, domain_radius: 1.75}
protocol: {t_ini: 0.4, t_stop: 0.2, t_release: 0.4, cycles: 2}
output:
  timeseries_interval: 0.02
  event_interval: 0.02
  snapshot_interval: 0.4
  movie_interval: 0.04
  movie_fps: 10
  movie_dpi: 40
"""
"""t_end = 1.6 (4000 steps of a 72 x 72 grid): a few seconds including the movie."""

runner = CliRunner()


def invoke(*args: str):
    return runner.invoke(app, [str(a) for a in args], catch_exceptions=False)


@pytest.fixture(scope="module")
def tiny_run(tmp_path_factory):
    """`pde-rotor run` of the tiny config with a fixed seed, plus the result it wrote."""
    root = tmp_path_factory.mktemp("cli")
    config_path = root / "tiny.yaml"
    config_path.write_text(TINY_YAML)
    out = root / "run"
    result = invoke("run", config_path, "--out", out, "--seed", "7", "--quiet")
    return config_path, out, result


def test_run_succeeds_and_lists_files(tiny_run):
    _, out, result = tiny_run
    assert result.exit_code == 0, result.output
    assert "run completed" in result.stdout
    assert "inversions: " in result.stdout
    for name in RunDirectory.FILES:
        if name != "bodies.nc":  # a run with bodies: writes it instead of the rotor's records
            assert (out / name).exists(), name
    assert not list(out.glob(f"*{PART_SUFFIX}"))


def test_config_yaml_is_resolved_with_seed_and_versions(tiny_run):
    config_path, out, _ = tiny_run
    written = load_config(out / "config.yaml")
    expected = load_config(config_path, ["noise.seed=7", "output.progress=false"])
    assert written == expected
    provenance = yaml.safe_load((out / "config.yaml").read_text())["provenance"]
    assert provenance["pde_rotor_version"] == pde_rotor.__version__
    assert provenance["seed"] == 7
    assert provenance["config_hash"] == written.config_hash()


def test_timeseries_nc_holds_the_rotor_with_attributes(tiny_run):
    _, out, _ = tiny_run
    config = load_config(out / "config.yaml")
    with xr.open_dataset(out / "timeseries.nc", engine="h5netcdf") as ds:
        assert set(TIMESERIES_VARIABLES) <= set(ds.data_vars)
        for name in TIMESERIES_VARIABLES:
            assert ds[name].attrs["units"]
            assert ds[name].attrs["equation"]
        assert ds.attrs["config_hash"] == config.config_hash()
        assert ds.attrs["status"] == "completed"
        assert ds.attrs["seed"] == 7
        t = ds["time"].values
        assert t[0] == 0.0 and t[-1] == pytest.approx(config.protocol.t_end)
        assert np.all(np.diff(t) > 0)
        assert np.all(np.isfinite(ds["omega"].values))


def test_events_csv_and_nc_agree(tiny_run):
    _, out, _ = tiny_run
    config = load_config(out / "config.yaml")
    with (out / "events.csv").open() as fh:
        rows = list(csv.DictReader(fh))
    assert list(rows[0]) == list(EVENT_COLUMNS)
    assert len(rows) == config.protocol.cycles
    with xr.open_dataset(out / "events.nc", engine="h5netcdf") as ev:
        assert list(ev["cycle"].values) == [int(r["cycle"]) for r in rows]
        np.testing.assert_array_equal(
            ev["omega_before"].values, [float(r["omega_before"]) for r in rows]
        )
        assert [bool(v) for v in ev["inverted"].values] == [r["inverted"] == "true" for r in rows]
        assert ev.attrs["config_hash"] == config.config_hash()
        assert "commit_fraction" in ev.attrs
    with xr.open_dataset(out / "timeseries.nc", engine="h5netcdf") as ts:
        for row in rows:  # omega before the stop is the time series at the stop time
            k = int(np.argmin(np.abs(ts["time"].values - float(row["t_stop"]))))
            assert ts["time"].values[k] == pytest.approx(float(row["t_stop"]), abs=1e-12)
            assert ts["omega"].values[k] == float(row["omega_before"])


def test_snapshots_h5_holds_the_fields(tiny_run):
    _, out, _ = tiny_run
    config = load_config(out / "config.yaml")
    storage = FileStorage(out / "snapshots.h5", write_mode="readonly")
    try:
        times = np.asarray(storage.times)
        expected = np.arange(0.0, config.protocol.t_end + 1e-9, config.output.snapshot_interval)
        np.testing.assert_allclose(times, expected, atol=1e-12)
        state = storage[-1]
        assert state.data.shape[0] == 3  # c, v_x, v_y
        assert np.all(np.isfinite(state.data))
        assert state.data[0].max() > 0  # camphor has spread from the pills
        assert len(storage.info["rotor_phi"]) == len(storage)
    finally:
        storage.close()


def test_movie_has_one_frame_per_interval(tiny_run):
    _, out, _ = tiny_run
    config = load_config(out / "config.yaml")
    movie = out / "movie.mp4"
    assert movie.stat().st_size > 0
    frames, _seconds = imageio_ffmpeg.count_frames_and_secs(str(movie))
    expected = math.floor(config.protocol.t_end / config.output.movie_interval + 1e-9) + 1
    assert frames == expected


def test_log_and_summary(tiny_run):
    _, out, _ = tiny_run
    log = (out / "run.log").read_text()
    assert "config hash" in log
    assert "run completed" in log
    assert (out / "summary.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_show_writes_a_figure(tiny_run, tmp_path):
    _, out, _ = tiny_run
    target = tmp_path / "fig.png"
    result = invoke("show", out, "--out", target)
    assert result.exit_code == 0, result.output
    assert target.read_bytes()[:4] == b"\x89PNG"


def test_show_of_a_missing_run_is_one_line(tmp_path):
    result = invoke("show", tmp_path / "nothing")
    assert result.exit_code == 2
    assert result.stderr.count("\n") == 1
    assert "not found" in result.stderr


def test_rerun_into_the_same_directory_is_refused(tiny_run):
    config_path, out, _ = tiny_run
    result = invoke("run", config_path, "--out", out, "--quiet")
    assert result.exit_code == 2
    assert "already holds a run" in result.stderr


def test_info_names_versions_and_threads():
    result = invoke("info")
    assert result.exit_code == 0
    for word in ("pde_rotor", "py-pde", "numba", "numpy", "threads", "backend"):
        assert word in result.stdout


def _numba_without_cuda_core(allow_simulator: bool = False) -> str | None:
    """numba's deprecated numba.cuda imports, numba-cuda's numba.cuda.core does not."""
    raise ModuleNotFoundError("No module named 'numba.cuda.core'", name="numba.cuda.core")


@pytest.mark.parametrize("installed", ["numba.cuda only", "nothing"])
def test_info_without_gpu_support_says_what_to_install(monkeypatch, installed):
    """A plain install (no numba-cuda) gets an install hint, not a raw import error."""
    fake = None
    if installed == "numba.cuda only":
        fake = types.ModuleType("pde_rotor.backends.gpu")
        fake.unavailable_reason = _numba_without_cuda_core
    monkeypatch.setitem(sys.modules, "pde_rotor.backends.gpu", fake)
    result = invoke("info")
    assert result.exit_code == 0
    (line,) = [line for line in result.stdout.splitlines() if line.startswith("gpu")]
    assert "pip install 'numba-cuda[cu12]'" in line and "not installed" in line
    assert "ModuleNotFoundError" not in line and "numba.cuda.core" not in line


def test_check_prints_a_loadable_config(tmp_path):
    path = tmp_path / "c.yaml"
    path.write_text(COARSE_YAML)
    result = invoke("check", path, "--set", "protocol.t_stop=1.5")
    assert result.exit_code == 0, result.output
    back = tmp_path / "back.yaml"
    back.write_text(result.stdout)
    assert load_config(back).protocol.t_stop == 1.5


@pytest.mark.parametrize("case", list(BAD_INPUTS), ids=list(BAD_INPUTS))
def test_bad_input_exits_2_with_one_line(tmp_path, case):
    """Every bad input through `pde-rotor run`: exit 2, one line, nothing created."""
    text, overrides, key, allowed = BAD_INPUTS[case]
    path = tmp_path / "c.yaml"
    path.write_text(COARSE_YAML if text is None else text)
    args = ["run", path, "--out", tmp_path / "out", "--quiet"]
    for override in overrides:
        args += ["--set", override]
    result = invoke(*args)
    assert result.exit_code == 2
    assert result.stderr.startswith("error: ")
    assert result.stderr.count("\n") == 1
    assert key in result.stderr and allowed in result.stderr
    assert "Traceback" not in result.output
    assert not (tmp_path / "out").exists()


def test_long_run_announces_its_estimate_in_the_first_line(tmp_path, monkeypatch):
    """``{}`` is the paper's 10.6 M steps with a movie: the estimate comes before anything."""

    def not_run(*args, **kwargs):
        raise OutputError("stopped where the run would start")

    monkeypatch.setattr(api, "run", not_run)
    first_lines = []
    for name, text in (("defaults.yaml", "{}\n"), ("tiny.yaml", TINY_YAML)):
        path = tmp_path / name
        path.write_text(text)
        result = invoke("run", path, "--out", tmp_path / f"out-{name}", "--quiet")
        assert "stopped where the run would start" in result.stderr
        first_lines.append(result.stdout.splitlines()[0])
    assert first_lines[0].startswith("pde-rotor: long run, about ")
    assert "10.6 M steps" in first_lines[0] and "movie frames" in first_lines[0]
    assert "estimate" in first_lines[0]
    assert first_lines[1].startswith("pde-rotor: running ")


def test_missing_config_file_exits_2(tmp_path):
    result = invoke("run", tmp_path / "missing.yaml", "--quiet")
    assert result.exit_code == 2
    assert "not found" in result.stderr


def test_gpu_backend_without_gpu_exits_2(tmp_path, monkeypatch):
    """No GPU (and no simulator): one line before anything is created or compiled."""
    monkeypatch.setattr(
        backends, "gpu_unavailable_reason", lambda allow_simulator=False: "no GPU found"
    )
    path = tmp_path / "c.yaml"
    path.write_text(TINY_YAML)
    result = invoke("run", path, "--backend", "gpu", "--out", tmp_path / "o")
    assert result.exit_code == 2
    assert result.stderr.count("\n") == 1
    assert "solver.backend = 'gpu': no GPU found" in result.stderr
    assert not (tmp_path / "o").exists()


def test_auto_backend_records_the_backend_that_ran(monkeypatch):
    """solver.backend = auto: the files and the result name the backend that really ran.

    Both backends run through py-pde's Controller; spies on what advances the run
    between interrupts: the fused CPU kernel, or an ensemble backend (the GPU path).
    Exactly one of them runs, and it is the one recorded (cpu here, where auto never
    picks the CUDA simulator; gpu on a GPU machine).
    """
    calls = []
    cpu_step = FusedStepper.__call__
    ensemble_run = backends.run_ensemble

    def spy_cpu(self, *args, **kwargs):
        calls.append("cpu")
        return cpu_step(self, *args, **kwargs)

    def spy_ensemble(*args, **kwargs):
        calls.append(kwargs["backend"])
        return ensemble_run(*args, **kwargs)

    monkeypatch.setattr(FusedStepper, "__call__", spy_cpu)
    monkeypatch.setattr(backends, "run_ensemble", spy_ensemble)
    config = yaml.safe_load(TINY_YAML)
    config["solver"] = {"backend": "auto"}
    config["output"].update(movie=False, progress=False, snapshot_interval=None)
    result = pde_rotor.run(config)
    ran = set(calls)
    assert len(ran) == 1
    assert ran == {result.backend}
    assert result.timeseries.attrs["backend"] == result.backend
    assert result.events.attrs["backend"] == result.backend
    assert (result.timeseries.attrs["device"] == "cpu") == (result.backend == "cpu")


def test_divergence_exits_1_and_keeps_what_was_written(tmp_path):
    """A large initial omega and a stiff flow coupling break the advection limit: NaN/Inf."""
    path = tmp_path / "c.yaml"
    path.write_text(TINY_YAML)
    out = tmp_path / "run"
    result = invoke(
        "run", path, "--out", out, "--quiet", "--set", "rotor.omega0=1e4", "--set", "flow.drag=1e3"
    )
    assert result.exit_code == 1
    assert result.stderr.startswith("error: simulation diverged at t = ")
    assert result.stderr.count("\n") == 1
    assert not list(out.glob(f"*{PART_SUFFIX}"))
    with xr.open_dataset(out / "timeseries.nc", engine="h5netcdf") as ds:
        assert ds.attrs["status"] == "diverged"
        assert "diverged" in ds.attrs["message"]
        assert ds.sizes["time"] >= 1
    with (out / "events.csv").open() as fh:
        assert next(csv.reader(fh)) == list(EVENT_COLUMNS)
    storage = FileStorage(out / "snapshots.h5", write_mode="readonly")
    try:
        assert len(storage) >= 1
        assert storage.info["status"] == "diverged"
    finally:
        storage.close()
    assert "diverged" in (out / "run.log").read_text()


def test_api_run_in_memory_draws_and_records_a_seed():
    config = yaml.safe_load(TINY_YAML)
    config["output"]["progress"] = False
    result = pde_rotor.run(config)
    assert isinstance(result, pde_rotor.RunResult)
    assert result.ok and result.run_dir is None and result.files == {}
    assert isinstance(result.config.noise.seed, int)
    assert result.timeseries.attrs["seed"] == result.config.noise.seed
    assert result.events.sizes["cycle"] == result.config.protocol.cycles
    assert 0.0 <= result.inversion_probability <= 1.0


def test_api_run_raises_on_divergence_after_writing(tmp_path):
    config = yaml.safe_load(TINY_YAML)
    config.update(DIVERGING)
    with pytest.raises(SimulationDivergedError):
        pde_rotor.run(config, tmp_path / "run", movie=False, progress=False)
    assert (tmp_path / "run" / "timeseries.nc").exists()
    result = pde_rotor.run(config, movie=False, progress=False, check=False)
    assert result.status == "diverged"
    assert "diverged at t" in result.message


def test_result_load_round_trip(tiny_run):
    _, out, _ = tiny_run
    result = pde_rotor.RunResult.load(out)
    assert result.ok
    assert result.config == load_config(Path(out) / "config.yaml")
    snap = result.snapshot()
    assert snap is not None and snap.data.shape[0] == 3


def test_show_during_a_run_reads_events_csv(tiny_run, tmp_path):
    """While a run goes, events.nc does not exist yet: show uses the rows of events.csv."""
    import shutil

    _, out, _ = tiny_run
    running = tmp_path / "running"
    shutil.copytree(out, running)
    (running / "events.nc").unlink()
    result = pde_rotor.RunResult.load(running)
    with xr.open_dataset(out / "events.nc", engine="h5netcdf") as ev:
        for name in ("omega_before", "direction_after", "inverted", "time_to_commit"):
            np.testing.assert_array_equal(result.events[name].values, ev[name].values)
        np.testing.assert_array_equal(result.events["cycle"].values, ev["cycle"].values)
    assert invoke("show", running).exit_code == 0


COMMANDS = (
    "run",
    "show",
    "check",
    "info",
    "sweep",
    "report",
    "compact",
    "plot",
    "gallery",
    "predict",
    "stability",
)
SUBCOMMANDS = (
    "predict measure",
    "predict point",
    "predict calibrate",
    "predict check",
    "predict map",
)


def test_help_lists_the_commands():
    result = invoke("--help")
    assert result.exit_code == 0
    for command in COMMANDS:
        assert command in result.stdout


@pytest.mark.parametrize("command", COMMANDS + SUBCOMMANDS)
def test_help_shows_defaults_and_no_bool_types(command):
    """Defaults written as [default: ...] survive (rich markup used to eat them and leave a
    bare "."), and flags are not labelled <bool>."""
    result = runner.invoke(app, [*command.split(), "--help"], env={"COLUMNS": "100"})
    assert result.exit_code == 0
    assert "<bool>" not in result.stdout
    text = " ".join(result.stdout.split())
    assert " ." not in text
    if command in ("run", "show", "sweep", "report", "gallery", "predict measure", "predict map"):
        assert "[default: " in text


def test_usage_doc_synopsis_names_every_command():
    """docs/usage.md's CLI synopsis has a line for every command of the app."""
    doc = (Path(__file__).parents[2] / "docs" / "usage.md").read_text()
    synopsis = doc.split("## The CLI", 1)[1].split("```text", 1)[1].split("```", 1)[0]
    named = {line.split()[1] for line in synopsis.splitlines() if line.startswith("pde-rotor ")}
    registered = {c.name or c.callback.__name__ for c in app.registered_commands}
    registered |= {g.name for g in app.registered_groups}
    assert named == registered
    assert named == set(COMMANDS)


def test_check_takes_several_files(tmp_path):
    """`check configs/*.yaml`: one line per file, every bad one named, exit 2 if any."""
    good = tmp_path / "good.yaml"
    good.write_text(COARSE_YAML)
    bad = tmp_path / "bad.yaml"
    bad.write_text("protocol: {t_stp: 1.0}\n")
    sweep = tmp_path / "sweep.yaml"
    sweep.write_text("name: s\naxes: {protocol.t_stop: [1.0]}\nsamples: 2\nseed: 1\n")
    result = invoke("check", good, bad, sweep, good)
    assert result.exit_code == 2
    assert result.stdout.splitlines() == [
        line for line in result.stdout.splitlines() if line.startswith(f"ok: {good}: t_end = ")
    ]
    assert len(result.stdout.splitlines()) == 2
    errors = result.stderr.splitlines()
    assert errors[0].startswith(f"error: {bad}: protocol.t_stp: unknown key")
    assert errors[1].startswith(f"error: {sweep} is a sweep file")
    assert len(errors) == 2
    assert invoke("check", good, good).exit_code == 0


@pytest.mark.parametrize(
    ("code", "heavy"),
    [
        ("import pde_rotor.cli.main", ("numba", "xarray", "dask", "pde", "matplotlib")),
        ("import pde_rotor; pde_rotor.__version__", ("numba", "xarray", "dask", "pde")),
        (
            "from pde_rotor.cli.main import app; app(['check', 'configs/quickstart.yaml'])",
            ("numba", "xarray", "dask", "pde", "matplotlib"),
        ),
    ],
)
def test_the_command_line_starts_without_the_solver_stack(code, heavy):
    """--version, --help and check import neither the solver nor numba, py-pde, xarray,
    dask or matplotlib (seconds of imports on a loaded machine): each command imports
    what it needs when it runs."""
    probe = (
        "import sys\n"
        f"try:\n    {code}\nexcept SystemExit:\n    pass\n"
        f"print(sorted(m for m in {heavy!r} if m in sys.modules))\n"
    )
    root = Path(__file__).resolve().parents[2]
    done = subprocess.run(
        [sys.executable, "-c", probe], capture_output=True, text=True, cwd=root, check=False
    )
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip().splitlines()[-1] == "[]", done.stdout


def test_the_lazy_package_names_are_the_real_objects():
    import pde_rotor
    from pde_rotor.api import run
    from pde_rotor.config import RotorConfig

    assert pde_rotor.run is run and pde_rotor.RotorConfig is RotorConfig
    assert set(pde_rotor.__all__) <= set(dir(pde_rotor))
    with pytest.raises(AttributeError, match="no attribute 'nothing'"):
        _ = pde_rotor.nothing
