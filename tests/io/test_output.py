"""Run directory and atomic writing: a file with its final name is always complete."""

from __future__ import annotations

import csv

import numpy as np
import pytest
import xarray as xr

from pde_rotor.io.output import (
    AppendOnlyCSV,
    OutputError,
    RunDirectory,
    atomic_path,
    part_path,
    write_netcdf_atomic,
    write_text_atomic,
)


def test_atomic_text_write_replaces_whole_file(tmp_path):
    path = tmp_path / "a.txt"
    write_text_atomic(path, "old")
    write_text_atomic(path, "new content")
    assert path.read_text() == "new content"
    assert not part_path(path).exists()


def test_failed_write_leaves_no_file_and_no_part(tmp_path):
    path = tmp_path / "a.nc"
    with pytest.raises(RuntimeError), atomic_path(path) as tmp:
        tmp.write_bytes(b"half")
        raise RuntimeError("crash in the middle")
    assert not path.exists()
    assert not part_path(path).exists()


def test_failed_rewrite_keeps_previous_complete_file(tmp_path):
    path = tmp_path / "a.txt"
    write_text_atomic(path, "complete")
    with pytest.raises(KeyboardInterrupt), atomic_path(path) as tmp:
        tmp.write_text("partial")
        raise KeyboardInterrupt
    assert path.read_text() == "complete"


def test_file_only_appears_when_complete(tmp_path):
    path = tmp_path / "a.txt"
    with atomic_path(path) as tmp:
        tmp.write_text("x")
        assert tmp.parent == path.parent  # same directory: os.replace is atomic
        assert not path.exists()
    assert path.exists()


def test_netcdf_round_trip(tmp_path):
    ds = xr.Dataset({"omega": ("time", np.arange(5.0), {"units": "rad"})}, attrs={"h": "x"})
    path = tmp_path / "ts.nc"
    write_netcdf_atomic(ds, path)
    with xr.open_dataset(path, engine="h5netcdf") as back:
        xr.testing.assert_identical(back.load(), ds)


def test_csv_rows_are_on_disk_before_close(tmp_path):
    path = tmp_path / "events.csv"
    table = AppendOnlyCSV(path, ["cycle", "inverted", "x"])
    table.append({"cycle": 1, "inverted": True, "x": 0.1})
    table.append({"cycle": 2, "inverted": False, "x": float("nan")})
    # read through a separate file handle while the writer is still open
    with path.open() as fh:
        rows = list(csv.DictReader(fh))
    assert rows == [
        {"cycle": "1", "inverted": "true", "x": "0.1"},
        {"cycle": "2", "inverted": "false", "x": "nan"},
    ]
    table.close()
    table.close()
    with pytest.raises(ValueError, match="closed"):
        table.append({"cycle": 3, "inverted": True, "x": 0.0})


def test_run_directory_refuses_an_earlier_run(tmp_path):
    run = RunDirectory.create(tmp_path / "run")
    run.config.write_text("x")
    with pytest.raises(OutputError, match="already holds a run"):
        RunDirectory.create(tmp_path / "run")
    part_path(run.movie).write_text("x")
    again = RunDirectory.create(tmp_path / "run", overwrite=True)
    assert not again.config.exists()
    assert not part_path(again.movie).exists()


def test_run_directory_keeps_notes_beside_an_earlier_run(tmp_path):
    RunDirectory.create(tmp_path)
    (tmp_path / "config.yaml").write_text("earlier run")
    (tmp_path / "notes.txt").write_text("mine")
    RunDirectory.create(tmp_path, overwrite=True)
    assert (tmp_path / "notes.txt").read_text() == "mine"
    assert not (tmp_path / "config.yaml").exists()


def test_run_directory_refuses_somebody_elses_directory(tmp_path):
    (tmp_path / "x.txt").write_text("mine")
    for overwrite in (False, True):
        with pytest.raises(OutputError, match=r"holds x\.txt and no run"):
            RunDirectory.create(tmp_path, overwrite=overwrite)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["x.txt"]


def test_run_directory_on_a_file_is_an_error(tmp_path):
    target = tmp_path / "file"
    target.write_text("x")
    with pytest.raises(OutputError, match="is a file"):
        RunDirectory.create(target)


def test_default_path_names_the_config(tmp_path):
    path = RunDirectory.default_path("configs/quickstart.yaml", root=tmp_path)
    assert path.parent == tmp_path
    assert path.name.startswith("quickstart-")
    rerun = RunDirectory.default_path(tmp_path / "myrun" / "config.yaml")
    assert rerun.name.startswith("myrun-")


def test_log_handler_writes_and_detaches(tmp_path):
    import logging

    from pde_rotor.io.output import detach_log

    run = RunDirectory.create(tmp_path / "run")
    level = logging.getLogger("pde_rotor").level
    handler = run.attach_log()
    logging.getLogger("pde_rotor.test").info("hello %d", 42)
    detach_log(handler)
    logging.getLogger("pde_rotor.test").info("after detach")
    text = run.log.read_text()
    assert "hello 42" in text
    assert "after detach" not in text
    assert logging.getLogger("pde_rotor").level == level
