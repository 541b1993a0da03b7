"""CLI contract for `hyperlattice geometry` and `hyperlattice lattice`."""

import json
import subprocess
import sys

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from hyperlattice.cli import main
from hyperlattice.paper_values import paper_value


def run_cli(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def test_geometry_json_keys_and_values(capsys):
    code, out, err = run_cli(capsys, "geometry", "-p", "7", "8", "9", "10", "inf", "--json")
    assert code == 0
    rows = json.loads(out)
    assert [r["p"] for r in rows] == [7, 8, 9, 10, "inf"]
    for r in rows:
        assert set(r) == {"p", "q", "r0", "d0", "h", "site_area"}
    assert round(rows[0]["h"], 6) == paper_value("geometry_h", 7).value
    assert rows[-1]["h"] == pytest.approx(0.5)


def test_lattice_json_contract(capsys):
    code, out, _ = run_cli(capsys, "lattice", "-p", "7", "-q", "3", "--rings", "6", "--json")
    assert code == 0
    info = json.loads(out)
    for key in ("p", "q", "rings", "sites", "edges", "sites_per_ring", "d0", "h", "radius"):
        assert key in info
    assert info["sites"] == 2240 and info["edges"] == 2856
    assert info["sites_per_ring"] == [7, 28, 77, 203, 532, 1393]
    assert info["radius"] == pytest.approx(np.sqrt(2240 / 2268))


def test_lattice_writes_dat_and_npz(tmp_path, capsys):
    dat = tmp_path / "coordinates.dat"
    assert main(["lattice", "--rings", "6", "--out", str(dat)]) == 0
    assert np.loadtxt(dat).shape == (2240, 2)
    assert "written to" in capsys.readouterr().out
    npz = tmp_path / "lg.npz"
    assert main(["lattice", "--rings", "3", "--line-graph", "--out", str(npz), "--json"]) == 0
    info = json.loads(capsys.readouterr().out)
    with np.load(npz) as f:
        assert f["z"].shape == (info["sites"],) and str(f["kind"]) == "line_graph"


@pytest.mark.parametrize(
    "argv",
    [
        ["lattice", "-p", "6", "-q", "3"],
        ["lattice", "-p", "4", "-q", "4"],
        ["lattice", "--rings", "0"],
        ["lattice", "--rings", "-2"],
        ["lattice", "--rings", "two"],
        ["lattice", "--rings", "40"],
        ["lattice", "--out", "x.txt"],
        ["geometry", "-p", "5"],
        ["geometry", "-p", "seven"],
        ["nonsense"],
    ],
)
def test_errors_are_one_line_and_exit_2(argv, capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    with pytest.raises(SystemExit) as exc:
        sys.exit(main(argv))
    assert exc.value.code == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "error" in err and "Traceback" not in err


@settings(max_examples=40, deadline=None)
@given(p=st.integers(-3, 12), q=st.integers(-3, 12), rings=st.integers(-3, 3))
def test_any_invalid_combination_exits_2(p, q, rings):
    valid = p >= 3 and q >= 3 and (p - 2) * (q - 2) > 4 and rings >= 1
    try:
        code = main(["lattice", "-p", str(p), "-q", str(q), "--rings", str(rings), "--json"])
    except SystemExit as exc:
        code = exc.code
    assert (code == 0) == valid
    if not valid:
        assert code == 2


def test_console_script_runs_as_module():
    res = subprocess.run([sys.executable, "-m", "hyperlattice", "lattice", "--rings", "2", "--json"],
                         capture_output=True, text=True, check=True)
    assert json.loads(res.stdout)["sites"] == 35
    bad = subprocess.run([sys.executable, "-m", "hyperlattice", "lattice", "-p", "5"], capture_output=True, text=True)
    assert bad.returncode == 2 and bad.stderr.count("\n") == 1 and bad.stdout == ""
