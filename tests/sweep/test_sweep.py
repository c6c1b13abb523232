"""Tests of pde_rotor.sweep: schema, seeds, resumable dask execution and the report.

Every sweep here runs on a tiny grid (domain radius 1.75, dx = delta = 0.05,
dt = 4e-4) with very short times, so that one run takes a fraction of a second.
"""

from __future__ import annotations

import json
import math
import os
import shutil
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
import yaml
from scipy import stats

import pde_rotor
from pde_rotor.config import RotorConfig
from pde_rotor.statistics.proportions import CCW, CW, wilson_interval
from pde_rotor.sweep import (
    CHAIN,
    POOLED,
    RUNS_DIR,
    Run,
    RunLog,
    Sweep,
    SweepError,
    SweepSpec,
    base_config,
    execute,
    execute_group,
    format_table,
    gather,
    local_workers,
    mcnemar_p,
    read_runs,
    report,
    run_seed,
    run_sweep,
    shipped_base,
    stop_group,
    usable_cores,
    warm_state,
)

TINY_BASE = {
    "grid": {"domain_radius": 1.75, "dx": 0.05, "dt": 4e-4},
    "geometry": {"smoothing": 0.05},
    "protocol": {"t_ini": 2.0, "t_stop": 0.2, "t_release": 1.6, "cycles": 3},
    "noise": {"sigma": 1e-6},
}

TINY_SWEEP = {
    "name": "tiny",
    "base": TINY_BASE,
    "axes": {"protocol.t_stop": [0.2, 1.2]},
    "estimator": {"kind": "restart", "warmup": 2.0},
    "samples": 3,
    "seed": 7,
}


def write_sweep(path: Path, data: dict) -> Path:
    path.write_text(yaml.safe_dump(data, sort_keys=False), encoding="utf-8")
    return path


def tiny_sweep(**changes) -> Sweep:
    data = json.loads(json.dumps(TINY_SWEEP))
    data.update(changes)
    return Sweep.from_spec(SweepSpec.model_validate(data))


@pytest.fixture(scope="module")
def two_worker_sweep(tmp_path_factory) -> tuple[Path, xr.Dataset]:
    """The tiny sweep run uninterrupted on a LocalCluster of 2 workers, and its report."""
    root = tmp_path_factory.mktemp("sweep2")
    path = write_sweep(root / "tiny.yaml", TINY_SWEEP)
    outcome = run_sweep(path, root / "out", workers=2, progress=False)
    assert outcome.failed == []
    assert outcome.computed == outcome.total == 12
    return root / "out", report(root / "out", echo=False)


# ---------------------------------------------------------------------------------------
# schema and seeds
# ---------------------------------------------------------------------------------------


def test_axes_accept_lists_and_ranges():
    sweep = tiny_sweep(
        axes={
            "protocol.t_stop": {"start": 0.4, "stop": 1.6, "step": 0.4},
            "geometry.asymmetry": {"start": 0.0, "stop": 1e-4, "num": 3},
            "flow.enabled": [True, False],
        }
    )
    assert sweep.axes["protocol.t_stop"] == [0.4, 0.8, 1.2, 1.6]
    assert sweep.axes["geometry.asymmetry"] == [0.0, 5e-5, 1e-4]
    assert sweep.shape == (4, 3, 2)
    runs = sweep.runs()
    assert len(runs) == 4 * 3 * 2 * 2 * 3
    assert {r.direction for r in runs} == {CCW, CW}
    assert len({r.key for r in runs}) == len(runs)
    assert runs[-1].config["flow"]["enabled"] is False


@pytest.mark.parametrize(
    ("change", "message"),
    [
        ({"axes": {"protocol.t_stopp": [1.0]}}, "t_stopp"),
        ({"axes": {"protocol.t_stop": [-1.0]}}, "t_stop"),
        ({"axes": {"protocol.t_stop": [0.2001]}}, "multiple"),
        ({"axes": {"noise.seed": [1, 2]}}, "seed"),
        ({"axes": {"protocol.t_stop": {"start": 0, "stop": 1}}}, "num or step"),
        ({"samples": 0}, "samples"),
        ({"estimator": {"kind": "bootstrap"}}, "estimator"),
    ],
)
def test_invalid_sweeps_are_rejected_with_one_line(tmp_path, change, message):
    data = {**TINY_SWEEP, **change}
    path = write_sweep(tmp_path / "bad.yaml", data)
    with pytest.raises(SweepError, match=message) as err:
        Sweep.load(path)
    assert "\n" not in str(err.value)


def test_base_from_a_file_and_set_overrides(tmp_path):
    (tmp_path / "base.yaml").write_text(yaml.safe_dump(TINY_BASE), encoding="utf-8")
    data = {**TINY_SWEEP, "base": "base.yaml", "set": {"geometry.asymmetry": 2e-5}}
    sweep = Sweep.load(write_sweep(tmp_path / "s.yaml", data))
    assert sweep.base["geometry"]["asymmetry"] == 2e-5
    inline = tiny_sweep(set={"geometry.asymmetry": 2e-5})
    assert [r.key for r in sweep.runs()] == [r.key for r in inline.runs()]


def test_base_config_reads_a_large_design_without_planning_it(tmp_path, monkeypatch):
    """base_config gives the validated base of a sweep file (base file, ``set`` applied)
    without planning its runs; an invalid base is one SweepError naming the key."""
    (tmp_path / "base.yaml").write_text(yaml.safe_dump(TINY_BASE), encoding="utf-8")
    axes = {"protocol.t_stop": {"start": 0.1, "stop": 4.0, "num": 400}}
    data = {**TINY_SWEEP, "base": "base.yaml", "set": {"grid.dx": 0.0625}, "axes": axes}
    path = write_sweep(tmp_path / "s.yaml", data)

    def no_planning(self):
        raise AssertionError("base_config planned the runs")

    monkeypatch.setattr(Sweep, "runs", no_planning)
    config = base_config(path)
    assert isinstance(config, RotorConfig)
    assert (config.grid.dx, config.grid.domain_radius) == (0.0625, 1.75)
    write_sweep(path, {**data, "set": {"grid.dx": -1.0}})
    with pytest.raises(SweepError, match=r"grid\.dx"):
        base_config(path)


def test_set_changes_the_sweep_files_own_keys(tmp_path):
    """--set shrinks a sweep: samples, axis values, a dropped axis, the base's keys, the
    estimator; the runs it keeps are runs of the full sweep (same files, resumable)."""
    data = {**TINY_SWEEP, "axes": {"protocol.t_stop": [0.2, 1.2], "geometry.asymmetry": [0, 1e-4]}}
    path = write_sweep(tmp_path / "s.yaml", data)
    full = Sweep.load(path)
    small = Sweep.load(
        path,
        [
            "samples=1",
            "axes.protocol.t_stop=[1.2]",
            "axes.geometry.asymmetry=null",
            "set.geometry.asymmetry=1.0e-4",
            "estimator.release_cap=1.2",
            "seed=7",
        ],
    )
    assert small.spec.samples == 1
    assert small.axes == {"protocol.t_stop": [1.2]}
    assert small.base["geometry"]["asymmetry"] == 1e-4
    assert small.spec.estimator.release_cap == 1.2
    assert len(small.runs()) == 2
    same_estimator = Sweep.load(
        path, ["samples=1", "axes.protocol.t_stop=[1.2]", "axes.geometry.asymmetry=[1.0e-4]"]
    )
    assert {r.key for r in same_estimator.runs()} < {r.key for r in full.runs()}


@pytest.mark.parametrize(
    ("override", "message"),
    [
        ("sample=3", "not a key of the sweep file (allowed: name, description, base, set.KEY"),
        ("base.grid.dx=0.05", "the base config's keys: set.grid.dx=VALUE"),
        ("axes=[1]", "not a key of the sweep file"),
        ("samples", "KEY.PATH=VALUE"),
        ("samples=0", "samples"),
        ("axes.protocol.t_stopp=[1.0]", "t_stopp"),
        ("base=papr", "'papr' is not a shipped base (shipped: coarse, paper)"),
    ],
)
def test_bad_set_of_a_sweep_is_one_line(tmp_path, override, message):
    path = write_sweep(tmp_path / "s.yaml", TINY_SWEEP)
    with pytest.raises(SweepError) as err:
        Sweep.load(path, [override])
    assert message in str(err.value)
    assert "\n" not in str(err.value)


def test_a_copied_sweep_file_finds_its_shipped_base(tmp_path):
    """base: paper / coarse name configs shipped in the package, wherever the file is."""
    copy = tmp_path / "elsewhere" / "fig5_quick.yaml"
    copy.parent.mkdir()
    copy.write_text((SWEEPS / "fig5_quick.yaml").read_text())
    original = Sweep.load(SWEEPS / "fig5_quick.yaml")
    assert yaml.safe_load(copy.read_text())["base"] == "coarse"
    assert [r.key for r in Sweep.load(copy).runs()] == [r.key for r in original.runs()]
    assert shipped_base("paper").parent.parent == Path(pde_rotor.__file__).parent


def test_a_run_config_given_as_sweep_says_what_a_sweep_file_is(tmp_path):
    path = tmp_path / "run.yaml"
    path.write_text(yaml.safe_dump(TINY_BASE))
    with pytest.raises(SweepError, match=r"is a run config .* not a sweep file: a sweep file has"):
        Sweep.load(path)
    path.write_text(yaml.safe_dump({k: v for k, v in TINY_SWEEP.items() if k != "samples"}))
    with pytest.raises(SweepError, match=r"samples: missing \(a sweep file has base"):
        Sweep.load(path)


def test_seeds_depend_only_on_the_run_itself():
    coords = {"protocol.t_stop": 1.2, "geometry.asymmetry": 2e-5}
    seed = run_seed(7, coords, 0, CCW)
    assert run_seed(7, dict(reversed(coords.items())), 0, CCW) == seed
    others = {
        run_seed(8, coords, 0, CCW),
        run_seed(7, coords, 1, CCW),
        run_seed(7, coords, 0, CW),
        run_seed(7, {**coords, "protocol.t_stop": 1.6}, 0, CCW),
    }
    assert seed not in others and len(others) == 4
    # adding axis values or samples leaves the runs of existing points unchanged
    small = tiny_sweep()
    large = tiny_sweep(axes={"protocol.t_stop": [0.2, 0.6, 1.2]}, samples=4)
    assert {r.key for r in small.runs()} < {r.key for r in large.runs()}
    seeds = [r.config["noise"]["seed"] for r in large.runs()]
    assert len(set(seeds)) == len(seeds)
    assert all(0 <= s < 2**63 for s in seeds)


# ---------------------------------------------------------------------------------------
# single runs
# ---------------------------------------------------------------------------------------


def test_protocol_run_counts_the_sign_changes_of_omega():
    sweep = tiny_sweep(estimator={"kind": "protocol"}, samples=1, axes={})
    (run,) = sweep.runs()
    content = execute(run)
    res = content["result"]
    omegas = np.array(res["omegas"])
    assert omegas.size == TINY_BASE["protocol"]["cycles"] + 1
    flips = np.sign(omegas[1:]) != np.sign(omegas[:-1])
    assert res["inversions_ccw"] + res["inversions_cw"] == flips.sum()
    assert res["n_ccw"] + res["n_cw"] == TINY_BASE["protocol"]["cycles"]
    # short stops invert the rotation (paper, Figs. 4a and 5)
    assert flips.all()


def test_restart_run_is_reproducible_and_randomises_the_stop_angle():
    sweep = tiny_sweep(samples=4, axes={})
    runs = [r for r in sweep.runs() if r.direction == CW]
    results = [execute(r)["result"] for r in runs]
    again = execute(runs[0])["result"]
    assert again == results[0]
    period = np.pi / 3
    config = RotorConfig.model_validate(runs[0].config)
    warm = warm_state(config, sweep.spec.estimator, CW)
    for res in results:
        assert res["direction_before"] == CW
        # the stop is where the drawn extra steps of steady rotation take the rotor
        expected = warm.rotor.phi + warm.rotor.omega * res["extra_steps"] * config.grid.dt
        miss = (res["phi_stop"] - expected) % period
        assert min(miss, period - miss) < 0.05 * period
        # a short stop (t_stop = 0.2) inverts the rotation (paper, Figs. 4a and 5)
        assert res["committed"] and res["direction_after"] == CCW
    assert len({res["extra_steps"] for res in results}) > 1


BANK = {"kind": "bank", "warmup": 2.0}


def test_bank_stops_are_shared_across_the_noise_axis_and_drawn_per_sample():
    """Runs at the two noise levels of one sample share their stop (same angle, same
    plate torque at its end); every sample, direction and point draws its own angle."""
    sweep = tiny_sweep(
        estimator=BANK, samples=3, axes={"protocol.t_stop": [0.2, 1.2], "noise.sigma": [0, 1e-5]}
    )
    groups: dict[str, list[Run]] = {}
    for run in sweep.runs():
        groups.setdefault(stop_group(run), []).append(run)
    stops = []
    for group in groups.values():
        results = [c["result"] for c in execute_group(group)]
        assert [r.coords["noise.sigma"] for r in group] == [0, 1e-5]
        assert len({(r["extra_steps"], r["phi_stop"], r["torque_end"]) for r in results}) == 1
        stops.append(results[0]["extra_steps"])
    # 2 stop durations x 2 directions x 3 samples: 12 stops, drawn independently
    assert len(stops) == 12 and len(set(stops)) >= 8
    # the other estimators never group runs
    restart = tiny_sweep(samples=2, axes={"noise.sigma": [0, 1e-5]})
    assert len({stop_group(r) for r in restart.runs()}) == len(restart.runs())


def test_bank_releases_from_a_shared_stop_equal_separate_runs():
    sweep = tiny_sweep(estimator=BANK, samples=1, axes={"noise.sigma": [0, 1e-4]})
    group = [r for r in sweep.runs() if r.direction == CCW]
    shared = execute_group(group)
    alone = [execute_group([run])[0] for run in group]
    for one, other in zip(shared, alone, strict=True):
        assert one["key"] == other["key"]
        assert one["result"] == other["result"]
    quiet, noisy = (c["result"] for c in shared)
    # one stop: same angle, same plate torque at its end; the releases differ by the noise
    assert quiet["extra_steps"] == noisy["extra_steps"]
    assert quiet["torque_end"] == noisy["torque_end"] != 0
    assert quiet["omega_end"] != noisy["omega_end"]
    for res in (quiet, noisy):
        assert res["direction_before"] == CCW
        assert res["committed"]


def test_bank_stop_angles_are_uniform_and_independent_of_the_sweep_layout():
    """Stop seeds: one per (point without noise axes, direction, sample), unchanged when
    axis values are added, and their angles fill the period like uniform draws."""
    small = tiny_sweep(estimator=BANK, samples=50, axes={"noise.sigma": [0, 1e-5]})
    seeds = {(r.direction, r.sample): r.stop_seed for r in small.runs()}
    assert len(set(seeds.values())) == 100
    large = tiny_sweep(estimator=BANK, samples=50, axes={"noise.sigma": [0, 1e-5, 1e-4]})
    assert {(r.direction, r.sample): r.stop_seed for r in large.runs()} == seeds
    fractions = [np.random.default_rng(s).integers(0, 1000) / 1000 for s in seeds.values()]
    assert stats.kstest(fractions, "uniform").pvalue > 1e-3


def test_mcnemar_counts_only_discordant_pairs():
    same = {i: i % 2 == 0 for i in range(20)}
    assert mcnemar_p(same, same) == 1.0
    # 8 pairs inverted only at the first value, none only at the second: p = 2 / 2^8
    first = {i: True for i in range(10)}
    second = {i: i < 2 for i in range(10)}
    assert mcnemar_p(first, second) == pytest.approx(2 / 2**8)
    assert np.isnan(mcnemar_p(first, {}))


def test_bank_sweep_report(tmp_path):
    data = dict(TINY_SWEEP, estimator=BANK, samples=2, axes={"noise.sigma": [0, 1e-5]})
    path = write_sweep(tmp_path / "bank.yaml", data)
    outcome = run_sweep(path, tmp_path / "out", workers=1, progress=False)
    assert outcome.failed == []
    assert outcome.computed == outcome.total == 8
    ds = report(tmp_path / "out", echo=False)
    assert ds.attrs["estimator"] == "bank"
    assert (ds["runs_done"] == ds["runs_expected"]).all()
    assert (ds["stops_ccw"] == ds["stops_cw"]).all()
    assert ds["mcnemar_p_sigma"].dims == ("sigma", "sigma_ref")
    assert "design: paired: the values of sigma share each stop" in format_table(ds)
    # a second call finds every run done
    again = run_sweep(path, tmp_path / "out", workers=1, progress=False)
    assert (again.skipped, again.computed) == (8, 0)


def test_bank_report_pairs_the_noise_values_by_their_shared_stop(tmp_path):
    """sigma = 0: every stop inverts; sigma = 1e-5: only samples 0 and 1 of each
    direction. The 16 discordant pairs all lie on one side: McNemar p = 2 / 2^16."""
    sweep = tiny_sweep(estimator=BANK, samples=10, axes={"noise.sigma": [0, 1e-5]})
    contents = []
    for run in sweep.runs():
        flips = run.coords["noise.sigma"] == 0 or run.sample < 2
        result = {
            "direction_before": run.direction,
            "direction_after": -run.direction if flips else run.direction,
            "omega_before": 170.0 * run.direction,
            "committed": True,
            "t_commit": 0.8,
        }
        content = {"key": run.key, "direction": run.direction, "sample": run.sample}
        contents.append({**content, "result": result})
    store_runs(tmp_path, contents)
    ds = gather(sweep, tmp_path)
    p = ds["mcnemar_p_sigma"]
    assert float(p.sel(sigma=1e-5, sigma_ref=0)) == pytest.approx(2 / 2**16)
    assert float(p.sel(sigma=0, sigma_ref=1e-5)) == pytest.approx(2 / 2**16)
    assert float(p.sel(sigma=0, sigma_ref=0)) == 1.0
    assert "paired design" in p.attrs["long_name"]
    *_, first, second = format_table(ds).splitlines()
    assert first.split()[-1] == "-" and second.split()[-1] == f"{2 / 2**16:.3g}"


# ---------------------------------------------------------------------------------------
# dask execution, resume, report
# ---------------------------------------------------------------------------------------


def test_report_of_a_tiny_sweep(two_worker_sweep, capsys):
    sweep_dir, ds = two_worker_sweep
    assert list(ds.sizes) == ["t_stop"]
    assert ds["t_stop"].attrs["config_key"] == "protocol.t_stop"
    assert ds["t_stop"].values.tolist() == [0.2, 1.2]
    assert (ds["runs_done"] == ds["runs_expected"]).all()
    assert (ds["stops"] == 2 * TINY_SWEEP["samples"]).all()
    assert (ds["stops_ccw"] == ds["stops_cw"]).all()
    assert (ds["inversions"] == ds["inversions_ccw"] + ds["inversions_cw"]).all()
    assert ((ds["P_low"] <= ds["P"]) & (ds["P"] <= ds["P_high"])).all()
    assert (ds["mean_abs_omega"] > 100).all()
    # short stops always invert (paper, Fig. 5)
    assert float(ds["P"].sel(t_stop=0.2)) == 1.0
    on_disk = xr.load_dataset(sweep_dir / "report.nc", engine="h5netcdf")
    xr.testing.assert_identical(on_disk, ds)
    report(sweep_dir)
    table = capsys.readouterr().out
    assert table == format_table(ds) + "\n"
    assert len(table.splitlines()) == 1 + 3 + 1 + 2  # title, legend, header, a row per point


def store_runs(sweep_dir: Path, contents: list[dict]) -> None:
    """Store `contents` as the finished runs of `sweep_dir` (one log)."""
    (sweep_dir / RUNS_DIR).mkdir(parents=True)
    with RunLog(sweep_dir) as log:
        for content in contents:
            log.append(content)


def fake_restarts(sweep_dir: Path, sweep: Sweep, inverted: dict[int, int]) -> None:
    """Stored runs of every run of `sweep`: the first inverted[direction] samples of
    each direction inverted, the others not."""
    contents = []
    for run in sweep.runs():
        after = -run.direction if run.sample < inverted[run.direction] else run.direction
        result = {
            "direction_before": run.direction,
            "direction_after": after,
            "omega_before": 170.0 * run.direction,
            "committed": True,
            "t_commit": 0.8,
        }
        contents.append({"key": run.key, "result": result})
    store_runs(sweep_dir, contents)


def test_p_is_pooled_for_a_symmetric_rotor_and_the_chain_value_otherwise(tmp_path):
    """7/10 inversions from CCW, 0/10 from CW. Delta = 0: both directions estimate one
    probability, P = 7/20 pooled with its Wilson interval. Delta = 1e-4: the chain value
    2ab/(a+b) = 0 (the rotor ends up turning CW for good). The dataset and the table say
    which definition P holds at each point."""
    sweep = tiny_sweep(samples=10, axes={"geometry.asymmetry": [0.0, 1e-4]})
    fake_restarts(tmp_path, sweep, {CCW: 7, CW: 0})
    ds = gather(sweep, tmp_path)
    sym, asym = ds.sel(asymmetry=0.0), ds.sel(asymmetry=1e-4)
    assert float(sym["P"]) == pytest.approx(0.35) == float(sym["P_pooled"])
    assert (float(sym["P_low"]), float(sym["P_high"])) == wilson_interval(7, 20)
    assert float(asym["P"]) == 0.0 == float(asym["P_chain"])
    assert float(asym["P_pooled"]) == pytest.approx(0.35)
    assert float(asym["P_low"]) == 0.0 < float(asym["P_high"])
    assert [int(v) for v in ds["P_estimator"].values] == [POOLED, CHAIN]
    long_name = ds["P"].attrs["long_name"]
    assert "Delta = 0: pooled inversions / stops" in long_name
    assert "Delta != 0: two-state chain 2ab/(a+b)" in long_name
    assert "97.5 % Wilson bounds" in ds["P_estimator"].attrs["long_name"]
    title, *legend, header, row_pooled, row_chain = format_table(ds).splitlines()
    assert "(restart estimator" in title
    assert header.split()[1:4] == ["P", "95%", "interval"]
    assert "At Delta = 0 P pools" in " ".join(legend)
    assert all(len(line) <= 100 for line in legend)
    assert row_pooled.split()[1] == "0.350" and row_pooled.split()[4:6] == ["7/10", "0/10"]
    assert row_chain.split()[1] == "0.000" and row_chain.split()[4:6] == ["7/10", "0/10"]


def test_an_older_stored_report_is_read_with_the_current_rule(tmp_path):
    """Reports written before the rule hold the chain value at Delta = 0 too; read
    back, P there is the pooled fraction with its Wilson interval."""
    from pde_rotor.sweep.stored import load_report

    sweep = tiny_sweep(samples=10, axes={"geometry.asymmetry": [0.0, 1e-4]})
    fake_restarts(tmp_path, sweep, {CCW: 7, CW: 0})
    current = gather(sweep, tmp_path)
    old = current.drop_vars(["P_estimator", "P_pooled_low", "P_pooled_high"])
    for name in ("P", "P_low", "P_high"):
        old[name] = current[name.replace("P", "P_chain", 1)]
    old.to_netcdf(tmp_path / "old.nc", engine="h5netcdf")
    read = load_report(tmp_path / "old.nc")
    for name in ("P", "P_low", "P_high", "P_estimator"):
        np.testing.assert_array_equal(read[name].values, current[name].values)
    assert "Delta = 0: pooled" in read["P"].attrs["long_name"]


def test_protocol_report_says_p_is_inversions_over_m(tmp_path):
    sweep = tiny_sweep(samples=2, axes={}, estimator={"kind": "protocol"})
    counts = {"inversions_ccw": 2, "n_ccw": 2, "inversions_cw": 1, "n_cw": 1}
    result = {**counts, "omegas": [170.0, -170.0, 170.0, -1]}
    store_runs(tmp_path, [{"key": run.key, "result": result} for run in sweep.runs()])
    ds = gather(sweep, tmp_path)
    assert float(ds["P"]) == float(ds["P_pooled"]) == 1.0
    assert "(protocol estimator): inversions / stops" in ds["P"].attrs["long_name"]
    _, legend, _, header, row = format_table(ds).splitlines()
    assert header.split()[:3] == ["P", "95%", "interval"] and legend.startswith("P: inversions")
    assert row.split()[:4] == ["1.000", "[0.610,", "1.000]", "4/4"]
    assert row.split()[4] == "2/2"


def test_one_worker_of_two_threads_gives_the_same_dataset_as_two_workers(
    two_worker_sweep, tmp_path
):
    """Neither the number of workers nor the threads of their runs change a result."""
    _, ds2 = two_worker_sweep
    path = write_sweep(tmp_path / "tiny.yaml", TINY_SWEEP)
    outcome = run_sweep(path, tmp_path / "out", workers=1, threads=2, progress=False)
    assert outcome.computed == 12, outcome.failed
    xr.testing.assert_identical(report(tmp_path / "out", echo=False), ds2)


def test_workers_times_threads_fit_the_cores(monkeypatch):
    """By default as many workers as the cores hold; more threads than cores are refused
    in one line that says what to give."""
    from pde_rotor.sweep import execution

    monkeypatch.setattr(execution, "usable_cores", lambda: 4)
    assert local_workers(None) == 4
    assert local_workers(None, 2) == 2
    assert local_workers(3, 1) == 3
    with pytest.raises(SweepError, match=r"^--workers 3 x --threads 2 = 6 threads exceed the 4 "):
        local_workers(3, 2)
    with pytest.raises(SweepError, match=r"give at most --threads 4$"):
        local_workers(None, 5)


def test_resume_after_a_killed_sweep(two_worker_sweep, tmp_path):
    """Kill the sweep process mid-sweep; the rerun computes only the missing runs, into a
    log of its own (the killed process's log is left as it was), and its lock is taken
    over and removed at the end."""
    _, reference = two_worker_sweep
    path = write_sweep(tmp_path / "tiny.yaml", TINY_SWEEP)
    out = tmp_path / "out"
    script = textwrap.dedent(
        f"""
        from pde_rotor.sweep import run_sweep
        run_sweep({str(path)!r}, {str(out)!r}, workers=1, progress=False)
        """
    )
    proc = subprocess.Popen([sys.executable, "-c", script], start_new_session=True)
    runs_dir = out / RUNS_DIR
    deadline = time.monotonic() + 120
    try:
        while time.monotonic() < deadline:
            if len(read_runs(out)) >= 3 or proc.poll() is not None:
                break
            time.sleep(0.05)
    finally:
        os.killpg(proc.pid, signal.SIGKILL)
        proc.wait()
    kept = len(read_runs(out))
    assert 3 <= kept < 12, "the sweep was not killed mid-way"
    before = {p.name: (p.stat().st_mtime_ns, p.read_bytes()) for p in runs_dir.glob("*.jsonl")}
    assert len(before) == 1  # the killed process's log

    sweep = Sweep.load(path)
    outcome = run_sweep(sweep, out, workers=1, progress=False)
    assert outcome.skipped == kept
    assert outcome.computed == 12 - kept
    for name, (mtime, content) in before.items():
        p = runs_dir / name
        assert p.stat().st_mtime_ns == mtime and p.read_bytes() == content
    assert len(list(runs_dir.glob("*.jsonl"))) == 2
    assert set(read_runs(out)) == {r.key for r in sweep.runs()}
    assert not (out / ".lock").exists()
    xr.testing.assert_identical(report(out, echo=False), reference)
    # a third call finds nothing to do
    assert run_sweep(sweep, out, progress=False).computed == 0


def test_a_copied_store_resumes_elsewhere_with_nothing_recomputed(
    two_worker_sweep, tmp_path, monkeypatch
):
    """The sweep directory moves as a clone moves it (copied to another path, new file
    times): resuming there finds every run and gives the same report."""
    from pde_rotor.sweep import execution

    sweep_dir, reference = two_worker_sweep
    moved = tmp_path / "clone" / "data" / "sweeps" / "tiny"
    shutil.copytree(sweep_dir, moved)
    (moved / "report.nc").unlink()
    started: list[object] = []
    monkeypatch.setattr(execution, "_start_client", lambda *args: started.append(args))
    outcome = run_sweep(moved / "sweep.yaml", moved, progress=False)
    assert (outcome.skipped, outcome.computed, started) == (12, 0, [])
    xr.testing.assert_identical(report(moved, echo=False), reference)
    keys = {r.key for r in Sweep.load(moved).runs()}
    assert keys == set(read_runs(sweep_dir))


def test_unreadable_legacy_run_files_are_recomputed_and_foreign_files_ignored(tmp_path, caplog):
    """A legacy store (runs/<key>.json) whose file is truncated, beside a file that is
    no run file: both are reported, neither counts, the run is recomputed."""
    sweep = tiny_sweep(samples=1, axes={})
    out = tmp_path / "out"
    (out / RUNS_DIR).mkdir(parents=True)
    runs: list[Run] = sweep.runs()
    (out / RUNS_DIR / f"{runs[0].key}.json").write_text('{"key": "trunc', encoding="utf-8")
    (out / RUNS_DIR / "unrelated.json").write_text("{}", encoding="utf-8")
    assert read_runs(out) == {}
    assert [r.getMessage().split(":")[0] for r in caplog.records] == [
        str(out / RUNS_DIR / f"{runs[0].key}.json"),
        str(out / RUNS_DIR / "unrelated.json"),
    ]
    outcome = run_sweep(sweep, out, workers=1, progress=False)
    assert outcome.computed == 2
    ds = gather(sweep, out)
    assert int(ds["runs_done"]) == 2 and int(ds["stops"]) == 2


def test_sweep_config_validates_like_a_run_config():
    sweep = tiny_sweep()
    for run in sweep.runs():
        cfg = RotorConfig.model_validate(run.config)
        assert cfg.noise.seed == run.config["noise"]["seed"]


SWEEPS = Path(__file__).resolve().parents[2] / "configs" / "sweeps"
FIGURES = ("fig5", "fig7a", "fig7b", "fig7c", "fig8", "fig9")


@pytest.mark.parametrize("name", FIGURES)
def test_figure_sweeps_have_a_quick_coarse_and_a_full_paper_variant(name):
    full = Sweep.load(SWEEPS / f"{name}.yaml")
    quick = Sweep.load(SWEEPS / f"{name}_quick.yaml")
    paper = RotorConfig()
    assert full.base["grid"]["dx"] == paper.grid.dx and full.base["grid"]["dt"] == paper.grid.dt
    assert quick.base["grid"]["dx"] > paper.grid.dx
    assert list(full.axes) == list(quick.axes)
    for key in full.axes:  # the quick grid is coarser
        assert len(quick.axes[key]) <= len(full.axes[key])
    assert len(quick.runs()) < len(full.runs())
    assert full.spec.estimator.kind == quick.spec.estimator.kind == "restart"
    # the paper counts M = 100 stops per point; the full variants at least as many
    assert 2 * full.spec.samples >= paper.protocol.cycles


def test_cli_dry_run_counts_runs_and_estimates_the_cost(two_worker_sweep, tmp_path):
    """--dry-run computes nothing and creates nothing; it counts what a rerun would do."""
    from typer.testing import CliRunner

    from pde_rotor.cli.main import app

    sweep_dir, _ = two_worker_sweep
    path = write_sweep(tmp_path / "tiny.yaml", TINY_SWEEP)
    runner = CliRunner()
    args = ["sweep", str(path), "--dry-run", "--workers", "2", "-o"]
    fresh = runner.invoke(app, [*args, str(tmp_path / "new"), "--set", "samples=2"])
    assert fresh.exit_code == 0, fresh.output
    assert "2 points x 4 runs = 8 runs, 0 already done" in fresh.stdout
    assert "to compute: 8 runs on a LocalCluster of 2 worker processes, 1 thread each" in (
        fresh.stdout
    )
    assert "estimated cost: about " in fresh.stdout and "estimate" in fresh.stdout
    assert not (tmp_path / "new").exists()
    threaded = runner.invoke(
        app, ["sweep", str(path), "--dry-run", "--threads", "2", "-o", str(tmp_path / "new")]
    )
    assert threaded.exit_code == 0, threaded.output
    cores = usable_cores()
    assert f"LocalCluster of {cores // 2} worker process" in threaded.stdout
    assert f"2 threads each ({cores // 2 * 2} of the {cores} usable cores)" in threaded.stdout
    crowded = runner.invoke(app, [*args, str(tmp_path / "new"), "--threads", str(cores)])
    assert crowded.exit_code == 2
    assert f"--workers 2 x --threads {cores} = {2 * cores} threads exceed" in crowded.output
    grown = runner.invoke(app, [*args, str(sweep_dir), "--set", "samples=4"])
    assert grown.exit_code == 0, grown.output
    assert "16 runs, 12 already done" in grown.stdout and "to compute: 4 runs" in grown.stdout


def test_cli_sweep_and_report(two_worker_sweep, tmp_path):
    from typer.testing import CliRunner

    from pde_rotor.cli.main import app
    from pde_rotor.statistics.crossing import report_crossings

    sweep_dir, ds = two_worker_sweep
    runner = CliRunner()
    # a finished sweep: nothing to compute (no cluster is started), the report is printed
    result = runner.invoke(app, ["sweep", str(sweep_dir / "sweep.yaml"), "-o", str(sweep_dir)])
    assert result.exit_code == 0, result.output
    assert "12 already done, 0 computed, 0 failed" in result.output
    assert format_table(ds) in result.output
    target = tmp_path / "copy.nc"
    result = runner.invoke(app, ["report", str(sweep_dir), "--out", str(target)])
    assert result.exit_code == 0, result.output
    xr.testing.assert_identical(xr.load_dataset(target, engine="h5netcdf"), ds)
    (_, found), *_ = report_crossings(ds, 0.75)
    result = runner.invoke(app, ["report", str(sweep_dir), "-o", str(target), "--crossing", "0.75"])
    assert result.exit_code == 0, result.output
    assert f"crossing: {found.describe()}" in result.output
    bad = write_sweep(tmp_path / "bad.yaml", {**TINY_SWEEP, "axes": {"protocol.t_stopp": [1]}})
    result = runner.invoke(app, ["sweep", str(bad), "-o", str(tmp_path / "never")])
    assert result.exit_code == 2
    assert "error: sweep point protocol.t_stopp = 1: unknown key" in result.output
    assert not (tmp_path / "never").exists()
    result = runner.invoke(app, ["report", str(tmp_path)])
    assert result.exit_code == 2 and "not a sweep directory" in result.output


def test_a_subset_run_keeps_the_directory_design(two_worker_sweep, tmp_path, monkeypatch):
    """A run of a subset (``--set axes.KEY=[...]``) prints the subset's table but leaves
    the directory's sweep.yaml, and so its report.nc, the whole design; a sweep with runs
    outside the recorded design replaces it; ``pde-rotor report FILE`` reports the file's
    whole design from data/sweeps/<stem>."""
    from typer.testing import CliRunner

    from pde_rotor.cli.main import app
    from pde_rotor.sweep.store import holds, prepare

    sweep_dir, ds = two_worker_sweep
    monkeypatch.chdir(tmp_path)
    store = tmp_path / "data" / "sweeps" / "tiny"
    shutil.copytree(sweep_dir, store)
    recorded = (store / "sweep.yaml").read_text()
    path = write_sweep(tmp_path / "tiny.yaml", TINY_SWEEP)
    runner = CliRunner()
    subset = ["sweep", str(path), "-o", str(store), "--set", "axes.protocol.t_stop=[1.2]"]
    result = runner.invoke(app, [*subset, "--set", "samples=2"])
    assert result.exit_code == 0, result.output
    assert "4 already done, 0 computed" in result.output
    asked = gather(tiny_sweep(axes={"protocol.t_stop": [1.2]}, samples=2), store)
    assert asked.sizes["t_stop"] == 1 and format_table(asked) in result.output
    assert (store / "sweep.yaml").read_text() == recorded
    xr.testing.assert_identical(xr.load_dataset(store / "report.nc", engine="h5netcdf"), ds)
    assert holds(tiny_sweep(), tiny_sweep(samples=1))
    assert not holds(tiny_sweep(), tiny_sweep(seed=8))
    assert not holds(tiny_sweep(), tiny_sweep(axes={"protocol.t_stop": [0.2, 1.3]}))
    prepare(tiny_sweep(axes={"protocol.t_stop": [0.2, 2.2]}), store)
    grown = runner.invoke(app, ["report", str(store), "-o", "grown.nc"])
    assert grown.exit_code == 0, grown.output
    assert list(xr.load_dataset("grown.nc", engine="h5netcdf").t_stop) == [0.2, 2.2]
    whole = runner.invoke(app, ["report", str(path), "-o", "whole.nc"])
    assert whole.exit_code == 0, whole.output
    xr.testing.assert_identical(xr.load_dataset("whole.nc", engine="h5netcdf"), ds)
    missing = runner.invoke(app, ["report", str(write_sweep(tmp_path / "other.yaml", TINY_SWEEP))])
    assert missing.exit_code == 2 and "data/sweeps/other holds no sweep.yaml" in missing.output


@pytest.mark.parametrize("how", ["SIGTERM to the process", "Ctrl-C to the process group"])
def test_cli_sweep_stops_cleanly_on_sigterm_and_ctrl_c(tmp_path, how):
    """SIGTERM (a batch system ending the job) or Ctrl-C (SIGINT to the terminal's whole
    process group, dask's worker processes included) exits with 130, keeps finished runs,
    leaves no worker process behind and says in one line how many runs are kept: no
    worker prints a traceback. 48 runs, so that the sweep cannot finish in the moment
    between the test seeing two stored runs and its signal arriving (under load, results
    reach the main process in bursts). The child starts with SIGINT at its default: a
    test session started in the background of a non-interactive shell inherits SIGINT
    ignored, and so would the sweep, which then ran to its end (exit 0)."""
    import psutil

    path = write_sweep(tmp_path / "tiny.yaml", {**TINY_SWEEP, "samples": 12})
    out = tmp_path / "out"
    command = [sys.executable, "-c", "from pde_rotor.cli.main import app; app()"]
    args = ["sweep", str(path), "-o", str(out), "--workers", "1", "-q"]
    proc = subprocess.Popen(
        [*command, *args],
        start_new_session=True,
        stderr=subprocess.PIPE,
        text=True,
        # a terminal's foreground job: SIGINT at its default, whatever this process inherited
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
    )
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline and proc.poll() is None:
        if len(read_runs(out)) >= 2:
            break
        time.sleep(0.05)
    children = psutil.Process(proc.pid).children(recursive=True)
    assert children, "the LocalCluster started no worker process"
    if how.startswith("SIGTERM"):
        proc.send_signal(signal.SIGTERM)
    else:
        os.killpg(proc.pid, signal.SIGINT)
    try:
        _, stderr = proc.communicate(timeout=60)
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
    assert proc.returncode == 130
    _, alive = psutil.wait_procs(children, timeout=30)
    assert not alive
    kept = len(read_runs(out))
    total = len(Sweep.load(path).runs())
    assert 2 <= kept < total
    assert "Traceback" not in stderr
    lines = stderr.splitlines()
    assert len(lines) == 2, stderr
    assert lines[0].startswith("pde-rotor: sweep ")
    assert lines[1] == (
        f"interrupted: {kept} of {total} runs are kept in {out}; rerun the same command to resume"
    )


def test_runs_alternate_directions_within_a_spin_up_group():
    """A sweep stopped part way has both directions at the points it reached."""
    from pde_rotor.sweep.execution import in_order

    sweep = Sweep.load(SWEEPS / "science_grid_symmetric.yaml")
    runs = sweep.runs()
    ordered = in_order(list(reversed(runs)))
    assert sorted(r.key for r in ordered) == sorted(r.key for r in runs)
    first = ordered[: 2 * sweep.spec.samples]  # one point, both directions
    assert len({r.point for r in first}) == 1
    assert [r.direction for r in first[:4]] == [min(CW, CCW), max(CW, CCW)] * 2
    assert [r.sample for r in first[:4]] == [0, 0, 1, 1]


@pytest.mark.parametrize("path", sorted(SWEEPS.glob("science_*.yaml")), ids=lambda p: p.stem)
def test_science_sweeps_run_the_default_scheme_on_paper_parameters(path):
    """The science sweeps: bank estimator, the default scheme, delta = 0.025, dt = 1e-4."""
    sweep = Sweep.load(path)
    for run in sweep.runs()[:: sweep.spec.samples]:
        cfg = RotorConfig.model_validate(run.config)
        assert cfg.numerics.scheme == RotorConfig().numerics.scheme
        assert (cfg.geometry.smoothing, cfg.grid.dt) == (0.025, 1e-4)
    assert sweep.spec.estimator.kind == "bank"
    assert 2 * sweep.spec.samples >= 100


def test_report_label_counts_stops_of_measured_points_only():
    """A report of a sweep in progress: the label gives the stops of the measured points
    and how many of the design's points are measured (it said "0-200 stops")."""
    from pde_rotor.sweep.stored import SweepData

    ds = xr.Dataset(
        {"stops": ("t_stop", [200, 200, 0])},
        coords={"t_stop": [0.5, 1.0, 1.5]},
        attrs={"sweep": "s", "estimator": "restart", "grid_dx": 0.025, "grid_dt": 1e-4},
    )
    label = SweepData(ds, Path("s.nc"), computed=False).label()
    assert "200 stops per point (2 of 3 points measured);" in label
    done = SweepData(ds.isel(t_stop=[0, 1]), Path("s.nc"), computed=False).label()
    assert "200 stops per point;" in done


def test_report_records_the_grid_its_runs_used(tmp_path):
    """A report's grid_dx / grid_dt are the runs' own: the base config's, an axis's single
    value, or NaN (the header says "swept") where the axis has several; never the base
    value that an axis overrides."""
    base = gather(tiny_sweep(), tmp_path)
    assert (base.attrs["grid_dx"], base.attrs["grid_dt"]) == (0.05, 4e-4)
    fine = {**TINY_SWEEP["base"], "grid": {**TINY_BASE["grid"], "dt": 2e-4}}
    one = gather(tiny_sweep(base=fine, axes={"grid.dx": [1 / 30]}), tmp_path)
    assert one.attrs["grid_dx"] == pytest.approx(1 / 30)
    assert "dx = 0.0333333, dt = 0.0002" in format_table(one).splitlines()[0]
    many = gather(tiny_sweep(base=fine, axes={"grid.dx": [0.05, 1 / 30]}), tmp_path)
    assert math.isnan(many.attrs["grid_dx"])
    assert "dx = swept" in format_table(many).splitlines()[0]
