"""Sparse operators built from a lattice."""

import numpy as np
import pytest
import scipy.sparse as sp

from hyperlattice import adjacency, hamiltonian, ring_lattice
from hyperlattice.graph.operators import incidence


def test_adjacency_symmetric_binary_and_matches_edges():
    lat = ring_lattice(7, 3, 5)
    a = adjacency(lat)
    assert sp.isspmatrix_csr(a) and a.has_sorted_indices
    assert (a != a.T).nnz == 0
    assert set(np.unique(a.data).tolist()) == {1.0}
    assert a.nnz == 2 * lat.edges.shape[0]
    assert np.array_equal(np.asarray(a.sum(axis=1)).ravel(), lat.degree)
    i, j = lat.edges.T
    assert np.all(np.asarray(a[i, j]).ravel() == 1)


def test_heptagon_spectrum_exact():
    # l = 1: a single 7-cycle, eigenvalues of H = -A are -2 cos(2 pi n / 7)
    h = hamiltonian(ring_lattice(7, 3, 1)).toarray()
    ev = np.sort(np.linalg.eigvalsh(h))
    exact = np.sort(-2 * np.cos(2 * np.pi * np.arange(7) / 7))
    assert np.allclose(ev, exact, atol=1e-14)


def test_hamiltonian_hopping_and_onsite_forms():
    lat = ring_lattice(7, 3, 3)
    a = adjacency(lat).toarray()
    assert np.array_equal(hamiltonian(lat, t=2.5).toarray(), -2.5 * a)
    v = np.linspace(-1, 1, lat.sites)
    expected = -a + np.diag(v)
    assert np.allclose(hamiltonian(lat, onsite=v).toarray(), expected)
    assert np.allclose(hamiltonian(lat, onsite=lambda z, ring: np.linspace(-1, 1, z.shape[0])).toarray(), expected)
    assert np.allclose(hamiltonian(lat, onsite=0.3).toarray(), -a + 0.3 * np.eye(lat.sites))
    # a radial confinement written as an array-first modifier
    h = hamiltonian(lat, onsite=lambda z, ring: np.abs(z) ** 2)
    assert np.allclose(h.diagonal(), np.abs(lat.z) ** 2)


@pytest.mark.parametrize("onsite", [np.zeros(5), np.full(112, np.nan), "x"])
def test_bad_onsite(onsite):
    lat = ring_lattice(7, 3, 3)
    with pytest.raises(ValueError):
        hamiltonian(lat, onsite=onsite)


def test_bad_inputs():
    with pytest.raises(ValueError):
        adjacency("not a lattice")
    with pytest.raises(ValueError):
        hamiltonian(ring_lattice(7, 3, 2), t=float("nan"))


def test_incidence():
    lat = ring_lattice(8, 3, 3)
    b = incidence(lat)
    assert b.shape == (lat.sites, lat.edges.shape[0])
    assert np.array_equal(np.asarray(b.sum(axis=0)).ravel(), np.full(lat.edges.shape[0], 2))
    # B B^T = D + A
    lhs = (b @ b.T).toarray()
    assert np.array_equal(lhs, np.diag(lat.degree) + adjacency(lat).toarray())


@pytest.mark.parametrize("bad", [None, "lattice", 3])
def test_non_lattices_refused(bad):
    from hyperlattice.graph.operators import onsite_values

    for fn in (adjacency, hamiltonian, incidence):
        with pytest.raises(ValueError, match="Lattice"):
            fn(bad)
    with pytest.raises(ValueError, match="Lattice"):
        onsite_values(bad, 1.0)  # used to raise AttributeError


@pytest.mark.parametrize("onsite", [[1.0, [2.0, 3.0]], lambda z, ring: None, lambda z, ring: "x", {"a": 1}])
def test_bad_onsite_is_a_sentence(onsite):
    with pytest.raises(ValueError, match="on-site"):
        hamiltonian(ring_lattice(7, 3, 2), onsite=onsite)


@pytest.mark.parametrize("dtype", ["nonsense", object, str])
def test_adjacency_bad_dtype(dtype):
    with pytest.raises(ValueError, match="dtype"):
        adjacency(ring_lattice(7, 3, 2), dtype=dtype)


def test_adjacency_dtypes():
    lat = ring_lattice(7, 3, 2)
    assert adjacency(lat, dtype=np.int8).dtype == np.int8
    assert adjacency(lat, dtype="complex128").dtype == np.complex128


@pytest.mark.parametrize("onsite", [1 + 2j, np.full(19, 0.5j), True, np.ones(19, dtype=bool)])
def test_onsite_must_be_real(onsite):
    # H = -tA + diag(V) is Hermitian: complex and boolean "potentials" are refused
    with pytest.raises(ValueError, match="on-site"):
        hamiltonian(_lat19(), onsite=onsite)


def _lat19():
    return ring_lattice(19, 3, 1)  # a single 19-gon: 19 sites


def test_onsite_complex_with_zero_imaginary_part_is_real():
    lat = _lat19()
    h = hamiltonian(lat, onsite=np.full(19, 0.5 + 0j))
    assert h.dtype == np.float64
    assert np.allclose(h.diagonal(), 0.5)
