"""Solver internals: neighbour tables, the Chebyshev kernel, the dense fallback, residual checks."""

import subprocess
import sys

import numpy as np
import pytest
import scipy.linalg as sla

from hyperlattice.errors import ConvergenceError, ConvergenceWarning
from hyperlattice.graph import solvers
from hyperlattice.graph.lattice import line_graph, ring_lattice
from hyperlattice.graph.operators import hamiltonian
from hyperlattice.graph.operators import SectorTable, _fixed_width, full_table
from hyperlattice.graph.symmetry import sector_table


def test_importing_the_graph_side_does_not_compile_or_import_numba():
    code = ("import sys, hyperlattice, hyperlattice.graph.solvers, hyperlattice.graph.spectrum, "
            "hyperlattice.graph.symmetry; print('numba' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"


@pytest.mark.parametrize("lat", [ring_lattice(7, 3, 3), line_graph(ring_lattice(7, 3, 2))], ids=["73-3", "line"])
def test_full_table_is_the_hamiltonian(lat):
    v = lambda z, ring: 0.2 * ring - 0.1 * z.real  # noqa: E731 - any real on-site term
    table = full_table(lat, t=1.5, onsite=v)
    h = hamiltonian(lat, t=1.5, onsite=v)
    assert (table.to_csr() != h).nnz == 0
    x = np.random.default_rng(1).standard_normal((lat.sites, 3))
    # the numba kernel reproduces H x (sums in a different order: rounding only)
    assert np.allclose(solvers._matvec(table, x), h @ x, rtol=0, atol=1e-13)
    lo, hi = table.bounds()
    e = np.linalg.eigvalsh(h.toarray())
    assert lo <= e[0] and e[-1] <= hi  # Gershgorin


def test_fixed_width_pads_with_zero_weight_self_loops():
    rows = np.array([0, 0, 2])
    cols = np.array([1, 2, 0])
    vals = np.array([1.0, 2.0, 3.0])
    tc, tv = _fixed_width(3, rows, cols, vals)
    assert tc.shape == (3, 2) and tc.dtype == np.int32
    assert tc[0].tolist() == [1, 2] and tv[0].tolist() == [1.0, 2.0]
    assert tc[1].tolist() == [1, 1] and tv[1].tolist() == [0.0, 0.0]   # empty row: itself, weight 0
    assert tc[2].tolist() == [0, 2] and tv[2].tolist() == [3.0, 0.0]


@pytest.mark.parametrize("m", [0, 1, 3])
def test_chebyshev_lowest_matches_dense(m):
    table = sector_table(ring_lattice(7, 3, 5), m)
    exact = sla.eigvalsh(table.to_csr().toarray())[:4]
    with solvers._single_threaded_blas():
        e, v, info = solvers._chebyshev_lowest(table, 4, 1e-10, None, f"m={m}")
    assert np.allclose(e, exact, atol=1e-12, rtol=0)
    assert np.all(solvers._residuals(table, v, e) < 1e-10)
    assert info["products"] > 0
    e_dense, v_dense = solvers._dense_lowest(table, 4)
    assert np.allclose(e_dense, exact, atol=1e-13)
    # more levels than the block has: the dense fallback returns all of them
    assert solvers._dense_lowest(table, 10**6)[0].shape == (table.size,)


def test_chebyshev_progress_is_reported():
    table = sector_table(ring_lattice(7, 3, 6), 0)
    seen = []
    solvers._chebyshev_lowest(table, 2, 1e-10, seen.append, "m=0")
    assert seen and all(s.startswith("m=0: ") and s.endswith("products") for s in seen)


def test_check_residuals_raises_far_off_and_warns_near():
    solvers._check_residuals(np.array([1e-12, 5e-11]), 1e-10, "x")
    solvers._check_residuals(np.array([]), 1e-10, "x")
    with pytest.warns(ConvergenceWarning, match="slightly exceeds"):
        solvers._check_residuals(np.array([5e-10]), 1e-10, "x")
    for bad in (2e-8, np.nan, np.inf):
        with pytest.raises(ConvergenceError, match="exceeds the tolerance"):
            solvers._check_residuals(np.array([1e-12, bad]), 1e-10, "x")


def _blas_threads() -> list[int]:
    """Thread counts of the BLAS libraries loaded in this process, read independently of the guard."""
    from threadpoolctl import threadpool_info

    return [info["num_threads"] for info in threadpool_info() if info["user_api"] == "blas"]


def test_single_threaded_blas_restores_the_setting():
    from threadpoolctl import threadpool_limits

    assert _blas_threads(), "numpy and scipy load a BLAS"
    with threadpool_limits(2, user_api="blas"):  # a known starting point, whatever the session set
        before = _blas_threads()
        with solvers._single_threaded_blas():
            assert all(n == 1 for n in _blas_threads())
        assert _blas_threads() == before
        with pytest.raises(RuntimeError):  # restored on the way out of an exception too
            with solvers._single_threaded_blas():
                raise RuntimeError("boom")
        assert _blas_threads() == before


def test_sector_table_type_and_complexity():
    lat = ring_lattice(7, 3, 3)
    t0, t1 = sector_table(lat, 0), sector_table(lat, 1)
    assert isinstance(t0, SectorTable) and t0.m == 0 and t1.m == 1
    assert not t0.is_complex and t1.is_complex
    assert t0.size == t1.size == lat.sites // 7
    assert full_table(lat).m is None and full_table(lat).size == lat.sites


@pytest.mark.parametrize("kwargs,match", [
    ({"t": None}, "hopping t"), ({"t": np.nan}, "finite"), ({"t": "1"}, "hopping t"), ({"t": True}, "hopping t"),
    ({"onsite": lambda z, ring: 1j * z.real}, "real"),
])
def test_full_table_bad_input(kwargs, match):
    with pytest.raises(ValueError, match=match):
        full_table(ring_lattice(7, 3, 2), **kwargs)
    with pytest.raises(ValueError, match="Lattice"):
        full_table(None)
