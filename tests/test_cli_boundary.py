"""The ``boundary`` command: JSON keys and CSV columns (issue contract), consistency, errors."""

import csv
import json
import math

import numpy as np
import pytest

from hyperlattice.cli import main
from hyperlattice.compare.boundary import boundary_correlator, outer_ring
from hyperlattice.graph.lattice import ring_lattice

KEYS = ["p", "q", "rings", "omega", "lambda", "mass2", "delta_continuum", "delta_lattice", "delta_lattice_err",
        "mass2_ads_radius_1", "ads_radius", "mass2_input", "delta_formulas", "delta_continuum_improved",
        "delta_lattice_stat", "delta_lattice_window", "delta_lattice_sys", "delta_lattice_sys_rings",
        "delta_lattice_sys_spacing", "delta_lattice_total_err"]


def test_json_contract(capsys):
    assert main(["boundary", "-p", "7", "-q", "3", "--rings", "5", "--omega=-3.2", "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    assert list(d) == KEYS
    ref = boundary_correlator(ring_lattice(7, 3, 5), -3.2)
    assert d["delta_lattice"] == ref.delta_lattice and d["lambda"] == ref.lam and d["mass2"] == -ref.lam
    assert d["rings"] == 5 and d["omega"] == -3.2
    assert d["delta_lattice_sys"] == ref.delta_lattice_sys and d["delta_lattice_total_err"] == ref.delta_lattice_total_err


def test_mass2_with_ads_radius(capsys):
    """Issue 28 item 2: --mass2 1 --ads-radius 1 is unit-radius AdS2 (Delta = 1.618), and the output shows
    both conventions' formulas and the systematic error beside the fit error."""
    assert main(["boundary", "--rings", "6", "--mass2", "1", "--ads-radius", "1"]) == 0
    text = capsys.readouterr().out
    assert "mass^2 = 4 in the paper's metric (AdS radius 1/2) = 1 in unit-radius AdS2" in text
    assert "1/2 + sqrt(1 + m^2)/2 = 1.207107" in text and "1/2 + sqrt(1/4 + m^2) = 1.618034" in text
    assert "Delta continuum = 1.618034" in text and "systematic (lattice spacing" in text
    assert main(["boundary", "--rings", "6", "--mass2", "1", "--ads-radius", "0.5", "--json",
                 "--no-systematic"]) == 0
    d = json.loads(capsys.readouterr().out)
    assert abs(d["delta_continuum"] - 1.2071067811865475) < 1e-12 and d["delta_lattice_sys"] is None


@pytest.mark.parametrize("argv,match", [
    (["--mass2", "1"], "needs ads_radius"),
    (["--mass2", "1", "--ads-radius", "2"], "names the convention"),
    (["--ads-radius", "1"], "give it with --mass2"),
    (["--mass2", "1", "--ads-radius", "1", "--omega=-3.5"], "not both"),
])
def test_mass2_refusals_are_one_line(capsys, argv, match):
    assert main(["boundary", "--rings", "4", *argv]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and match in err


def test_json_beyond_bf_bound_is_null(capsys):
    assert main(["boundary", "--rings", "5", "--omega=-2.93", "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    assert d["delta_continuum"] is None and d["delta_lattice"] > 0


def test_csv_contract(tmp_path, capsys):
    out = tmp_path / "b.csv"
    assert main(["boundary", "--rings", "5", "--omega=-3.0", "--out", str(out)]) == 0
    with open(out) as fh:
        rows = list(csv.DictReader(fh))
    assert list(rows[0]) == ["site", "theta", "graph", "continuum"]
    lat = ring_lattice(7, 3, 5)
    ring = outer_ring(lat)
    assert [int(r["site"]) for r in rows] == ring.tolist()           # one row per outer-ring site
    ref = boundary_correlator(lat, -3.0)                             # default source: first outer site
    assert np.array_equal([float(r["graph"]) for r in rows], ref.graph)   # G_ij itself
    c = np.array([float(r["continuum"]) for r in rows])
    assert math.isinf(c[0]) and np.allclose(c[1:], ref.continuum[1:], rtol=1e-15)
    assert np.allclose([float(r["theta"]) for r in rows], ref.theta)


def test_site_plot_and_text(tmp_path, capsys):
    lat = ring_lattice(7, 3, 5)
    site = int(outer_ring(lat)[17])
    fig = tmp_path / "b.png"
    assert main(["boundary", "--rings", "5", "--site", str(site), "--plot", str(fig)]) == 0
    assert fig.stat().st_size > 1000
    out = capsys.readouterr().out
    assert f"source {site}" in out and "Delta lattice" in out


def test_errors_exit_2(capsys, tmp_path):
    for argv in (["boundary", "--rings", "5", "--site", "0"],                 # not on the outer ring
                 ["boundary", "--rings", "5", "--omega=-2.0"],                # in the band
                 ["boundary", "--rings", "5", "--site", "99999"],
                 ["boundary", "--rings", "2"],                                # too few rings for the window
                 ["boundary", "--rings", "4", "--plot", str(tmp_path / "x")],  # no suffix
                 ["boundary", "--rings", "4", "--out", str(tmp_path)]):
        try:
            code = main(argv)
        except SystemExit as exc:       # argparse refuses the value itself
            code = exc.code
        assert code == 2
        err = capsys.readouterr().err
        assert len(err.strip().splitlines()) == 1 and "Traceback" not in err


@pytest.mark.slow
def test_csv_dirichlet_continuum_keeps_the_columns(tmp_path, capsys):
    out = tmp_path / "d.csv"
    assert main(["boundary", "--rings", "5", "--omega=-3.2", "--continuum-disk", "dirichlet", "--out", str(out)]) == 0
    with open(out) as fh:
        rows = list(csv.DictReader(fh))
    assert list(rows[0]) == ["site", "theta", "graph", "continuum"]
    ref = boundary_correlator(ring_lattice(7, 3, 5), -3.2, continuum_disk="dirichlet")
    got = np.array([float(r["continuum"]) for r in rows])
    assert np.array_equal(np.isnan(got), np.isnan(ref.continuum)) and np.any(np.isnan(got))
    k = np.isfinite(ref.continuum)
    assert np.array_equal(got[k], ref.continuum[k])
