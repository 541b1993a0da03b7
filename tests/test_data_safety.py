"""Nothing the user owns is lost: ``--clear-cache`` deletes only the package's own cache entries,
``sweep --out`` refuses a directory that is not a sweep's and ``reproduce --out`` one that is not a
report's, ``qubits`` refuses one file for two outputs.

(Issue 19, item 5; the sweep directory's integrity under two writers is in test_sweep_robust.py.)
"""

from __future__ import annotations

import json

import pytest

from hyperlattice import __version__
from hyperlattice.cache import MARKER, Cache
from hyperlattice.cli import main

INPUTS = {"p": 7, "q": 3, "rings": 2}


def _user_files(root):
    """A user's own files where the cache will live: a thesis, a stray JSON, a look-alike name."""
    (root / "thesis").mkdir(parents=True)
    (root / "thesis" / "c.tex").write_text("x")
    (root / "notes.json").write_text("{}")
    (root / __version__).mkdir()
    # named like an entry, in the cache's own subdirectory, but not written by the cache
    (root / __version__ / f"mine-{'0' * 24}.json").write_text('{"my": "data"}')
    (root / __version__ / "plot.png").write_bytes(b"\x89PNG")
    return sorted(str(p.relative_to(root)) for p in root.rglob("*"))


def test_clear_deletes_only_the_entries_it_wrote(tmp_path):
    before = _user_files(tmp_path)
    cache = Cache(tmp_path)
    cache.get("graph_levels", INPUTS, lambda: {"E0": -2.5})
    cache.get("graph_levels", {**INPUTS, "rings": 3}, lambda: {"E0": -2.7})
    assert (tmp_path / __version__ / MARKER).is_file()
    assert cache.clear() == 2
    after = sorted(str(p.relative_to(tmp_path)) for p in tmp_path.rglob("*"))
    assert after == before                                  # every user file, and only those, is left
    assert (tmp_path / "thesis" / "c.tex").read_text() == "x"


def test_clear_of_an_unmarked_directory_deletes_nothing(tmp_path):
    # a version-named directory without the marker is not the cache's, whatever its files look like
    (tmp_path / __version__).mkdir()
    entry = tmp_path / __version__ / f"graph_levels-{'a' * 24}.json"
    entry.write_text(json.dumps({"schema": "hyperlattice-cache/1"}))
    assert Cache(tmp_path).clear() == 0
    assert entry.exists()


def _fake_reproduce(out_dir, max_rings, *, cache, progress):
    cache.get("graph_levels", INPUTS, lambda: {"E0": -2.5})
    return {"out_dir": str(out_dir), "sections": [], "seconds": 0.0,
            "cache_hits": cache.hits, "cache_misses": cache.misses, "cache_reused": cache.reused}


@pytest.mark.parametrize("how", ["--cache-dir", "HYPERLATTICE_CACHE", "out-is-cache"])
def test_cli_clear_cache_keeps_user_files(how, tmp_path, monkeypatch, capsys):
    # the recipe: mkdir -p /tmp/u/thesis; echo x > c.tex; reproduce --cache-dir /tmp/u --clear-cache
    import hyperlattice.report as report

    monkeypatch.setattr(report, "reproduce", _fake_reproduce)  # the clearing, not the paper, is under test
    user = tmp_path / "u"
    before = _user_files(user)
    out = user if how == "out-is-cache" else tmp_path / "r"
    args = ["reproduce", "--out", str(out), "--max-rings", "2", "--clear-cache"]
    if how == "HYPERLATTICE_CACHE":
        monkeypatch.setenv("HYPERLATTICE_CACHE", str(user))
    else:
        args += ["--cache-dir", str(user)]
    for _ in range(2):                       # the second run clears what the first one stored
        # a directory holding the user's files is not the report's to write into: refused untouched
        assert main(args) == (2 if how == "out-is-cache" else 0)
    err = capsys.readouterr().err
    if how == "out-is-cache":
        assert "not a report directory" in err and err.count("\n") == 2
    left = sorted(str(p.relative_to(user)) for p in user.rglob("*"))
    assert set(before) <= set(left)
    assert (user / "thesis" / "c.tex").read_text() == "x"
    assert (user / __version__ / "plot.png").exists()


@pytest.mark.parametrize("second", ["same", "dot-path", "symlink"])
def test_qubits_refuses_one_file_for_out_and_edges(second, tmp_path, capsys):
    f = tmp_path / "f.csv"
    f.write_text("mine\n")
    other = {"same": f, "dot-path": tmp_path / "." / "f.csv", "symlink": tmp_path / "g.csv"}[second]
    if second == "symlink":
        other.symlink_to(f)
    assert main(["qubits", "--rings", "4", "--qubit-sites", "0,10", "--out", str(f), "--edges", str(other)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "same file" in err
    assert f.read_text() == "mine\n"            # refused before anything was written


def test_reproduce_refuses_a_directory_of_the_users(tmp_path, monkeypatch, capsys):
    # issue 28 item 6: `reproduce --out DIR` overwrote the user's own report.md and figures in DIR
    import hyperlattice.report as report

    mine = tmp_path / "paper"
    mine.mkdir()
    (mine / "report.md").write_text("my own report")
    (mine / "fig_paper_fig3.png").write_bytes(b"mine")
    assert main(["reproduce", "--out", str(mine), "--max-rings", "2", "--no-cache"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "not a report directory" in err and "fig_paper_fig3.png" in err
    with pytest.raises(ValueError, match="not a report directory"):
        report.reproduce(mine, max_rings=2, cache=Cache(tmp_path / "c", enabled=False))
    assert (mine / "report.md").read_text() == "my own report"
    assert sorted(f.name for f in mine.iterdir()) == ["fig_paper_fig3.png", "report.md"]


def test_reproduce_reuses_its_own_directory(tmp_path, monkeypatch):
    # a new directory gets its manifest when the run starts; a rerun into it (or an empty one) is accepted
    import hyperlattice.report as report
    from hyperlattice import __version__
    from hyperlattice.report import manifest

    out = tmp_path / "r"
    out.mkdir()
    assert report._out_directory("out_dir", out) == out
    manifest.start(out, __version__)
    with manifest.writing(out, "report.md") as path:
        path.write_text("an earlier run's")
    assert report._out_directory("out_dir", out) == out
    # a run interrupted while writing a file leaves it listed as pending: still the report's own
    with pytest.raises(KeyboardInterrupt), manifest.writing(out, "fig_paper_fig1.png") as path:
        path.write_bytes(b"half")
        raise KeyboardInterrupt
    assert report._out_directory("out_dir", out) == out


@pytest.mark.parametrize("tamper", ["empty marker", "braces", "old format", "added file", "edited output",
                                    "listed directory", "bad checksum"])
def test_reproduce_refuses_a_directory_whose_manifest_does_not_verify(tmp_path, tamper, capsys):
    """Any _report.json (even an empty one a user made) used to let ``reproduce --out`` write into the
    directory: only the report's own manifest, with every file listed and unchanged, does now."""
    import json

    from hyperlattice import __version__
    from hyperlattice.cli import main
    from hyperlattice.report import MARKER, manifest

    out = tmp_path / "mine"
    out.mkdir()
    (out / "notes.txt").write_text("my notes")
    if tamper == "empty marker":
        (out / MARKER).write_text("")
    elif tamper == "braces":
        (out / MARKER).write_text("{}")
    elif tamper == "old format":
        (out / MARKER).write_text(json.dumps({"format": "hyperlattice-report/1", "version": __version__}))
    else:
        (out / "notes.txt").unlink()
        manifest.start(out, __version__)
        with manifest.writing(out, "report.md") as path:
            path.write_text("the report")
        if tamper == "added file":
            (out / "notes.txt").write_text("my notes")
        elif tamper == "edited output":
            (out / "report.md").write_text("my own edits")
        elif tamper == "listed directory":
            (out / "report.md").unlink()
            (out / "report.md").mkdir()
        else:
            data = json.loads((out / MARKER).read_text())
            data["files"]["report.md"] = "0" * 64
            (out / MARKER).write_text(json.dumps(data))
    before = sorted((f.name, f.stat().st_mtime_ns) for f in out.iterdir())
    assert main(["reproduce", "--out", str(out), "--max-rings", "2", "--no-cache"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "not a report directory" in err, err
    assert sorted((f.name, f.stat().st_mtime_ns) for f in out.iterdir()) == before
