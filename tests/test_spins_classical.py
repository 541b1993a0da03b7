"""Classical spin Monte Carlo (hyperlattice.spins.classical) against exact results.

* Ising: exact enumeration of every state on graphs of up to 16 sites (ferro- and antiferromagnet,
  with and without field, frustrated, weighted couplings);
* XY and Heisenberg: open chains (independent bonds: <s_i.s_j> = u^|i-j| with u = I_1/I_0 or the
  Langevin function coth(beta) - 1/beta) and rings (transfer-matrix sums over Bessel functions);
* error bars: repeated chains with different seeds fall within 1 sigma about 68 % of the time;
* checkpoints, bad input, the command line.
"""

from __future__ import annotations

import json
import math
import warnings

import numpy as np
import pytest
from scipy.special import iv

import hyperlattice as hl
from hyperlattice.cli import main
from hyperlattice.graph.clusters import pbc_cluster
from hyperlattice.spins import classical_mc, classical_mc_memory, merge_classical
from hyperlattice.spins.classical import SpinWarning


def _chain(n: int, periodic: bool = False) -> np.ndarray:
    a = np.zeros((n, n))
    for i in range(n - 1):
        a[i, i + 1] = a[i + 1, i] = 1.0
    if periodic:
        a[0, n - 1] = a[n - 1, 0] = 1.0
    return a


def _ising_exact(adj, J, h, beta) -> dict:
    """Every observable of the Ising model by enumeration of the 2^N states."""
    a = np.asarray(adj.toarray() if hasattr(adj, "toarray") else adj, dtype=float)
    n = a.shape[0]
    states = 1 - 2 * ((np.arange(2 ** n)[:, None] >> np.arange(n)[None, :]) & 1).astype(float)
    E = -0.5 * J * np.einsum("si,ij,sj->s", states, a, states) - h * states.sum(axis=1)
    w = np.exp(-beta * (E - E.min()))
    w /= w.sum()
    m = states.mean(axis=1)
    out = {"e": w @ E / n, "c": beta ** 2 * (w @ E ** 2 - (w @ E) ** 2) / n, "m": w @ m, "m2": w @ m ** 2,
           "m_abs": w @ np.abs(m)}
    out["U4"] = 1 - (w @ m ** 4) / (3 * out["m2"] ** 2)
    out["chi"] = beta * n * out["m2"]
    # the bipartition, if any (breadth-first two-colouring)
    eps = np.zeros(n)
    eps[0] = 1
    order = [0]
    for u in order:
        for v in np.flatnonzero(a[u]):
            if eps[v] == 0:
                eps[v] = -eps[u]
                order.append(v)
    if len(order) == n and all(eps[i] != eps[j] for i, j in zip(*np.nonzero(a))):
        ms = states @ eps / n
        out.update(m2_s=w @ ms ** 2, m_abs_s=w @ np.abs(ms))
        out["U4_s"] = 1 - (w @ ms ** 4) / (3 * out["m2_s"] ** 2)
        out["chi_s"] = beta * n * out["m2_s"]
    return out


def _check(r, exact: dict, nsig: float = 4.0) -> None:
    for k, v in exact.items():
        val, err = getattr(r, k), getattr(r, k + "_err")
        assert abs(val - v) < nsig * err + 1e-12, f"{k}: {val} +- {err}, exact {v} ({(val - v) / err:.1f} sigma)"


def _run(system, **kw):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", SpinWarning)
        return classical_mc(system, progress=False, **kw)


HEPTAGON = hl.ring_lattice(7, 3, 1)
BOLZA = pbc_cluster(8, 3, "bolza")


def _weighted() -> np.ndarray:
    rng = np.random.default_rng(5)
    a = np.triu(rng.uniform(0.2, 1.5, size=(10, 10)) * (rng.random((10, 10)) < 0.4), 1)
    a += np.diag(np.ones(9), 1) * 0.7
    return a + a.T


#: (system, parameters, sweeps, update that must run); fast cases first
ISING_CASES = [
    pytest.param(HEPTAGON, dict(J=1.0, h=0.0, beta=0.6), 8000, "wolff", id="heptagon-ferro"),
    pytest.param(HEPTAGON, dict(J=-1.0, h=0.4, beta=0.8), 8000, "heat-bath", id="heptagon-frustrated-field"),
    pytest.param(BOLZA, dict(J=1.0, h=0.0, beta=0.5), 20000, "wolff", id="bolza-ferro", marks=pytest.mark.slow),
    pytest.param(BOLZA, dict(J=-1.0, h=0.0, beta=0.7), 20000, "wolff", id="bolza-antiferro", marks=pytest.mark.slow),
    pytest.param(BOLZA, dict(J=1.0, h=0.2, beta=0.4), 20000, "heat-bath", id="bolza-ferro-field",
                 marks=pytest.mark.slow),
    pytest.param(BOLZA, dict(J=-1.0, h=0.5, beta=0.8), 20000, "heat-bath", id="bolza-antiferro-field",
                 marks=pytest.mark.slow),
    pytest.param(_weighted(), dict(J=1.0, h=0.0, beta=0.6), 20000, "wolff", id="weighted-ferro",
                 marks=pytest.mark.slow),
    pytest.param(BOLZA, dict(J=-1.0, h=0.0, beta=0.7), 20000, "swendsen-wang", id="bolza-antiferro-sw",
                 marks=pytest.mark.slow),
    pytest.param(_weighted(), dict(J=-0.8, h=0.3, beta=0.9), 20000, "heat-bath", id="weighted-frustrated-field",
                 marks=pytest.mark.slow),
]


@pytest.mark.machine_independence          # the update chosen is a label
@pytest.mark.parametrize("system, kw, sweeps, update", ISING_CASES)
def test_ising_matches_exact_enumeration(system, kw, sweeps, update):
    adj = system if isinstance(system, np.ndarray) else (system.adjacency() if hasattr(system, "genus")
                                                         else hl.adjacency(system))
    exact = _ising_exact(adj, **kw)
    r = _run(system, model="ising", sweeps=sweeps, seed=7, **kw,
             **({"update": update} if update == "swendsen-wang" else {}))
    assert r.update == update
    if update in ("wolff", "swendsen-wang"):
        key = "m2_s" if kw["J"] < 0 else "m2"
        assert abs(r.m2_improved - exact[key]) < 4 * r.m2_improved_err
    _check(r, exact)
    if "m2_s" not in exact:
        assert math.isnan(r.m2_s)


def _xy_ring(beta, n):
    def lnz(b):
        k = np.arange(-40, 41)
        return math.log(float(np.sum(iv(k, b) ** n)))
    return lnz


def _heisenberg_ring(beta, n):
    def lnz(b):
        ell = np.arange(0, 40)
        lam = 4 * np.pi * np.sqrt(np.pi / (2 * b)) * iv(ell + 0.5, b)
        return math.log(float(np.sum((2 * ell + 1) * lam ** n)))
    return lnz


def _from_lnz(lnz, beta, n) -> dict:
    d = 1e-3
    f = [lnz(beta + k * d) for k in (-2, -1, 0, 1, 2)]
    d1 = (f[0] - 8 * f[1] + 8 * f[3] - f[4]) / (12 * d)
    d2 = (-f[0] + 16 * f[1] - 30 * f[2] + 16 * f[3] - f[4]) / (12 * d * d)
    return {"e": -d1 / n, "c": beta ** 2 * d2 / n}


def _open_chain_exact(model, beta, n) -> dict:
    if model == "xy":
        u = iv(1, beta) / iv(0, beta)
        du = 1 - u / beta - u * u
    else:
        u = 1 / math.tanh(beta) - 1 / beta
        du = 1 / beta ** 2 - 1 / math.sinh(beta) ** 2
    idx = np.arange(n)
    m2 = float(np.sum(u ** np.abs(idx[:, None] - idx[None, :]))) / n ** 2
    return {"e": -(n - 1) / n * u, "c": beta ** 2 * (n - 1) / n * du, "m2": m2, "chi": beta * n * m2}


@pytest.mark.parametrize("model", ["xy", "heisenberg"])
@pytest.mark.parametrize("update", ["wolff", "swendsen-wang", "local"])
def test_open_chain_matches_bessel_and_langevin(model, update):
    n, beta = 6, 1.3
    r = _run(_chain(n), model=model, beta=beta, sweeps=20000, seed=3, update=update)
    _check(r, _open_chain_exact(model, beta, n))


@pytest.mark.slow
@pytest.mark.parametrize("model", ["xy", "heisenberg"])
@pytest.mark.parametrize("beta", [0.7, 2.0])
def test_ring_matches_transfer_matrix(model, beta):
    n = 8
    lnz = (_xy_ring if model == "xy" else _heisenberg_ring)(beta, n)
    exact = _from_lnz(lnz, beta, n)
    for update in ("wolff", "swendsen-wang", "local"):
        r = _run(_chain(n, periodic=True), model=model, beta=beta, sweeps=40000, seed=4, update=update)
        _check(r, exact)


@pytest.mark.slow
def test_error_bars_cover_about_68_percent():
    """40 chains per observable: the fraction within 1 sigma of the exact value is 68 % +- 7 %."""
    inside = []
    exact = _ising_exact(BOLZA.adjacency(), J=1.0, h=0.0, beta=0.4)
    exact_xy = _open_chain_exact("xy", 1.3, 6)
    for seed in range(40):
        r = _run(BOLZA, model="ising", beta=0.4, sweeps=3000, seed=100 + seed)
        for k in ("e", "m2", "c", "U4"):
            inside.append(abs(getattr(r, k) - exact[k]) < getattr(r, k + "_err"))
        r = _run(_chain(6), model="xy", beta=1.3, sweeps=3000, seed=200 + seed, update="local")
        for k in ("e", "m2"):
            inside.append(abs(getattr(r, k) - exact_xy[k]) < getattr(r, k + "_err"))
    frac = float(np.mean(inside))
    assert 0.55 < frac < 0.82, frac


@pytest.mark.machine_independence
def test_update_choice_and_staggered_observables():
    r = _run(BOLZA, model="heisenberg", J=-1.0, beta=2.0, sweeps=400, seed=1)
    assert r.update == "wolff" and "sublattice gauge" in r.update_reason
    # the antiferromagnet orders in the staggered moment, not the uniform one
    assert r.m2_s > 5 * r.m2 and np.isfinite(r.U4_s)
    assert abs(r.m2_improved - r.m2_s) < 4 * math.hypot(r.m2_improved_err, r.m2_s_err)
    with pytest.raises(ValueError, match="Wolff update needs h = 0"):
        classical_mc(BOLZA, model="ising", beta=1.0, h=0.1, update="wolff", sweeps=10, progress=False)
    with pytest.raises(ValueError, match="Wolff update needs"):
        classical_mc(HEPTAGON, model="ising", beta=1.0, J=-1.0, update="wolff", sweeps=10, progress=False)


@pytest.mark.machine_independence
def test_rings_and_correlation_by_distance():
    lat = hl.ring_lattice(7, 3, 3)
    r = _run(lat, model="xy", beta=0.4, sweeps=3000, seed=2)
    assert list(r.ring_index) == [1, 2, 3] and int(r.ring_sites.sum()) == lat.sites
    # the ring averages are the site averages, ring by ring
    assert np.allclose(r.ring_energy[0], r.site_energy[lat.ring == 1].mean())
    assert r.distance_kind == "hyperbolic" and np.all(np.diff(r.corr_distance) > 0)
    # above T_c the correlation decays with distance (first class against the farthest)
    assert r.corr[0] - r.corr[-1] > 4 * math.hypot(r.corr_err[0], r.corr_err[-1])
    # from the centre: the pairs with a first-ring site, every one counted once
    c = _run(lat, model="ising", beta=0.3, sweeps=2000, seed=3, correlation_from="centre")
    assert c.distance_kind == "hyperbolic from the centre"
    assert int(c.corr_pairs.sum()) == 7 * (lat.sites - 7) + 21
    assert c.corr[0] > c.corr[-1]
    with pytest.raises(ValueError, match="needs a flake"):
        classical_mc(BOLZA, model="ising", beta=0.3, correlation_from="centre", progress=False)


@pytest.mark.machine_independence
def test_merge_and_checkpoint(tmp_path):
    kw = dict(model="ising", beta=0.5, sweeps=600, thermalization=50)
    full = _run(HEPTAGON, seed=5, **kw)
    ck = tmp_path / "ck"
    _run(HEPTAGON, seed=5, checkpoint=ck, **{**kw, "sweeps": 300})
    resumed = _run(HEPTAGON, seed=5, checkpoint=ck, **kw)
    assert resumed.e == full.e and resumed.m2 == full.m2        # bit-identical continuation
    with pytest.raises(ValueError, match="other parameters"):
        classical_mc(HEPTAGON, seed=5, checkpoint=ck, progress=False, **{**kw, "beta": 0.6})
    # a damaged file is refused in one sentence
    f = ck / "spins_classical_chain.npz"
    data = dict(np.load(f))
    data["spins"] = -data["spins"]
    np.savez(f, **data)
    with pytest.raises(ValueError, match="damaged"):
        classical_mc(HEPTAGON, seed=5, checkpoint=ck, progress=False, **kw)
    m = merge_classical([full, _run(HEPTAGON, seed=6, **kw)])
    assert m.chains == 2 and m.sweeps == 1200 and m.seeds == (5, 6)
    with pytest.raises(ValueError, match="seed occurs twice"):
        merge_classical([full, full])


@pytest.mark.parametrize("kw, match", [
    (dict(model="potts", beta=1.0), "unknown model"),
    (dict(model="ising", beta=0.0), "beta must be positive"),
    (dict(model="ising", beta=-1.0), "beta must be positive"),
    (dict(model="ising", beta=float("nan")), "beta"),
    (dict(model="ising", T=-2.0), "T must be positive"),
    (dict(model="ising", beta=1.0, T=1.0), "exactly one"),
    (dict(model="ising"), "exactly one"),
    (dict(model="ising", beta=1.0, sweeps=-3), "sweeps"),
    (dict(model="ising", beta=1.0, h=float("nan")), "h"),
    (dict(model="ising", beta=1.0, update="metropolis"), "update"),
])
def test_bad_input_is_one_sentence(kw, match):
    with pytest.raises(ValueError, match=match):
        classical_mc(HEPTAGON, progress=False, **kw)


def test_bad_graphs():
    with pytest.raises(ValueError, match="symmetric"):
        classical_mc(np.triu(np.ones((4, 4)), 1), model="ising", beta=1.0, progress=False)
    with pytest.raises(ValueError, match="finite"):
        classical_mc(np.full((3, 3), np.nan), model="ising", beta=1.0, progress=False)
    with pytest.raises(ValueError, match="system must be"):
        classical_mc("graph", model="ising", beta=1.0, progress=False)


@pytest.mark.machine_independence
def test_cli_contract(capsys):
    assert main(["spins", "classical", "--model", "ising", "--cluster", "bolza", "--J", "-1", "--h", "0",
                 "--T", "2", "--sweeps", "500", "--seed", "1", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    for k in ("sites", "e", "c", "m2", "U4", "chi"):
        assert k in out and k + "_err" in out if k != "sites" else k in out
    assert out["sites"] == 16 and out["update"] == "wolff" and out["chi_s"] > out["chi"]
    assert isinstance(out["tau_int"], dict)


@pytest.mark.parametrize("argv", [
    ["--model", "potts", "--rings", "2", "--beta", "1"],
    ["--model", "ising", "--rings", "2", "--beta", "0"],
    ["--model", "ising", "--rings", "2", "--beta", "nan"],
    ["--model", "ising", "--rings", "2", "--beta", "1", "--sweeps", "-5"],
    ["--model", "ising", "--rings", "2", "--T", "1", "--J", "nan"],
    ["--model", "ising", "--cluster", "bolza", "--line-graph", "--beta", "1"],
    ["--model", "ising", "--rings", "2", "--beta", "1", "--h", "1", "--update", "wolff"],
])
def test_cli_bad_input_exit_2(argv, capsys):
    with pytest.raises(SystemExit) as exc:
        code = main(["spins", "classical", *argv])
        raise SystemExit(code)
    assert exc.value.code == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and "error" in err


@pytest.mark.machine_independence
def test_cli_interrupt_keeps_the_chain(tmp_path, monkeypatch, capsys):
    """Ctrl-C: the chain is saved, one line, exit 130; the same command resumes and finishes."""
    from hyperlattice.spins import _classical_kernels as K

    real = K.run
    calls = []

    def interrupted(*args):
        calls.append(1)
        if len(calls) == 3:
            raise KeyboardInterrupt
        return real(*args)

    monkeypatch.setattr(K, "run", interrupted)
    argv = ["spins", "classical", "--model", "xy", "--rings", "2", "--beta", "0.5", "--sweeps", "400",
            "--seed", "4", "--checkpoint", str(tmp_path / "ck"), "--json"]
    assert main(argv) == 130
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and "interrupted" in err and "resume" in err
    assert (tmp_path / "ck" / "spins_classical_chain.npz").exists()
    monkeypatch.setattr(K, "run", real)
    assert main(argv) == 0
    resumed = json.loads(capsys.readouterr().out)
    assert main(argv[:-3] + ["--json"]) == 0             # the same chain without a checkpoint
    assert json.loads(capsys.readouterr().out)["e"] == resumed["e"]


@pytest.mark.parametrize("model", ["ising", "xy", "heisenberg"])
def test_free_spins(model):
    """J = 0: independent unit spins, <|m|^2> = 1/N, e = 0 (a zero coupling constrains no gauge)."""
    lat = hl.ring_lattice(7, 3, 2)
    r = _run(lat, model=model, J=0.0, beta=1.0, sweeps=3000, seed=8)
    assert r.e == 0.0 and abs(r.m2 - 1 / lat.sites) < 4 * r.m2_err


def test_memory_refused_before_work(monkeypatch, capsys):
    """A chain that will not fit is refused in one sentence, before any allocation or sweep."""
    from hyperlattice import _validate

    need = classical_mc_memory(hl.ring_lattice(7, 3, 3), model="xy")
    monkeypatch.setattr(_validate, "available_memory", lambda: need // 2)
    with pytest.raises(MemoryError, match="classical spin chain on 112 sites"):
        classical_mc(hl.ring_lattice(7, 3, 3), model="xy", beta=1.0, progress=False)
    assert main(["spins", "classical", "--model", "xy", "--rings", "3", "--beta", "1"]) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and "needs about" in err


def test_sweep_task_spins(tmp_path):
    """A temperature grid through the Dask sweep's task table (serial here): one row per point."""
    from hyperlattice.sweep.engine import run_sweep
    from hyperlattice.sweep.store import read_table

    grid = {"rings": [2], "T": [1.5, 3.0], "sweeps": [500], "seed": [1]}
    rep = run_sweep("spins", grid, tmp_path / "s", scheduler="serial", progress=False)
    assert rep.ok and rep.completed == 2
    rows = read_table(tmp_path / "s").rows()
    assert len(rows) == 2 and {r["update_used"] for r in rows} == {"wolff"}
    cold, hot = sorted(rows, key=lambda r: r["T"])
    assert cold["m2"] > hot["m2"] and len(cold["ring_alignment"]) == 2
    with pytest.raises(ValueError, match="model"):
        run_sweep("spins", {"model": ["potts"]}, tmp_path / "bad", scheduler="serial", progress=False)


@pytest.mark.parametrize("model, edit, match", [
    ("ising", lambda s: s * 0.5, "other than \\+1 and -1"),
    ("xy", lambda s: s * 1.01, "not unit vectors"),
    ("heisenberg", lambda s: s + np.nan, "non-finite spins"),
])
def test_checkpoint_ranges(tmp_path, model, edit, match):
    """A checkpoint whose checksum was recomputed after an edit is still refused by its values."""
    from hyperlattice.bosons import _checkpoint

    kw = dict(model=model, beta=0.5, sweeps=100, thermalization=10, seed=3)
    _run(HEPTAGON, checkpoint=tmp_path, **kw)
    f = tmp_path / "spins_classical_chain.npz"
    meta, arrays = _checkpoint.read(f)
    arrays["spins"] = edit(arrays["spins"])
    _checkpoint.write(f, meta, arrays)
    with pytest.raises(ValueError, match=match):
        classical_mc(HEPTAGON, checkpoint=tmp_path, progress=False, **{**kw, "sweeps": 200})


def test_checkpoint_directory_lock(tmp_path):
    from filelock import FileLock

    with FileLock(str(tmp_path / ".spins_classical.lock")):
        with pytest.raises(ValueError, match="in use by another run"):
            classical_mc(HEPTAGON, model="ising", beta=0.5, sweeps=50, seed=1, checkpoint=tmp_path, progress=False)


def test_saved_result_ranges(tmp_path):
    import dataclasses

    from hyperlattice.spins import ClassicalResult

    r = _run(HEPTAGON, model="ising", beta=0.5, sweeps=200, seed=1)
    r.save(tmp_path / "ok.json")
    assert ClassicalResult.load(tmp_path / "ok.json").e == r.e
    for change, match in ((dict(m2=1.5), "outside \\[0, 1\\]"), (dict(U4=0.9), "exceeds 2/3"),
                          (dict(model="potts"), "not one of")):
        dataclasses.replace(r, **change).save(tmp_path / "bad.json")
        with pytest.raises(ValueError, match=match):
            ClassicalResult.load(tmp_path / "bad.json")


@pytest.mark.parametrize("matrix, match", [
    (np.array([[0.0, np.nan], [np.nan, 0.0]]), "finite"),
    (np.array([[0.0, 1.0], [2.0, 0.0]]), "symmetric"),
    (np.array([[0.0, 1j], [1j, 0.0]]), "real"),
])
def test_cli_adjacency_ranges(tmp_path, capsys, matrix, match):
    """--adjacency is checked by value (finite, real, symmetric couplings), refused in one line, exit 2."""
    f = tmp_path / "a.npy"
    np.save(f, matrix)
    assert main(["spins", "classical", "--model", "ising", "--adjacency", str(f), "--beta", "1", "--sweeps", "10"]) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and match in err
