"""``hyperlattice spectrum --method pair``: E0 and E1 from the sector-only build, same JSON keys."""

import json

import numpy as np
import pytest

from hyperlattice.cli import main


@pytest.mark.slow
def test_pair_equals_the_default_solver(capsys):
    assert main(["spectrum", "--rings", "6", "--json"]) == 0
    ref = json.loads(capsys.readouterr().out)
    assert main(["spectrum", "--rings", "6", "--method", "pair", "--json"]) == 0
    got = json.loads(capsys.readouterr().out)
    assert set(got) == set(ref)
    assert got["method"] == "sector-shift-invert" and got["sites"] == ref["sites"]
    np.testing.assert_allclose(got["energies"], ref["energies"], atol=1e-12)
    assert (got["n"], got["m"]) == (ref["n"], ref["m"])
    assert max(got["residuals"]) <= 1e-10


def test_pair_plain_output(capsys):
    assert main(["spectrum", "--rings", "4", "--method", "pair"]) == 0
    assert "method=sector-shift-invert" in capsys.readouterr().out


@pytest.mark.parametrize("extra", [["--flux", "0.1"], ["--line-graph"], ["--sector", "1"], ["--levels", "3"]])
def test_pair_refuses_what_it_does_not_compute(extra, capsys):
    assert main(["spectrum", "--rings", "4", "--method", "pair"] + extra) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and "--method pair" in err
