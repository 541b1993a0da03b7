"""The sweep engine: bit-identical results on any scheduler, killed workers, interruption and resumption,
retries and reported failures, the Parquet table and its JSON fallback."""

from __future__ import annotations

import json
import os
import signal

import numpy as np
import pytest

from hyperlattice.sweep import SweepStore, expand_grid, read_table, run_sweep, task_key
from hyperlattice.sweep import engine, store as store_mod, tasks as tasks_mod

GRID = {"rings": [3], "W": [0.5, 8.0], "realization": [0, 1, 2], "ipr": [True]}
TIMEOUT = 120  # seconds: a hung scheduler fails the test instead of hanging CI


def _same(a, b) -> None:
    """Two tables hold the same bits in the same order."""
    assert list(a.columns) == list(b.columns)
    for name in a.columns:
        x, y = a.columns[name], b.columns[name]
        if isinstance(x, np.ndarray):
            assert x.dtype == y.dtype and x.tobytes() == y.tobytes(), name
        else:
            assert json.dumps(x) == json.dumps(y), name


@pytest.fixture(scope="module")
def serial_table(tmp_path_factory):
    path = tmp_path_factory.mktemp("serial")
    rep = run_sweep("disorder", GRID, path, scheduler="serial", progress=False)
    assert rep.ok and rep.completed == 6
    return read_table(path)


def test_keys_are_idempotent():
    with pytest.raises(ValueError, match=r"lists W = 1.0 twice"):   # was silently one task (issue 28)
        expand_grid("disorder", {"W": [1.0, 1.0, 2.0]})
    a = expand_grid("disorder", {"W": [1.0, 2.0]})
    assert len(a) == 2 and len(expand_grid("probe", {"x": [1, 1.0]})) == 2   # 1 and 1.0 differ
    assert task_key("disorder", a[0]) == task_key("disorder", dict(reversed(list(a[0].items()))))
    assert task_key("disorder", a[0]) != task_key("disorder", a[1])
    # 1 and 1.0 are different parameters (an int rings, a float W): keys keep the JSON type
    assert task_key("probe", {"x": 1, "sleep": 0.0}) != task_key("probe", {"x": 1.0, "sleep": 0.0})


def test_serial_table_and_metadata(serial_table):
    t = serial_table
    assert len(t) == 6 and list(t.columns["index"]) == list(range(6))
    assert t.metadata["task"] == "disorder" and t.metadata["version"]
    assert t.metadata["parameters"]["W"] == [0.5, 8.0]
    assert np.all(np.isfinite(t.columns["r_mean"])) and np.all(t.columns["r_count"] > 50)
    assert len(t.columns["dos_counts"][0]) == 60        # list columns survive the round trip


def test_parquet_metadata_and_rerun_skips(tmp_path):
    pq = pytest.importorskip("pyarrow.parquet")

    rep = run_sweep("probe", {"x": [1.0, 2.0, 3.0]}, tmp_path, scheduler="serial", progress=False)
    meta = json.loads(pq.read_schema(rep.table).metadata[b"hyperlattice"])
    assert meta["task"] == "probe" and meta["parameters"] == {"x": [1.0, 2.0, 3.0]} and "version" in meta
    again = run_sweep("probe", {"x": [1.0, 2.0, 3.0, 4.0]}, tmp_path, scheduler="serial", progress=False)
    assert (again.skipped, again.completed, again.total) == (3, 1, 4)
    assert list(read_table(tmp_path).columns["y"]) == [1.0, 4.0, 9.0, 16.0]
    with pytest.raises(ValueError, match="task 'probe'"):
        run_sweep("disorder", {"W": [1.0]}, tmp_path, scheduler="serial", progress=False)


def test_interrupted_sweep_resumes_to_the_same_table(serial_table, tmp_path):
    seen = []

    def stop_after_two(key):
        seen.append(key)
        if len(seen) == 2:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        run_sweep("disorder", GRID, tmp_path, scheduler="serial", progress=False, on_row=stop_after_two)
    assert len(read_table(tmp_path)) == 2               # what finished is on disk, consolidated
    rep = run_sweep("disorder", GRID, tmp_path, scheduler="serial", progress=False)
    assert (rep.skipped, rep.completed) == (2, 4)
    _same(read_table(tmp_path), serial_table)


def test_failures_are_retried_and_reported(tmp_path, monkeypatch):
    calls = {"n": 0}

    def flaky(x=0.0, sleep=0.0):
        calls["n"] += 1
        if x < 0:
            raise ValueError("negative x is not allowed here")
        if x == 2.0 and calls["n"] < 3:
            raise RuntimeError("transient")
        return {"y": x * x}

    monkeypatch.setitem(tasks_mod.TASKS, "probe", tasks_mod.Task("probe", flaky, tasks_mod._check_probe))
    rep = run_sweep("probe", {"x": [-1.0, 2.0]}, tmp_path, scheduler="serial", retries=2, progress=False)
    assert rep.completed == 1 and len(rep.failed) == 1 and not rep.ok
    assert rep.failed[0]["params"]["x"] == -1.0 and "negative x" in rep.failed[0]["error"]
    assert SweepStore(tmp_path).failures()[0]["key"] == rep.failed[0]["key"]
    # the next run retries the failed task, never the finished one
    rep2 = run_sweep("probe", {"x": [-1.0, 2.0]}, tmp_path, scheduler="serial", retries=0, progress=False)
    assert rep2.skipped == 1 and len(rep2.failed) == 1


def test_json_fallback_holds_the_same_bits(serial_table, tmp_path, monkeypatch):
    monkeypatch.setattr(store_mod, "have_pyarrow", lambda: False)
    rep = run_sweep("disorder", GRID, tmp_path, scheduler="serial", progress=False)
    assert rep.table.endswith("table.jsonl")
    _same(read_table(tmp_path), serial_table)


def test_without_dask_the_default_runs_serially(tmp_path, monkeypatch):
    monkeypatch.setattr(engine, "have_dask", lambda: False)
    rep = run_sweep("probe", {"x": [3.0]}, tmp_path, progress=False)
    assert rep.scheduler == "serial" and rep.ok
    with pytest.raises(ValueError, match="dask"):
        run_sweep("probe", {"x": [3.0]}, tmp_path, scheduler="tcp://127.0.0.1:1", progress=False)


@pytest.mark.slow
def test_local_cluster_is_bit_identical_to_the_default(serial_table, tmp_path):
    pytest.importorskip("distributed")
    from distributed import Client, LocalCluster

    # "local": a local cluster of worker processes started by the engine (the default scheduler=None
    # runs this tiny grid serially: tests/test_sweep_robust.py)
    rep = run_sweep("disorder", GRID, tmp_path / "default", scheduler="local", workers=2, progress=False,
                    timeout=TIMEOUT)
    assert rep.ok and "local" in rep.scheduler
    default = read_table(tmp_path / "default")
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=False, dashboard_address=":0") as cluster, \
            Client(cluster) as client:
        rep = run_sweep("disorder", GRID, tmp_path / "cluster", scheduler=client, progress=False, timeout=TIMEOUT)
        assert rep.ok
    cluster_table = read_table(tmp_path / "cluster")
    _same(default, cluster_table)
    _same(default, serial_table)


@pytest.mark.slow
def test_local_cluster_starts_while_port_8787_is_taken(tmp_path):
    """Dask's default dashboard port held by someone else (another cluster, a notebook, a concurrent
    test run) must not disturb the default local cluster: no warning (errors here), same rows."""
    pytest.importorskip("distributed")
    import socket

    holder = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
    try:
        try:
            holder.bind(("", 8787))
            holder.listen(1)
        except OSError:
            pass                                    # already taken by someone else: the same situation
        rep = run_sweep("probe", {"x": [1.0, 2.0]}, tmp_path, scheduler="threads", workers=2, progress=False,
                        timeout=TIMEOUT)
    finally:
        holder.close()
    assert rep.ok and rep.completed == 2
    assert np.array_equal(read_table(tmp_path).columns["y"], np.array([1.0, 4.0]))


@pytest.mark.slow
def test_killed_worker_still_gives_every_row_once(tmp_path):
    pytest.importorskip("distributed")
    from distributed import Client, LocalCluster

    n = 16
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=":0") as cluster, \
            Client(cluster) as client:
        pids = list(client.run(os.getpid).values())
        rows = []

        def kill_one(key):
            rows.append(key)
            if len(rows) == 3:
                os.kill(pids[0], signal.SIGKILL)        # a worker dies in the middle of the sweep

        rep = run_sweep("probe", {"x": [float(i) for i in range(n)], "sleep": [0.2]}, tmp_path, scheduler=client,
                        progress=False, timeout=TIMEOUT, on_row=kill_one)
        assert pids[0] not in client.run(os.getpid).values()     # it really died (the nanny restarted it)
    assert rep.ok, rep.failed
    t = read_table(tmp_path)
    assert len(t) == n and len(set(t.columns["key"])) == n
    assert list(t.columns["index"]) == list(range(n))
    assert np.array_equal(t.columns["y"], np.arange(n, dtype=float) ** 2)
    assert len(SweepStore(tmp_path).done()) == n


@pytest.mark.parametrize("backend", ["parquet", "json"])
def test_a_key_written_twice_is_one_row(tmp_path, backend):
    if backend == "parquet":
        pytest.importorskip("pyarrow")
    st = SweepStore(tmp_path, backend=backend)
    st.open("probe", {})
    row = {"key": "probe-a", "index": 0, "x": 1.0, "y": 1.0}
    st.write_rows([row], {})
    st.write_rows([row, {"key": "probe-b", "index": 1, "x": 2.0, "y": 4.0}], {})   # e.g. two racing runs
    assert st.done() == {"probe-a", "probe-b"}
    t = read_table(tmp_path)
    assert list(t.columns["key"]) == ["probe-a", "probe-b"]


def test_levels_task_matches_the_api(tmp_path):
    from hyperlattice import lowest_levels, ring_lattice

    run_sweep("levels", {"rings": [3], "flux": [0.0, 0.1]}, tmp_path, scheduler="serial", progress=False)
    t = read_table(tmp_path)
    for f, e0 in zip(t.columns["flux"], t.columns["E0"]):
        assert e0 == lowest_levels(ring_lattice(7, 3, 3), 2, flux=float(f)).energies[0]
    assert len(t.columns["E"][0]) == 2 and isinstance(t.columns["method"][0], str)
