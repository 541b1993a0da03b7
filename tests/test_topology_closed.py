"""Closed surfaces: second Chern numbers, spin Chern numbers, Landau bands of clusters in a field.

Euclidean references first (the 4D lattice Dirac model, a product of two QWZ tori, the honeycomb
Kane-Mele torus), then the clusters, with the continuum prediction for the Landau bands.
"""

from __future__ import annotations

import numpy as np
import pytest

import hyperlattice as hl
from hyperlattice.errors import ConvergenceError
from hyperlattice.topology import honeycomb_torus, model_terms, square_torus
from hyperlattice.topology.closed import dirac4_torus, kubo_chern, product_terms, second_chern, spin_chern
from hyperlattice.topology.landau import cluster_flux_phases, hofstadter_terms, intersection_form, landau_bands
from hyperlattice.topology.models import bloch_model_hamiltonian


# ---------------------------------------------------------------- first Chern numbers, two methods

def test_kubo_chern_matches_fukui_hatsugai_suzuki_on_the_square_qwz_torus():
    # Bianco-Resta sign: square-lattice QWZ at M = 1 has C = -1, at M = -1 C = +1, trivial at M = 3
    for M, c in [(1.0, -1), (-1.0, 1), (3.0, 0)]:
        assert kubo_chern(square_torus(), "qwz", M=M)[0, 1] == pytest.approx(c, abs=1e-3)


# ---------------------------------------------------------------- second Chern numbers

def test_second_chern_of_a_product_line_bundle_is_the_pfaffian_of_its_first_chern_numbers():
    # lowest band of H_a (x) 1 + 1 (x) H_b: a line bundle with C_12 = C_34 = -1, so C2 = c1^2/2 = 1, c2 = 0
    q = model_terms(square_torus(), "qwz", M=1.0)
    res = second_chern(product_terms(q, q), occupied=1, grid=8, max_grid=16, tol=0.01)
    assert res.chern2.tolist() == [1] and res.pfaffian.tolist() == [1] and res.c2.tolist() == [0]
    assert abs(res.chern2_raw[0] - 1) < 10 * res.error[0] + 1e-3


@pytest.mark.slow  # the same check runs in the fast tier as an example of docs/topology-surfaces.md
def test_second_chern_of_the_4d_dirac_model_in_one_phase():
    res = second_chern(dirac4_torus(-3.0), grid=8, max_grid=16, tol=0.01)
    assert res.chern2.tolist() == [-1] and res.pfaffian.tolist() == [0] and res.gap == pytest.approx(2.0)


@pytest.mark.slow
@pytest.mark.machine_independence
@pytest.mark.parametrize("m, c2", [(-5.0, 0), (-3.0, -1), (-1.0, 3), (1.0, -3), (3.0, 1), (5.0, 0)])
def test_second_chern_of_the_4d_dirac_model_in_every_phase(m, c2):
    # Qi, Hughes and Zhang, PRB 78, 195424 (2008): |C2| = 1, 3, 3, 1 in (-4,-2), (-2,0), (0,2), (2,4), 0 outside
    res = second_chern(dirac4_torus(m))
    assert res.chern2.tolist() == [c2]
    assert res.error[0] < 1e-3 and abs(res.chern2_raw[0] - c2) < 1e-3


def test_second_chern_bad_input():
    with pytest.raises(ValueError, match="four momenta"):
        second_chern(square_torus(), "qwz")
    with pytest.raises(ValueError, match="max_grid"):
        second_chern(dirac4_torus(-3.0), grid=8, max_grid=10)
    with pytest.raises(ValueError, match="gap closes"):
        second_chern(dirac4_torus(0.0), grid=8)
    with pytest.raises(ValueError):
        dirac4_torus(float("nan"))
    with pytest.raises(ValueError, match="open flake"):
        second_chern(hl.topology.square_flake(3), "qwz")


def test_second_chern_refuses_an_unconverged_grid():
    with pytest.raises(ConvergenceError, match="max_grid"):
        second_chern(dirac4_torus(-1.9), grid=4, max_grid=8, tol=1e-6)


# ---------------------------------------------------------------- spin Chern numbers

@pytest.mark.machine_independence
def test_spin_chern_of_the_kane_mele_honeycomb_torus():
    top = spin_chern(honeycomb_torus(), M=0.1, t2=0.2)
    assert top.chern_up[0, 1] == 1 and top.chern_down[0, 1] == -1
    assert top.spin_chern[0, 1] == 1 and top.z2[0, 1] == 1
    triv = spin_chern(honeycomb_torus(), M=2.0, t2=0.2)      # M > 3 sqrt(3) t2: trivial
    assert triv.spin_chern.tolist() == [[0, 0], [0, 0]] and triv.z2.tolist() == [[0, 0], [0, 0]]


def test_kane_mele_without_rashba_is_two_haldane_blocks():
    cl = hl.pbc_cluster(8, 3, "bolza")
    k = np.array([0.3, -1.1, 0.7, 2.0])
    km = np.linalg.eigvalsh(bloch_model_hamiltonian(model_terms(cl, "kane-mele", M=0.1, t2=0.3), k))
    up = np.linalg.eigvalsh(bloch_model_hamiltonian(model_terms(cl, "haldane", M=0.1, t2=0.3), k))
    dn = np.linalg.eigvalsh(bloch_model_hamiltonian(model_terms(cl, "haldane", M=0.1, t2=0.3, phi=-np.pi / 2), k))
    assert np.allclose(km, np.sort(np.concatenate([up, dn])), atol=1e-12)


@pytest.mark.machine_independence
def test_spin_chern_on_the_bolza_cluster():
    res = spin_chern(hl.pbc_cluster(8, 3, "bolza"), M=0.0, t2=0.3)
    assert np.array_equal(res.chern_up, -res.chern_down)
    assert np.array_equal(res.spin_chern, res.chern_up)
    assert np.array_equal(res.z2, np.mod(res.chern_up, 2))


def test_spin_chern_needs_a_bipartite_cubic_graph():
    with pytest.raises(ValueError, match="degree 3"):
        spin_chern(square_torus())


# ---------------------------------------------------------------- Landau bands on clusters

@pytest.mark.parametrize("name, p, q", [("bolza", 8, 3), ("dyck", 8, 3), ("klein", 7, 3)])
def test_intersection_form_is_unimodular_and_antisymmetric(name, p, q):
    Q = intersection_form(hl.pbc_cluster(p, q, name))
    assert np.array_equal(Q, -Q.T) and round(abs(np.linalg.det(Q))) == 1


def test_cluster_flux_phases_put_the_same_flux_through_every_face():
    c = hl.pbc_cluster(7, 3, "klein")
    a = cluster_flux_phases(c, 5)
    edges = np.asarray(c.edges)
    key = {(int(i), int(j)): k for k, (i, j) in enumerate(edges)}
    for face in np.asarray(c.faces):
        tot = 0.0
        for u, v in zip(face, np.roll(face, -1)):
            tot += a[key[(u, v)]] if u < v else -a[key[(v, u)]]
        assert np.exp(1j * tot) == pytest.approx(np.exp(2j * np.pi * 5 / c.n_faces), abs=1e-12)


def test_hofstadter_terms_without_flux_are_the_band_theory_hamiltonian():
    from hyperlattice.graph.bands import bloch_hamiltonian

    c = hl.pbc_cluster(8, 3, "bolza")
    k = np.array([0.4, -0.3, 1.2, 2.2])
    H0 = np.asarray(bloch_hamiltonian(c, k))
    H = bloch_model_hamiltonian(hofstadter_terms(c, 0), k)
    assert np.allclose(H, H0, atol=1e-14)


@pytest.mark.slow  # the same check runs in the fast tier as an example of docs/topology-surfaces.md
@pytest.mark.machine_independence
def test_lowest_landau_band_of_the_klein_cluster_matches_the_continuum():
    # Riemann-Roch: N_phi - g + 1 = 2 states in the lowest level; one unit of Hall conductance per
    # handle: its Chern matrix is the intersection form up to the sign of B
    res = landau_bands(hl.pbc_cluster(7, 3, "klein"), 4, levels=1, grid=8)
    assert res.bands.tolist() == [2] and res.degeneracy.tolist() == [2]
    assert bool(res.matches[0]) and res.gcd.tolist() == [1] and abs(res.pfaffian[0]) == 1
    assert res.energy_min[0] - 0.01 <= res.energy_continuum[0] <= res.energy_max[0] + 0.01


@pytest.mark.slow
@pytest.mark.machine_independence
@pytest.mark.parametrize("n_phi", [5])  # 4, 7 and 11: the table of docs/topology-surfaces.md
def test_landau_band_counts_follow_riemann_roch_on_the_klein_cluster(n_phi):
    res = landau_bands(hl.pbc_cluster(7, 3, "klein"), n_phi, levels=1)
    assert res.bands.tolist() == [n_phi - 2] == res.degeneracy.tolist()
    assert bool(res.matches[0])


def test_landau_bands_bad_input():
    c = hl.pbc_cluster(8, 3, "bolza")
    with pytest.raises(ValueError, match="n_phi"):
        landau_bands(c, 0)
    with pytest.raises(ValueError, match="gap"):
        landau_bands(c, 2)
    with pytest.raises(ValueError, match="Cluster"):
        cluster_flux_phases(square_torus(), 1)


# ---------------------------------------------------------------- frames of QWZ on clusters

def test_covariant_hop_is_the_flat_qwz_hop_in_the_plane():
    # a_ji = a_ij + pi (a straight bond): U(a) T0 U(a_ji - pi)^dagger = T(a) = (sz + i(cos a sx + sin a sy))/2
    from hyperlattice.topology.frames import _T0, _u

    sx = np.array([[0, 1], [1, 0]])
    sy = np.array([[0, -1j], [1j, 0]])
    sz = np.diag([1.0, -1.0])
    for a in (0.0, 0.7, np.pi / 2, 2.9):
        T = _u(a) @ _T0 @ np.conj(_u(a + np.pi - np.pi)).T
        assert np.allclose(T, 0.5 * (sz + 1j * (np.cos(a) * sx + np.sin(a) * sy)), atol=1e-15)


def test_covariant_frame_rotation_is_a_unitary_on_the_sites():
    from hyperlattice.topology.frames import qwz_frame_terms

    c = hl.pbc_cluster(8, 3, "bolza")
    alpha = np.random.default_rng(0).uniform(0, 2 * np.pi, c.sites)
    k = np.array([0.3, 1.2, -0.4, 2.0])
    e0 = np.linalg.eigvalsh(bloch_model_hamiltonian(qwz_frame_terms(c, M=1.0), k))
    e1 = np.linalg.eigvalsh(bloch_model_hamiltonian(qwz_frame_terms(c, M=1.0, alpha=alpha), k))
    assert np.allclose(e0, e1, atol=1e-12)


@pytest.mark.machine_independence
def test_covariant_frame_invariants_do_not_depend_on_the_labelling():
    # the covariant (spin-connection) frame: C = -Q (the intersection form) at M = 1 for every labelling
    from hyperlattice.topology.frames import frame_invariants, qwz_frame_terms, relabel_cluster

    c = hl.pbc_cluster(8, 3, "bolza")
    for d in (c, relabel_cluster(c, 1)):
        inv = frame_invariants(qwz_frame_terms(d, M=1.0))
        assert inv["chern"] == (-intersection_form(d)).tolist()
        assert (inv["gcd"], inv["abs_pfaffian"]) == (1, 1) and inv["gap"] > 0.7


def test_frames_bad_input():
    from hyperlattice.topology.frames import qwz_frame_terms

    c = hl.pbc_cluster(8, 3, "bolza")
    with pytest.raises(ValueError, match="frame"):
        qwz_frame_terms(c, frame="parallel")
    with pytest.raises(ValueError, match="alpha"):
        qwz_frame_terms(c, alpha=np.zeros(3))
    with pytest.raises(ValueError, match="Cluster"):
        qwz_frame_terms(square_torus())


@pytest.mark.machine_independence
def test_covariant_gap_closes_at_the_continuum_critical_mass_with_the_dirac_slope():
    # continuum: M_c = q/2 - q h^2/4 = 1.409 on {8,3}, gap 2|M - M_c| nearby; lattice (Bolza, 400 random k):
    # gaps 0.76 at M = 1 and 0.56 at M = 1.1 (slope 2 within 3 %), nearly closed at M_c
    from hyperlattice.topology.frames import covariant_critical_mass, qwz_frame_terms

    c = hl.pbc_cluster(8, 3, "bolza")
    mc = covariant_critical_mass(8, 3)
    assert mc == pytest.approx(1.409, abs=1e-3) and mc < 1.5
    K = np.random.default_rng(0).uniform(0, 2 * np.pi, (400, 4))

    def gap(M):
        e = np.linalg.eigvalsh(bloch_model_hamiltonian(qwz_frame_terms(c, M=M), K))
        return float((e[:, 16] - e[:, 15]).min())

    g1, g2, gc = gap(1.0), gap(1.1), gap(mc)
    assert (g1 - g2) / 0.1 == pytest.approx(2.0, rel=0.03)
    assert gc < 0.1 * g1
