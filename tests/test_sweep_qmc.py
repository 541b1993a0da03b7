"""The ``qmc`` sweep task: a tiny lobe grid through the serial path, chains merged per point."""

from __future__ import annotations

import numpy as np
import pytest

from hyperlattice.sweep import read_table, run_sweep
from hyperlattice.sweep.engine import expand_grid
from hyperlattice.sweep.qmc import merge_qmc
from hyperlattice.sweep.tasks import execute, get_task

GRID = {"rings": 1, "nmax": 2, "U": 8.0, "mu": [2.0, 4.0], "beta": 1.0, "sweeps": 1500, "seed": [1, 2, 3]}


def test_grid_runs_resumes_and_merges_like_merge_chains(tmp_path):
    where = tmp_path / "lobe"
    rep = run_sweep("qmc", GRID, where, scheduler="serial", progress=False)
    assert rep.ok and rep.total == 6 and rep.completed == 6
    again = run_sweep("qmc", GRID, where, scheduler="serial", progress=False)
    assert again.completed == 0 and again.skipped == 6
    table = read_table(where)
    assert len(table) == 6 and set(table.columns["sites"].tolist()) == {7}
    merged = merge_qmc(where)
    assert [r.mu for r in merged] == [2.0, 4.0]
    assert all(r.chains == 3 and sorted(r.seeds) == [1, 2, 3] and r.sweeps == 4500 for r in merged)

    # the same as the API: three chains by qmc, merged by merge_chains
    from hyperlattice import ring_lattice
    from hyperlattice.bosons import exact_thermal, merge_chains, qmc

    lat = ring_lattice(7, 3, 1)
    ref = merge_chains([qmc(lat, U=8.0, mu=4.0, beta=1.0, nmax=2, sweeps=1500, seed=s, progress=False)
                        for s in (1, 2, 3)])
    got = merged[1]
    for k in ("energy", "energy_err", "density", "density_err", "compressibility", "compressibility_err"):
        assert getattr(got, k) == pytest.approx(getattr(ref, k), rel=1e-12, abs=1e-15), k
    assert np.allclose(got.site_density, ref.site_density, rtol=1e-12, atol=0)
    assert got.condensate_fraction == pytest.approx(ref.condensate_fraction, rel=1e-12)
    if ref.green is not None:
        assert np.allclose(got.green, ref.green, rtol=1e-12, atol=0)
    # and right: within 4 sigma of the exact thermal averages
    ex = exact_thermal(lat, U=8.0, mu=4.0, beta=1.0, nmax=2)
    for k in ("energy", "density", "compressibility"):
        exact = getattr(ex, k)
        assert abs(getattr(got, k) - exact) < 4 * getattr(got, k + "_err"), k


def test_a_row_is_a_pure_function_of_its_parameters():
    params = dict(get_task("qmc").defaults, rings=1, nmax=2, U=4.0, mu=1.0, beta=1.0, sweeps=400, seed=7)
    a, b = execute("qmc", params), execute("qmc", params)
    assert a.keys() == b.keys() and "seconds" not in a
    for k in a:
        x, y = np.asarray(a[k]), np.asarray(b[k])
        # the stiffness of a flake is nan (no winding numbers): nan equals nan here
        assert np.array_equal(x, y, equal_nan=x.dtype.kind == "f"), k


def test_cluster_point():
    params = dict(get_task("qmc").defaults, cluster="bolza", p=8, nmax=1, U=0.0, mu=0.0, beta=0.5,
                  sweeps=400, seed=1)
    row = execute("qmc", params)
    assert row["sites"] == 16 and len(row["site_density"]) == 16 and len(row["bond_i"]) == 24


def test_cluster_rows_carry_the_stiffness_and_merge_it_like_merge_chains(tmp_path):
    # a periodic cluster has winding numbers: the row stores rho_s, det^(1/D), the D x D tensor and
    # their errors, the same numbers as the API's chain with the same seed
    from hyperlattice.bosons import merge_chains, qmc
    from hyperlattice.graph.clusters import pbc_cluster

    grid = {"cluster": "bolza", "p": 8, "nmax": 1, "U": 0.0, "mu": 0.2, "beta": 1.0, "sweeps": 600, "seed": [1, 2]}
    run_sweep("qmc", grid, tmp_path / "bolza", scheduler="serial", progress=False)
    rows = read_table(tmp_path / "bolza").rows()
    bolza = pbc_cluster(8, 3, "bolza")
    api = [qmc(bolza, U=0.0, mu=0.2, beta=1.0, nmax=1, sweeps=600, seed=s, progress=False) for s in (1, 2)]
    for row, ref in zip(rows, api):
        assert row["stiffness_dim"] == 4 and row["stiffness_note"] == ""          # genus 2: D = 4
        for k in ("rho_s", "rho_s_err", "stiffness_geometric", "stiffness_geometric_err"):
            assert np.isfinite(row[k]) and row[k] == getattr(ref, k), k
        assert row["rho_s_err"] > 0 and row["tau_stiffness"] == ref.tau_int["stiffness"]
        assert np.array_equal(np.asarray(row["stiffness"]), ref.stiffness.ravel())
        assert np.array_equal(np.asarray(row["stiffness_err"]), ref.stiffness_err.ravel())
    (merged,) = merge_qmc(tmp_path / "bolza")
    ref = merge_chains(api)
    assert merged.stiffness.shape == (4, 4) and merged.stiffness_note == ""
    assert np.allclose(merged.stiffness, ref.stiffness, rtol=1e-12, atol=0)
    assert np.allclose(merged.stiffness_err, ref.stiffness_err, rtol=1e-12, atol=0)
    for k in ("rho_s", "rho_s_err", "stiffness_geometric", "stiffness_geometric_err"):
        assert getattr(merged, k) == pytest.approx(getattr(ref, k), rel=1e-12), k
    assert merged.tau_int["stiffness"] == pytest.approx(ref.tau_int["stiffness"], rel=1e-12)


def test_a_flake_row_says_why_there_is_no_stiffness():
    params = dict(get_task("qmc").defaults, rings=1, nmax=2, U=4.0, mu=1.0, beta=1.0, sweeps=200, seed=7)
    row = execute("qmc", params)
    assert row["stiffness_dim"] == 0 and len(row["stiffness"]) == 0 and np.isnan(row["rho_s"])
    assert "flake" in row["stiffness_note"]


def _documented_columns() -> set:
    """The column names of the table of a qmc row in docs/qmc.md."""
    import re
    from pathlib import Path

    text = (Path(__file__).resolve().parents[1] / "docs" / "qmc.md").read_text(encoding="utf-8")
    start = text.index("a row of the `qmc` task holds these columns")
    names, in_table = set(), False
    for line in text[start:].splitlines()[1:]:
        if line.startswith("|"):
            in_table = True
            first = line.split(" | ")[0]
            names.update(re.findall(r"`([a-z_]+)`", first))
        elif in_table:
            break
    return names


def test_the_documented_columns_are_the_row():
    params = dict(get_task("qmc").defaults, rings=1, nmax=2, U=4.0, mu=1.0, beta=1.0, sweeps=200, seed=7)
    row = execute("qmc", params)
    assert _documented_columns() == set(row)


@pytest.mark.parametrize("grid,needle", [
    ({"beta": 0.0}, "beta must be positive"),
    ({"nmax": 0}, "nmax"),
    ({"t": 0.0}, "t = 0"),
    ({"cluster": "nowhere"}, "nowhere"),
    ({"seed": -1}, "seed"),
    ({"rings": 3, "nmax": 5, "beta": 1e12}, "allocate"),
    ({"colour": 1}, "no parameter"),
])
def test_grid_refused_before_work(grid, needle):
    with pytest.raises(ValueError, match=None) as info:
        expand_grid("qmc", grid)
    assert needle in str(info.value) and "\n" not in str(info.value)


def test_merge_refuses_other_sweeps(tmp_path):
    run_sweep("probe", {"x": [1.0]}, tmp_path / "p", scheduler="serial", progress=False)
    with pytest.raises(ValueError, match="qmc sweep"):
        merge_qmc(tmp_path / "p")
