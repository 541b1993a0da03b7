"""Rotation orbits and angular-momentum sector blocks."""

import numpy as np
import pytest
import scipy.linalg as sla

from hyperlattice.graph.lattice import line_graph, ring_lattice
from hyperlattice.graph.operators import hamiltonian
from hyperlattice.graph.symmetry import (
    lift,
    rotation_invariant,
    rotation_orbits,
    sector_hamiltonian,
    sector_table,
    signed_sector,
)


@pytest.mark.parametrize("p,q,rings", [(7, 3, 3), (8, 3, 3), (5, 4, 2), (7, 3, 1)])
def test_orbits_are_free_and_of_size_p(p, q, rings):
    lat = ring_lattice(p, q, rings)
    orb = rotation_orbits(lat)
    assert orb.size * p == lat.sites
    # rebuild every site by applying the rotation shift[site] times to its representative
    cur = orb.representatives[orb.orbit]
    for s in range(1, p):
        cur = np.where(orb.shift >= s, lat.rotation[cur], cur)
    assert np.array_equal(cur, np.arange(lat.sites))


def test_signed_sector_labels_and_validation():
    assert [signed_sector(m, 7) for m in range(7)] == [0, 1, 2, 3, -3, -2, -1]
    assert [signed_sector(m, 8) for m in range(8)] == [0, 1, 2, 3, 4, -3, -2, -1]
    assert signed_sector(-3, 7) == -3 and signed_sector(-1, 8) == -1
    for bad in (7, 9, -4, -5):
        with pytest.raises(ValueError, match="sector m must be in range"):
            signed_sector(bad, 7)
    with pytest.raises(ValueError, match="integer"):
        signed_sector(1.5, 7)


@pytest.mark.parametrize("lat", [ring_lattice(7, 3, 4), ring_lattice(8, 3, 3), line_graph(ring_lattice(7, 3, 3)),
                                 ring_lattice(6, 4, 2)], ids=["73-4", "83-3", "line73-3", "64-2"])
def test_sector_spectra_together_equal_the_full_spectrum(lat):
    full = np.linalg.eigvalsh(hamiltonian(lat).toarray())
    parts = []
    for m in range(lat.p):
        hm = sector_hamiltonian(lat, m).toarray()
        assert np.allclose(hm, hm.conj().T, atol=1e-14)
        if (2 * m) % lat.p == 0:
            assert not np.iscomplexobj(hm)
        parts.append(np.linalg.eigvalsh(hm))
    assert np.allclose(np.sort(np.concatenate(parts)), full, atol=1e-10)
    # m and p - m are complex conjugate blocks: degenerate
    for m in range(1, lat.p):
        assert np.allclose(parts[m], parts[lat.p - m], atol=1e-12)


def test_lifted_sector_eigenvector_is_a_rotation_eigenstate_with_the_same_residual():
    lat = ring_lattice(7, 3, 4)
    h = hamiltonian(lat, onsite=lambda z, ring: 0.1 * np.abs(z) ** 2)
    orb = rotation_orbits(lat)
    omega = np.exp(2j * np.pi / 7)
    for m in (0, 2, -3):
        table = sector_table(lat, m, onsite=lambda z, ring: 0.1 * np.abs(z) ** 2, orbits=orb)
        hm = table.to_csr().toarray()
        e, v = sla.eigh(hm)
        phi = v[:, 0] + 1e-3 * v[:, 1]  # deliberately not an exact eigenvector
        phi /= np.linalg.norm(phi)
        psi = lift(orb, m, phi)
        assert np.isclose(np.linalg.norm(psi), 1.0)
        assert np.allclose(psi[lat.rotation], omega**m * psi)
        sector_res = np.linalg.norm(hm @ phi - e[0] * phi)
        full_res = np.linalg.norm(h @ psi - e[0] * psi)
        assert np.isclose(sector_res, full_res, rtol=1e-12)


def test_sector_block_needs_a_rotation_invariant_onsite_term():
    lat = ring_lattice(7, 3, 2)
    assert rotation_invariant(lat, lambda z, ring: ring * 1.0)
    assert not rotation_invariant(lat, lambda z, ring: z.real)
    with pytest.raises(ValueError, match="not invariant"):
        sector_hamiltonian(lat, 0, onsite=lambda z, ring: z.real)
    with pytest.raises(ValueError, match="Lattice"):
        sector_hamiltonian(np.eye(3), 0)


def test_heptagon_blocks_are_bloch_phases():
    # one heptagon: one orbit, H_m = -(omega^m + omega^-m) = -2 cos(2 pi m / 7)
    lat = ring_lattice(7, 3, 1)
    for m in range(7):
        assert np.isclose(sector_hamiltonian(lat, m).toarray()[0, 0], -2 * np.cos(2 * np.pi * m / 7))


BAD = [None, float("nan"), True, "1", [1, 2], 1.5]


@pytest.mark.parametrize("bad", BAD, ids=repr)
def test_bad_sector_label(bad):
    with pytest.raises(ValueError, match="sector m must be an integer"):
        signed_sector(bad, 7)
    with pytest.raises(ValueError, match="sector m must be an integer"):
        sector_hamiltonian(ring_lattice(7, 3, 2), bad)
    with pytest.raises(ValueError, match="p must be an integer"):
        signed_sector(1, bad)


@pytest.mark.parametrize("bad", BAD[:-1], ids=repr)
def test_bad_lattice_hopping_and_orbits(bad):
    lat = ring_lattice(7, 3, 2)
    with pytest.raises(ValueError, match="Lattice"):
        rotation_invariant(bad)
    with pytest.raises(ValueError, match="Lattice"):
        rotation_orbits(bad)
    with pytest.raises(ValueError, match="hopping t"):
        sector_table(lat, 0, t=bad)
    with pytest.raises(ValueError, match="orbits"):
        lift(bad, 0, np.ones(5))
    if bad is not None:  # orbits=None means "compute them"
        with pytest.raises(ValueError, match="orbits"):
            sector_table(lat, 0, orbits=bad)


def test_orbits_of_another_lattice_are_refused():
    with pytest.raises(ValueError, match="different lattice"):
        sector_table(ring_lattice(7, 3, 3), 0, orbits=rotation_orbits(ring_lattice(7, 3, 2)))


@pytest.mark.parametrize("bad,match", [
    (None, "phi"), ("x", "phi"), (np.ones(4), "one row per orbit"), (np.full(5, np.nan), "NaN"),
    (np.ones((5, 2, 2)), "dimension"), ([[1.0], [1.0, 2.0]], "phi"), (np.ones(5, dtype=bool), "phi"),
])
def test_lift_checks_its_vectors(bad, match):
    orb = rotation_orbits(ring_lattice(7, 3, 2))
    with pytest.raises(ValueError, match=match):
        lift(orb, 1, bad)


def test_lift_keeps_real_vectors_real():
    orb = rotation_orbits(ring_lattice(8, 3, 2))
    assert not np.iscomplexobj(lift(orb, 0, np.ones(orb.size)))
    assert not np.iscomplexobj(lift(orb, 4, [1.0] * orb.size))     # m = p/2: phases +-1
    assert np.iscomplexobj(lift(orb, 1, np.ones(orb.size)))
    assert lift(orb, 0, np.ones((orb.size, 3))).shape == (8 * orb.size, 3)
