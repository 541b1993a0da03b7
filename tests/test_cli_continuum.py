"""CLI contract for `hyperlattice continuum`."""

import json

import pytest

from hyperlattice.cli import main
from hyperlattice.paper_values import paper_value

KEYS = {"p", "q", "rings", "radius", "h", "energies", "n", "m", "k", "asymptotic"}


def run_cli(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def test_json_contract_rings(capsys):
    code, out, _ = run_cli(capsys, "continuum", "-p", "7", "-q", "3", "--rings", "10", "--levels", "4", "--json")
    assert code == 0
    d = json.loads(out)
    assert set(d) == KEYS
    assert set(d["asymptotic"]) == {"E0", "E1", "E_inf"}
    assert (d["p"], d["q"], d["rings"]) == (7, 3, 10)
    assert len(d["energies"]) == len(d["n"]) == len(d["m"]) == len(d["k"]) == 4
    assert d["m"] == [0, 1, -1, 2] and d["n"] == [1, 1, 1, 1]
    assert round(d["energies"][0], 3) == -2.924 and round(d["energies"][1], 3) == -2.915
    assert d["energies"] == sorted(d["energies"])
    assert round(d["asymptotic"]["E_inf"], 5) == paper_value("E_inf").value
    assert d["radius"] == pytest.approx((105875 / (105875 + 28)) ** 0.5, rel=1e-14)


def test_json_radius_and_other_pq(capsys):
    code, out, _ = run_cli(capsys, "continuum", "-p", "9", "--radius", "0.9", "--levels", "3", "--json")
    assert code == 0
    d = json.loads(out)
    assert d["rings"] is None and d["radius"] == 0.9 and d["p"] == 9
    assert d["m"] == [0, 1, -1]


def test_table_output(capsys):
    code, out, _ = run_cli(capsys, "continuum", "--rings", "3", "--levels", "2")
    assert code == 0 and "asymptotic" in out and "-2.77038" in out


@pytest.mark.parametrize("argv", [
    ["continuum", "--radius", "1.0"],
    ["continuum", "--radius", "0"],
    ["continuum", "-p", "6", "--rings", "3"],
])
def test_bad_input_exit_2(capsys, argv):
    code, _, err = run_cli(capsys, *argv)
    assert code == 2 and err.strip() and len(err.strip().splitlines()) == 1


def test_rings_and_radius_are_exclusive(capsys):
    with pytest.raises(SystemExit) as exc:
        main(["continuum", "--rings", "3", "--radius", "0.5"])
    assert exc.value.code == 2


def test_small_radius_is_cheap(capsys):
    """`continuum --radius 1e-5 --levels 2` took 2.9 GB and 50 s (issue 10)."""
    import tracemalloc

    tracemalloc.start()
    try:
        code, out, _ = run_cli(capsys, "continuum", "--radius", "1e-5", "--levels", "2", "--json")
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert code == 0 and peak < 16e6
    d = json.loads(out)
    assert d["m"] == [0, 1] and d["k"][0] == pytest.approx(2.404825557695773 / 1e-5, rel=1e-5)


@pytest.mark.parametrize("argv", [
    ["continuum", "--radius", "1e-8"],
    ["continuum", "--levels", "1000000000"],
    ["continuum", "--rings", "100000"],
    ["continuum", "--radius", "nan"],
])
def test_refusals_are_one_line_exit_2(capsys, argv):
    try:
        code = main(argv)
    except SystemExit as exc:          # argparse's own refusals
        code = exc.code
    err = capsys.readouterr().err
    assert code == 2 and len(err.strip().splitlines()) == 1 and "Traceback" not in err


def test_dictionary_flag_same_keys_default_paper(capsys):
    """--dictionary improved prints the same JSON keys; the default is the paper's map, unchanged."""
    code, plain, _ = run_cli(capsys, "continuum", "--rings", "6", "--levels", "3", "--json")
    code2, paper, _ = run_cli(capsys, "continuum", "--rings", "6", "--levels", "3", "--json", "--dictionary", "paper")
    code3, impr, _ = run_cli(capsys, "continuum", "--rings", "6", "--levels", "3", "--json", "--dictionary",
                             "improved")
    assert code == code2 == code3 == 0
    assert plain == paper
    a, b = json.loads(paper), json.loads(impr)
    assert list(a) == list(b) and list(a["asymptotic"]) == list(b["asymptotic"])
    assert b["energies"][0] == pytest.approx(-2.8953296, abs=1e-6)      # improved map, l = 6
    assert b["asymptotic"]["E_inf"] == pytest.approx(-2.9409606137, abs=1e-9)
    assert b["radius"] > a["radius"]                                    # the Dirichlet wall lies further out
    code, text, _ = run_cli(capsys, "continuum", "--rings", "6", "--dictionary", "improved")
    assert code == 0 and "improved dictionary" in text


@pytest.mark.slow
def test_dictionary_flag_refused_with_flux(capsys):
    code = main(["continuum", "--rings", "3", "--flux", "0.05", "--dictionary", "improved"])
    err = capsys.readouterr().err
    assert code == 2 and len(err.strip().splitlines()) == 1
    # the flux path with the default dictionary still works
    assert main(["continuum", "--rings", "3", "--flux", "0.05", "--json"]) == 0


def test_many_levels_are_estimated_and_refused_before_work(capsys, monkeypatch):
    # issue 28 item 6: --levels 100000 ran on past a minute with no estimate or refusal
    import hyperlattice.continuum.spectrum as spectrum

    def never(*args, **kwargs):
        raise AssertionError("the levels were computed")

    monkeypatch.setattr(spectrum, "_lowest_states", never)
    assert main(["continuum", "--levels", "100000"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "up to about 100 min (100,000 levels)" in err and "fewer --levels" in err


def test_levels_beyond_the_validated_orders_are_one_physics_sentence():
    # was "the order m must be at most 1,000", a parameter the user never gave
    from hyperlattice.continuum.spectrum import continuum_levels

    with pytest.raises(ValueError, match=r"reach angular momenta \|m\| > 1,000.*ask for fewer levels\.$"):
        continuum_levels(7, 3, rings=10, levels=3500)
