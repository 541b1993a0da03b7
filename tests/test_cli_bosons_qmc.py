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


# ----------------------------------------------------------------------------
# the superfluid stiffness: on a cluster by default, --no-windings, and --windings for a user's graph
# ----------------------------------------------------------------------------

STIFFNESS_KEYS = ("rho_s", "rho_s_err", "stiffness_geometric", "stiffness_geometric_err", "stiffness",
                  "stiffness_err", "stiffness_note")
HARD_CORE = ["--nmax", "1", "--U", "0", "--mu", "0.3", "--beta", "0.5", "--sweeps", "400", "--seed", "2"]


def test_klein_json_carries_the_stiffness_with_errors(capsys):
    # the second example of docs/qmc.md (at beta = 0.5 a world line rarely winds around the Klein quartic)
    out = _json(capsys, ["--cluster", "klein", "-p", "7", "-q", "3", "--nmax", "1", "--U", "0", "--mu", "0.5",
                         "--beta", "1", "--sweeps", "500", "--seed", "2"])
    assert set(STIFFNESS_KEYS) <= set(out) and out["stiffness_note"] == ""
    assert np.isfinite(out["rho_s"]) and out["rho_s_err"] > 0
    assert np.isfinite(out["stiffness_geometric"]) and out["stiffness_geometric_err"] >= 0
    assert np.shape(out["stiffness"]) == (6, 6) and np.shape(out["stiffness_err"]) == (6, 6)   # genus 3: D = 6
    assert np.all(np.asarray(out["stiffness_err"]) >= 0) and "stiffness" in out["tau_int"]
    # rho_s is tr(Upsilon)/D
    assert out["rho_s"] == pytest.approx(np.trace(np.asarray(out["stiffness"])) / 6, rel=1e-12)


def test_no_windings_turns_it_off_and_says_why(capsys):
    out = _json(capsys, ["--cluster", "klein", *HARD_CORE, "--no-windings"])
    assert out["stiffness"] is None and out["rho_s"] is None and "stiffness" not in out["tau_int"]
    assert "windings=False" in out["stiffness_note"]
    flake = _json(capsys, [*HEPTAGON, *HARD_CORE])
    assert flake["stiffness"] is None and "flake" in flake["stiffness_note"]


def _square_files(tmp_path, L=3):
    import scipy.sparse as sp

    from hyperlattice.cli._bosons_qmc import edges
    from hyperlattice.compare.qmc_lobe import square_lattice, square_lattice_windings

    adj = sp.csr_matrix(square_lattice(L))
    sp.save_npz(tmp_path / "square.npz", adj)
    np.save(tmp_path / "square_dense.npy", adj.toarray())
    pairs, w = square_lattice_windings(L)
    lookup = {(int(i), int(j)): row for (i, j), row in zip(pairs, w)}
    lookup.update({(int(j), int(i)): -row for (i, j), row in zip(pairs, w)})
    ordered = np.array([lookup[(int(i), int(j))] for i, j in edges(adj)])
    np.save(tmp_path / "square_windings.npy", ordered)
    return adj, ordered


def test_edges_are_sorted_pairs_of_the_upper_triangle():
    import scipy.sparse as sp

    from hyperlattice.cli._bosons_qmc import edges

    a = sp.csr_matrix(np.array([[0, 1, 0, 2], [1, 0, 1, 0], [0, 1, 0, 1], [2, 0, 1, 0]], float))
    assert edges(a).tolist() == [[0, 1], [0, 3], [1, 2], [2, 3]]
    from hyperlattice import ring_lattice
    from hyperlattice.graph.clusters import pbc_cluster

    assert len(edges(ring_lattice(7, 3, 1))) == 7 and len(edges(pbc_cluster(8, 3, "bolza"))) == 24


def test_windings_file_for_a_user_graph_is_the_api(tmp_path, capsys):
    from hyperlattice.bosons import qmc
    from hyperlattice.compare.qmc_lobe import square_lattice_windings

    adj, _ = _square_files(tmp_path)
    args = ["--nmax", "1", "--U", "0", "--mu", "0.3", "--beta", "1", "--sweeps", "2000", "--seed", "3"]
    out = _json(capsys, ["--adjacency", str(tmp_path / "square.npz"), "--windings",
                         str(tmp_path / "square_windings.npy"), *args])
    ref = qmc(adj, U=0.0, mu=0.3, beta=1.0, nmax=1, sweeps=2000, seed=3, progress=False,
              windings=square_lattice_windings(3))
    assert out["sites"] == 9 and out["stiffness_note"] == ""
    for k in ("energy", "density", "rho_s", "rho_s_err", "stiffness_geometric"):
        assert out[k] == getattr(ref, k), k
    assert np.array_equal(np.asarray(out["stiffness"]), ref.stiffness)
    # exact rho_s of the 3 x 3 torus at these parameters (twisted-boundary ED, docs/qmc.md): within 4 sigma
    assert abs(out["rho_s"] - 0.491873) < 4 * out["rho_s_err"]
    # the same graph as a dense .npy, and without windings: no stiffness, and the note names the flag
    dense = _json(capsys, ["--adjacency", str(tmp_path / "square_dense.npy"), *args])
    assert dense["energy"] == out["energy"] and dense["stiffness"] is None
    assert "--windings" in dense["stiffness_note"]


def _bad_files(tmp_path):
    import scipy.sparse as sp

    adj, w = _square_files(tmp_path)
    np.save(tmp_path / "float_w.npy", w.astype(float))
    np.save(tmp_path / "short_w.npy", w[:-1])
    np.save(tmp_path / "flat_w.npy", w[:, 0])
    np.save(tmp_path / "wide_w.npy", np.zeros((len(w), 65), np.int64))
    np.save(tmp_path / "objects.npy", np.array([{"a": 1}], dtype=object), allow_pickle=True)
    np.save(tmp_path / "rect.npy", np.ones((3, 4)))
    np.save(tmp_path / "words.npy", np.array([["a", "b"], ["c", "d"]]))
    np.savez(tmp_path / "notsparse.npz", edges=np.zeros((3, 2)))
    (tmp_path / "junk.npy").write_bytes(b"not numpy")
    sp.save_npz(tmp_path / "flux.npz", sp.csr_matrix(np.array([[0, 1j], [-1j, 0]])))


@pytest.mark.parametrize("extra,needle", [
    (["--windings", "{tmp}/nowhere.npy"], "does not exist"),
    (["--windings", "{tmp}/square.npz"], "must end in .npy"),
    (["--windings", "{tmp}/float_w.npy"], "must hold integers"),
    (["--windings", "{tmp}/short_w.npy"], "(18 edges)"),
    (["--windings", "{tmp}/flat_w.npy"], "shape (edges, D)"),
    (["--windings", "{tmp}/wide_w.npy"], "D <= 64"),
    (["--windings", "{tmp}/objects.npy"], "Python objects"),
    (["--windings", "{tmp}/junk.npy"], "not an array written by numpy.save"),
    (["--windings", "{tmp}/square_windings.npy", "--no-windings"], "not allowed with"),
])
def test_bad_windings_one_line_exit_2(extra, needle, tmp_path, capsys):
    _bad_files(tmp_path)
    argv = ["--adjacency", str(tmp_path / "square.npz"), "--nmax", "1", "--U", "0", "--mu", "0", "--beta", "1",
            "--sweeps", "10", *[a.replace("{tmp}", str(tmp_path)) for a in extra]]
    _refused(argv, needle, capsys)


@pytest.mark.parametrize("name,needle", [
    ("nowhere.npz", "does not exist"),
    ("square.txt", "must end in .npz or .npy"),
    ("rect.npy", "square matrix"),
    ("words.npy", "must hold numbers"),
    ("objects.npy", "Python objects"),
    ("notsparse.npz", "not a sparse matrix written by scipy.sparse.save_npz"),
    ("junk.npy", "not a dense array written by numpy.save"),
    ("flux.npz", "sign problem"),
])
def test_bad_adjacency_one_line_exit_2(name, needle, tmp_path, capsys):
    _bad_files(tmp_path)
    (tmp_path / "square.txt").write_text("0 1\n1 0\n")
    argv = ["--adjacency", str(tmp_path / name), "--nmax", "1", "--U", "0", "--mu", "0", "--beta", "1",
            "--sweeps", "10"]
    _refused(argv, needle, capsys)


def _refused(argv, needle, capsys):
    try:
        code = main(["bosons", "qmc", *argv, "--json"])
    except SystemExit as exc:  # argparse's own errors (one line, see cli._OneLineParser)
        code = exc.code
    captured = capsys.readouterr()
    err = captured.err.strip()
    assert code == 2, err
    assert captured.out == ""
    assert "\n" not in err and needle in err and "Traceback" not in err, err
