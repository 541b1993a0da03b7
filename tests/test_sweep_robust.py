"""A sweep directory holds one grid's rows exactly once whatever runs write to it, refuses what is not
a sweep's, and the ``sweep`` command refuses bad grids and configurations in one line (issue 19).

Two writers at once are two real processes (the CLI), each bounded in time.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from hyperlattice.cli import main
from hyperlattice.sweep import SweepStore, read_table, run_sweep
from hyperlattice.sweep import engine

SRC = str(Path(__file__).resolve().parents[1] / "src")


def _cli(*args: str) -> subprocess.Popen:
    env = {**os.environ, "PYTHONPATH": SRC + os.pathsep + os.environ.get("PYTHONPATH", "")}
    return subprocess.Popen([sys.executable, "-m", "hyperlattice", *args], env=env,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)


def _err_line(capsys) -> str:
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "Traceback" not in err, err
    return err


def _check_table(path, xs) -> None:
    t = read_table(path)
    keys = list(t.columns["key"])
    assert len(keys) == len(set(keys)) == len(xs)                 # each key exactly once
    assert list(t.columns["index"]) == list(range(len(xs)))      # no collision
    assert sorted(t.columns["x"]) == sorted(xs)
    assert np.array_equal(t.columns["y"], np.asarray(t.columns["x"], dtype=float) ** 2)


def test_two_overlapping_sweeps_at_once_write_each_row_once(tmp_path):
    # the recipe: x=0:20 and x=10:30 into one directory at once gave 40 rows, 30 unique keys
    out = str(tmp_path / "D")
    procs = [_cli("sweep", "--task", "probe", "--grid", f"x={a}:{b}", "--grid", "sleep=0.05",
                  "--scheduler", "serial", "--out", out, "--no-progress") for a, b in ((0, 20), (10, 30))]
    for p in procs:
        _, err = p.communicate(timeout=60)
        assert p.returncode == 0, err
    _check_table(out, list(range(30)))
    meta = read_table(out).metadata
    grids = [g["x"] for g in meta["grids"]]
    assert sorted(map(tuple, grids)) == [tuple(range(0, 20)), tuple(range(10, 30))]   # neither grid dropped
    assert sorted(meta["parameters"]["x"]) == list(range(30))
    # the table file agrees with the parts
    pq = pytest.importorskip("pyarrow.parquet")
    table = pq.read_table(Path(out) / "table.parquet")
    assert table.num_rows == 30 and len(set(table.column("key").to_pylist())) == 30


@pytest.mark.parametrize("backend", ["parquet", "json"])
def test_sweeps_one_after_another_merge_grids_and_index(tmp_path, monkeypatch, backend):
    if backend == "json":
        from hyperlattice.sweep import store as store_mod

        monkeypatch.setattr(store_mod, "have_pyarrow", lambda: False)
    else:
        pytest.importorskip("pyarrow")
    run_sweep("probe", {"x": [0, 1, 2, 3]}, tmp_path, scheduler="serial", progress=False)
    rep = run_sweep("probe", {"x": [2, 3, 4, 5]}, tmp_path, scheduler="serial", progress=False)
    assert (rep.skipped, rep.completed) == (2, 2)
    _check_table(tmp_path, [0, 1, 2, 3, 4, 5])
    t = read_table(tmp_path)
    assert list(t.columns["x"]) == [0, 1, 2, 3, 4, 5]          # the merged grid's order
    assert t.metadata["grids"] == [{"x": [0, 1, 2, 3]}, {"x": [2, 3, 4, 5]}]
    run_sweep("probe", {"x": [0, 1, 2, 3]}, tmp_path, scheduler="serial", progress=False)
    assert len(read_table(tmp_path).metadata["grids"]) == 2    # a grid run again is listed once


def test_an_edited_json_part_is_refused_not_copied(tmp_path, monkeypatch):
    from hyperlattice.sweep import store as store_mod

    monkeypatch.setattr(store_mod, "have_pyarrow", lambda: False)
    run_sweep("probe", {"x": [1.0, 2.0]}, tmp_path, scheduler="serial", progress=False)
    (part,) = (tmp_path / "parts").glob("part-*.json")
    data = json.loads(part.read_text())
    data["rows"][0]["y"] = 99.0
    part.write_text(json.dumps(data))
    with pytest.raises(ValueError, match=r"part-.*\.json.*checksum") as exc:
        read_table(tmp_path)
    assert "\n" not in str(exc.value)
    with pytest.raises(ValueError, match="checksum"):
        run_sweep("probe", {"x": [1.0, 2.0]}, tmp_path, scheduler="serial", progress=False)


def test_an_edited_parquet_part_is_refused(tmp_path):
    pa = pytest.importorskip("pyarrow")
    pq = pytest.importorskip("pyarrow.parquet")
    run_sweep("probe", {"x": [1.0, 2.0]}, tmp_path, scheduler="serial", progress=False)
    (part,) = (tmp_path / "parts").glob("part-*.parquet")
    table = pq.read_table(part)
    y = table.column("y").to_pylist()
    table = table.set_column(table.column_names.index("y"), "y", pa.array([y[0] + 1.0, y[1]]))
    pq.write_table(table, part)                 # schema metadata (and its sha256) kept, a value changed
    with pytest.raises(ValueError, match="checksum"):
        read_table(tmp_path)


def test_cli_an_edited_part_is_one_line_exit_2(tmp_path, capsys):
    pa = pytest.importorskip("pyarrow")
    pq = pytest.importorskip("pyarrow.parquet")
    args = ["sweep", "--task", "probe", "--grid", "x=1,2", "--scheduler", "serial", "--out", str(tmp_path)]
    assert main(args) == 0
    (part,) = (tmp_path / "parts").glob("part-*.parquet")
    table = pq.read_table(part)
    table = table.set_column(table.column_names.index("y"), "y", pa.array([7.0, 7.0]))
    pq.write_table(table, part)
    capsys.readouterr()
    assert main(args) == 2
    err = _err_line(capsys)
    assert str(part) in err and ("checksum" in err or "cannot be read" in err)


def test_sweep_into_a_foreign_directory_is_refused(tmp_path, capsys):
    d = tmp_path / "mine"
    d.mkdir()
    (d / "table.parquet").write_bytes(b"my own table")
    (d / "_failures.json").write_text("[]")
    assert main(["sweep", "--task", "probe", "--grid", "x=1,2", "--scheduler", "serial", "--out", str(d)]) == 2
    assert "not a sweep directory" in _err_line(capsys)
    assert (d / "table.parquet").read_bytes() == b"my own table"      # untouched
    assert (d / "_failures.json").read_text() == "[]"
    assert sorted(p.name for p in d.iterdir()) == ["_failures.json", "table.parquet"]
    with pytest.raises(ValueError, match="not a sweep directory"):
        SweepStore(d)


def test_failures_of_an_earlier_run_are_kept_until_retried(tmp_path, monkeypatch):
    from hyperlattice.sweep import tasks as tasks_mod

    def picky(x=0.0, sleep=0.0):
        if x < 0:
            raise ValueError("negative")
        return {"y": x * x}

    monkeypatch.setitem(tasks_mod.TASKS, "probe", tasks_mod.Task("probe", picky, tasks_mod._check_probe))
    run_sweep("probe", {"x": [-1.0, 1.0]}, tmp_path, scheduler="serial", retries=0, progress=False)
    run_sweep("probe", {"x": [2.0]}, tmp_path, scheduler="serial", retries=0, progress=False)
    assert [f["params"]["x"] for f in SweepStore(tmp_path).failures()] == [-1.0]   # not wiped by run 2


@pytest.mark.parametrize("argv, match", [
    (["--grid", "x=1,2", "--grid", "x=3"], "given twice"),
    (["--grid", "x=1,1,2"], "lists x = 1 twice"),
    (["--grid", "x=0:10000000"], "10,000,000 tasks; at most"),
    (["--grid", "x=0:1000", "--grid", "sleep=0,1,2,3,4,5,6,7,8,9", "--grid", "y=0:1000"], "task 'probe' has no"),
])
def test_cli_bad_grids_refused_in_one_line(argv, match, tmp_path, capsys):
    out = tmp_path / "D"
    assert main(["sweep", "--task", "probe", *argv, "--scheduler", "serial", "--out", str(out)]) == 2
    assert match in _err_line(capsys)
    assert not (out / "_sweep.json").exists()              # refused before any work


def test_api_grid_size_cap_is_checked_before_expansion():
    grid = {"x": list(range(1001)), "sleep": [0.0] * 1001}   # 1,002,001 points, never expanded
    with pytest.raises(ValueError, match=r"1,002,001 tasks; at most 1,000,000"):
        engine.expand_grid("probe", grid)


def test_grid_size_cap_follows_memory(monkeypatch):
    monkeypatch.setattr(engine, "_memory_budget", lambda: 100 * engine._BYTES_PER_TASK)
    with pytest.raises(ValueError, match=r"at most 100 for the .* GiB of memory"):
        engine.expand_grid("probe", {"x": list(range(101))})


@pytest.mark.parametrize("config, match", [
    ({"task": "probe", "grid": [["x", [1, 2]]]}, "must be an object .* got a JSON array"),
    ({"task": "probe", "grid": "x=1"}, "got a JSON string"),
    (None, "nested too deeply"),
])
def test_cli_bad_config_one_sentence(config, match, tmp_path, capsys):
    cfg = tmp_path / "sweep.json"
    if config is None:
        cfg.write_text("[" * 100_000 + "]" * 100_000)          # 100,000 levels deep
    else:
        cfg.write_text(json.dumps({**config, "out": str(tmp_path / "D"), "scheduler": "serial"}))
    assert main(["sweep", str(cfg)]) == 2
    assert __import__("re").search(match, _err_line(capsys))


# -- schedulers: one line each, bounded in time (loopback addresses only) ------------------------

def _free_port() -> int:
    import socket

    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@pytest.fixture
def http_server():
    """``python -m http.server`` on a loopback port: something listens there, but not Dask."""
    import socket
    import time

    port = _free_port()
    proc = subprocess.Popen([sys.executable, "-m", "http.server", str(port), "--bind", "127.0.0.1"],
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        deadline = time.monotonic() + 10
        while True:
            try:
                socket.create_connection(("127.0.0.1", port), timeout=0.5).close()
                break
            except OSError:
                if time.monotonic() > deadline or proc.poll() is not None:
                    pytest.fail("the test's http.server did not start")
                time.sleep(0.05)
        yield f"tcp://127.0.0.1:{port}"
    finally:
        proc.kill()
        proc.wait(timeout=10)


def _sweep_seconds(capsys, tmp_path, *extra):
    import time

    pytest.importorskip("distributed")
    t0 = time.monotonic()
    code = main(["sweep", "--task", "probe", "--grid", "x=1,2", "--out", str(tmp_path / "D"), "--no-progress",
                 *extra])
    return code, time.monotonic() - t0, _err_line(capsys)


def test_a_port_that_does_not_speak_dask_respects_timeout(http_server, tmp_path, capsys):
    # it hung past 200 s whatever --timeout said
    code, seconds, err = _sweep_seconds(capsys, tmp_path, "--scheduler", http_server, "--timeout", "1.5")
    assert code == 2 and "did not answer as a Dask scheduler within 1.5 s" in err
    assert seconds < 10
    assert not (tmp_path / "D").exists()               # refused before the sweep directory was made


@pytest.mark.parametrize("address, match", [
    ("tcp://127.0.0.1:1", "cannot reach the Dask scheduler"),     # nothing listens: refused at once (was 30.8 s)
    ("tls://127.0.0.1:1", "TLS needs certificates"),               # was TypeError
    ("inproc://x", "no Dask scheduler inproc://x runs in this process"),   # was "not enough values to unpack"
])
def test_bad_scheduler_addresses_one_sentence(address, match, tmp_path, capsys):
    code, seconds, err = _sweep_seconds(capsys, tmp_path, "--scheduler", address, "--timeout", "5")
    assert code == 2 and match in err
    assert seconds < 10


def test_more_workers_than_cores_are_capped_with_one_warning(tmp_path, capsys, monkeypatch):
    monkeypatch.setattr(os, "cpu_count", lambda: 2)
    with pytest.warns(UserWarning, match="64 workers requested on a machine with 2 cores; using 2"):
        assert engine._local_workers(64) == 2
    assert engine._local_workers(None) == 2 and engine._local_workers(1) == 1
    # through the CLI (threads: the cap, not process start-up, is under test): one warning line only
    code = main(["sweep", "--task", "probe", "--grid", "x=1,2", "--out", str(tmp_path / "D"), "--no-progress",
                 "--scheduler", "threads", "--workers", "64", "--timeout", "60"])
    err = capsys.readouterr().err
    assert code == 0 and err.count("\n") == 1 and "using 2" in err and "Traceback" not in err


@pytest.mark.parametrize("text, key", [
    ('{"task": "probe", "grid": {"x": [1, 2], "x": [3]}, "out": "D"}', "x"),      # dropped x = 1, 2
    ('{"task": "probe", "task": "disorder", "grid": {"x": [1]}, "out": "D"}', "task"),
])
def test_cli_config_with_a_key_given_twice_is_refused(text, key, tmp_path, capsys, monkeypatch):
    # issue 28 item 6: json keeps the last of two equal keys, so a grid silently lost values
    monkeypatch.chdir(tmp_path)
    cfg = tmp_path / "sweep.json"
    cfg.write_text(text)
    assert main(["sweep", str(cfg), "--scheduler", "serial"]) == 2
    assert f"gives the key '{key}' twice" in _err_line(capsys)
    assert not (tmp_path / "D").exists()                    # refused before any work


def test_a_tiny_grid_does_not_start_a_local_cluster(tmp_path, monkeypatch):
    # issue 28 item 5: the default local cluster cost 6 s for 6 tiny tasks (0.7 s serially)
    pytest.importorskip("distributed")

    def no_cluster(*args, **kwargs):
        raise AssertionError("a local cluster was started for a tiny grid")

    monkeypatch.setattr(engine, "_run_dask", no_cluster)
    rep = engine.run_sweep("probe", {"x": [1.0, 2.0, 3.0, 4.0, 5.0, 6.0]}, tmp_path / "D", progress=False)
    assert rep.ok and rep.completed == 6
    assert rep.scheduler.startswith("serial (") and "s of tasks, less than the ~5 s a local cluster" in rep.scheduler


def test_a_grid_worth_it_starts_the_local_cluster(tmp_path, monkeypatch):
    # the first task runs here; when the rest would outlast the cluster's start-up, the rest goes to it
    pytest.importorskip("distributed")
    calls = []

    def fake_dask(task, ps, ks, write, retries, failures, bar, on_row, scheduler, workers, timeout):
        calls.append(len(ps))
        for p, k in zip(ps, ks):
            write(k, p, engine.execute(task, p))
        return "local (2 processes)"

    monkeypatch.setattr(engine, "_run_dask", fake_dask)
    monkeypatch.setattr(engine, "LOCAL_CLUSTER_SECONDS", 0.0)
    rep = engine.run_sweep("probe", {"x": [1.0, 2.0, 3.0]}, tmp_path / "D", progress=False)
    assert calls == [2] and rep.scheduler == "local (2 processes)" and rep.completed == 3
