"""``hyperlattice topology cluster --chern2 / --spin-chern`` and ``topology landau``: keys and errors."""

from __future__ import annotations

import json

from hyperlattice.cli import main


def test_cluster_spin_chern_keys(capsys):
    assert main(["topology", "cluster", "--model", "kane-mele", "--cluster", "bolza", "--M", "0", "--t2", "0.3",
                 "--spin-chern", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    for key in ("chern", "gcd", "pfaffian", "gap", "spin_chern", "z2", "chern_up", "chern_down"):
        assert key in out
    assert out["chern_up"] == out["spin_chern"]


def test_landau_keys(capsys):
    assert main(["topology", "landau", "--cluster", "bolza", "--nphi", "3", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["bands"] == [2] and out["degeneracy"] == [2] and len(out["intersection"]) == 4


def test_spin_chern_needs_kane_mele(capsys):
    assert main(["topology", "cluster", "--cluster", "bolza", "--spin-chern"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "kane-mele" in err[0]


def test_landau_too_much_flux_is_one_line(capsys):
    assert main(["topology", "landau", "--cluster", "bolza", "--nphi", "7"]) == 2
    assert len(capsys.readouterr().err.strip().splitlines()) == 1


def test_cluster_covariant_frame_keys(capsys):
    assert main(["topology", "cluster", "--cluster", "bolza", "--frame", "covariant", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    for key in ("chern", "gcd", "pfaffian", "gap"):
        assert key in out
    assert out["gcd"] == 1 and abs(out["pfaffian"]) == 1 and out["frame"] == "covariant"


def test_covariant_frame_needs_qwz(capsys):
    assert main(["topology", "cluster", "--cluster", "bolza", "--model", "haldane", "--frame", "covariant"]) == 2
    assert len(capsys.readouterr().err.strip().splitlines()) == 1
