"""Bad input for the topology room: models, markers, cluster Chern numbers (see tests/badinput.py)."""

from __future__ import annotations

import pytest

from badinput import api_cases, check_api, check_cli, cli_cases
from hyperlattice.graph.clusters import pbc_cluster
from hyperlattice.graph.lattice import ring_lattice
from hyperlattice.topology import kpm_marker, markers, models, surfaces

FLAKE = ring_lattice(8, 3, 2)
SQUARE = models.square_flake(4)
OCC = markers.occupied_states(FLAKE, "qwz", M=1.0)
TERMS = models.model_terms(models.square_torus(), "qwz", M=1.0)
BOLZA = pbc_cluster(8, 3, "bolza")

# (id, function, working keyword arguments, {argument: tags it legitimately accepts})
CASES = [
    ("square_flake", models.square_flake, dict(length=3), {}),
    ("honeycomb_flake", models.honeycomb_flake, dict(length=3), {}),
    ("model_terms", models.model_terms, dict(graph=SQUARE, model="qwz", M=1.0, flux=0.0, disorder=0.1, seed=1), {}),
    ("model_hamiltonian", models.model_hamiltonian, dict(terms=TERMS), {}),
    ("bloch_model_hamiltonian", models.bloch_model_hamiltonian, dict(terms=TERMS, k=[0.1, 0.2]), {}),
    ("cluster_angles", models.cluster_angles, dict(cluster=BOLZA), {}),
    ("orbitals", models.orbitals, dict(model="qwz"), {}),
    ("spin_operator", models.spin_operator, dict(model="kane-mele", sites=3), {}),
    ("occupied_states", markers.occupied_states, dict(graph=SQUARE, model="qwz", M=1.0, fermi=0.1),
     {"fermi": {"none"}}),
    ("local_markers", markers.local_markers, dict(graph=FLAKE, occupied=OCC, sites=[0], radius=1.0),
     {"sites": {"none"}, "radius": {"none"}}),
    ("flake_topology", markers.flake_topology, dict(graph=SQUARE, model="qwz", M=1.0, t2=0.2, phi=1.0, per_ring=2),
     {}),
    ("cluster_chern", surfaces.cluster_chern, dict(cluster=models.square_torus(), model="qwz", M=1.0, grid=8,
                                                   max_grid=16), {}),
    ("pfaffian", surfaces.pfaffian, dict(matrix=[[0, 1], [-1, 0]]), {}),
    ("edge_chirality", markers.edge_chirality, dict(graph=SQUARE, model="qwz", M=1.0, duration=1.0, steps=3,
                                                    width=1.0), {}),
    ("centre_marker", kpm_marker.centre_marker, dict(graph=FLAKE, model="qwz", M=1.0, moments=32, tol=10.0),
     {"radius": {"none"}}),
]

# (subcommand words, flag, values of BAD_CLI that are legitimate)
_NUM_OK = {"-1", "0", "3.5"}
CLI_FLAGS = [
    (["topology", "flake", "--rings", "2"], "--M", _NUM_OK),
    (["topology", "flake", "--rings", "2", "--model", "haldane"], "--t2", _NUM_OK),
    (["topology", "flake", "--rings", "2", "--model", "haldane"], "--phi", _NUM_OK),
    (["topology", "flake", "--rings", "2"], "--disorder", {"0", "3.5"}),
    (["topology", "flake", "--rings", "2"], "--seed", {"0"}),
    (["topology", "flake"], "--rings", set()),
    (["topology", "flake", "--rings", "2", "--model", "kane-mele"], "--rashba", _NUM_OK),
    (["topology", "flake", "--rings", "2"], "--fermi", {"-1", "0"}),          # 3.5: outside the spectrum
    (["topology", "flake", "--rings", "2"], "--frame", set()),
    (["topology", "flake", "--rings", "2"], "-p", set()),
    (["topology", "flake", "--rings", "2"], "-q", set()),
    (["topology", "flake", "--rings", "2"], "--model", set()),
    (["topology", "cluster"], "--cluster", set()),
    (["topology", "cluster", "--cluster", "bolza"], "--M", {"-1", "0", "3.5"}),   # 0: the gap closes (exit 2, 5 s)
    (["topology", "cluster", "--cluster", "bolza"], "--model", set()),
]


@pytest.mark.parametrize("func,good,arg,value", list(api_cases(CASES)))
def test_api(func, good, arg, value):
    check_api(func, good, arg, value)


@pytest.mark.parametrize("words,flag,value", list(cli_cases(CLI_FLAGS)))
def test_cli(words, flag, value, capsys, tmp_path, monkeypatch):
    check_cli(words, flag, value, capsys, tmp_path, monkeypatch)
