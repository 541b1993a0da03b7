"""``hyperlattice fluxmap``: the (f, l) comparison of graph and continuum levels with flux."""

import csv
import json

import numpy as np
import pytest

from hyperlattice.cli import main
from hyperlattice.compare.magnetic import magnetic_comparison


def test_json_table_and_figure_agree_with_the_api(tmp_path, capsys):
    out, table = tmp_path / "map.png", tmp_path / "map.csv"
    code = main(["fluxmap", "--rings", "2,3", "--fluxes", "3", "--fmax", "0.2", "--out", str(out),
                 "--table", str(table), "--json"])
    assert code == 0
    got = json.loads(capsys.readouterr().out)
    ref = magnetic_comparison(7, 3, rings=(2, 3), fluxes=np.linspace(0, 0.2, 3), levels=2)
    assert got["rings"] == [2, 3] and got["fluxes"] == [0.0, 0.1, 0.2]
    assert got["statement"] == ref.statement()
    assert got["max_relative_error"] == pytest.approx(float(np.nanmax(ref.relative_error)), rel=1e-12)
    assert out.stat().st_size > 10_000 and out.read_bytes()[:4] == b"\x89PNG"
    with table.open() as fh:
        rows = list(csv.DictReader(fh))
    assert len(rows) == 2 * 3 * 2
    assert set(rows[0]) == {"rings", "flux", "level", "n", "m", "E_graph", "E_continuum", "rel_error",
                            "lB_over_d0", "lB_over_R"}
    e = np.array([float(r["rel_error"]) for r in rows])
    np.testing.assert_array_equal(e, ref.relative_error.ravel())


def test_plain_output_is_the_statement(capsys):
    assert main(["fluxmap", "--rings", "2", "--fluxes", "2"]) == 0
    assert capsys.readouterr().out.startswith("Relative error of the 2 lowest levels below 0.001")


@pytest.mark.parametrize("words", [["--rings", "x"], ["--rings", "5-3"], ["--rings", "0"], ["--rings", "1-13"],
                                   ["--rings", "3-20"], ["--rings", "1-99999999999"], ["--fmax", "2"], ["--fmax", "-0.1"],
                                   ["--rings", "2", "--levels", "50"], ["--rings", "2", "--out", "map"],
                                   ["--rings", "2", "--table", "map.txt"]])
def test_bad_values_exit_2_with_one_line(words, capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    try:
        code = main(["fluxmap"] + words)
    except SystemExit as exc:
        code = exc.code
    err = capsys.readouterr().err
    assert code == 2 and len(err.strip().splitlines()) == 1, err
