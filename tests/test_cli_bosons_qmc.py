"""``hyperlattice bosons qmc``: the contract (keys, conventions), checkpoint resume and bad input."""

from __future__ import annotations

import json

import numpy as np
import pytest

from hyperlattice.cli import main

KEYS = ["sites", "energy", "energy_err", "density", "density_err", "compressibility", "compressibility_err",
        "tau_int"]
HEPTAGON = ["--rings", "1", "-p", "7", "-q", "3"]


def _json(capsys, argv):
    assert main(["bosons", "qmc", *argv, "--json"]) == 0
    return json.loads(capsys.readouterr().out)


def test_flake_contract_against_the_api_and_exact_thermal(capsys):
    out = _json(capsys, [*HEPTAGON, "--nmax", "2", "--U", "4", "--mu", "1", "--beta", "2", "--sweeps", "3000",
                         "--seed", "5"])
    assert list(out)[: len(KEYS)] == KEYS
    assert out["sites"] == 7 and set(out["tau_int"]) >= {"energy", "density", "compressibility"}
    assert (out["U"], out["mu"], out["t"], out["beta"], out["nmax"], out["seed"]) == (4.0, 1.0, 1.0, 2.0, 2, 5)
    # the same chain as the Python API with the same seed, bit for bit
    from hyperlattice import ring_lattice
    from hyperlattice.bosons import exact_thermal, qmc

    lat = ring_lattice(7, 3, 1)
    ref = qmc(lat, U=4.0, mu=1.0, beta=2.0, nmax=2, sweeps=3000, seed=5, progress=False)
    for k in KEYS[1:-1]:
        assert out[k] == getattr(ref, k), k
    # conventions: energy is the total <H> with -mu N, density and kappa per site (exact within 4 sigma)
    ex = exact_thermal(lat, U=4.0, mu=1.0, beta=2.0, nmax=2)
    for k in ("energy", "density", "compressibility"):
        assert out[k + "_err"] > 0
        exact = getattr(ex, k)
        assert abs(out[k] - exact) < 4 * out[k + "_err"], k


def test_cluster_hard_core_and_hopping(capsys):
    out = _json(capsys, ["--cluster", "bolza", "-p", "8", "-q", "3", "--nmax", "1", "--U", "0", "--t", "0.5",
                         "--mu", "0", "--beta", "1", "--sweeps", "2000", "--seed", "2"])
    assert out["sites"] == 16 and out["t"] == 0.5 and out["nmax"] == 1
    # hard-core bosons at mu = 0 are particle-hole symmetric on any graph: half filling
    assert abs(out["density"] - 0.5) < 4 * out["density_err"]
    assert out["compressibility"] > 0


def test_text_output(capsys):
    assert main(["bosons", "qmc", *HEPTAGON, "--nmax", "2", "--U", "4", "--mu", "1", "--beta", "1",
                 "--sweeps", "500", "--seed", "3"]) == 0
    text = capsys.readouterr().out
    assert "energy" in text and "+-" in text and "tau_int" in text and "seed 3" in text


def test_checkpoint_resume_is_the_uninterrupted_chain(tmp_path, capsys):
    args = [*HEPTAGON, "--nmax", "2", "--U", "4", "--mu", "1", "--beta", "1", "--seed", "11",
            "--thermalization", "100"]
    whole = _json(capsys, [*args, "--sweeps", "1200"])
    first = _json(capsys, [*args, "--sweeps", "600", "--checkpoint", str(tmp_path / "ck")])
    resumed = _json(capsys, [*args, "--sweeps", "1200", "--checkpoint", str(tmp_path / "ck")])
    assert first["sweeps"] == 600 and resumed["sweeps"] == 1200
    for k in ("energy", "density", "compressibility"):
        assert resumed[k] == whole[k], k
    assert np.isfinite(resumed["energy_err"])


@pytest.mark.parametrize("argv,needle", [
    (["--rings", "1", "--nmax", "2", "--mu", "1", "--beta", "1"], "--U"),
    (["--rings", "1", "--nmax", "2", "--U", "1", "--beta", "1"], "--mu"),
    (["--rings", "1", "--cluster", "bolza", "--nmax", "2", "--U", "1", "--mu", "1", "--beta", "1"], "not allowed"),
    (["--cluster", "nowhere", "--nmax", "2", "--U", "1", "--mu", "1", "--beta", "1"], "unknown cluster"),
    (["--rings", "1", "--nmax", "0", "--U", "1", "--mu", "1", "--beta", "1"], "--nmax"),
    (["--rings", "1", "--nmax", "2", "--U", "nan", "--mu", "1", "--beta", "1"], "--U"),
    (["--rings", "1", "--nmax", "2", "--U", "1", "--mu", "inf", "--beta", "1"], "--mu"),
    (["--rings", "1", "--nmax", "2", "--U", "1", "--mu", "1", "--beta", "0"], "--beta"),
    (["--rings", "1", "--nmax", "2", "--U", "1", "--mu", "1", "--beta", "-2"], "--beta"),
    (["--rings", "1", "--nmax", "2", "--U", "1", "--mu", "1", "--beta", "1", "--sweeps", "0"], "--sweeps"),
    (["--rings", "1", "--nmax", "2", "--U", "1", "--mu", "1", "--beta", "1", "--seed", "-1"], "--seed"),
    (["--rings", "1", "--nmax", "2", "--U", "1", "--mu", "1", "--beta", "1", "--t", "0"], "t = 0"),
    (["--rings", "1", "-p", "5", "--nmax", "2", "--U", "1", "--mu", "1", "--beta", "1"], "{5,3}"),
    (["--cluster", "klein", "-p", "8", "--nmax", "2", "--U", "1", "--mu", "1", "--beta", "1"], "klein"),
    (["--rings", "3", "--nmax", "5", "--U", "1", "--mu", "1", "--beta", "1e12"], "allocate"),
])
def test_bad_input_one_line_exit_2(argv, needle, capsys):
    try:
        code = main(["bosons", "qmc", *argv, "--json"])
    except SystemExit as exc:  # argparse's own errors (one line, see cli._OneLineParser)
        code = exc.code
    assert code == 2
    captured = capsys.readouterr()
    assert captured.out == ""
    err = captured.err.strip()
    assert "\n" not in err and needle in err and "Traceback" not in err


def test_checkpoint_that_is_a_file_is_refused(tmp_path, capsys):
    f = tmp_path / "file"
    f.write_text("x")
    code = main(["bosons", "qmc", *HEPTAGON, "--nmax", "2", "--U", "1", "--mu", "1", "--beta", "1",
                 "--sweeps", "10", "--checkpoint", str(f), "--json"])
    assert code == 2
    captured = capsys.readouterr()
    assert captured.out == "" and "--checkpoint" in captured.err and "not a directory" in captured.err


def test_progress_bar_goes_to_stderr_and_the_json_stays_clean(capsys, monkeypatch):
    from hyperlattice import _progress

    monkeypatch.setattr(_progress, "DELAY", 0.0)
    code = main(["bosons", "qmc", *HEPTAGON, "--nmax", "2", "--U", "4", "--mu", "1", "--beta", "1",
                 "--sweeps", "300", "--thermalization", "100", "--seed", "4", "--json", "--progress"])
    out, err = capsys.readouterr()
    assert code == 0 and json.loads(out)["sweeps"] == 300
    assert "qmc" in err and "400/400" in err
