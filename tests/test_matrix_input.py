"""A Hamiltonian given as a matrix (scipy.sparse or 2-d array) where a lattice is not essential:
lowest_levels, full_spectrum and the partition function, checked against dense eigvalsh."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg as sla
import scipy.sparse as sp

from hyperlattice.graph import spectrum
from hyperlattice.graph.lattice import ring_lattice
from hyperlattice.graph.operators import adjacency, hamiltonian
from hyperlattice.graph.spectrum import (MatrixSpectrum, full_spectrum, lowest_levels, partition_function)


@pytest.fixture(scope="module")
def lat():
    return ring_lattice(7, 3, 3)      # 112 sites, degenerate +-m pairs


@pytest.mark.parametrize("fmt", ["csr", "csc", "coo", "dense"])
def test_lowest_levels_of_minus_a_match_eigvalsh(lat, fmt):
    a = adjacency(lat)
    h = (-a).toarray() if fmt == "dense" else (-a).asformat(fmt)
    res = lowest_levels(h, 5)
    exact = sla.eigvalsh((-a).toarray())[:5]
    assert isinstance(res, MatrixSpectrum) and res.method == "dense" and res.sites == lat.sites
    np.testing.assert_allclose(res.energies, exact, rtol=0, atol=1e-12)
    assert res.errors.max() < 1e-12 and res.dtype == "float64"
    # the same energies as the lattice route, which also labels them
    np.testing.assert_allclose(res.energies, lowest_levels(lat, 5).energies, rtol=0, atol=1e-12)


@pytest.mark.parametrize("method", ["shift-invert", "sparse"])
def test_the_sparse_route_runs_and_says_so(lat, method):
    h = -adjacency(lat, dtype=np.float64).tocsc()
    res = lowest_levels(h, 4, method=method, eigenvectors=True)
    assert res.method == "shift-invert" and res.backend in ("cholmod", "superlu")
    assert "Shift-invert" in res.description
    np.testing.assert_allclose(res.energies, sla.eigvalsh(h.toarray())[:4], rtol=0, atol=1e-10)
    v = res.eigenvectors
    np.testing.assert_allclose(np.linalg.norm(h @ v - v * res.energies, axis=0), res.errors, atol=1e-12)


def test_auto_takes_shift_invert_above_dense_max(lat, monkeypatch):
    monkeypatch.setattr(spectrum, "DENSE_MAX", 50)
    res = lowest_levels(-adjacency(lat), 3)
    assert res.method == "shift-invert"
    np.testing.assert_allclose(res.energies, sla.eigvalsh(-adjacency(lat).toarray())[:3], rtol=0, atol=1e-10)


@pytest.mark.parametrize("method", ["dense", "shift-invert"])
def test_complex_hermitian_matrix(lat, method):
    h = hamiltonian(lat, flux=0.13)      # Peierls phases: complex Hermitian, +-m split
    assert np.iscomplexobj(h.data)
    res = lowest_levels(h.tocoo(), 4, method=method)
    assert res.dtype == "complex128"
    np.testing.assert_allclose(res.energies, sla.eigvalsh(h.toarray())[:4], rtol=0, atol=1e-10)
    np.testing.assert_allclose(res.energies, lowest_levels(lat, 4, flux=0.13).energies, rtol=0, atol=1e-10)


def test_full_spectrum_and_partition_function_of_a_matrix(lat):
    h = -adjacency(lat)
    np.testing.assert_allclose(full_spectrum(h), sla.eigvalsh(h.toarray()), rtol=0, atol=1e-12)
    beta = np.array([0.5, 2.0])
    np.testing.assert_allclose(partition_function(h, beta), partition_function(lat, beta), rtol=1e-12)


def test_rounding_asymmetry_passes_and_a_real_one_is_refused(lat):
    h = (-adjacency(lat)).tolil()
    h[0, 1] = h[0, 1] * (1 + 1e-15)     # rounding-size: accepted (and symmetrised)
    assert lowest_levels(h.tocsr(), 2).energies.shape == (2,)
    h[0, 1] = -0.5                       # no longer symmetric
    with pytest.raises(ValueError, match=r"^H must be symmetric: max \|H - H\^\+\| = 0\.5"):
        lowest_levels(h.tocsr(), 2)
    c = sp.csr_matrix(np.array([[0.0, 1j], [1j, 0.0]]))
    with pytest.raises(ValueError, match="^H must be Hermitian"):
        lowest_levels(c, 1)


@pytest.mark.parametrize("kwargs, words", [
    ({"t": 2.0}, "^t is for a lattice Hamiltonian"),
    ({"onsite": 0.5, "flux": 0.1}, "^onsite, flux are for a lattice Hamiltonian"),
    ({"sector": 1}, "^sector is"),
    ({"method": "sector"}, "method='sector' needs a lattice"),
    ({"levels": 200}, "exceeds the 112 states of this matrix"),
])
def test_lattice_options_with_a_matrix_are_refused(lat, kwargs, words):
    kwargs = {"levels": 2, **kwargs}
    with pytest.raises(ValueError, match=words):
        lowest_levels(-adjacency(lat), **kwargs)


@pytest.mark.parametrize("bad, words", [
    (sp.csr_matrix((3, 4)), "non-empty square matrix"),
    (np.array([[0.0, np.nan], [np.nan, 0.0]]), "NaN or infinite"),
    (np.array([["a", "b"], ["c", "d"]]), "^H "),
    ([[0.0, 1.0], [1.0, 0.0]], "^expected a Lattice"),
])
def test_bad_matrices_are_refused_in_one_sentence(bad, words):
    with pytest.raises(ValueError, match=words):
        lowest_levels(bad, 1)


def test_a_dense_identity_is_a_matrix_not_a_bad_lattice():
    # to the eigensolver's error bound (16 n eps ||H||): LAPACK happens to return a diagonal
    # matrix's eigenvalues exactly, which is not what the test is about
    tol = 16 * 3 * np.finfo(float).eps
    res = lowest_levels(np.eye(3), 2)
    np.testing.assert_allclose(res.energies, [1.0, 1.0], rtol=0, atol=tol)
    np.testing.assert_allclose(full_spectrum(np.eye(3)), [1.0, 1.0, 1.0], rtol=0, atol=tol)


def test_kpm_takes_any_sparse_format_and_checks_symmetry_with_a_tolerance(lat):
    from hyperlattice.graph.kpm import graph_operator

    a = adjacency(lat).tolil()
    a[0, 1] = a[0, 1] * (1 + 1e-15)          # rounding: accepted (an exact check refused this)
    op = graph_operator(a.tocoo())
    assert op.sites == lat.sites and op.label == f"matrix, {lat.sites} rows"
    a[0, 1] = 0.5
    with pytest.raises(ValueError, match="^the matrix must be symmetric"):
        graph_operator(a.tocsc())
    c = sp.csr_matrix(np.array([[0.0, 1j], [1j, 0.0]]))
    with pytest.raises(ValueError, match="^the matrix must be Hermitian"):
        graph_operator(c)


def test_full_spectrum_and_partition_function_of_a_complex_hermitian_matrix(lat):
    h = hamiltonian(lat, flux=0.13)
    exact = sla.eigvalsh(h.toarray())
    np.testing.assert_allclose(full_spectrum(h.tocsc()), exact, rtol=0, atol=1e-12)
    beta = np.array([0.5, 2.0])
    neg = exact[exact < 0]            # Z sums the negative levels only (the paper's Fig. 2 inset)
    np.testing.assert_allclose(partition_function(h, beta), np.exp(-np.outer(beta, neg)).sum(axis=1), rtol=1e-12)


def test_kpm_takes_a_complex_hermitian_matrix(lat):
    """A flux Hamiltonian through KPM (its real 2N embedding): exact local moments, and stochastic
    moments within their error bars of the exact trace; sites count the N sites, not 2N rows."""
    from hyperlattice.graph.kpm import EPS, graph_operator, kpm_dos, local_dos

    a = -hamiltonian(lat, flux=0.13)          # KPM takes A, H = -A
    energies, vectors = np.linalg.eigh(-a.toarray())
    op = graph_operator(a.tocoo())
    assert op.copies == 2 and op.sites == 2 * lat.sites and op.bound == pytest.approx(3.0, abs=1e-12)
    theta = np.arccos(energies / (op.bound / (1 - EPS)))
    n = np.arange(20)[:, None]
    ldos = local_dos(a, 5, 20)
    exact_local = (np.cos(n * theta) * np.abs(vectors[5]) ** 2).sum(axis=1)
    np.testing.assert_allclose(ldos.mu, exact_local, rtol=0, atol=1e-13)
    assert ldos.sites == lat.sites
    with pytest.raises(ValueError, match="not a site"):
        local_dos(a, lat.sites, 20)
    dos = kpm_dos(a, 20, vectors=64, seed=2, kind="phase")
    exact = np.cos(n * theta).mean(axis=1)
    assert dos.sites == dos.traced_sites == lat.sites and dos.mu[0] == 1.0
    assert np.all(np.abs(dos.mu - exact) <= 5 * dos.mu_err + 1e-12)


@pytest.mark.slow
def test_a_hugely_degenerate_lowest_level_is_refused_before_allocating():
    """The zero matrix of 10^7 rows: every level is 0, so the proof that no level was missed asks
    ARPACK for n - 2 of them, an n x n basis (728 TiB). Refused with one sentence, nothing allocated."""
    from hyperlattice.graph.factor import FactorMemoryError

    with pytest.raises(FactorMemoryError, match="Lanczos basis .* more than the"):
        lowest_levels(sp.csr_matrix((10**7, 10**7)), 2)
