"""``hyperlattice bosons ed``: the contract (keys, ascending energies at mu = 0) and its errors."""

from __future__ import annotations

import json

import numpy as np
import pytest

from hyperlattice.cli import main

KEYS = ["sites", "particles", "nmax", "U", "t", "dim", "energies"]


def _json(capsys, argv):
    assert main(argv) == 0
    return json.loads(capsys.readouterr().out)


def test_flake_contract(capsys):
    out = _json(capsys, ["bosons", "ed", "--rings", "1", "-p", "7", "-q", "3", "--particles", "3", "--nmax", "2",
                         "--U", "1.7", "--levels", "5", "--json"])
    assert list(out)[: len(KEYS)] == KEYS
    assert (out["sites"], out["particles"], out["nmax"], out["U"], out["t"], out["dim"]) == (7, 3, 2, 1.7, 1.0, 77)
    e = np.array(out["energies"])
    assert e.shape == (5,) and np.all(np.diff(e) >= 0)
    assert out["method"] == "sectors" and len(out["m"]) == 5 and len(out["residuals"]) == 5
    # the same numbers as the API
    from hyperlattice import ring_lattice
    from hyperlattice.bosons.ed import bose_hubbard

    ref = bose_hubbard(ring_lattice(7, 3, 1), 3, 2, 1.7, levels=5, observables=False)
    assert np.array_equal(e, ref.energies)


def test_cluster_contract_and_hopping(capsys):
    out = _json(capsys, ["bosons", "ed", "--cluster", "bolza", "-p", "8", "-q", "3", "--particles", "2",
                         "--nmax", "1", "--U", "0", "--t", "0.5", "--levels", "2", "--json", "--observables"])
    assert out["sites"] == 16 and out["dim"] == 120 and out["t"] == 0.5 and out["cluster"] == "bolza"
    # two hard-core bosons with t = 1/2: at least the free value 2 * (-3 t) = -3 (hard-core repulsion)
    assert out["energies"][0] > -3.0
    assert 0 < out["condensate_fraction"] <= 1


def test_text_table(capsys):
    assert main(["bosons", "ed", "--rings", "1", "-p", "7", "--particles", "2", "--nmax", "2", "--U", "1",
                 "--levels", "3"]) == 0
    text = capsys.readouterr().out
    assert "dimension 28" in text and "residual" in text and "truncated" not in text


@pytest.mark.parametrize("argv,needle", [
    (["--rings", "1", "--particles", "2", "--nmax", "2"], "--U"),
    (["--rings", "1", "--cluster", "bolza", "--particles", "2", "--nmax", "2", "--U", "1"], "not allowed"),
    (["--cluster", "nowhere", "--particles", "2", "--nmax", "2", "--U", "1"], "unknown cluster"),
    (["--rings", "1", "--particles", "30", "--nmax", "2", "--U", "1"], "do not fit"),
    (["--rings", "1", "--particles", "2", "--nmax", "0", "--U", "1"], "nmax"),
    (["--rings", "1", "--particles", "2", "--nmax", "2", "--U", "nan"], "--U"),
    (["--rings", "1", "--particles", "-1", "--nmax", "2", "--U", "1"], "--particles"),
    (["--rings", "1", "-p", "5", "--particles", "2", "--nmax", "2", "--U", "1"], "{5,3}"),
    (["--cluster", "klein", "-p", "8", "--particles", "2", "--nmax", "2", "--U", "1"], "klein"),
    (["--rings", "4", "--particles", "60", "--nmax", "3", "--U", "1"], "needs about"),
])
def test_bad_input_one_line_exit_2(argv, needle, capsys):
    try:
        code = main(["bosons", "ed", *argv, "--json"])
    except SystemExit as exc:  # argparse's own errors (one line, see cli._OneLineParser)
        code = exc.code
    assert code == 2
    captured = capsys.readouterr()
    assert captured.out == ""
    err = captured.err.strip()
    assert "\n" not in err and needle in err and "Traceback" not in err


def test_more_levels_than_states_is_said(capsys):
    # issue 28 item 6: --levels 8 on a 7-state basis returned 7 levels without a word
    import json as _json

    from hyperlattice.bosons.ed import bose_hubbard
    from hyperlattice.graph.lattice import ring_lattice

    res = bose_hubbard(ring_lattice(7, 3, 1), 1, 1, 1.0, levels=8)
    assert res.energies.size == 7 and res.note == "8 levels asked, but the basis has only 7 states: all 7 are listed."
    assert bose_hubbard(ring_lattice(7, 3, 1), 1, 1, 1.0, levels=7).note == ""
    args = ["bosons", "ed", "--rings", "1", "--particles", "1", "--nmax", "1", "--U", "1", "--levels", "8"]
    assert main(args) == 0
    assert "note: 8 levels asked, but the basis has only 7 states" in capsys.readouterr().out
    assert main(args + ["--json"]) == 0
    assert _json.loads(capsys.readouterr().out)["note"].startswith("8 levels asked")
