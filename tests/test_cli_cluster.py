"""``hyperlattice cluster``: the contract (names, keys, arrays) and its errors."""

from __future__ import annotations

import json

import numpy as np
import pytest

from hyperlattice.cli import main

KEYS = ["name", "p", "q", "sites", "edges", "faces", "genus", "systole"]


@pytest.mark.slow
def test_list_json(capsys):
    assert main(["cluster", "-p", "8", "-q", "3", "--list", "--json", "--max-sites", "5000"]) == 0
    entries = json.loads(capsys.readouterr().out)
    assert isinstance(entries, list) and [e["name"] for e in entries][:2] == ["bolza", "dyck"]
    for e in entries:
        assert list(e) == KEYS
        assert (e["p"], e["q"]) == (8, 3)
    bolza = entries[0]
    assert (bolza["sites"], bolza["edges"], bolza["faces"], bolza["genus"]) == (16, 24, 6, 2)


@pytest.mark.slow
def test_list_default_reaches_1e5(capsys):
    assert main(["cluster", "-p", "7", "-q", "3", "--list", "--json"]) == 0
    entries = json.loads(capsys.readouterr().out)
    names = [e["name"] for e in entries]
    assert "klein" in names and "PSL(2,13)" in names
    assert max(e["sites"] for e in entries) <= 100_000


def test_list_text(capsys):
    assert main(["cluster", "-p", "7", "-q", "3", "--list", "--max-sites", "400"]) == 0
    out = capsys.readouterr().out
    assert "klein" in out and "PSL(2,13)" in out and "systole" in out


def test_name_out_npz(tmp_path, capsys):
    out = tmp_path / "klein.npz"
    assert main(["cluster", "-p", "7", "-q", "3", "--name", "klein", "--out", str(out)]) == 0
    with np.load(out) as data:
        assert set(data.files) == {"edges", "faces"}
        edges, faces = data["edges"], data["faces"]
    assert edges.shape == (84, 2) and faces.shape == (24, 7)
    assert edges.min() == 0 and edges.max() == 55 and faces.min() == 0 and faces.max() == 55
    # each face is a closed walk along the edges
    pairs = {tuple(sorted(e)) for e in edges.tolist()}
    for f in faces.tolist():
        for k in range(7):
            assert tuple(sorted((f[k], f[(k + 1) % 7]))) in pairs
    assert "klein" in capsys.readouterr().out


def test_name_json(capsys):
    assert main(["cluster", "-p", "8", "-q", "3", "--name", "PSL(2,17)", "--json"]) == 0
    info = json.loads(capsys.readouterr().out)
    assert info["sites"] == 816 and info["systole"] == 15 and info["systole_exact"] is True


def test_min_sites(capsys):
    assert main(["cluster", "-p", "7", "-q", "3", "--min-sites", "1000", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["name"] == "PSL(2,29)"


@pytest.mark.parametrize("argv", [
    ["cluster", "-p", "7", "-q", "3", "--name", "nope"],
    ["cluster", "-p", "7", "-q", "3", "--name", "bolza"],
    ["cluster", "-p", "4", "-q", "4", "--list"],
    ["cluster", "-p", "7", "-q", "3", "--list", "--name", "klein"],
    ["cluster", "-p", "7", "-q", "3", "--name", "klein", "--out", "x.csv"],
    ["cluster", "-p", "7", "-q", "3", "--name", "klein", "--out", "/nonexistent/dir/x.npz"],
    ["cluster", "-p", "7", "-q", "3", "--name", "PSL(2,99991)"],
])
def test_errors_are_one_line(argv, capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert len([line for line in err.splitlines() if line.strip()]) == 1 and "Traceback" not in err


def test_a_huge_min_sites_is_estimated_and_refused_before_work(capsys, monkeypatch):
    # issue 28 item 6: --min-sites 100000000 ran on past a minute with no estimate or refusal
    import hyperlattice.graph.clusters as clusters

    def never(*args, **kwargs):
        raise AssertionError("the cluster was built")

    monkeypatch.setattr(clusters, "_lookup", never)
    assert main(["cluster", "--min-sites", "100000000"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "PSL(2,853): 103,441,604 sites" in err and "smaller --min-sites" in err


@pytest.mark.parametrize("argv, head", [
    (["cluster", "--name", "Bolza"], "{8,3} cluster bolza: 16 sites"),             # case, and p from the name
    (["cluster", "--name", "KLEIN-DUAL"], "{3,7} cluster klein-dual: 24 sites"),
    (["cluster", "--name", "psl(2,13)"], "{7,3} cluster PSL(2,13)"),
    (["cluster", "--name", "Macbeath"], "{7,3} cluster macbeath: 168 sites, 252 edges, 72 faces, genus 7"),
    (["bosons", "meanfield", "--cluster", "BOLZA"], "{8,3} cluster bolza (16 sites)"),
    (["bosons", "ed", "--cluster", "bolza", "--particles", "1", "--nmax", "1", "--U", "1", "--levels", "1"],
     "Bose-Hubbard ED on the {8,3} cluster bolza"),
    (["dos", "--cluster", "Bolza", "--moments", "20", "--vectors", "2"], None),
])
def test_cluster_names_as_people_type_them(argv, head, capsys):
    # issue 28 item 5: names case-insensitive, p and q taken from a named cluster (no -p 8 needed)
    assert main(argv) == 0
    out = capsys.readouterr().out
    assert head is None or out.startswith(head), out[:200]


def test_a_typed_p_still_wins_and_is_checked(capsys):
    assert main(["cluster", "--name", "bolza", "-p", "7"]) == 2
    assert "is a {8,3} cluster, not {7,3}" in capsys.readouterr().err
