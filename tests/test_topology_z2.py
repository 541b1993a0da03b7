"""The Z2 index with Rashba coupling (Wilson loops on closed surfaces) and the parallel-transport frame on flakes.

References: Kane and Mele's phase diagram on the honeycomb torus (PRL 95, 146802 and 226801 (2005)),
the spin Chern numbers of the s_z-conserving case, the Levi-Civita holonomy of a {8,3} face.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import hyperlattice as hl
from hyperlattice.topology import flake_topology, honeycomb_torus, model_terms
from hyperlattice.topology.closed import spin_chern
from hyperlattice.topology.models import model_hamiltonian, transport_rotation
from hyperlattice.topology.z2 import time_reversal_error, wilson_phases, z2_index

LSO = 0.06   # lambda_SO = t2 at phi = pi/2; Kane-Mele's boundaries 3 sqrt3 lambda_SO = 0.312, 2 sqrt3 lambda_SO = 0.208


# ---------------------------------------------------------------- Z2 on the honeycomb torus

@pytest.mark.machine_independence
@pytest.mark.parametrize("M, rashba, z2", [
    (0.29, 0.0, 1), (0.33, 0.0, 0),        # lambda_R = 0: Z2 = 1 for |lambda_v| < 3 sqrt3 lambda_SO
    (0.0, 0.19, 1),                        # lambda_v = 0: open gap up to lambda_R = 2 sqrt3 lambda_SO
    (0.2, 0.1, 1), (0.2, 0.15, 0),         # the Rashba-reduced region at finite lambda_v
])
def test_z2_follows_kane_mele_phase_diagram(M, rashba, z2):
    res = z2_index(honeycomb_torus(), M=M, t2=LSO, rashba=rashba)
    assert res.z2.tolist() == [z2]
    assert res.gap > 0.05 and res.indirect_gap > 0.05 and res.clearance.min() > 0.1


@pytest.mark.machine_independence
@pytest.mark.parametrize("M", [0.1, 0.9, 1.2])
def test_z2_without_rashba_is_the_spin_chern_number_mod_2(M):
    sc = spin_chern(honeycomb_torus(), M=M, t2=0.2)
    assert z2_index(honeycomb_torus(), M=M, t2=0.2).z2.tolist() == [int(sc.spin_chern[0, 1]) % 2]


def test_time_reversal_holds_with_rashba_and_wilson_phases_pair_at_k_zero():
    terms = model_terms(honeycomb_torus(), "kane-mele", M=0.1, t2=0.2, rashba=0.1)
    assert time_reversal_error(terms) < 1e-12
    ka, ph, gap = wilson_phases(terms, 0, 1, grid=8)
    assert ph.shape == (9, 2) and gap > 0.1
    # Kramers pairs at k_a = 0 and pi: the two Wannier centres coincide
    assert abs(np.angle(np.exp(1j * (ph[0, 0] - ph[0, 1])))) < 1e-6


def test_z2_warns_for_a_semimetal():
    with pytest.warns(UserWarning, match="bands overlap"):
        z2_index(honeycomb_torus(), M=0.0, t2=0.2, rashba=0.6)


def test_z2_refuses_an_open_graph_and_qwz():
    with pytest.raises(ValueError, match="closed surface"):
        z2_index(hl.ring_lattice(8, 3, 2))
    with pytest.raises(ValueError, match="open graph"):
        time_reversal_error(model_terms(hl.ring_lattice(8, 3, 2), "kane-mele"))


@pytest.mark.slow
@pytest.mark.machine_independence
def test_z2_on_bolza_without_rashba_matches_spin_chern_and_stays_with_rashba():
    bolza = hl.pbc_cluster(8, 3, "bolza")
    sc = spin_chern(bolza, M=0.3, t2=0.2)
    res = z2_index(bolza, M=0.3, t2=0.2)
    allzero = np.all(res.fixed <= 0, axis=1)
    want = [int(sc.spin_chern[a, b]) % 2 for a, b in res.subtori[allzero]]
    assert res.z2[allzero].tolist() == want
    assert len(res.z2) == 24
    assert z2_index(bolza, M=0.3, t2=0.2, rashba=0.05).z2.tolist() == res.z2.tolist()


# ---------------------------------------------------------------- the parallel-transport frame on flakes

def test_transport_frame_holonomy_is_the_face_angle_and_h_is_hermitian():
    lat = hl.ring_lattice(8, 3, 3)
    tail, head, a, delta = transport_rotation(lat)
    ring1 = np.flatnonzero(np.asarray(lat.ring) == 1)            # the central octagon, counterclockwise
    total = sum(delta[np.flatnonzero((tail == i) & (head == j))[0]] for i, j in zip(ring1, np.roll(ring1, -1)))
    assert total == pytest.approx(-(6 * np.pi - 2 * np.pi * 8 / 3), abs=1e-9)   # minus the Levi-Civita holonomy
    H = model_hamiltonian(model_terms(lat, "qwz", M=1.0, frame="transport"))
    assert abs(H - H.getH()).max() < 1e-14


def test_transport_frame_keeps_the_invariants_where_the_gap_is_clean():
    lat = hl.ring_lattice(8, 3, 3)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        a = flake_topology(lat, "qwz", M=0.9, frame="chord")
        b = flake_topology(lat, "qwz", M=0.9, frame="transport")
    assert abs(a.marker - b.marker) < 0.01 and abs(a.kitaev - b.kitaev) < 0.01 and round(a.bott) == round(b.bott) == -1


def test_transport_frame_is_refused_off_qwz_flakes():
    with pytest.raises(ValueError, match="transport"):
        model_terms(hl.ring_lattice(8, 3, 2), "kane-mele", frame="transport")
    with pytest.raises(ValueError, match="transport"):
        model_terms(honeycomb_torus(), "qwz", frame="transport")


# ---------------------------------------------------------------- flakes: spin Chern marker, spin Bott, gap of P s_z P

@pytest.mark.machine_independence
def test_kane_mele_flake_with_rashba_keeps_z2_where_the_spin_gap_is_open():
    # {8,3}: the clean gap of the Haldane copies at about a third filling (E_F = -1.247, t2 = 0.2)
    top = flake_topology(hl.ring_lattice(8, 3, 3), "kane-mele", M=0.0, t2=0.2, rashba=0.2, fermi=-1.247)
    assert top.spin_gap > 1.0 and top.z2 == 1 and round(top.bott) == 1 and abs(top.marker - 1) < 0.15
    out = top.summary()
    assert out["z2"] == 1 and out["spin_bott"] == top.bott and out["spin_gap"] == top.spin_gap


def test_kane_mele_flake_warns_when_the_spin_gap_closes():
    with pytest.warns(UserWarning, match="P s_z P"):
        flake_topology(hl.ring_lattice(8, 3, 3), "kane-mele", M=0.0, t2=0.2, rashba=0.2)


def test_chord_frame_is_the_transport_frame_without_the_connection_on_its_sigma_z_part():
    # the chord of a circular-arc geodesic makes equal angles with both tangents: theta = a + delta/2,
    # so T_chord = U(delta/2) T_transport U(delta/2): the same sigma_x, sigma_y part, a real sigma_z part
    lat = hl.ring_lattice(8, 3, 3)
    _, _, a, delta = transport_rotation(lat)
    chord = model_terms(lat, "qwz", M=1.0).blocks
    tr = model_terms(lat, "qwz", M=1.0, frame="transport").blocks
    u = np.zeros((len(delta), 2, 2), dtype=complex)
    u[:, 0, 0], u[:, 1, 1] = np.exp(-0.25j * delta), np.exp(0.25j * delta)
    assert np.abs(u @ tr @ u - chord).max() < 1e-12
    assert np.abs(np.diagonal(chord, axis1=1, axis2=2).imag).max() < 1e-15
