"""The topological Anderson insulator: the SCBA on the graph, the conductance sweep task, the stored scan."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

import hyperlattice as hl
from hyperlattice.topology import square_flake
from hyperlattice.topology.anderson import scba, scba_boundary

STORED = Path(__file__).resolve().parents[1] / "benchmarks" / "topology_tai_boundary.json"


def _bloch_scba(M: float, W: float, n: int = 200) -> tuple[complex, complex]:
    """The SCBA of square-lattice QWZ at E = 0 on an n x n Brillouin-zone grid (the reference)."""
    k = 2 * np.pi * (np.arange(n) + 0.5) / n
    kx, ky = np.meshgrid(k, k)
    s0 = sz = 0j
    for _ in range(2000):
        dz = M + sz + np.cos(kx) + np.cos(ky)
        e = -s0
        den = e * e - dz * dz - np.sin(kx) ** 2 - np.sin(ky) ** 2
        new0, newz = W * W / 12 * np.mean(e / den), W * W / 12 * np.mean(dz / den)
        if max(abs(new0 - s0), abs(newz - sz)) < 1e-13:
            break
        s0, sz = 0.5 * (s0 + new0), 0.5 * (sz + newz)
    return new0, newz


def test_the_graph_scba_is_the_bloch_scba_on_the_square_lattice():
    # a gapped (trivial, M = 2.5) square flake with an absorbing edge: its centre is the infinite lattice
    res = scba(square_flake(20), M=2.5, disorder=[1.5, 3.0])
    for W, sz in zip((1.5, 3.0), res.sigma_z):
        ref0, refz = _bloch_scba(2.5, W)
        assert abs(sz - refz) < 5e-4 * W * W
    # the Born term pushes the trivial mass down, towards the Chern phase (the TAI's mechanism)
    assert res.mass[1] < res.mass[0] < 2.5


def test_particle_hole_symmetry_makes_sigma_z_real_and_sigma_0_imaginary():
    res = scba(hl.ring_lattice(8, 3, 3), M=1.6, disorder=[2.0, 4.0])
    assert np.all(np.abs(res.sigma_z.imag) < 1e-12) and np.all(np.abs(res.sigma_0.real) < 1e-12)
    assert np.all(res.broadening >= 0) and res.broadening[1] > res.broadening[0]
    assert res.frame_part < 0.2          # the chord frame's sigma_x, sigma_y part of a block, left out
    df = res.to_dataframe()
    assert list(df.columns[:3]) == ["W", "mass", "broadening"]


def test_the_boundary_is_where_the_renormalised_mass_reaches_the_critical_mass():
    lat = hl.ring_lattice(8, 3, 3)
    b = scba_boundary(lat, masses=[1.3, 1.7], critical_mass=1.42)
    assert b.critical_disorder[0] == 0.0                    # topological without disorder
    w = float(b.critical_disorder[1])
    assert abs(scba(lat, M=1.7, disorder=w).mass[0] - 1.42) < 1e-6


def test_bad_input_is_one_sentence():
    lat = hl.ring_lattice(8, 3, 3)
    with pytest.raises(ValueError, match="disorder"):
        scba(lat, M=1.0, disorder=[-1.0])
    with pytest.raises(ValueError, match="M"):
        scba(lat, M=float("nan"), disorder=1.0)
    with pytest.raises(ValueError, match="two rings"):
        scba(hl.ring_lattice(8, 3, 1), M=1.0, disorder=1.0)
    with pytest.raises(ValueError, match="critical_mass"):
        scba_boundary(lat, masses=[1.6], critical_mass=float("inf"))


def test_the_conductance_task_runs_one_realization_and_checks_its_parameters():
    from hyperlattice.sweep import tasks

    task = tasks.get_task("conductance")
    params = dict(task.defaults, rings=3, M=1.6, W=3.0, seed=1)
    task.check(params)
    row = tasks.execute("conductance", params)
    assert set(row) == {"conductance", "error"} and row["error"] < 1e-10
    assert row == tasks.execute("conductance", params)          # same seed, same bits
    for bad, match in ((dict(W=-1.0), "W"), (dict(model="box"), "model"), (dict(arc=0.5), "arc"),
                       (dict(rings=9), "sites")):
        with pytest.raises(ValueError, match=match):
            task.check(dict(params, **bad))


def test_the_stored_scan_is_what_the_code_computes():
    from hyperlattice.topology.transport import conductance

    data = json.loads(STORED.read_text())
    block = next(b for b in data["ensembles"] if b["rings"] == 4 and b["M"] == 1.6)
    j = block["W"].index(3.0)
    g = conductance(hl.ring_lattice(8, 3, 4), "qwz", M=1.6, disorder=3, seed=5).conductance[0]
    assert abs(block["G"][5][j] - g) < 2e-6
    sc = data["scba"]
    i = sc["masses"].index(1.6)
    b = scba_boundary(hl.ring_lattice(8, 3, 4), masses=[1.6], critical_mass=sc["critical_mass"])
    assert abs(sc["boundary"]["4"]["mid"][i] - b.critical_disorder[0]) < 1e-5
    # and the table's crossing of the stored curves
    import sys

    sys.path.insert(0, str(STORED.parent))
    from topology_tai_boundary import _crossings

    lo, hi = _crossings(np.array(block["W"]), np.mean(block["G"], axis=0))
    assert 2.0 < lo < 2.5 and 5.0 < hi < 6.0


@pytest.mark.slow
def test_the_scba_boundary_converges_with_the_flake():
    # the absorbing edge makes the centre see the infinite lattice: l = 5 and 6 agree to a hundredth
    b5 = scba_boundary(hl.ring_lattice(8, 3, 5), masses=[1.6, 1.8], critical_mass=1.42)
    b6 = scba_boundary(hl.ring_lattice(8, 3, 6), masses=[1.6, 1.8], critical_mass=1.42)
    assert np.all(np.abs(b5.critical_disorder - b6.critical_disorder) < 0.02)
