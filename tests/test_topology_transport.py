"""Two-terminal conductance of Chern flakes (Landauer–Caroli with wide-band leads on the edge).

Reference values, each with its source and tolerance:

* in the bulk gap of a Chern insulator G = |C| e²/h (one chiral edge channel per edge between the
  contacts; Halperin, PRB 25, 2185 (1982)): square QWZ at M = ±1 (C = ∓1), honeycomb Haldane
  (C = 1), {8,3} QWZ at M = ±1 (marker ∓1, ``tests/test_topology.py``);
* a trivial insulator (square QWZ at M = 3, {8,3} QWZ at M = 2.5) has G = 0 up to tunnelling
  through the gap, exponentially small in the flake's size;
* the sparse Caroli sum equals the dense trace Tr[Γ_L G Γ_R G†] with G a dense inverse (brute force).
"""

from __future__ import annotations

import json

import numpy as np
import pytest

import hyperlattice as hl
from hyperlattice.cli import main
from hyperlattice.topology import honeycomb_flake, square_flake
from hyperlattice.topology.markers import _rows
from hyperlattice.topology.models import model_hamiltonian, model_terms
from hyperlattice.topology.transport import Conductance, conductance, edge_contacts

# (graph, model, params, G in e²/h at E = 0, tolerance)
PLATEAUS = [
    ("square 10", "qwz", dict(M=1.0), 1.0, 1e-3),
    ("square 10", "qwz", dict(M=-1.0), 1.0, 1e-3),
    ("square 10", "qwz", dict(M=3.0), 0.0, 1e-3),
    ("honeycomb 8", "haldane", dict(M=0.0, t2=0.2), 1.0, 1e-3),
    ("{8,3} l=3", "qwz", dict(M=1.0), 1.0, 1e-3),
    ("{8,3} l=3", "qwz", dict(M=-1.0), 1.0, 1e-3),
    ("{8,3} l=3", "qwz", dict(M=2.5), 0.0, 1e-3),
]


def _graph(name):
    return {"square 10": lambda: square_flake(10), "honeycomb 8": lambda: honeycomb_flake(8),
            "{8,3} l=3": lambda: hl.ring_lattice(8, 3, 3)}[name]()


@pytest.mark.parametrize("name, model, params, expected, tol", PLATEAUS)
def test_conductance_is_the_chern_number_in_the_gap(name, model, params, expected, tol):
    res = conductance(_graph(name), model, energies=[0.0], **params)
    assert abs(res.conductance[0] - expected) < tol
    assert res.error[0] < 1e-10


def test_sparse_caroli_equals_the_dense_trace():
    lat = hl.ring_lattice(8, 3, 2)
    left, right = edge_contacts(lat, 0.2)
    E, gamma = 0.3, 1.5
    res = conductance(lat, "qwz", M=1.0, energies=[E], coupling=gamma, contacts=(left, right))
    H = model_hamiltonian(model_terms(lat, "qwz", M=1.0)).toarray()
    gl, gr = np.zeros(len(H)), np.zeros(len(H))
    gl[_rows(left, 2)], gr[_rows(right, 2)] = gamma, gamma
    G = np.linalg.inv(E * np.eye(len(H)) - H + 0.5j * np.diag(gl + gr))
    T = np.trace(np.diag(gl) @ G @ np.diag(gr) @ G.conj().T).real
    assert abs(res.conductance[0] - T) < 1e-10 * max(1.0, T)


def test_plateau_breaks_down_in_the_bands_and_vanishes_outside_the_spectrum():
    res = conductance(hl.ring_lattice(8, 3, 3), "qwz", M=1.0, energies=[-0.2, 0.2, 0.5, 4.0])
    assert np.all(np.abs(res.conductance[:2] - 1) < 1e-3)
    assert abs(res.conductance[2] - 1) > 0.1          # bulk states: not quantised
    assert res.conductance[3] < 1e-6                  # above the spectrum (|E| < 2.5 here)
    df = res.to_dataframe()
    assert list(df.columns) == ["energy", "conductance", "error"]


def test_plateau_survives_weak_disorder():
    lat = hl.ring_lattice(8, 3, 3)
    g = [conductance(lat, "qwz", M=1.0, disorder=1.0, seed=s).conductance[0] for s in range(3)]
    assert np.all(np.abs(np.array(g) - 1) < 1e-3)


@pytest.mark.machine_independence
def test_default_contacts_are_two_opposite_arcs_of_the_edge():
    lat = hl.ring_lattice(8, 3, 3)
    left, right = edge_contacts(lat)
    assert len(left) == len(right) and np.intersect1d(left, right).size == 0
    assert np.all(lat.ring[left] >= lat.ring.max() - 1) and np.all(lat.z[right].real > 0)
    assert np.all(lat.z[left].real < 0)


@pytest.mark.parametrize("kwargs, match", [
    (dict(energies=[np.nan]), "energies"),
    (dict(energies=[]), "at least one"),
    (dict(coupling=0.0), "coupling"),
    (dict(arc=0.5), "arc"),
    (dict(contacts=([0, 1], [1, 2])), "disjoint"),
    (dict(contacts=([0],)), "pair"),
    (dict(M=np.nan), "M"),
])
def test_bad_input_is_refused_in_one_sentence(kwargs, match):
    with pytest.raises(ValueError, match=match):
        conductance(hl.ring_lattice(8, 3, 2), "qwz", **kwargs)


def test_a_torus_has_no_edge_to_contact():
    from hyperlattice.topology import square_torus

    with pytest.raises(ValueError, match="open flake"):
        conductance(square_torus(), "qwz")


def test_cli_json_states_the_units(capsys):
    assert main(["topology", "conductance", "--rings", "2", "--M", "1", "--energies", "-0.1,0", "--coupling", "2",
                 "--arc", "0.25", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["units"] == {"energy": "t", "conductance": "e^2/h"}
    assert out["energy"] == [-0.1, 0.0] and len(out["conductance_e2h"]) == 2


def test_result_round_trips():
    res = conductance(square_flake(6), "qwz", M=1.0)
    back = Conductance.from_dict(json.loads(json.dumps(res.as_dict())))
    assert np.array_equal(back.conductance, res.conductance)


@pytest.mark.slow
def test_plateau_on_the_l4_flake_and_its_disorder_average():
    """{8,3} l = 4 (768 sites): G = 1 across the centre's gap, and the mean over 4 seeds stays 1 at W = 2."""
    lat = hl.ring_lattice(8, 3, 4)
    res = conductance(lat, "qwz", M=1.0, energies=np.linspace(-0.25, 0.25, 5))
    assert np.all(np.abs(res.conductance - 1) < 1e-3)
    g = [conductance(lat, "qwz", M=1.0, disorder=2.0, seed=s).conductance[0] for s in range(4)]
    assert abs(np.mean(g) - 1) < 0.01


@pytest.mark.slow
def test_topological_anderson_insulator_plateau_of_the_average():
    """QWZ on the l = 4 {8,3} flake at M = 1.52 (trivial, M_c ≈ 1.48): G ≈ 0 clean, the mean over 16
    realizations at W = 3 is one e²/h within 0.1 (docs/topology.md: 1.026 ± 0.045)."""
    lat = hl.ring_lattice(8, 3, 4)
    assert conductance(lat, "qwz", M=1.52).conductance[0] < 0.05
    g = [conductance(lat, "qwz", M=1.52, disorder=3.0, seed=s).conductance[0] for s in range(16)]
    assert abs(np.mean(g) - 1) < 0.1
