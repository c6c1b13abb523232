"""Tests of pde_rotor.sweep.store: append-only run logs, one-pass reading, compaction,
the lock of a sweep directory, legacy stores and failing writes.

Nothing here computes a run: records are made up, and run_sweep's computation is
replaced by one that stores a made-up record per run.
"""

from __future__ import annotations

import errno
import json
import logging
import os
import re
import socket
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest
import xarray as xr
from typer.testing import CliRunner

from pde_rotor.cli.main import app
from pde_rotor.statistics.proportions import CCW, CW
from pde_rotor.sweep import (
    COMPACT_FILE,
    RUNS_DIR,
    RunLog,
    StoreBusyError,
    StoreError,
    Sweep,
    compact,
    execution,
    gather,
    lock,
    read_runs,
    run_sweep,
)
from pde_rotor.sweep.store import LOCK_FILE, prepare
from tests.sweep.test_sweep import TINY_SWEEP, fake_restarts, tiny_sweep, write_sweep


def record(key: str, result: object = 1.0, **extra: object) -> dict:
    return {"key": key, "result": {"value": result}, **extra}


def write_log(sweep_dir: Path, name: str, text: str) -> Path:
    """A log file written by hand (torn, corrupt or duplicate lines)."""
    path = sweep_dir / RUNS_DIR / name
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text, encoding="utf-8")
    return path


def line(content: dict) -> str:
    return json.dumps(content, separators=(",", ":")) + "\n"


def files(sweep_dir: Path) -> dict[str, bytes]:
    """Every file under `sweep_dir` with its bytes."""
    return {
        str(p.relative_to(sweep_dir)): p.read_bytes() for p in sweep_dir.rglob("*") if p.is_file()
    }


def fake_compute(sweep, groups, outcome, log, *args) -> None:
    """run_sweep's computation, replaced: one made-up record per run."""
    for group in groups:
        for run in group:
            log.append(record(run.key, run.sample))
        outcome.computed += len(group)


def test_appended_runs_read_back_as_they_were_written(tmp_path):
    """One compact JSON line per record, in a log named after the writing process that
    exists only from its first record; NaN and nested values survive."""
    (tmp_path / RUNS_DIR).mkdir()
    contents = [record("a", float("nan")), record("b", [1, -2.5]), record("c", {"x": True})]
    with RunLog(tmp_path) as log:
        assert not log.path.exists()
        for content in contents:
            log.append(content)
    host = re.sub(r"[^A-Za-z0-9.-]", "_", socket.gethostname())
    assert re.fullmatch(rf"{re.escape(host)}-{os.getpid()}-[0-9a-f]{{8}}\.jsonl", log.path.name)
    assert log.path.read_text(encoding="utf-8").splitlines() == [
        json.dumps(c, separators=(",", ":")) for c in contents
    ]
    stored = read_runs(tmp_path)
    assert list(stored) == ["a", "b", "c"]
    assert json.dumps(stored) == json.dumps({c["key"]: c for c in contents})
    assert read_runs(tmp_path / "missing") == {}


def test_a_torn_last_line_is_ignored_reported_once_and_recomputed(tmp_path, caplog, monkeypatch):
    """A process killed mid-write leaves a last line without its newline; a corrupt line
    elsewhere is skipped too. One warning line names the file and its lines; the runs
    count as not finished, so run_sweep computes them again."""
    sweep = tiny_sweep(samples=1, axes={})
    prepare(sweep, tmp_path)
    first, second = sweep.runs()
    torn = write_log(
        tmp_path, "a.jsonl", line(record(first.key)) + "{not json\n" + line(record(second.key))[:20]
    )
    caplog.set_level(logging.WARNING)
    assert list(read_runs(tmp_path)) == [first.key]
    assert [r.getMessage() for r in caplog.records] == [
        f"{torn}: lines 2, 3: not a complete run record (torn or corrupt), ignored: a run "
        "stored only there is recomputed"
    ]
    monkeypatch.setattr(execution, "_compute", fake_compute)
    outcome = run_sweep(sweep, tmp_path, progress=False)
    assert (outcome.skipped, outcome.computed) == (1, 1)
    assert set(read_runs(tmp_path)) == {first.key, second.key}


def test_a_run_stored_twice_counts_once(tmp_path, caplog):
    """Copies of one record (a log merged twice, a compaction cut short) count once
    without a warning; records that differ outside the result (another wall time) too,
    the same one kept whichever file is read first; different results are warned of
    in one line naming both places, and one of them is kept, the same every time."""
    caplog.set_level(logging.WARNING)
    write_log(tmp_path, "a.jsonl", line(record("k")) + line(record("t", wall_time=2.0)))
    write_log(tmp_path, "b.jsonl", line(record("k")) + line(record("t", wall_time=1.0)))
    stored = read_runs(tmp_path)
    assert len(stored) == 2 and stored["t"]["wall_time"] == 1.0
    assert caplog.records == []
    (tmp_path / RUNS_DIR / "a.jsonl").rename(tmp_path / RUNS_DIR / "c.jsonl")
    assert read_runs(tmp_path)["t"]["wall_time"] == 1.0

    write_log(tmp_path, "d.jsonl", line(record("k", 2.0)))
    kept = read_runs(tmp_path)["k"]
    (message,) = [r.getMessage() for r in caplog.records]
    assert message.startswith("run k is stored twice with different results (")
    assert "b.jsonl:1" in message and "d.jsonl:1" in message and "\n" not in message
    (tmp_path / RUNS_DIR / "d.jsonl").rename(tmp_path / RUNS_DIR / "0.jsonl")
    assert read_runs(tmp_path)["k"] == kept


def mixed_store(sweep_dir: Path) -> Sweep:
    """A restart sweep's store as a merge of clones leaves it: half of the runs as
    legacy files, the other half in two logs, one run in both, plus a torn line."""
    sweep = tiny_sweep(samples=5, axes={"geometry.asymmetry": [0.0, 1e-4]})
    prepare(sweep, sweep_dir)
    fake_restarts(sweep_dir.parent / "made", sweep, {CCW: 3, CW: 1})
    contents = list(read_runs(sweep_dir.parent / "made").values())
    half = len(contents) // 2
    for content in contents[:half]:  # as write_run of earlier versions wrote them
        path = sweep_dir / RUNS_DIR / f"{content['key']}.json"
        path.write_text(line(content), encoding="utf-8")
    write_log(sweep_dir, "h1-1-00000000.jsonl", "".join(map(line, contents[half - 1 : -3])))
    write_log(sweep_dir, "h2-2-00000000.jsonl", "".join(map(line, contents[-3:])) + '{"key"')
    return sweep


def test_compaction_is_lossless_and_idempotent(tmp_path, caplog):
    """Legacy files and logs merge into one runs.jsonl sorted by key, each run once; the
    merged files are removed, nothing temporary is left, the report is unchanged.
    Compacting again leaves the file untouched."""
    sweep_dir = tmp_path / "s"
    sweep = mixed_store(sweep_dir)
    before, report = read_runs(sweep_dir), gather(sweep, sweep_dir)
    assert len(before) == len(sweep.runs())

    done = compact(sweep_dir)
    assert (done.runs, done.merged, done.dropped) == (len(before), len(before) // 2 + 2, 1)
    assert sorted(p.name for p in (sweep_dir / RUNS_DIR).iterdir()) == [COMPACT_FILE]
    assert not (sweep_dir / LOCK_FILE).exists()
    text = (sweep_dir / RUNS_DIR / COMPACT_FILE).read_text(encoding="utf-8")
    assert text == "".join(line(before[key]) for key in sorted(before))
    caplog.clear()
    assert read_runs(sweep_dir) == before and caplog.records == []
    xr.testing.assert_identical(gather(sweep, sweep_dir), report)

    stat = (sweep_dir / RUNS_DIR / COMPACT_FILE).stat()
    again = compact(sweep_dir)
    assert (again.runs, again.merged, again.dropped) == (len(before), 1, 0)
    assert (sweep_dir / RUNS_DIR / COMPACT_FILE).stat().st_mtime_ns == stat.st_mtime_ns
    assert (sweep_dir / RUNS_DIR / COMPACT_FILE).read_text(encoding="utf-8") == text


def test_a_legacy_store_is_read_and_migrated_by_the_compact_command(tmp_path, monkeypatch):
    """A store of one file per run (an old clone) is read as it is, resumes with nothing
    recomputed, and `pde-rotor compact` (given the directory or the sweep file) converts
    it into runs.jsonl with the same report."""
    sweep_dir = tmp_path / "data" / "sweeps" / "tiny"
    sweep = tiny_sweep(samples=2, axes={"geometry.asymmetry": [0.0, 1e-4]})
    prepare(sweep, sweep_dir)
    fake_restarts(tmp_path / "made", sweep, {CCW: 1, CW: 0})
    for key, content in read_runs(tmp_path / "made").items():
        (sweep_dir / RUNS_DIR / f"{key}.json").write_text(line(content), encoding="utf-8")
    report = gather(sweep, sweep_dir)
    assert set(read_runs(sweep_dir)) == {run.key for run in sweep.runs()}

    runner = CliRunner()
    result = runner.invoke(app, ["compact", str(sweep_dir)])
    assert result.exit_code == 0, result.output
    n = len(sweep.runs())
    assert result.output == (
        f"compacted {sweep_dir}: {n} runs from {n} files into "
        f"{sweep_dir / RUNS_DIR / COMPACT_FILE}\n"
    )
    assert [p.name for p in (sweep_dir / RUNS_DIR).iterdir()] == [COMPACT_FILE]
    xr.testing.assert_identical(gather(sweep, sweep_dir), report)
    spec = write_sweep(tmp_path / "tiny.yaml", {**TINY_SWEEP, "samples": 2})
    monkeypatch.chdir(tmp_path)  # the sweep file's store: data/sweeps/tiny under it
    result = runner.invoke(app, ["compact", str(spec)])
    assert result.exit_code == 0 and f"{n} runs from 1 file " in result.output
    missing = runner.invoke(app, ["compact", str(tmp_path / "nowhere")])
    assert missing.exit_code == 2 and missing.output.count("error:") == 1


def test_a_store_compacted_while_it_is_read_is_read_whole(tmp_path, monkeypatch):
    """A reader that lists the logs just before a compaction merges and removes them
    lists the files again and finds every run, once."""
    write_log(tmp_path, "a.jsonl", line(record("a")))
    write_log(tmp_path, "b.jsonl", line(record("b")))
    read_bytes = Path.read_bytes
    compacted = []

    def compact_first(path: Path) -> bytes:
        if not compacted:
            compacted.append(path)
            monkeypatch.setattr(Path, "read_bytes", read_bytes)  # the compaction reads
            compact(tmp_path)
        return read_bytes(path)

    monkeypatch.setattr(Path, "read_bytes", compact_first)
    assert sorted(read_runs(tmp_path)) == ["a", "b"]
    assert compacted == [tmp_path / RUNS_DIR / "a.jsonl"]
    assert [p.name for p in (tmp_path / RUNS_DIR).iterdir()] == [COMPACT_FILE]


def test_two_processes_appending_at_once_lose_nothing(tmp_path):
    """Two writers in two processes append to the same store at the same time, each to
    its own log: every record is read back, once, with no torn line."""
    (tmp_path / RUNS_DIR).mkdir()
    script = textwrap.dedent(
        """
        import sys
        from pde_rotor.sweep import RunLog
        name, directory = sys.argv[1:]
        sys.stdin.readline()  # start together
        with RunLog(directory) as log:
            for i in range(300):
                log.append({"key": f"{name}{i}", "result": {"i": i}, "shared": "x" * 200})
        """
    )
    procs = [
        subprocess.Popen(
            [sys.executable, "-c", script, name, str(tmp_path)], stdin=subprocess.PIPE, text=True
        )
        for name in ("a", "b")
    ]
    for proc in procs:
        proc.stdin.write("go\n")
        proc.stdin.close()
    assert [proc.wait(timeout=60) for proc in procs] == [0, 0]
    stored = read_runs(tmp_path)
    assert set(stored) == {f"{name}{i}" for name in "ab" for i in range(300)}
    assert len(list((tmp_path / RUNS_DIR).glob("*.jsonl"))) == 2


def test_a_second_sweep_on_a_busy_directory_is_refused_in_one_line(tmp_path, monkeypatch):
    """While another process holds the lock of a sweep directory, run_sweep, `pde-rotor
    sweep` and compaction are refused with one line naming the directory and the holder,
    and leave the directory as it was; once the holder is done, the sweep runs."""
    sweep_dir = tmp_path / "out"
    path = write_sweep(tmp_path / "tiny.yaml", {**TINY_SWEEP, "samples": 1})
    sweep = Sweep.load(path)
    prepare(sweep, sweep_dir)
    holder = subprocess.Popen(
        [
            sys.executable,
            "-c",
            "import sys; from pde_rotor.sweep import lock\n"
            f"with lock({str(sweep_dir)!r}):\n"
            "    print('locked', flush=True); sys.stdin.readline()",
        ],
        stdin=subprocess.PIPE,
        stdout=subprocess.PIPE,
        text=True,
    )
    try:
        assert holder.stdout.readline() == "locked\n"
        untouched = files(sweep_dir)
        monkeypatch.setattr(execution, "_compute", fake_compute)
        with pytest.raises(StoreBusyError) as err:
            run_sweep(sweep, sweep_dir, progress=False)
        message = str(err.value)
        assert message == (
            f"{sweep_dir} is busy: a sweep (pid {holder.pid} on host {socket.gethostname()}) "
            "is writing to it; wait for it to finish or stop it, then rerun"
        )
        with pytest.raises(StoreBusyError):
            compact(sweep_dir)
        # refused at once: before the sweep file is read, any header or any work
        with monkeypatch.context() as patch:
            patch.setattr(Sweep, "load", classmethod(lambda *a, **k: pytest.fail("loaded")))
            result = CliRunner().invoke(app, ["sweep", str(path), "-o", str(sweep_dir), "-q"])
        assert result.exit_code == 2
        assert result.output == f"error: {message}\n"
        assert files(sweep_dir) == untouched
    finally:
        holder.communicate("done\n", timeout=60)
    assert holder.returncode == 0 and not (sweep_dir / LOCK_FILE).exists()
    outcome = run_sweep(sweep, sweep_dir, progress=False)
    n = len(sweep.runs())
    assert (outcome.computed, len(read_runs(sweep_dir))) == (n, n)
    assert not (sweep_dir / LOCK_FILE).exists()


def test_the_lock_is_released_when_the_sweep_fails(tmp_path):
    with pytest.raises(RuntimeError), lock(tmp_path):
        raise RuntimeError
    with lock(tmp_path) as path:
        assert path.read_text(encoding="utf-8") == (
            f"pid {os.getpid()} on host {socket.gethostname()}\n"
        )
    assert list(tmp_path.iterdir()) == []


def test_a_full_disk_is_one_error_and_keeps_what_was_stored(tmp_path, monkeypatch):
    """A write that fails (ENOSPC) raises one StoreError line naming the log, leaves no
    part of its record behind, and the records stored before stay readable; the next
    append, once there is room, follows them."""
    (tmp_path / RUNS_DIR).mkdir()
    real_write = os.write
    log = RunLog(tmp_path)
    log.append(record("a"))

    def half_then_full(fd: int, data: bytes) -> int:
        real_write(fd, data[: len(data) // 2])
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    monkeypatch.setattr(os, "write", half_then_full)
    with pytest.raises(StoreError) as err:
        log.append(record("b"))
    monkeypatch.setattr(os, "write", real_write)
    assert str(err.value) == (
        f"cannot store a finished run in {log.path}: No space left on device; the 1 runs "
        "stored before by this process are kept: make room (or make the directory "
        "writable) and rerun to resume"
    )
    assert log.path.read_text(encoding="utf-8") == line(record("a"))
    assert list(read_runs(tmp_path)) == ["a"]
    log.append(record("c"))
    log.close()
    assert list(read_runs(tmp_path)) == ["a", "c"]


def test_an_unwritable_store_stops_the_sweep_with_one_line(tmp_path, monkeypatch):
    """`pde-rotor sweep` whose store cannot be written (a file where runs/ should be;
    a full disk mid-sweep) ends with exit code 2 and one error line; the runs stored
    before the failure stay readable and the lock is released."""
    path = write_sweep(tmp_path / "tiny.yaml", {**TINY_SWEEP, "samples": 2})
    blocked = tmp_path / "blocked"
    blocked.mkdir()
    (blocked / RUNS_DIR).write_text("", encoding="utf-8")
    (blocked / "sweep.yaml").write_text("", encoding="utf-8")  # a sweep directory, broken
    runner = CliRunner()
    result = runner.invoke(app, ["sweep", str(path), "-o", str(blocked), "-q"])
    assert result.exit_code == 2
    assert result.output.splitlines()[-1].startswith(
        f"error: cannot write the sweep directory {blocked}: "
    )

    appended = []

    def fill_up(self, content: dict) -> None:
        if len(appended) == 3:
            msg = f"cannot store a finished run in {self.path}: No space left on device"
            raise StoreError(msg)
        appended.append(content)
        real_append(self, content)

    real_append = RunLog.append
    monkeypatch.setattr(execution, "_compute", fake_compute)
    monkeypatch.setattr(RunLog, "append", fill_up)
    out = tmp_path / "out"
    result = runner.invoke(app, ["sweep", str(path), "-o", str(out), "-q"])
    assert result.exit_code == 2
    assert result.output.count("error:") == 1 and "No space left on device" in result.output
    assert len(read_runs(out)) == 3 and not (out / LOCK_FILE).exists()


ROOT = Path(__file__).resolve().parents[2]


def test_the_committed_stores_are_compacted_and_read_whole(caplog):
    """Every sweep directory of the repository (a sweep stopped part way too) is
    committed compacted: one runs.jsonl sorted by key, read without a warning; fig9's
    holds 6400 runs of its sweep file's design (what a clone resumes from)."""
    caplog.set_level(logging.WARNING)
    stores = sorted((ROOT / "data" / "sweeps").iterdir())
    assert {"fig5", "fig9", "science_calibration"} <= {s.name for s in stores}
    for sweep_dir in stores:
        assert [p.name for p in (sweep_dir / RUNS_DIR).iterdir()] == [COMPACT_FILE]
        keys = list(read_runs(sweep_dir))
        assert keys == sorted(keys)
    assert caplog.records == []
    stored = read_runs(ROOT / "data" / "sweeps" / "fig9")
    design = Sweep.load(ROOT / "configs" / "sweeps" / "fig9.yaml")
    assert sum(run.key in stored for run in design.runs()) == len(stored) == 6400
