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


FULL_DISK_SCRIPT = """
import resource, signal, sys
from pathlib import Path
import numpy as np, xarray as xr
from pde_rotor.io.output import AppendOnlyCSV, write_netcdf_atomic

signal.signal(signal.SIGXFSZ, signal.SIG_IGN)  # EFBIG instead of a signal
small, path = xr.Dataset({"a": ("t", np.arange(10.0))}), Path(sys.argv[1])
write_netcdf_atomic(small, path)  # a complete earlier copy
table = AppendOnlyCSV(path.with_name("rows.csv"), ["i", "x"])
resource.setrlimit(resource.RLIMIT_FSIZE, (20_000, resource.RLIM_INFINITY))
large = xr.Dataset({k: ("t", np.arange(5000.0)) for k in "abcd"})
for attempt in range(3):
    try:
        write_netcdf_atomic(large, path)
    except OSError as err:
        print("failed", err.errno, err.filename)
try:
    for i in range(10_000):
        table.append({"i": i, "x": 0.5 * i})
except OSError as err:
    print("row failed", i)
table.close()
"""


def test_writes_on_a_full_disk_fail_cleanly_and_keep_the_complete_files(tmp_path):
    """A disk that fills up: HDF5 cannot close a file whose write failed, and writing the
    same file again then crashed the process (segmentation fault). Here the file-size
    limit stands in for the full disk (EFBIG instead of ENOSPC, the same failing write):
    every write raises OSError naming its file, the earlier complete copy stays, and
    the CSV ends with its last whole row."""
    import subprocess
    import sys

    path = tmp_path / "timeseries.nc"
    done = subprocess.run(
        [sys.executable, "-c", FULL_DISK_SCRIPT, str(path)],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert done.returncode == 0, done.stderr[-2000:]
    assert done.stdout.count(f"failed 27 {path}") == 3, done.stdout
    assert done.stderr == ""
    with xr.open_dataset(path, engine="h5netcdf") as ds:
        assert ds["a"].values.tolist() == list(range(10))
    assert not part_path(path).exists()
    rows = list(csv.DictReader((tmp_path / "rows.csv").open(newline="")))
    last = int(done.stdout.split("row failed ")[1])
    assert len(rows) == last and rows[-1] == {"i": str(last - 1), "x": repr(0.5 * (last - 1))}


def test_a_log_that_cannot_be_written_goes_quiet(tmp_path, capsys):
    """logging prints a traceback to stderr for every record a full disk refuses; the
    run's log stops instead, keeping what it wrote, so that the one error line of the
    run is all a user sees."""
    import errno
    import logging

    from pde_rotor.io.output import detach_log

    run = RunDirectory.create(tmp_path / "run")
    handler = run.attach_log()
    logger = logging.getLogger("pde_rotor")
    logger.info("before")

    class FullDisk:
        def write(self, text: str) -> None:
            raise OSError(errno.ENOSPC, "No space left on device")

        def flush(self) -> None:
            raise OSError(errno.ENOSPC, "No space left on device")

        def close(self) -> None:
            self.flush()

    handler.stream = FullDisk()  # type: ignore[assignment]
    logger.info("lost")
    logger.error("lost too")
    detach_log(handler)
    assert capsys.readouterr().err == ""
    assert "before" in run.log.read_text() and "lost" not in run.log.read_text()
