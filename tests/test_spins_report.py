"""The report's magnetism section (hyperlattice.report.magnetism): its stored runs, tables and sentences."""

from __future__ import annotations

import math

import pytest

from hyperlattice.report.magnetism import (FLAKE_HEADER, TC_HEADER, bethe_tc, flake_rows, magnetism_section,
                                           stored_spins, tc_rows)


def test_stored_runs_and_tables():
    data = stored_spins()
    assert bethe_tc(3) == pytest.approx(1.0 / math.atanh(0.5)) and bethe_tc(4) == pytest.approx(2.8854, abs=1e-4)
    rows = tc_rows(data)
    assert [r[0] for r in rows] == ["{7,3}", "{8,3}", "{5,4}"] and all(len(r) == len(TC_HEADER) for r in rows)
    for key in ("7,3", "8,3", "5,4"):
        t = data["closed"][key]
        # every T_c lies below its Bethe value, the exponent of chi near the mean-field 1/2
        assert t["tc"] + 4 * t["tc_err"] < bethe_tc(t["q"]) and abs(t["chi_exponent"] - 0.5) < 0.1
        assert len(t["clusters"]) >= 3
    fl = flake_rows(data)
    assert len(fl) == len(data["flakes"]) and all(len(r) == len(FLAKE_HEADER) for r in fl)
    for f in data["flakes"].values():          # two scales: the bulk aligns far above the boundary
        assert f["T_half_bulk"] - f["T_half_boundary"] > 10 * math.hypot(f["T_half_bulk_err"], f["T_half_boundary_err"])


@pytest.mark.slow
def test_section(tmp_path):
    sec = magnetism_section(tmp_path, lambda msg: None)
    assert sec.anchor == "magnetism" and len(sec.tables) == 4 and len(sec.figures) == 2
    assert (tmp_path / "fig_spins_flakes.png").stat().st_size > 0
    q = sec.tables[3].rows[0]
    e, err = (float(x.replace("−", "-")) for x in q[2].split(" ± "))
    assert abs(e - float(q[3].replace("−", "-"))) < 4 * err          # SSE against exact diagonalisation
