"""Bad input for maps kept as darts, the {8,8} Dirac model, the twist marker and fillings (see tests/badinput.py)."""

from __future__ import annotations

import pytest

from badinput import api_cases, check_api, check_cli, cli_cases
from hyperlattice.graph.clusters import pbc_cluster
from hyperlattice.topology import closed, dartmaps, models, surfaces, twist_marker

BOLZA = pbc_cluster(8, 3, "bolza")
TERMS = models.model_terms(BOLZA, "haldane", M=0.0, t2=0.2)

# (id, function, working keyword arguments, {argument: tags it legitimately accepts})
CASES = [
    ("dart_map", dartmaps.dart_map, dict(p=8, q=8, relators=["x Y^4"], name="one", max_cosets=1000),
     {"name": {"none", "nan", "inf", "bool", "str", "ragged", "object", "complex"}}),
    ("named_dart_map", dartmaps.named_dart_map, dict(name="one-site"), {}),
    ("dirac4_terms", dartmaps.dirac4_terms, dict(m_map="one-site", m=-3.0), {}),
    ("particle_hole", closed.particle_hole, dict(terms=TERMS, tol=1e-9), {}),
    ("chern2_density", closed.chern2_density, dict(system=closed.dirac4_torus(-3.0), dirs=(0, 1, 2, 3),
                                                  k=[[0.1, 0.2, 0.3, 0.4]]), {}),
    ("cluster_chern", surfaces.cluster_chern, dict(cluster=BOLZA, model="haldane", M=0.0, t2=0.2, fermi_level=-1.3),
     {"fermi_level": {"none"}}),
    ("twist_marker", twist_marker.twist_marker, dict(system=TERMS, pairs=[(0, 1)], fermi_level=-1.3),
     {"pairs": {"none"}, "fermi_level": {"none"}}),
]

# (subcommand words, flag, values of BAD_CLI that are legitimate)
CLI_FLAGS = [
    (["topology", "cluster", "--cluster", "bolza", "--model", "haldane", "--M", "0"], "--fermi-level", {"0"}),
    (["topology", "cluster", "--cluster", "bolza", "--model", "haldane", "--M", "0"], "--filling", set()),
    (["topology", "cluster", "--cluster", "one-site", "--model", "dirac4"], "--M", {"-1", "0", "3.5", "1e22"}),
]


@pytest.mark.parametrize("func,good,arg,value", list(api_cases(CASES)))
def test_api(func, good, arg, value):
    check_api(func, good, arg, value)


@pytest.mark.parametrize("words,flag,value", list(cli_cases(CLI_FLAGS)))
def test_cli(words, flag, value, capsys, tmp_path, monkeypatch):
    check_cli(words, flag, value, capsys, tmp_path, monkeypatch)


@pytest.mark.parametrize("argv", [
    ["--model", "dirac4", "--cluster", "bolza"],                       # not a {8,8} map of the Dirac model
    ["--model", "dirac4", "--cluster", "one-site", "-q", "3"],          # the Dirac model needs {8,8}
    ["--model", "dirac4", "--cluster", "one-site", "--spin-chern"],
    ["--model", "haldane", "--cluster", "bolza", "--filling", "1/3"],   # not a whole number of bands
    ["--model", "haldane", "--cluster", "bolza", "--M", "0", "--fermi-level", "-1.9"],   # inside a band
    ["--model", "qwz", "--cluster", "bolza", "--frame", "covariant", "--filling", "1/2"],
    ["--model", "haldane", "--cluster", "bolza", "--filling", "1/4", "--fermi-level", "-1"],
])
def test_cli_refusals_are_one_line(argv, capsys):
    from hyperlattice.cli import main

    try:
        code = main(["topology", "cluster"] + argv)
    except SystemExit as exc:
        code = exc.code
    err = capsys.readouterr().err
    assert code == 2, err
    assert len([x for x in err.splitlines() if x.strip()]) == 1, err
