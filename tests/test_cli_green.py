"""The ``green`` command: CSV columns, JSON keys, consistency with the library, errors."""

import csv
import json
import math

import numpy as np
import pytest

from hyperlattice.cli import main
from hyperlattice.compare.green import compare_green
from hyperlattice.graph.lattice import ring_lattice

COLUMNS = "site,ring,re_z,im_z,distance,graph_re,graph_im,continuum_re,continuum_im".split(",")


def test_csv_contract(tmp_path, capsys):
    out = tmp_path / "g.csv"
    assert main(["green", "-p", "7", "-q", "3", "--rings", "3", "--omega=-2.95", "--site", "10", "--out", str(out)]) == 0
    with open(out) as fh:
        rows = list(csv.DictReader(fh))
    assert list(rows[0].keys()) == COLUMNS
    lat = ring_lattice(7, 3, 3)
    assert len(rows) == lat.sites
    ref = compare_green(lat, -2.95, 10)
    g = np.array([float(r["graph_re"]) + 1j * float(r["graph_im"]) for r in rows])
    c = np.array([float(r["continuum_re"]) + 1j * float(r["continuum_im"]) for r in rows])
    assert np.allclose(g, ref.graph, rtol=1e-15)
    keep = np.arange(lat.sites) != 10
    assert np.allclose(c[keep], ref.continuum[keep], rtol=1e-15)
    assert math.isinf(c[10].real)                      # continuum G is singular at the source
    assert [int(r["ring"]) for r in rows] == lat.ring.tolist()
    assert np.allclose([float(r["distance"]) for r in rows], ref.distance)
    # graph and continuum columns are directly comparable (same normalization, eq21)
    assert np.linalg.norm(g[keep] - c[keep]) / np.linalg.norm(g[keep]) == pytest.approx(ref.rel_l2)


def test_json_keys_complex_omega(capsys):
    assert main(["green", "--rings", "3", "--omega=-2.5+0.1j", "--site", "10", "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    assert set(d) == {"p", "q", "rings", "site", "omega", "lambda", "radius", "rel_l2"}
    assert d["omega"] == {"re": -2.5, "im": 0.1}
    assert d["lambda"]["im"] > 0 and 0 < d["rel_l2"] < 1
    assert d["radius"] == pytest.approx(math.sqrt(112 / 140))


@pytest.mark.parametrize("argv,msg", [
    (["green", "--rings", "3", "--site", "112"], "not a site"),
    (["green", "--rings", "3", "--omega=nan"], "finite"),
])
def test_errors_exit_2(argv, msg, capsys):
    # run-time ValueError -> return code 2; argparse type errors -> SystemExit(2)
    try:
        code = main(argv)
    except SystemExit as exc:
        code = exc.code
    assert code == 2
    err = capsys.readouterr().err
    assert msg in err and err.count("\n") <= 3


@pytest.mark.parametrize("where", ["directory", "missing-folder"])
def test_unwritable_out_refused_before_computing(where, tmp_path, capsys, monkeypatch):
    import hyperlattice.compare.green as cg

    def fail(*args, **kwargs):
        raise AssertionError("computed before checking --out")

    monkeypatch.setattr(cg, "compare_green", fail)
    target = tmp_path if where == "directory" else tmp_path / "no" / "g.csv"
    assert main(["green", "--rings", "2", "--out", str(target)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and ("--out" in err or "cannot write" in err)


@pytest.mark.parametrize("tol", ["3.5", "0", "-1", "nan", "1e400"])
def test_tol_must_be_a_tolerance(tol, capsys):
    with pytest.raises(SystemExit) as exc:
        main(["green", "--rings", "2", f"--tol={tol}"])
    assert exc.value.code == 2 and capsys.readouterr().err.count("\n") == 1


def test_oserror_while_writing_is_one_line(tmp_path, capsys, monkeypatch):
    """A write that fails after the checks (disk full, ...) gives one line and exit 2."""
    import builtins

    real_open = builtins.open

    def full_disk(path, *args, **kwargs):
        if str(path).endswith("g.csv"):
            raise OSError(28, "No space left on device", str(path))
        return real_open(path, *args, **kwargs)

    monkeypatch.setattr(builtins, "open", full_disk)
    assert main(["green", "--rings", "2", "--out", str(tmp_path / "g.csv")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "No space left on device" in err and "Traceback" not in err
