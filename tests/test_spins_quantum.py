"""The spin-1/2 XXZ SSE (spins.quantum.xxz_qmc) against full diagonalisation in S^z blocks.

Reference: xxz_exact (every S^z block diagonalised, thermal averages exact to rounding). Each
QMC number must lie within 4 of its own error bars of the exact value; the error bars
themselves are checked against the scatter of independent seeds (slow test).
"""

from __future__ import annotations

import json
import math
import subprocess
import sys

import numpy as np
import pytest
import scipy.sparse as sp

import hyperlattice as hl
from hyperlattice.bosons import qmc
from hyperlattice.spins.quantum import XXZExact, XXZResult, merge_xxz, xxz_exact, xxz_qmc


def _piece(p: int, q: int, outer: int) -> sp.csr_matrix:
    """Ring 1 of the {p,q} flake (a p-gon) and the ring-2 neighbours of its first ``outer`` sites."""
    from hyperlattice.graph.operators import adjacency

    a = sp.csr_matrix(adjacency(hl.ring_lattice(p, q, 2)))
    extra = [int(j) for i in range(outer) for j in a[i].indices if j >= p]
    keep = np.array(list(range(p)) + extra)
    return a[keep][:, keep].tocsr()


RING8 = hl.ring_lattice(8, 3, 1)
HEPTAGON = hl.ring_lattice(7, 3, 1)
PIECE83 = _piece(8, 3, 4)          # 12 sites of the {8,3} flake: an octagon and four neighbours (bipartite)
PIECE73 = _piece(7, 3, 4)          # 11 sites of the {7,3} flake: a heptagon (odd cycle) and four neighbours


def _check(r, ex, names=("e", "c", "chi_u", "mz", "s_pi"), k=4.0):
    for name in names:
        v, err, want = getattr(r, name), getattr(r, name + "_err"), getattr(ex, name)
        if name == "s_pi" and not r.bipartite:
            assert math.isnan(v) and math.isnan(want)
            continue
        assert abs(v - want) < k * err + 1e-9, (name, v, err, want)


def test_heisenberg_ring_matches_exact():
    ex = xxz_exact(RING8, J=1.0, Delta=1.0, beta=2.0)
    r = xxz_qmc(RING8, J=1.0, Delta=1.0, beta=2.0, sweeps=8000, seed=3, progress=False)
    _check(r, ex)
    assert np.all(np.abs(r.bond_zz - ex.bond_zz) < 4.5 * r.bond_zz_err)
    assert np.all(np.abs(r.bond_xy - ex.bond_xy) < 4.5 * r.bond_xy_err)
    assert np.all(np.abs(r.site_stag - ex.site_stag) < 4.5 * r.site_stag_err)
    # the staggered correlations of the sites add up to s_pi
    # (the site arrays average 32 long bins, s_pi every complete short bin: the same chain up to a tail)
    assert abs(r.site_stag.sum() - r.s_pi) < r.s_pi_err
    assert isinstance(r, XXZResult) and r.converged and r.bipartite


def test_exact_ground_state_of_the_heisenberg_ring():
    # 8-site Heisenberg ring: E0/N = -0.4563867 (Bethe ansatz, e.g. Sandvik AIP Conf. Proc. 1297, table)
    x = xxz_exact(RING8, J=1.0, Delta=1.0, beta=80.0)
    assert isinstance(x, XXZExact)
    assert abs(x.ground_energy / 8 + 0.45638668) < 1e-7
    # SU(2): at h = 0 the zz and the xy correlation of each bond are in ratio 1 : 2
    assert np.allclose(2 * x.bond_zz, x.bond_xy, atol=1e-10)


def test_xy_case_is_the_bosons_hard_core_model():
    # Delta = 0: J(SxSx + SySy) - h Sz = hard-core bosons with t = -J/2, mu = h, plus h N / 2
    kw = dict(beta=1.5, sweeps=6000, seed=5, progress=False)
    r = xxz_qmc(HEPTAGON, J=-1.0, Delta=0.0, h=0.4, **kw)
    ex = xxz_exact(HEPTAGON, J=-1.0, Delta=0.0, h=0.4, beta=1.5)
    b = qmc(HEPTAGON, U=0.0, mu=0.4, t=0.5, nmax=1, measure_green=False, **kw)
    assert abs(ex.e * 7 - (b.energy + 0.4 * 7 / 2)) < 4 * b.energy_err
    assert abs(r.e - ex.e) < 4 * r.e_err


@pytest.mark.parametrize("system", [HEPTAGON, PIECE73])
def test_frustrated_antiferromagnet_is_refused(system):
    with pytest.raises(ValueError, match="odd cycle is frustrated"):
        xxz_qmc(system, J=1.0, Delta=1.0, beta=1.0, sweeps=10)


def test_mixed_signs_and_bad_input_are_refused():
    tri = sp.csr_matrix(np.array([[0, 1, -1], [1, 0, -1], [-1, -1, 0]], dtype=float))
    with pytest.raises(ValueError, match="mixed sign"):
        xxz_qmc(tri, J=1.0, Delta=1.0, beta=1.0, sweeps=10)
    for kw, msg in ((dict(J=float("nan")), "J"), (dict(beta=0.0), "beta"), (dict(beta=-1.0), "beta"),
                    (dict(sweeps=-5), "sweeps"), (dict(J=0.0), "J = 0"), (dict(Delta=float("inf")), "Delta")):
        args = dict(J=1.0, Delta=1.0, beta=1.0, sweeps=10) | kw
        with pytest.raises(ValueError, match=msg):
            xxz_qmc(RING8, progress=False, **args)
    with pytest.raises(ValueError, match="at most 16 sites"):
        xxz_exact(hl.ring_lattice(8, 3, 2), J=1.0, Delta=1.0, beta=1.0)


def test_checkpoint_resumes_bit_identically(tmp_path):
    kw = dict(J=1.0, Delta=0.5, h=0.2, beta=1.0, thermalization=300, seed=9, progress=False)
    whole = xxz_qmc(RING8, sweeps=4000, **kw)
    xxz_qmc(RING8, sweeps=2000, checkpoint=tmp_path, **kw)
    resumed = xxz_qmc(RING8, sweeps=4000, checkpoint=tmp_path, **kw)
    for k in ("e", "e_err", "c", "chi_u", "s_pi", "s_pi_err"):
        assert getattr(resumed, k) == getattr(whole, k), k
    assert np.array_equal(resumed.bond_zz, whole.bond_zz)
    with pytest.raises(ValueError, match="other parameters"):
        xxz_qmc(RING8, sweeps=4000, checkpoint=tmp_path, **(kw | dict(h=0.3)))
    with pytest.raises(ValueError, match="more than"):
        xxz_qmc(RING8, sweeps=1000, checkpoint=tmp_path, **kw)


def test_memory_is_refused_before_the_chain_starts():
    with pytest.raises(MemoryError, match="operator string"):
        xxz_qmc(hl.ring_lattice(8, 3, 4), J=1.0, Delta=1.0, beta=1e12, sweeps=10)


def test_frustrated_graphs_are_fine_for_exact_diagonalisation():
    x = xxz_exact(HEPTAGON, J=1.0, Delta=1.0, beta=1.0)
    assert math.isnan(x.s_pi) and x.e < 0


def _cli(*args):
    return subprocess.run([sys.executable, "-m", "hyperlattice", "spins", "quantum", *args], capture_output=True,
                          text=True)


def test_cli_json_contract_and_bad_input():
    out = _cli("--rings", "1", "-p", "8", "-q", "3", "--J", "1", "--Delta", "1", "--h", "0", "--beta", "1",
               "--sweeps", "2000", "--seed", "1", "--json")
    assert out.returncode == 0, out.stderr
    data = json.loads(out.stdout)
    for k in ("sites", "e", "e_err", "c", "c_err", "chi_u", "chi_u_err", "s_pi", "s_pi_err", "tau_int", "update"):
        assert k in data
    ex = xxz_exact(RING8, J=1.0, Delta=1.0, beta=1.0)
    assert abs(data["e"] - ex.e) < 4 * data["e_err"]
    for bad in (["--beta", "0"], ["--sweeps", "-3"], ["--J", "nan"], ["--rings", "1", "-p", "7"]):
        args = dict(zip(["--rings", "-p", "-q", "--J", "--Delta", "--h", "--beta", "--sweeps"],
                        ["1", "8", "3", "1", "1", "0", "1", "100"]))
        args.update(dict(zip(bad[::2], bad[1::2])))
        r = _cli(*[x for kv in args.items() for x in kv])
        assert r.returncode == 2, (bad, r.stdout, r.stderr)
        assert len(r.stderr.strip().splitlines()) == 1 and "Traceback" not in r.stderr, r.stderr


# ------------------------------------------------------------------------------------------------
# slow: the full table against exact diagonalisation, the error bars against the seeds' scatter
# ------------------------------------------------------------------------------------------------

# (system, J, Delta, h, beta): ferromagnets on any graph, antiferromagnets on bipartite graphs
TABLE = [
    (RING8, 1.0, 1.0, 0.0, 4.0),
    (RING8, 1.0, 0.5, 0.3, 2.0),
    (RING8, 1.0, 2.0, 0.0, 2.0),
    (RING8, 1.0, -0.5, 0.5, 1.0),
    (PIECE83, 1.0, 1.0, 0.0, 3.0),
    (PIECE83, 1.0, 1.5, 0.4, 2.0),
    (PIECE83, -1.0, 1.0, 0.2, 2.0),
    (HEPTAGON, -1.0, 1.0, 0.0, 2.0),
    (HEPTAGON, -1.0, 0.3, 0.5, 2.0),
    (PIECE73, -1.0, 2.0, 0.0, 1.0),
    (PIECE73, -0.7, 0.0, 1.0, 2.0),
]


@pytest.mark.slow
@pytest.mark.parametrize("system, J, Delta, h, beta", TABLE)
def test_xxz_matches_exact_diagonalisation(system, J, Delta, h, beta):
    ex = xxz_exact(system, J=J, Delta=Delta, h=h, beta=beta)
    r = xxz_qmc(system, J=J, Delta=Delta, h=h, beta=beta, sweeps=20000, seed=17, progress=False)
    _check(r, ex)
    assert np.all(np.abs(r.site_sz - ex.site_sz) < 4.5 * r.site_sz_err + 1e-9)
    assert np.all(np.abs(r.bond_zz - ex.bond_zz) < 4.5 * r.bond_zz_err + 1e-9)
    assert np.all(np.abs(r.bond_xy - ex.bond_xy) < 4.5 * r.bond_xy_err + 1e-9)


@pytest.mark.slow
def test_error_bars_against_the_scatter_of_seeds():
    ex = xxz_exact(PIECE83, J=1.0, Delta=1.0, beta=2.0)
    runs = [xxz_qmc(PIECE83, J=1.0, Delta=1.0, beta=2.0, sweeps=3000, seed=100 + s, progress=False)
            for s in range(24)]
    for name in ("e", "chi_u", "s_pi"):
        z = np.array([(getattr(r, name) - getattr(ex, name)) / getattr(r, name + "_err") for r in runs])
        inside = float(np.mean(np.abs(z) < 1))
        # 68 % expected; 24 draws: 3 sigma of the binomial is +-0.29
        assert 0.4 < inside < 0.96, (name, inside, z)
    m = merge_xxz(runs)
    _check(m, ex, names=("e", "chi_u", "s_pi"))


def _twisted_free_energy(n: int, J: float, Delta: float, beta: float, theta: float) -> float:
    """F(theta) of the n-spin XXZ ring with the phase e^{i theta} on the hop 9 -> 0 of an up spin (every S^z block)."""
    i = np.arange(n)
    states = np.arange(2 ** n)
    bits = (states[:, None] >> i[None, :]) & 1
    z = 0.0
    for k in range(n + 1):
        basis = states[bits.sum(axis=1) == k]
        sz = bits[basis] - 0.5
        H = np.diag((sz * np.roll(sz, -1, axis=1)).sum(axis=1) * J * Delta).astype(complex)
        for b in range(n):
            x, y = b, (b + 1) % n
            src = np.flatnonzero(bits[basis, x] != bits[basis, y])
            dst = np.searchsorted(basis, basis[src] ^ ((1 << x) | (1 << y)))
            phase = np.ones(src.size, dtype=complex)
            if b == n - 1:
                phase = np.where(bits[basis[src], x] == 1, np.exp(1j * theta), np.exp(-1j * theta))
            H[dst, src] += 0.5 * J * phase
        z += np.exp(-beta * np.linalg.eigvalsh(H)).sum()
    return float(-np.log(z) / beta)


@pytest.mark.slow
@pytest.mark.parametrize("J, Delta", [(-1.0, 0.5), (1.0, 1.0)])
def test_spin_stiffness_against_twisted_exact_diagonalisation(J, Delta):
    # a ring of 6 spins with winding 1 on the bond 5 -> 0: rho_s = <W^2>/beta = d^2F/dtheta^2 at theta = 0
    n, beta = 6, 4.0
    i = np.arange(n)
    a = sp.coo_matrix((np.ones(n), (i, (i + 1) % n)), shape=(n, n))
    a = (a + a.T).tocsr()
    w = np.zeros((n, 1), dtype=np.int64)
    w[-1, 0] = 1
    r = xxz_qmc(a, J=J, Delta=Delta, beta=beta, sweeps=20000, seed=4, windings=(np.column_stack([i, (i + 1) % n]), w),
                progress=False)
    d = 0.02
    f = [_twisted_free_energy(n, J, Delta, beta, t) for t in (-d, 0.0, d)]
    rho = (f[0] - 2 * f[1] + f[2]) / d ** 2
    assert rho > 0.02 and abs(r.rho_s - rho) < 4 * r.rho_s_err, (r.rho_s, r.rho_s_err, rho)


def test_sweep_task_runs_a_grid_of_chains(tmp_path):
    from hyperlattice.sweep import read_table, run_sweep

    grid = {"rings": [1], "beta": [1.0], "seed": [1, 2], "sweeps": [2000]}
    run_sweep("spins_quantum", grid, tmp_path / "sq", scheduler="serial", progress=False)
    rows = read_table(tmp_path / "sq").rows()
    assert len(rows) == 2 and {r["seed"] for r in rows} == {1, 2}
    ex = xxz_exact(RING8, J=1.0, Delta=1.0, beta=1.0)
    for r in rows:
        assert abs(r["e"] - ex.e) < 4 * r["e_err"] and len(r["ring_stag"]) == 1
    with pytest.raises(ValueError, match="odd cycle"):
        run_sweep("spins_quantum", {"p": [7], "seed": [1]}, tmp_path / "bad", scheduler="serial", progress=False)
