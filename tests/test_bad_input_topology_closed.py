"""Bad input for closed-surface topology: second and spin Chern numbers, frames, Landau bands (see tests/badinput.py)."""

from __future__ import annotations

import pytest

from badinput import api_cases, check_api, check_cli, cli_cases
from hyperlattice.graph.clusters import pbc_cluster
from hyperlattice.topology import closed, frames, landau, models

BOLZA = pbc_cluster(8, 3, "bolza")
TERMS = models.model_terms(models.square_torus(), "qwz", M=1.0)
DIRAC = closed.dirac4_torus(-3.0)
COV = frames.qwz_frame_terms(BOLZA, M=1.0)

# (id, function, working keyword arguments, {argument: tags it legitimately accepts})
CASES = [
    ("dirac4_torus", closed.dirac4_torus, dict(m=-3.0), {}),
    ("product_terms", closed.product_terms, dict(a=TERMS, b=TERMS), {}),
    ("kubo_chern", closed.kubo_chern, dict(system=models.square_torus(), model="qwz", grid=8), {}),
    ("second_chern", closed.second_chern, dict(system=DIRAC, grid=4, max_grid=8, tol=0.5), {}),
    ("spin_chern", closed.spin_chern, dict(system=models.honeycomb_torus(), M=0.1, t2=0.2), {}),
    ("cluster_flux_phases", landau.cluster_flux_phases, dict(cluster=BOLZA, n_phi=3), {}),
    ("intersection_form", landau.intersection_form, dict(cluster=BOLZA), {}),
    ("hofstadter_terms", landau.hofstadter_terms, dict(cluster=BOLZA, n_phi=3, t=1.0), {}),
    ("landau_bands", landau.landau_bands, dict(cluster=BOLZA, n_phi=3, levels=1), {}),
    ("spin_connection_signs", frames.spin_connection_signs, dict(cluster=BOLZA), {}),
    ("qwz_frame_terms", frames.qwz_frame_terms, dict(cluster=BOLZA, M=1.0, frame="covariant"), {}),
    ("relabel_cluster", frames.relabel_cluster, dict(cluster=BOLZA, seed=1), {}),
    ("frame_invariants", frames.frame_invariants, dict(terms=COV, grid=8, max_grid=16), {}),
    ("covariant_critical_mass", frames.covariant_critical_mass, dict(p=8, q=3), {}),
]

# (subcommand words, flag, values of BAD_CLI that are legitimate)
CLI_FLAGS = [
    (["topology", "landau", "--cluster", "bolza"], "--nphi", set()),
    (["topology", "landau", "--cluster", "bolza", "--nphi", "3"], "--levels", set()),
    (["topology", "landau", "--nphi", "3"], "--cluster", set()),
    (["topology", "cluster", "--cluster", "bolza"], "--frame", set()),
]


@pytest.mark.parametrize("func,good,arg,value", list(api_cases(CASES)))
def test_api(func, good, arg, value):
    check_api(func, good, arg, value)


@pytest.mark.parametrize("words,flag,value", list(cli_cases(CLI_FLAGS)))
def test_cli(words, flag, value, capsys, tmp_path, monkeypatch):
    check_cli(words, flag, value, capsys, tmp_path, monkeypatch)
