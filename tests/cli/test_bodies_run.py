"""`pde-rotor run` of a config with bodies: progress bar and compile notice, run.log as the
run goes, the fast-body warning, the contact exit code, ``--set protocol...`` and the cost."""

from __future__ import annotations

import logging
from pathlib import Path

import pytest
import xarray as xr
import yaml
from typer.testing import CliRunner

from pde_rotor.cli.common import EXIT_CONTACT
from pde_rotor.cli.main import app
from pde_rotor.config import load_config
from pde_rotor.sweep.cost import estimate_run
from pde_rotor.trackers import bodies as body_trackers
from pde_rotor.trackers.progress import ProgressBarTracker

CONFIGS = Path(__file__).resolve().parents[2] / "configs" / "bodies"

BOAT = {
    "name": "boat",
    "plate": {"shape": "none"},
    "pills": [{"x": 0.0, "y": 0.0}],
    "motion": {"kind": "free", "mass": 1e-5, "friction": 1e-4},
    "start": {"x": 0.0, "y": 0.0, "velocity": [60.0, 0.0]},
}
"""A free pill launched at 60 with the rotor's friction (it keeps going): 0.24 of a cell
per step at dx = 0.05, dt = 2e-4; it reaches the rim of a dish of radius 2 near t = 0.023."""

ROTOR = {
    "name": "arm",
    "plate": {"shape": "none"},
    "pills": [{"x": 0.3, "y": 0.0}, {"x": -0.3, "y": 0.0}],
    "motion": {"kind": "fixed_axis"},
    "start": {"omega": 0.1},
}


def write_config(tmp_path: Path, bodies: list[dict], t_ini: float) -> Path:
    data = {
        "grid": {"dx": 0.05, "dt": 2e-4, "domain_radius": 2.0},
        "numerics": {"scheme": "paper"},
        "protocol": {"t_ini": t_ini, "cycles": 0},
        "bodies": bodies,
        "output": {"timeseries_interval": 0.004, "movie": False, "snapshot_interval": None},
    }
    path = tmp_path / "bodies.yaml"
    path.write_text(yaml.safe_dump(data))
    return path


def test_a_body_at_the_rim_ends_the_run_with_its_own_code_one_line_and_a_warning(tmp_path):
    config = write_config(tmp_path, [BOAT], 0.1)
    out = tmp_path / "run"
    result = CliRunner().invoke(app, ["run", str(config), "--out", str(out)])
    assert result.exit_code == EXIT_CONTACT != 130
    errors = [line for line in result.stderr.splitlines() if line.startswith("error:")]
    assert len(errors) == 1
    assert errors[0].startswith("error: body boat reached the dish's edge at t = ")
    warnings = [line for line in result.stderr.splitlines() if line.startswith("warning:")]
    assert len(warnings) == 1
    assert warnings[0].startswith("warning: body boat moves 0.24 of a cell per step at t = 0 ")
    assert ProgressBarTracker.COMPILING in result.stderr
    with xr.open_dataset(out / "bodies.nc") as ds:
        assert ds.attrs["status"] == "stopped"
    log = (out / "run.log").read_text()
    assert "bodies run" in log and "moves 0.24 of a cell per step" in log


def test_run_log_grows_while_the_run_goes(tmp_path, monkeypatch):
    config = write_config(tmp_path, [ROTOR], 0.05)
    out = tmp_path / "run"
    seen: list[str] = []
    handle = body_trackers.BodiesLogTracker.handle

    def spy(self, field, t):
        handle(self, field, t)
        if abs(t - 0.025) < 1e-9:
            seen.append((out / "run.log").read_text())

    monkeypatch.setattr(body_trackers.BodiesLogTracker, "handle", spy)
    result = CliRunner().invoke(app, ["run", str(config), "--out", str(out), "-q"])
    assert result.exit_code == 0, result.output
    assert len(seen) == 1
    assert "bodies run" in seen[0] and "t = 0.025 of 0.05: arm |U| 0 omega " in seen[0]
    progress = [line for line in (out / "run.log").read_text().splitlines() if " of 0.05: " in line]
    assert len(progress) == 10
    assert ProgressBarTracker.COMPILING not in result.stderr  # --quiet: no bar


def test_set_protocol_follows_the_bodies_that_copy_the_run_protocol(caplog):
    with caplog.at_level(logging.WARNING, logger="pde_rotor"):
        cfg = load_config(CONFIGS / "two_rotors.yaml", ["protocol.t_stop=1.0"])
    assert cfg.bodies[0].protocol.t_stop == 1.0  # "stopped" copies the run's protocol
    assert cfg.bodies[1].protocol is None  # "running" is never stopped
    assert cfg.protocol.t_end == pytest.approx(120.0)
    assert caplog.records == []


def test_set_protocol_that_reaches_no_body_warns_once(caplog):
    with caplog.at_level(logging.WARNING, logger="pde_rotor"):
        cfg = load_config(
            CONFIGS / "two_rotors.yaml", ["bodies[0].protocol.t_ini=5.0", "protocol.t_stop=1.0"]
        )
    assert cfg.bodies[0].protocol.t_stop == 2.0
    assert len(caplog.records) == 1
    message = caplog.records[0].getMessage()
    assert "--set protocol.t_stop=1.0" in message and "bodies[0] (stopped)" in message
    assert "\n" not in message


def test_set_protocol_of_bodies_without_stops_is_quiet(caplog):
    with caplog.at_level(logging.WARNING, logger="pde_rotor"):
        cfg = load_config(CONFIGS / "free_disk.yaml", ["protocol.t_ini=1.0"])
    assert cfg.protocol.t_end == 1.0
    assert caplog.records == []


def test_check_shows_the_protocol_warning_as_one_line(tmp_path):
    result = CliRunner().invoke(
        app,
        [
            "check",
            str(CONFIGS / "two_rotors.yaml"),
            "--set",
            "bodies[0].protocol.t_ini=5.0",
            "--set",
            "protocol.t_stop=1.0",
        ],
    )
    assert result.exit_code == 0
    lines = [line for line in result.stderr.splitlines() if line.startswith("warning:")]
    assert len(lines) == 1 and "no body follows the run's protocol" in lines[0]


def test_the_estimate_counts_each_body_by_its_motion_and_footprint():
    base = load_config(CONFIGS / "two_rotors.yaml")
    data = base.model_dump(mode="json")
    one = dict(data, bodies=data["bodies"][:1])
    fixed = dict(data, bodies=[dict(data["bodies"][1], motion={"kind": "fixed"}, start={})])
    seconds = {
        name: estimate_run(type(base).model_validate(d), movie=False).seconds
        for name, d in (("two", data), ("one", one), ("fixed", fixed))
    }
    per_rotor = seconds["two"] - seconds["one"]
    assert per_rotor > 0
    assert seconds["one"] - per_rotor < seconds["fixed"] < seconds["one"]
