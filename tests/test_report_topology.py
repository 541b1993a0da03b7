"""The report's topology section: the {8,3} QWZ rows (flake beside cluster) and the stored Haldane scan."""

from __future__ import annotations

import math

import pytest

from hyperlattice.report.topology import qwz_phase_rows, stored_haldane_scan, topology_section


@pytest.mark.machine_independence
def test_qwz_rows_put_flake_and_cluster_side_by_side():
    """M = 1: Chern insulator (Bolza gcd 1, one e²/h); M = 2.5: trivial (gcd 0, no conductance)."""
    topo, trivial = qwz_phase_rows([1.0, 2.5], rings=3)
    assert topo["gcd"] == 1 and abs(topo["conductance"] - 1) < 1e-3 and topo["marker"] < -0.5
    assert trivial["gcd"] == 0 and trivial["conductance"] < 1e-3 and abs(trivial["marker"]) < 0.05


def test_stored_haldane_scan_is_consistent():
    """Every scanned row is in a gap of the centre's LDOS; a confirmed clean row has G and the marker on one integer."""
    scan = stored_haldane_scan()
    assert scan["meta"]["confirm_rings"] == scan["meta"]["rings"] + 1
    for r in scan["scan"]:
        assert r["gap"] > 0 and 0 < r["filling"] < 1 and math.isfinite(r["marker"])
    clean = [r for r in scan["confirm"] if abs(r["conductance"] - round(r["conductance"])) < 0.01
             and round(r["conductance"]) >= 1 and abs(r["marker_R6"] - round(r["conductance"])) < 0.05]
    assert clean, "the stored scan holds no clean Chern insulator"


@pytest.mark.slow
def test_section_has_its_tables_and_figure(tmp_path):
    sec = topology_section(tmp_path, lambda msg: None)
    assert [t.name for t in sec.tables] == ["topology_qwz", "topology_haldane", "topology_haldane_confirm"]
    assert (tmp_path / "fig_topology_qwz.png").exists() and sec.part == "beyond"
    assert "clean Chern insulator" in sec.text[1]
