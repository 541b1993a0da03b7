"""CLI contract of issue 11: ``--flux`` on spectrum and continuum, the ``butterfly`` command."""

import csv
import json

import numpy as np
import pytest

from hyperlattice.cli import main
from hyperlattice.continuum.magnetic import magnetic_levels
from hyperlattice.graph.butterfly import butterfly
from hyperlattice.graph.lattice import ring_lattice
from hyperlattice.graph.spectrum import lowest_levels

SPECTRUM_KEYS = {"p", "q", "rings", "sites", "method", "energies", "n", "m", "sector", "residuals", "continuum_energies",
                 "ambiguous", "split"}
CONTINUUM_KEYS = {"p", "q", "rings", "radius", "h", "energies", "n", "m", "k", "asymptotic"}


def run_cli(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def test_spectrum_flux_json(capsys):
    code, out, _ = run_cli(capsys, "spectrum", "--rings", "3", "--levels", "3", "--flux", "0.1", "--json")
    assert code == 0
    d = json.loads(out)
    assert set(d) == SPECTRUM_KEYS | {"flux"} and d["flux"] == 0.1
    ref = lowest_levels(ring_lattice(7, 3, 3), 3, flux=0.1)
    np.testing.assert_allclose(d["energies"], ref.energies, rtol=0, atol=1e-12)
    assert d["m"] == [int(v) for v in ref.m] and d["m"][:2] == [0, 1]
    assert d["sector"] == [int(v) for v in ref.sector] and d["split"] == []      # a field leaves no +-m pair


def test_spectrum_flux_zero_keeps_numbers(capsys):
    _, out0, _ = run_cli(capsys, "spectrum", "--rings", "3", "--json")
    _, out1, _ = run_cli(capsys, "spectrum", "--rings", "3", "--json", "--flux", "0")
    d0, d1 = json.loads(out0), json.loads(out1)
    assert "flux" not in d0 and d1.pop("flux") == 0.0
    assert d0 == d1


def test_continuum_flux_json(capsys):
    code, out, _ = run_cli(capsys, "continuum", "--rings", "4", "--levels", "3", "--flux", "0.1", "--json")
    assert code == 0
    d = json.loads(out)
    assert set(d) == CONTINUUM_KEYS | {"flux"} and d["flux"] == 0.1
    ref = magnetic_levels(7, 3, rings=4, levels=3, flux=0.1)
    np.testing.assert_allclose(d["energies"], ref.energies, rtol=0, atol=1e-14)
    assert d["m"] == [0, 1, 2]


def test_continuum_flux_zero_keeps_numbers(capsys):
    _, out0, _ = run_cli(capsys, "continuum", "--rings", "4", "--json")
    _, out1, _ = run_cli(capsys, "continuum", "--rings", "4", "--json", "--flux", "0")
    d0, d1 = json.loads(out0), json.loads(out1)
    assert set(d0) == CONTINUUM_KEYS and d1.pop("flux") == 0.0
    assert d0 == d1


def test_text_output_with_flux(capsys):
    code, out, _ = run_cli(capsys, "spectrum", "--rings", "3", "--flux", "0.2")
    assert code == 0 and "flux=0.2" in out and "degenerate" not in out
    # regression: the zero-field "deg" column (2 for m != 0) was printed with flux, where m and -m split
    assert "deg" not in out.splitlines()[1]
    code, out, _ = run_cli(capsys, "continuum", "--rings", "3", "--flux", "0.2")
    assert code == 0 and "flux=0.2" in out


def test_butterfly_table_and_figure(capsys, tmp_path):
    png, table = tmp_path / "b.png", tmp_path / "b.csv"
    code, out, _ = run_cli(capsys, "butterfly", "--rings", "3", "--fluxes", "5", "--out", str(png),
                           "--table", str(table), "--json")
    assert code == 0
    d = json.loads(out)
    assert d["fluxes"] == 5 and d["sites"] == 112 and (d["flux_min"], d["flux_max"]) == (0.0, 1.0)
    assert png.stat().st_size > 1000
    with open(table, newline="") as fh:
        rows = list(csv.reader(fh))
    assert rows[0] == ["flux", "m", "energy"] and len(rows) == 1 + 5 * 112
    ref = butterfly(ring_lattice(7, 3, 3), np.linspace(0, 1, 5))
    np.testing.assert_array_equal(np.array([float(r[2]) for r in rows[1:]]), ref.energies.ravel())
    np.testing.assert_array_equal(np.array([int(r[1]) for r in rows[1:]]), ref.m.ravel())


def test_butterfly_svg_with_continuum(capsys, tmp_path):
    svg = tmp_path / "b.svg"
    code, _, _ = run_cli(capsys, "butterfly", "--rings", "3", "--fluxes", "3", "--out", str(svg), "--continuum")
    assert code == 0 and svg.read_text().lstrip().startswith("<?xml")


@pytest.mark.parametrize("argv, words", [
    (["butterfly", "--out", "/nonexistent-dir/b.png"], "does not exist"),
    (["butterfly", "--out", "b.txt"], "must end in"),
    (["butterfly", "--table", "b.txt"], "must end in .csv"),
    (["butterfly", "--fluxes", "0"], "--fluxes"),
    (["butterfly", "--fluxes", "100000"], "--fluxes"),
    (["butterfly", "-p", "2"], ""),
    (["butterfly", "--rings", "0"], "--rings"),
    (["spectrum", "--flux", "nan"], "--flux"),
    (["spectrum", "--flux", "1e9"], "flux"),
    (["continuum", "--flux", "inf"], "--flux"),
    (["continuum", "--flux", "1e9"], "flux"),
])
def test_bad_values_one_line_exit_2(capsys, tmp_path, monkeypatch, argv, words):
    monkeypatch.chdir(tmp_path)
    with pytest.raises(SystemExit) as exc:
        code = main(argv)
        raise SystemExit(code)
    assert exc.value.code == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and words in err and "Traceback" not in err


def test_butterfly_output_checked_before_computing(capsys, monkeypatch, tmp_path):
    import hyperlattice.graph.butterfly as flux

    def boom(*a, **k):
        raise AssertionError("computed before checking --out")

    monkeypatch.setattr(flux, "butterfly", boom)
    code = main(["butterfly", "--out", str(tmp_path / "missing" / "b.png")])
    assert code == 2
