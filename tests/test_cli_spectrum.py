"""``hyperlattice spectrum``: the JSON contract, sectors, line graph, errors."""

import json

import numpy as np
import pytest

from hyperlattice.cli import main
from hyperlattice.paper_values import paper_value

KEYS = {"p", "q", "rings", "sites", "method", "energies", "n", "m", "sector", "residuals", "continuum_energies",
        "ambiguous", "split"}


def run_json(capsys, *argv):
    assert main(["spectrum", *argv, "--json"]) == 0
    return json.loads(capsys.readouterr().out)


def test_json_contract(capsys):
    out = run_json(capsys, "-p", "7", "-q", "3", "--rings", "5", "--levels", "4")
    assert set(out) == KEYS
    assert (out["p"], out["q"], out["rings"], out["sites"]) == (7, 3, 5, 847)
    assert out["method"] in ("dense", "sparse", "sector-dense", "sector-sparse", "sector-shift-invert")
    lengths = {len(out[k]) for k in ("energies", "n", "m", "sector", "residuals", "continuum_energies")}
    assert lengths == {4}
    assert out["energies"] == sorted(out["energies"])
    # degenerate +-1 pair listed once per state, +m first
    assert out["m"] == [0, 1, -1, 2] and out["n"] == [1, 1, 1, 1] and out["sector"] == [0, 1, 6, 2]
    assert out["energies"][1] == out["energies"][2]
    assert out["ambiguous"] == [] and out["split"] == []
    assert max(out["residuals"]) < 1e-10
    assert abs(out["energies"][0] - paper_value("E0_graph", 5).value) < 5e-4  # paper, Tab1, l = 5


def test_sector_accepts_signed_and_unsigned(capsys):
    a = run_json(capsys, "--rings", "4", "--levels", "3", "--sector", "6")
    b = run_json(capsys, "--rings", "4", "--levels", "3", "--sector", "-1")
    assert a == b
    # the lattice knows sector 6 = -1 mod 7; its second level continues the continuum (1, 6), not (2, -1)
    assert a["sector"] == [6, 6, 6]
    assert a["m"] == [-1, 6, -1] and a["n"] == [1, 1, 2]


def test_line_graph(capsys):
    out = run_json(capsys, "--rings", "3", "--levels", "2", "--line-graph")
    assert out["sites"] == 140  # edges of the 3-ring lattice
    assert len(out["energies"]) == 2


def test_table_output(capsys):
    assert main(["spectrum", "--rings", "2", "--levels", "3"]) == 0
    text = capsys.readouterr().out
    assert "method=sector-dense" in text and "-2.636404" in text
    assert "sector" in text.splitlines()[1] and "continuum level each state continues" in text


def test_labels_are_the_continuum_levels_the_states_continue(capsys):
    """Issue 28 item 1: {8,3}, l = 8, ten levels. The lattice knows m only modulo 8: the two states of
    sector 4 continue the continuum pair (1, +-4), which the lattice splits by ~0.1 %, and the tenth
    state is (1, 5) (sector 5) - before, they were labelled (2, 4) and (2, 3)."""
    out = run_json(capsys, "-p", "8", "--rings", "8", "--levels", "10")
    assert out["m"] == [0, 1, -1, 2, -2, 3, -3, 4, -4, 5]
    assert out["n"] == [1] * 10
    assert out["sector"] == [0, 1, 7, 2, 6, 3, 5, 4, 4, 5]
    assert out["ambiguous"] == []
    (split,) = out["split"]
    assert (split["n"], split["m"], split["levels"], split["resolved"]) == (1, 4, [7, 8], True)
    assert 0.0025 < split["splitting"] < 0.003 and 0.0009 < split["relative"] < 0.0011
    # the same run as a table says so in words
    assert main(["spectrum", "-p", "8", "--rings", "8", "--levels", "10"]) == 0
    text = capsys.readouterr().out
    assert "splits the continuum pair (n, m) = (1, ±4) by 0.00278 (0.10%)" in text


def test_labels_with_flux_match_the_magnetic_levels(capsys):
    out = run_json(capsys, "--rings", "4", "--levels", "4", "--flux", "0.1")
    assert out["flux"] == 0.1 and out["split"] == []
    assert out["m"] == [0, 1, 2, 3] and out["sector"] == [0, 1, 2, 3]


@pytest.mark.parametrize("argv,match", [
    (["--sector", "7"], "sector m must be in range"),
    (["--sector", "x"], "sector m must be an integer"),
    (["--tol", "-1"], "tol"),
    (["-p", "6", "-q", "3"], ""),
    # more levels than states used to be cut silently to N (the 35 states of two rings)
    (["--levels", "10000"], "levels = 10,000 exceeds the 35 states"),
    (["--levels", "36", "--method", "dense"], "exceeds the 35 states"),
    (["--levels", "36", "--method", "sparse"], "exceeds the 35 states"),
    (["--tol", "nan"], "tol"),
])
def test_errors_are_one_line_and_exit_2(capsys, argv, match):
    assert main(["spectrum", "--rings", "2", *argv]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "error" in err and match in err


def test_argparse_errors_exit_2(capsys):
    with pytest.raises(SystemExit) as exc:
        main(["spectrum", "--rings", "0"])
    assert exc.value.code == 2
    assert np.char.count(capsys.readouterr().err, "\n") == 1


def test_all_states_by_levels_equal_to_n(capsys):
    out = run_json(capsys, "--rings", "2", "--levels", "35")
    assert len(out["energies"]) == 35 and out["sites"] == 35


@pytest.mark.slow
def test_line_graph_at_ten_rings(capsys):
    # used to fail (wrong line-graph rotation from ten rings on)
    out = run_json(capsys, "--rings", "10", "--levels", "2", "--line-graph")
    assert out["sites"] == 135_135 and out["m"] == [0, 1] and out["method"] == "sector-shift-invert"
    assert max(out["residuals"]) < 1e-10


def test_a_command_imports_only_its_own_module(capsys):
    # start-up (issue 20): `hyperlattice spectrum` must not import every command (cmd_scaling pulls
    # scipy.integrate, ~0.5 s); a fresh interpreter, since this process has imported them all
    import os
    import subprocess
    import sys
    from pathlib import Path

    src = str(Path(__file__).resolve().parents[1] / "src")
    code = ("import sys, io, contextlib; from hyperlattice.cli import main\n"
            "with contextlib.redirect_stdout(io.StringIO()): rc = main(['spectrum', '--rings', '2', '--json'])\n"
            "print(rc, sorted(m for m in sys.modules if m.startswith('hyperlattice.cli.cmd_')))")
    env = dict(os.environ, PYTHONPATH=src + os.pathsep + os.environ.get("PYTHONPATH", ""))
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, timeout=120)
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip() == "0 ['hyperlattice.cli.cmd_spectrum']"
    # an unknown word still gets the full parser: its one-line error lists every command
    with pytest.raises(SystemExit) as info:
        main(["spectrm"])
    err = capsys.readouterr().err.strip().splitlines()
    assert info.value.code == 2 and len(err) == 1 and "'scaling'" in err[0] and "'spectrum'" in err[0]


def test_levels_stand_alone_when_the_continuum_refuses(capsys, monkeypatch):
    """A continuum request beyond its cost limit leaves the graph levels with their sectors and says why."""
    import hyperlattice.compare.levels as lv

    def refuse(spec, **_):
        raise ValueError("the continuum levels needed would take too long.")

    monkeypatch.setattr(lv, "continuum_labels", refuse)
    out = run_json(capsys, "--rings", "2", "--levels", "3")
    assert out["n"] is None and out["m"] is None and out["sector"] == [0, 1, 6]
    assert out["labels_note"] == "the continuum levels needed would take too long."
    assert main(["spectrum", "--rings", "2", "--levels", "3"]) == 0
    text = capsys.readouterr().out
    assert "no continuum labels: the continuum levels needed would take too long." in text
