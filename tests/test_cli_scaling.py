"""CLI: ``hyperlattice scaling ...`` and ``hyperlattice dictionary``."""

import json
import math

import pytest

from hyperlattice.cli import main


def run_json(capsys, argv):
    assert main(argv) == 0
    return json.loads(capsys.readouterr().out)


def test_angles_json(capsys):
    out = run_json(capsys, ["scaling", "angles", "--rings", "4", "--json"])
    assert out["sites"] == 315 and out["max_star_residual"] < 1e-10
    assert len(out["profile"]["r"]) == out["distinct_radii"]


def test_counting_json(capsys):
    out = run_json(capsys, ["scaling", "counting", "--json"])
    assert abs(out["intercept"] + 9.096) < 1e-3 and out["window"] == "all"


def test_convergence_json(capsys):
    out = run_json(capsys, ["scaling", "convergence", "--rings", "3", "--json"])
    for k, power in {"2": 3, "3": 4}.items():
        assert abs(out["orders"][k]["exponent"] - power) < 0.2


def test_operator_and_sums_text(capsys, tmp_path):
    png = tmp_path / "sh.png"
    assert main(["scaling", "operator", "--rings", "3", "--h", "0.1", "--plot", str(png)]) == 0
    assert "0.100000" in capsys.readouterr().out and png.stat().st_size > 1000
    assert main(["scaling", "sums", "--rings", "4", "--function", "gaussian"]) == 0
    assert "exp(-d^2" in capsys.readouterr().out


def test_dictionary_json(capsys):
    out = run_json(capsys, ["dictionary", "--t", "1", "--mu", "0.5", "--U", "2", "--json"])
    assert out["continuum"]["mu_prime"] == 3.5
    assert out["continuum"]["U_prime"] == pytest.approx(2 * math.pi / 28)
    assert out["field_scale"] == pytest.approx(math.sqrt(28 / math.pi))


@pytest.mark.parametrize("argv", [
    ["scaling", "operator", "--h", "0.5"],
    ["scaling", "counting", "--rings", "1"],
    ["scaling", "convergence", "--h-min", "0.1", "--h-max", "0.05"],
    ["dictionary", "-p", "6"],
])
def test_bad_input_exit_2(capsys, argv):
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "error" in err


def test_argparse_rejects_nan(capsys):
    with pytest.raises(SystemExit) as exc:
        main(["dictionary", "--t", "nan"])
    assert exc.value.code == 2
