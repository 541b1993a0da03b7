"""The ``qubits`` command: bound state, J(d) table, spin-model edge list, errors."""

import csv
import json

import numpy as np
import pytest

from hyperlattice.cli import main
from hyperlattice.graph.lattice import ring_lattice
from hyperlattice.graph.qubits import bound_state, spin_model


def test_json_and_table(tmp_path, capsys):
    out = tmp_path / "j.csv"
    assert main(["qubits", "--rings", "5", "--omega-q=-3.1", "--g", "0.05", "--out", str(out), "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    assert set(d) == {"bound_state", "exchange", "table"}
    ref = bound_state(ring_lattice(7, 3, 5), 0, -3.1, 0.05)
    assert d["bound_state"]["energy"] == ref.energy and d["bound_state"]["size"] == pytest.approx(ref.size)
    with open(out) as fh:
        rows = list(csv.DictReader(fh))
    assert list(rows[0]) == ["d", "J_graph", "J_continuum", "rel_diff"] and len(rows) == len(d["table"])
    assert np.all(np.diff([float(r["d"]) for r in rows]) > 0)


def test_edges(tmp_path, capsys):
    edges = tmp_path / "e.csv"
    assert main(["qubits", "--rings", "5", "--qubit-sites", "0,10,30", "--edges", str(edges)]) == 0
    assert "spin model: 3 qubits" in capsys.readouterr().out
    with open(edges) as fh:
        rows = list(csv.DictReader(fh))
    assert list(rows[0]) == ["i", "j", "site_i", "site_j", "J"] and len(rows) == 3
    sm = spin_model(ring_lattice(7, 3, 5), [0, 10, 30], -3.1, 0.05)
    assert float(rows[0]["J"]) == sm.couplings[0, 1]


def test_line_graph(capsys):
    assert main(["qubits", "--rings", "4", "--line-graph", "--omega-q=-4.1"]) == 0
    assert "line graph of {7,3}" in capsys.readouterr().out


def test_errors_exit_2(capsys, tmp_path):
    for argv in (["qubits", "--rings", "4", "--omega-q=-2.0"],
                 ["qubits", "--rings", "4", "--site", "-1"],
                 ["qubits", "--rings", "4", "--edges", str(tmp_path / "e.csv")],        # needs --qubit-sites
                 ["qubits", "--rings", "4", "--qubit-sites", "0,0", "--edges", str(tmp_path / "e.csv")],
                 ["qubits", "--rings", "4", "--qubit-sites", "a,b"],
                 ["qubits", "--rings", "4", "--g", "0"]):
        try:
            code = main(argv)
        except SystemExit as exc:       # argparse refuses the value itself
            code = exc.code
        assert code == 2
        err = capsys.readouterr().err
        assert len(err.strip().splitlines()) == 1 and "Traceback" not in err
