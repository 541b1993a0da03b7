"""The on-disk cache: checked entries, recomputation of bad ones, atomic concurrent writes."""

from __future__ import annotations

import json
import multiprocessing
import warnings

import numpy as np
import pytest

from hyperlattice import __version__
from hyperlattice.cache import MARKER, SCHEMA, Cache, CacheWarning, _checksum
from hyperlattice.cli import main
from hyperlattice.results import Levels

INPUTS = {"p": 7, "q": 3, "rings": 4, "levels": 2}
VALUE = {"E0": -2.93, "E1": -2.87, "m": [0, 1], "method": "sector"}


class Counter:
    """A compute function that counts its calls."""

    def __init__(self, value=VALUE):
        self.value, self.calls = value, 0

    def __call__(self):
        self.calls += 1
        return self.value


def _levels() -> Levels:
    return Levels(energies=np.array([-2.9, -2.8]), n=np.array([1, 1], dtype=np.int32), m=None,
                  errors=np.array([1e-13, np.inf]), error_kind="residual", method="dense",
                  description="d", p=7, q=3)


def _entry(cache: Cache, name="graph_levels", inputs=INPUTS):
    (path,) = (cache.directory / __version__).glob(f"{name}-*.json")
    return path


def test_hit_after_miss(tmp_path):
    cache, compute = Cache(tmp_path), Counter()
    assert cache.get("graph_levels", INPUTS, compute) == VALUE
    assert cache.get("graph_levels", INPUTS, compute) == VALUE
    # the second read is of an entry this object wrote: reused within the run, not a hit from an earlier run
    assert (compute.calls, cache.hits, cache.misses, cache.reused) == (1, 0, 1, 1)
    later = Cache(tmp_path)
    assert later.get("graph_levels", INPUTS, compute) == VALUE
    assert (compute.calls, later.hits, later.misses, later.reused) == (1, 1, 0, 0)
    entry = json.loads(_entry(cache).read_text())
    assert entry["schema"] == SCHEMA and entry["type"] == "dict" and entry["inputs"] == INPUTS
    assert entry["version"] == __version__ and entry["sha256"] == _checksum(VALUE)
    # other inputs, another entry
    assert cache.get("graph_levels", {**INPUTS, "rings": 5}, compute) == VALUE and compute.calls == 2


def test_result_values_round_trip(tmp_path):
    cache, compute = Cache(tmp_path), Counter(_levels())
    first = cache.get("levels", {"rings": 3}, compute)
    again = cache.get("levels", {"rings": 3}, compute, expect=Levels)
    assert compute.calls == 1 and isinstance(again, Levels) and again is not first
    assert again.n.dtype == np.int32 and again.m is None and np.array_equal(again.errors, first.errors)
    assert not again.energies.flags.writeable


def _bad_entries(path, good: dict):
    """(label, how to spoil the entry) for every kind of bad entry."""
    def edit(**change):
        return json.dumps({**good, **change})

    value = good["value"]
    return {
        "unparsable": lambda: path.write_text('{"schema": "hyperlattice-cache/1", "value": {'),
        "empty": lambda: path.write_text(""),
        "binary": lambda: path.write_bytes(b"\xff\xfe\x00garbage"),
        "wrong-shape-list": lambda: path.write_text("[1, 2, 3]"),
        "wrong-shape-bare-value": lambda: path.write_text(json.dumps(value)),  # the old format
        "other-schema": lambda: path.write_text(edit(schema="hyperlattice-cache/0")),
        "missing-key": lambda: path.write_text(json.dumps({k: v for k, v in good.items() if k != "sha256"})),
        # a hand-edited number: E0 + 0.5 landed in table_paper_table4.csv before
        "hand-edited": lambda: path.write_text(edit(value={**value, "E0": value["E0"] + 0.5})),
        "other-inputs": lambda: path.write_text(edit(inputs={**good["inputs"], "rings": 9})),
        "value-not-dict": lambda: path.write_text(edit(value=[1, 2], sha256=_checksum([1, 2]))),
        "unknown-result-type": lambda: path.write_text(
            edit(type="NoSuchResult", value={"type": "NoSuchResult"}, sha256=_checksum({"type": "NoSuchResult"}))),
        "directory": lambda: (path.unlink(), path.mkdir(), (path / "inside").write_text("x")),
    }


BAD_KINDS = sorted(_bad_entries(None, {"value": {"E0": 0.0}, "inputs": {}}))


@pytest.mark.parametrize("kind", BAD_KINDS)
def test_bad_entry_is_discarded_and_recomputed(kind, tmp_path):
    cache, compute = Cache(tmp_path), Counter()
    cache.get("graph_levels", INPUTS, compute)
    path = _entry(cache)
    good = json.loads(path.read_text())
    _bad_entries(path, good)[kind]()
    with pytest.warns(CacheWarning, match="discarded and recomputed"):
        value = cache.get("graph_levels", INPUTS, compute)
    assert value == VALUE and compute.calls == 2 and cache.misses == 2
    assert json.loads(path.read_text()) == good  # rewritten as a valid entry
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert cache.get("graph_levels", INPUTS, compute) == VALUE and compute.calls == 2


def test_bad_result_entry_is_recomputed(tmp_path):
    cache, compute = Cache(tmp_path), Counter(_levels())
    cache.get("levels", {"rings": 3}, compute)
    path = _entry(cache, "levels")
    entry = json.loads(path.read_text())
    broken = {**entry["value"], "energies": {"__ndarray__": "float64", "shape": [5], "data": [1.0]}}
    path.write_text(json.dumps({**entry, "value": broken, "sha256": _checksum(broken)}))
    with pytest.warns(CacheWarning, match="cannot be rebuilt"):
        assert isinstance(cache.get("levels", {"rings": 3}, compute), Levels)
    assert compute.calls == 2


def test_expected_type_mismatch_is_recomputed(tmp_path):
    cache = Cache(tmp_path)
    cache.get("levels", {"rings": 3}, Counter())  # a dict stored where Levels is expected
    compute = Counter(_levels())
    with pytest.warns(CacheWarning, match="not the expected Levels"):
        assert isinstance(cache.get("levels", {"rings": 3}, compute, expect=Levels), Levels)


def test_no_temporary_files_left(tmp_path):
    cache = Cache(tmp_path)
    for i in range(5):
        cache.put("graph_levels", INPUTS, {**VALUE, "i": i})
    names = [p.name for p in (tmp_path / __version__).iterdir() if p.name != MARKER]
    assert len(names) == 1 and names[0].endswith(".json")


def _writer(directory: str, worker: int, rounds: int) -> int:
    warnings.simplefilter("error")  # a discarded (half-written) entry would raise here
    cache = Cache(directory)
    for i in range(rounds):
        cache.put("graph_levels", INPUTS, {**VALUE, "worker": worker, "round": i})
        value = cache.get("graph_levels", INPUTS, Counter({"worker": -1}))
        assert value.get("worker") in (0, 1), value  # never recomputed: always a complete entry
    return worker


def test_concurrent_writers_never_collide(tmp_path):
    """Two processes x 20 writes to one key (the old fixed temp name crashed 1 run in 11)."""
    ctx = multiprocessing.get_context("spawn")  # fork of a threaded process warns
    with ctx.Pool(2) as pool:
        done = pool.starmap(_writer, [(str(tmp_path), 0, 20), (str(tmp_path), 1, 20)])
    assert sorted(done) == [0, 1]
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        value = Cache(tmp_path).get("graph_levels", INPUTS, Counter({"worker": -1}))
    assert value["round"] == 19 and value["worker"] in (0, 1)
    assert [p.suffix for p in (tmp_path / __version__).iterdir() if p.name != MARKER] == [".json"]


def test_unwritable_directory_refused_at_construction(tmp_path):
    afile = tmp_path / "afile"
    afile.write_text("x")
    for bad in (afile, afile / "sub"):
        with pytest.raises(ValueError, match="cache directory"):
            Cache(bad)
    Cache(afile, enabled=False)  # a disabled cache never touches its directory


def test_disabled_cache_computes_and_stores_nothing(tmp_path):
    cache, compute = Cache(tmp_path / "c", enabled=False), Counter()
    cache.get("graph_levels", INPUTS, compute)
    cache.get("graph_levels", INPUTS, compute)
    assert compute.calls == 2 and not (tmp_path / "c").exists()


def test_store_failure_only_warns(tmp_path):
    cache, compute = Cache(tmp_path), Counter()
    (tmp_path / __version__).write_text("a file where the version folder goes")
    with pytest.warns(CacheWarning, match="could not store"):
        assert cache.get("graph_levels", INPUTS, compute) == VALUE


def test_default_directory_from_environment(tmp_path, monkeypatch):
    monkeypatch.setenv("HYPERLATTICE_CACHE", str(tmp_path / "env"))
    assert Cache().directory == tmp_path / "env" and (tmp_path / "env").is_dir()


@pytest.mark.parametrize("call, match", [
    (lambda c: c.get("bad name!", {}, Counter()), "name"),
    (lambda c: c.get("x", [1], Counter()), "inputs"),
    (lambda c: c.get("x", {"a": object()}, Counter()), "inputs"),
    (lambda c: c.get("x", {"a": float("nan")}, Counter()), "inputs"),
    (lambda c: c.get("x", {}, Counter([1, 2])), "dict or a Result"),
    (lambda c: c.put("x", {}, {"a": np.arange(3)}), "JSON values"),
    (lambda c: c.get("x", {}, Counter(), expect=list), "expect"),
    (lambda c: Cache(c.directory, enabled="yes"), "enabled"),
])
def test_bad_arguments_are_valueerror(call, match, tmp_path):
    with pytest.raises(ValueError, match=match):
        call(Cache(tmp_path))


def test_clear(tmp_path):
    cache = Cache(tmp_path / "c")
    cache.get("graph_levels", INPUTS, Counter())
    assert cache.clear() == 1
    assert not any((tmp_path / "c").iterdir())  # the entries and the version subdirectory went
    assert cache.get("graph_levels", INPUTS, Counter()) == VALUE  # usable again


@pytest.mark.parametrize("where", ["file", "below-a-file"])
def test_cli_bad_cache_dir_exits_2_before_computing(where, tmp_path, capsys):
    afile = tmp_path / "afile"
    afile.write_text("x")
    target = afile if where == "file" else afile / "cache"
    assert main(["reproduce", "--out", str(tmp_path / "out"), "--cache-dir", str(target)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "cache directory" in err
    assert not (tmp_path / "out" / "report.html").exists()
