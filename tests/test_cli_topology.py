"""``hyperlattice topology``: the JSON keys of the contract, text output, one-line errors."""

from __future__ import annotations

import json

import pytest

from hyperlattice.cli import main

pytestmark = pytest.mark.filterwarnings("ignore:the Bott index is unreliable")


def test_flake_json_has_the_contract_keys(capsys):
    assert main(["topology", "flake", "--model", "qwz", "-p", "8", "-q", "3", "--rings", "2", "--M", "1", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    for key in ("sites", "marker", "marker_by_ring", "kitaev", "bott", "gap"):
        assert key in out
    assert out["sites"] == 48 and len(out["marker_by_ring"]) == 2


def test_cluster_json_has_the_contract_keys(capsys):
    assert main(["topology", "cluster", "--model", "qwz", "--cluster", "bolza", "-p", "8", "-q", "3", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    for key in ("chern", "gcd", "pfaffian", "gap"):
        assert key in out
    assert len(out["chern"]) == 4 and out["gcd"] == 1


def test_big_flake_switches_to_the_chebyshev_marker(monkeypatch, capsys):
    from hyperlattice.topology import markers

    monkeypatch.setattr(markers, "MAX_DENSE_ROWS", 50)
    assert main(["topology", "flake", "--rings", "2", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["method"] == "kpm" and out["bott"] is None and "marker_error" in out


@pytest.mark.parametrize("argv", [
    ["topology", "flake", "--model", "chern"],
    ["topology", "flake", "--M", "nan"],
    ["topology", "flake", "--model", "haldane", "-p", "7", "--rings", "2"],
    ["topology", "cluster", "--cluster", "nosuch"],
])
def test_bad_input_is_one_line_and_exit_2(argv, capsys):
    try:
        code = main(argv)
    except SystemExit as exc:
        code = exc.code
    err = [line for line in capsys.readouterr().err.splitlines() if line.strip()]
    assert code == 2 and len(err) == 1
