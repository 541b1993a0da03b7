"""Closed surfaces: the {8,8} Dirac model and its second Chern number, why the {8,3} models have C2 = 0
(a class-D particle-hole symmetry), Chern numbers away from half filling, and the twist marker.

References with their tolerances: the 4D lattice Dirac model's C2 = -1, 3, -3, 1 in the four gapped
intervals of m (Qi, Hughes and Zhang, PRB 78, 195424 (2008), with the curvature sign of
hyperlattice.topology.closed); class D has no invariant in four dimensions (Schnyder et al., PRB 78,
195125 (2008)); the twist marker's sum rule is the single-point Chern number (Ceresoli and Resta, PRB
76, 012405 (2007)), exact only as the cluster outgrows the correlation length.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

import hyperlattice as hl
from hyperlattice.topology import closed, dartmaps, models, surfaces, twist_marker
from hyperlattice.topology.frames import qwz_frame_terms
from hyperlattice.topology.landau import intersection_form

BOLZA = hl.pbc_cluster(8, 3, "bolza")


# ---------------------------------------------------------------------------------------------
# maps kept as darts and the {8,8} Dirac model
# ---------------------------------------------------------------------------------------------

@pytest.mark.parametrize("name,sites,genus", [("one-site", 1, 2), ("two-site", 2, 3)])
def test_dart_maps_close_with_unimodular_windings(name, sites, genus):
    m = dartmaps.named_dart_map(name)
    assert (m.sites, m.genus) == (sites, genus)
    w = m.windings
    assert np.array_equal(w[m.reverse], -w)
    # faces (orbits of d -> y(x(d))) sum to zero, and the 2g loops left by the tree-cotree are a basis
    face = dartmaps._orbits(m.rotate[m.reverse])
    for f in range(face.max() + 1):
        assert not np.any(w[face == f].sum(axis=0))
    assert np.linalg.matrix_rank(w) == 2 * genus


def test_one_site_dirac_model_is_the_4d_lattice_dirac_model():
    # one vertex, four loops with unit windings: H(k) is dirac4_torus's at the same k (up to the order of the k's)
    t = dartmaps.dirac4_terms("one-site", -1.3)
    assert t.sites == 1 and sorted(np.abs(t.windings).sum(axis=0).tolist()) == [2, 2, 2, 2]
    k = np.random.default_rng(0).uniform(0, 2 * np.pi, (5, 4))
    e1 = np.linalg.eigvalsh(models.bloch_model_hamiltonian(t, k))
    ref = closed.dirac4_torus(-1.3)
    # same spectrum as sum_j sin k_j G_j + (m + sum cos k_j) G_5: +-sqrt(sum sin^2 + (m + sum cos)^2), doubly
    # degenerate, for the permuted momenta
    d = np.sqrt(np.sum(np.sin(k) ** 2, axis=1) + (-1.3 + np.cos(k).sum(axis=1)) ** 2)
    assert np.allclose(e1, np.stack([-d, -d, d, d], axis=1), atol=1e-12)
    assert np.allclose(np.linalg.eigvalsh(models.bloch_model_hamiltonian(ref, k)), e1, atol=1e-12)


def test_dirac_model_refuses_maps_that_do_not_cover_the_one_site_map():
    # {8,8} with y^2 = ... : Z8 x Z2 with x = (4, 0)? take a map whose x is not y^4 modulo the cover: (x y)^2 y^4
    with pytest.raises(ValueError):
        dartmaps.dirac4_terms(dartmaps.dart_map(8, 3, ["(x y x y x Y)^2"], name="bolza-darts"))


@pytest.mark.slow
@pytest.mark.parametrize("m,c2", [(-5.0, 0), (-3.0, -1), (-1.0, 3), (1.0, -3), (3.0, 1), (5.0, 0)])
def test_one_site_dirac_model_every_phase(m, c2):
    res = closed.second_chern(dartmaps.dirac4_terms("one-site", m), tol=0.01)
    assert res.chern2.tolist() == [c2]


@pytest.mark.slow
def test_two_site_cover_second_chern_numbers():
    # genus 3, fifteen 4-subtori; at m = -3.5 the cover's gap on the grids is 0.072 (against 1 for the one-site
    # Abelian bands): the non-Abelian sectors of the one-site model come close to closing it
    res = closed.second_chern(dartmaps.dirac4_terms("two-site", -3.5), grid=8, max_grid=20, tol=0.05)
    assert res.chern2.tolist() == [0, 0, -1, 0, 1, 1, 0, -1, -1, 0, 0, 1, 0, 1, -1]
    assert 0.05 < res.gap < 0.1


# ---------------------------------------------------------------------------------------------
# why C2 = 0 on {8,3}: particle-hole symmetry of class D
# ---------------------------------------------------------------------------------------------

@pytest.mark.parametrize("label,terms,square", [
    ("qwz lift", models.model_terms(BOLZA, "qwz", M=1.0), 1),
    ("qwz covariant", qwz_frame_terms(BOLZA, M=1.0), 1),
    ("haldane M=0 phi=pi/2", models.model_terms(BOLZA, "haldane", M=0.0, t2=0.3), 1),
    ("haldane M=0.2", models.model_terms(BOLZA, "haldane", M=0.2, t2=0.3), None),
    ("haldane phi=1", models.model_terms(BOLZA, "haldane", M=0.0, t2=0.3, phi=1.0), None),
    ("dirac4", dartmaps.dirac4_terms("one-site", -3.0), None),
])
def test_particle_hole_symmetry_of_the_models(label, terms, square):
    ph = closed.particle_hole(terms)
    assert (None if ph is None else ph["square"]) == square, label


def test_class_d_makes_the_second_chern_density_odd():
    k = np.random.default_rng(1).uniform(0, 2 * np.pi, (3, 4))
    qwz = models.model_terms(BOLZA, "qwz", M=1.0)
    a, b = closed.chern2_density(qwz, k=k), closed.chern2_density(qwz, k=-k)
    assert np.max(np.abs(a)) > 1e-4 and np.allclose(a, -b, atol=1e-12 * np.max(np.abs(a)) + 1e-15)
    d = closed.dirac4_torus(-3.0)
    assert np.allclose(closed.chern2_density(d, k=k), closed.chern2_density(d, k=-k), atol=1e-12)


# ---------------------------------------------------------------------------------------------
# Chern numbers away from half filling
# ---------------------------------------------------------------------------------------------

@pytest.mark.machine_independence
def test_haldane_c_plus_one_gap_on_bolza_is_plus_the_intersection_form():
    # the flake's C = +1 gap (t2 = 0.2, E_F = -1.247 at filling 0.299 on the flakes) holds 5 of Bolza's 16 bands
    res = surfaces.cluster_chern(BOLZA, "haldane", M=0.0, t2=0.2, fermi_level=-1.247)
    assert res.occupied == 5 and np.array_equal(res.chern, intersection_form(BOLZA))
    assert res.fermi_window[0] < -1.247 < res.fermi_window[1]
    same = surfaces.cluster_chern(BOLZA, "haldane", M=0.0, t2=0.2, occupied=5)
    assert np.array_equal(same.chern, res.chern) and same.fermi_level is None


def test_fermi_level_in_a_band_is_refused():
    for e_f in (-1.85, -2.0, -0.9):
        with pytest.raises(ValueError, match="lies in a band"):
            surfaces.cluster_chern(BOLZA, "haldane", M=0.0, t2=0.2, fermi_level=e_f)
    with pytest.raises(ValueError, match="not both"):
        surfaces.cluster_chern(BOLZA, "haldane", M=0.0, t2=0.2, fermi_level=-1.3, occupied=5)


# ---------------------------------------------------------------------------------------------
# the twist marker
# ---------------------------------------------------------------------------------------------

def test_twist_marker_sum_rule_and_locality_on_dyck():
    dyck = hl.pbc_cluster(8, 3, "dyck")
    Q = intersection_form(dyck)
    pairs = [(0, b) for b in range(1, 6)]
    res = twist_marker.twist_marker(qwz_frame_terms(dyck, M=1.0), pairs=pairs)
    # covariant QWZ at M = 1 has C = -Q; one twist point gives it within 5e-3 on 32 sites (4.7e-3 measured)
    assert np.abs(res.total + Q).max() < 0.01
    assert np.allclose(res.marker.sum(axis=1), [res.total[a, b] for a, b in pairs], atol=1e-10)
    for s, (a, b) in enumerate(pairs):
        if Q[a, b] != 0:
            assert res.within(3)[s] == pytest.approx(1.0, abs=0.01)


def test_twist_marker_gram_in_chunks_is_the_same(monkeypatch):
    terms = qwz_frame_terms(BOLZA, M=1.0)
    whole = twist_marker.twist_marker(terms, pairs=[(0, 2)])
    monkeypatch.setattr(twist_marker, "_GRAM_BYTES", 1.0)
    chunked = twist_marker.twist_marker(terms, pairs=[(0, 2)])
    assert np.allclose(whole.total, chunked.total, atol=1e-12)
    assert np.allclose(whole.total, -whole.total.T)


def test_twist_marker_table_accumulates_to_the_pair_total():
    res = twist_marker.twist_marker(qwz_frame_terms(BOLZA, M=1.0), pairs=[(0, 2)])
    df = res.table()
    assert df["cumulative"].iloc[-1] == pytest.approx(res.total[0, 2], abs=1e-10)


# ---------------------------------------------------------------------------------------------
# CLI
# ---------------------------------------------------------------------------------------------

def _json(capsys, argv):
    from hyperlattice.cli import main

    assert main(argv) == 0
    return json.loads(capsys.readouterr().out)


def test_cli_dirac4_chern2_keys(capsys):
    out = _json(capsys, ["topology", "cluster", "--model", "dirac4", "--cluster", "one-site", "-p", "8", "-q", "8",
                         "--M", "3", "--chern2", "--json"])
    for key in ("chern", "gcd", "pfaffian", "gap", "chern2", "chern2_pfaffian", "subtori", "occupied"):
        assert key in out
    assert out["chern2"] == [1] and out["genus"] == 2 and out["sites"] == 1


def test_cli_filling_and_fermi_level_agree(capsys):
    base = ["topology", "cluster", "--model", "haldane", "--cluster", "bolza", "--M", "0", "--t2", "0.2", "--json"]
    a = _json(capsys, base + ["--filling", "5/16"])
    b = _json(capsys, base + ["--fermi-level", "-1.3"])
    assert a["chern"] == b["chern"] and a["occupied"] == b["occupied"] == 5 and b["fermi_level"] == -1.3
