"""Bad input for periodic clusters, groups and band theory (see tests/badinput.py)."""

from __future__ import annotations

import pytest

from badinput import api_cases, check_api, check_cli, cli_cases
from hyperlattice.graph import bands, clusters, groups

BOLZA = clusters.pbc_cluster(8, 3, "bolza")

# (id, function, working keyword arguments, {argument: tags it legitimately accepts})
CASES = [
    ("pbc_cluster", clusters.pbc_cluster, dict(p=7, q=3, name="klein"), {"name": {"none"}}),
    ("pbc_cluster_min_sites", clusters.pbc_cluster, dict(p=8, q=3, min_sites=10), {"min_sites": {"none"}}),
    ("list_clusters", clusters.list_clusters, dict(p=8, q=3, max_sites=100), {}),
    ("psl2_cluster", clusters.psl2_cluster, dict(p=7, q=3, r=13), {}),
    ("psl2_primes", clusters.psl2_primes, dict(p=7, q=3, r_max=50), {}),
    ("same_map", clusters.same_map, dict(a=BOLZA, b=BOLZA), {}),
    ("cluster_from_relators", clusters.cluster_from_relators,
     dict(p=7, q=3, relators=["(x Y x y)^4"]), {}),
    ("lattice_ball_counts", clusters.lattice_ball_counts, dict(p=7, q=3, radius=3), {}),
    ("map_code", clusters.map_code, dict(cluster=clusters.pbc_cluster(8, 3, "bolza"), vertex=0, slot=0), {}),
    ("coset_table", groups.coset_table, dict(n_generators=2, relators=["x^2", "y^3", "(x y)^3"]),
     {"relators": {"ragged"}}),
    ("parse_word", groups.parse_word, dict(text="x y X"), {}),
    ("permutation_group_order", groups.permutation_group_order, dict(generators=[[1, 0, 2], [1, 2, 0]]),
     {"generators": {"ragged"}}),
    ("psl2_element_order", groups.psl2_element_order, dict(m=(0, 1, 6, 0), r=7), {}),
    ("psl2_triple", groups.psl2_triple, dict(p=7, q=3, r=13), {}),
    ("psl2_dart_tables", groups.psl2_dart_tables, dict(x=(0, 1, 6, 0), y=(0, 6, 1, 1), r=7), {}),
    ("psl2_map", groups.psl2_map, dict(x=(0, 1, 6, 0), y=(0, 6, 1, 1), r=7, q=3), {}),
    ("edge_windings", bands.edge_windings, dict(cluster=BOLZA), {}),
    ("bloch_hamiltonian", bands.bloch_hamiltonian, dict(cluster=BOLZA, k=[0.1, 0.2, 0.3, 0.4], t=1.0), {}),
    ("abelian_cover", bands.abelian_cover, dict(cluster=BOLZA, n=2), {}),
    ("k_path", bands.k_path, dict(genus=2, points=4), {}),
    ("band_structure", bands.band_structure, dict(cluster=BOLZA, points=3), {}),
    ("abelian_dos", bands.abelian_dos, dict(cluster=BOLZA, samples=8, bins=10, seed=0, batches=2), {}),
]

# (subcommand words, flag, values of BAD_CLI that are legitimate)
CLI_FLAGS = [
    (["cluster", "--list"], "-p", set()),
    (["cluster", "--list"], "-q", set()),
    (["cluster", "--list"], "--max-sites", set()),
    (["cluster"], "--min-sites", set()),
    (["cluster"], "--name", set()),
    (["cluster", "--name", "klein"], "--out", set()),
]


@pytest.mark.parametrize("func,good,arg,value", list(api_cases(CASES)))
def test_api(func, good, arg, value):
    check_api(func, good, arg, value)


@pytest.mark.parametrize("words,flag,value", list(cli_cases(CLI_FLAGS)))
def test_cli(words, flag, value, capsys, tmp_path, monkeypatch):
    check_cli(words, flag, value, capsys, tmp_path, monkeypatch)
