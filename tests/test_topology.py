"""Topological models and invariants: Euclidean limits first, then hyperbolic flakes and clusters.

Reference values (each with its source and tolerance):

| system | invariant | value | source |
|---|---|---|---|
| square QWZ, M = +1 / -1 / 3 | Chern (FHS, marker, Kitaev, Bott) | -1 / +1 / 0 | QWZ, PRB 74, 085308; sign of Bianco–Resta |
| honeycomb Haldane, t2 = 0.2, phi = pi/2, M = 0 / 1.5 | Chern | +1 / 0 | Haldane, PRL 61, 2015: abs(M) < 3 sqrt(3) t2 |
| {8,3} QWZ M = 1, l = 3 | Kitaev / local marker at the centre | -1 / -0.98 | this package (converges with l) |
"""

from __future__ import annotations

import numpy as np
import pytest

import hyperlattice as hl
from hyperlattice.topology import (flake_topology, honeycomb_flake, honeycomb_torus, model_hamiltonian, model_terms,
                                   square_flake, square_torus)
from hyperlattice.topology.surfaces import cluster_chern, pfaffian

pytestmark = pytest.mark.filterwarnings("ignore:the Bott index is unreliable")


@pytest.mark.machine_independence
@pytest.mark.parametrize("M,chern", [(1.0, -1), (-1.0, 1), (3.0, 0)])
def test_square_qwz_bloch_chern_has_the_bianco_resta_sign(M, chern):
    res = cluster_chern(square_torus(), "qwz", M=M)
    assert res.chern.tolist() == [[0, chern], [-chern, 0]]
    assert abs(res.chern_raw[0, 1] - chern) < 1e-9
    assert res.gap > 1.9


def test_square_qwz_bloch_hamiltonian_is_the_textbook_one():
    from hyperlattice.topology.models import bloch_model_hamiltonian

    kx, ky, M = 0.3, -1.1, 0.7
    H = bloch_model_hamiltonian(model_terms(square_torus(), "qwz", M=M), [kx, ky])
    sx, sy, sz = np.array([[0, 1], [1, 0]]), np.array([[0, -1j], [1j, 0]]), np.diag([1, -1])
    ref = (M + np.cos(kx) + np.cos(ky)) * sz - np.sin(kx) * sx - np.sin(ky) * sy
    assert np.allclose(H, ref, atol=1e-14)


@pytest.mark.machine_independence
@pytest.mark.parametrize("M,chern", [(0.0, 1), (1.5, 0)])
def test_honeycomb_haldane_bloch_chern(M, chern):
    assert cluster_chern(honeycomb_torus(), "haldane", M=M, t2=0.2).chern[0, 1] == chern


@pytest.mark.parametrize("M,chern", [(1.0, -1), (-1.0, 1), (3.0, 0)])
def test_square_flake_markers_agree_with_the_bloch_chern_number(M, chern):
    top = flake_topology(square_flake(12), "qwz", M=M, per_ring=2)
    assert abs(top.marker - chern) < 0.02
    assert abs(top.kitaev - chern) < 0.02
    assert abs(top.bott - chern) < 1e-6
    assert abs(top.flat_by_ring[0] - chern) < 0.02      # the flat marker is right in flat space
    assert top.gap > 1.5


def test_honeycomb_flake_haldane_markers():
    top = flake_topology(honeycomb_flake(12), "haldane", M=0.0, t2=0.2, per_ring=2)
    assert abs(top.marker - 1) < 0.03
    assert abs(top.kitaev - 1) < 0.01


def test_hyperbolic_flake_local_marker_quantises_where_the_flat_one_does_not():
    # {8,3} QWZ at M = 1: Kitaev's sum and the local marker give -1, the flat Bianco–Resta marker
    # in disk coordinates does not (the chart is not isometric over a correlation length)
    top = flake_topology(hl.ring_lattice(8, 3, 3), "qwz", M=1.0)
    assert abs(top.kitaev + 1) < 0.01
    assert abs(top.marker + 1) < 0.03
    assert abs(top.bott + 1) < 1e-6
    assert top.flat_by_ring[0] > -0.7               # -0.61: not quantised
    assert top.recentred_by_ring[0] > -0.9          # -0.82: recentring does not cure it
    assert abs(top.marker_by_ring[-1]) < 0.2        # the edge ring: the disk leaves the flake
    df = top.to_dataframe()
    assert list(df["ring"]) == [1, 2, 3]


def test_turns_around_every_face_are_left_turns_on_flakes_and_clusters():
    from hyperlattice.graph.flux import faces
    from hyperlattice.topology.models import _darts

    for graph, cycles in [(hl.pbc_cluster(8, 3, "bolza"), None), (hl.ring_lattice(8, 3, 3), "flake")]:
        dd = _darts(graph)
        d1, d2, turn = dd.paths
        key = {(int(dd.tail[a]), int(dd.head[a]), int(dd.head[b])): int(s) for a, b, s in zip(d1, d2, turn)}
        fs = [np.asarray(f) for f in (graph.faces if cycles is None else faces(graph))]
        seen = {key[(int(f[j]), int(f[(j + 1) % len(f)]), int(f[(j + 2) % len(f)]))] for f in fs for j in range(len(f))}
        assert seen == {1}


def test_flake_hamiltonian_is_hermitian_and_rotation_covariant_spectrum():
    lat = hl.ring_lattice(8, 3, 2)
    for model in ("qwz", "haldane", "kane-mele"):
        H = model_hamiltonian(model_terms(lat, model, M=0.3, rashba=0.1 if model == "kane-mele" else 0.0))
        assert abs(H - H.getH()).max() < 1e-14


def test_kane_mele_spin_chern_on_a_honeycomb_flake():
    top = flake_topology(honeycomb_flake(10), "kane-mele", M=0.0, t2=0.2, per_ring=2)
    assert abs(abs(top.kitaev) - 1) < 0.05


def test_cluster_chern_matrix_invariants():
    res = cluster_chern(hl.pbc_cluster(8, 3, "bolza"), "qwz", M=1.0)
    c = res.chern
    assert c.shape == (4, 4) and np.array_equal(c, -c.T)
    assert res.pfaffian == round(pfaffian(c))
    assert res.gap > 0.1
    # a change of homology basis A in GL(4, Z): gcd invariant, |Pf| invariant
    A = np.array([[1, 1, 0, 0], [0, 1, 0, 0], [0, 0, 1, 2], [0, 0, 0, 1]])
    c2 = A.T @ c @ A
    import math

    assert math.gcd(*[abs(int(x)) for x in c2[np.triu_indices(4, 1)]]) == res.gcd
    assert abs(pfaffian(c2)) == abs(res.pfaffian)


def test_cluster_angles_are_antipodal_on_every_edge():
    from hyperlattice.topology.models import _cluster_darts, cluster_angles

    c = hl.pbc_cluster(8, 3, "bolza")
    a = cluster_angles(c).ravel()
    rev = _cluster_darts(c).rev
    assert np.allclose(np.exp(1j * a[rev]), -np.exp(1j * a))


@pytest.mark.parametrize("call,match", [
    (lambda: flake_topology(square_flake(4), "chern"), "model"),
    (lambda: flake_topology(square_flake(4), "qwz", M=float("nan")), "M"),
    (lambda: flake_topology(square_flake(4), "qwz", fermi=100.0), "outside the spectrum"),
    (lambda: cluster_chern(square_flake(4), "qwz"), "closed surface"),
    (lambda: model_terms(square_flake(4), "haldane"), "degree 3"),
    (lambda: model_terms(hl.ring_lattice(7, 3, 2), "haldane"), "bipartite"),
])
def test_bad_input_is_one_sentence(call, match):
    with pytest.raises(ValueError, match=match):
        call()


def test_chebyshev_centre_marker_matches_dense_on_the_same_disks():
    from hyperlattice.topology import occupied_states
    from hyperlattice.topology.kpm_marker import centre_marker
    from hyperlattice.topology.markers import _geometry, _local_kitaev

    g = square_flake(14)
    res = centre_marker(g, "qwz", M=1.0, moments=512)
    occ = occupied_states(g, "qwz", M=1.0, fermi=0.0)
    geo = _geometry(g)
    ref = np.mean([_local_kitaev(geo, occ.vectors, 2, geo.z[i], res.parameters["radius"]) for i in res.evaluated_sites])
    assert abs(res.marker - ref) < 2e-3
    assert res.marker_error < 2e-3          # the estimate (N vs N/2) is of the size of the true error
    assert abs(res.marker + 1) < 0.01


def test_chebyshev_marker_warns_when_the_moments_are_too_few():
    from hyperlattice.errors import ConvergenceWarning
    from hyperlattice.topology.kpm_marker import centre_marker

    with pytest.warns(ConvergenceWarning, match="raise moments"):
        centre_marker(hl.ring_lattice(8, 3, 3), "qwz", M=1.0, moments=32, tol=1e-3)


def test_bott_index_on_the_rectangular_honeycomb_flake():
    top = flake_topology(honeycomb_flake(8), "haldane", M=0.0, t2=0.2, per_ring=2)
    assert abs(top.bott - 1) < 1e-6 and top.bott_reliable


@pytest.mark.slow
def test_hyperbolic_markers_converge_with_the_flake():
    from hyperlattice.topology.kpm_marker import centre_marker

    top = flake_topology(hl.ring_lattice(8, 3, 4), "qwz", M=1.0, per_ring=2)
    assert abs(top.marker + 1) < 2e-3 and abs(top.kitaev + 1) < 1e-3
    assert top.flat_by_ring[0] > -0.7 and top.recentred_by_ring[0] > -0.9
    res = centre_marker(hl.ring_lattice(8, 3, 4), "qwz", M=1.0, moments=512)
    assert abs(res.marker + 1) < 2e-3 and res.marker_error < 1e-3


def test_sweep_task_runs_one_realization_and_checks_its_parameters():
    from hyperlattice.sweep import tasks

    task = tasks.get_task("topology")
    params = dict(task.defaults, rings=3, W=1.0, seed=2, moments=64)
    task.check(params)
    row = tasks.execute("topology", params)
    assert set(row) == {"marker", "marker_error", "kitaev", "gap"}
    again = tasks.execute("topology", params)
    assert row["marker"] == again["marker"]          # same seed, same bits
    with pytest.raises(ValueError, match="W"):
        task.check(dict(params, W=-1.0))
    with pytest.raises(ValueError, match="model"):
        task.check(dict(params, model="kane-mele"))


@pytest.mark.machine_independence
@pytest.mark.parametrize("graph,model,M,chern", [
    (square_flake(10), "qwz", 1.0, -1), (square_flake(10), "qwz", -1.0, 1), (square_flake(10), "qwz", 3.0, 0),
    (honeycomb_flake(8), "haldane", 0.0, 1), (hl.ring_lattice(8, 3, 3), "qwz", 1.0, -1),
    (hl.ring_lattice(8, 3, 3), "qwz", -1.0, 1),
])
def test_edge_packets_run_against_the_chern_number(graph, model, M, chern):
    # measured convention: a flake with C = -1 (Bianco–Resta sign) has edge states running counterclockwise
    from hyperlattice.topology import edge_chirality

    res = edge_chirality(graph, model, M=M)
    assert res.chirality == -chern
    if chern:
        assert abs(res.angle[-1]) > 0.1 and res.packet_weight > 0.3


def test_the_geodesic_tangent_frame_gives_the_same_invariants():
    lat = hl.ring_lattice(8, 3, 3)
    chord = flake_topology(lat, "qwz", M=1.0, per_ring=1)
    tangent = flake_topology(lat, "qwz", M=1.0, per_ring=1, frame="tangent")
    assert abs(chord.kitaev - tangent.kitaev) < 1e-3 and abs(chord.marker - tangent.marker) < 1e-3
    H = model_hamiltonian(model_terms(lat, "qwz", M=1.0, frame="tangent"))
    assert abs(H - H.getH()).max() < 1e-14
