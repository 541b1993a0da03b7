"""Parallel tempering of the classical spin models (hyperlattice.spins.tempering): every temperature's
chain against exact enumeration on a frustrated graph, the exchange statistics, bad input, the CLI."""

from __future__ import annotations

import json
import warnings

import numpy as np
import pytest

import hyperlattice as hl
from hyperlattice.cli import main
from hyperlattice.spins import TemperingResult, tempering_mc
from hyperlattice.spins.classical import SpinWarning

HEPTAGON = hl.adjacency(hl.ring_lattice(7, 3, 1)).toarray()


def _exact_e_m2(adj, J, h, beta):
    n = adj.shape[0]
    states = 1 - 2 * ((np.arange(2 ** n)[:, None] >> np.arange(n)[None, :]) & 1).astype(float)
    E = -0.5 * J * np.einsum("si,ij,sj->s", states, adj, states) - h * states.sum(axis=1)
    w = np.exp(-beta * (E - E.min()))
    w /= w.sum()
    m = states.mean(axis=1)
    return w @ E / n, w @ m ** 2


def _pt(system, **kw):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", SpinWarning)
        return tempering_mc(system, progress=False, **kw)


@pytest.mark.machine_independence          # the update chosen is a label, the exchanges are counted
@pytest.mark.parametrize("J, h", [(-1.0, 0.0), pytest.param(-1.0, 0.3, marks=pytest.mark.slow)])
def test_each_temperature_matches_exact_enumeration(J, h):
    """The odd ring is frustrated (heat-bath); every chain, exchanges included, samples its own beta."""
    r = _pt(HEPTAGON, model="ising", J=J, h=h, beta=[1.5, 0.3, 0.7], sweeps=3000, seed=4)
    assert r.update == "heat-bath" and np.all(np.diff(r.beta) > 0)
    for b, c in zip(r.beta, r.chains):
        assert c.beta == b
        e, m2 = _exact_e_m2(HEPTAGON, J, h, b)
        assert abs(c.e - e) < 4 * c.e_err and abs(c.m2 - m2) < 4 * c.m2_err
    assert r.attempts.sum() == 3000 + 300 and np.all((r.acceptance > 0) & (r.acceptance <= 1))
    assert r.round_trips > 0
    df = r.to_dataframe()
    assert list(df["beta"]) == list(r.beta) and "tau_e" in df


@pytest.mark.machine_independence
def test_same_seed_same_run_and_saved(tmp_path):
    a = _pt(HEPTAGON, model="xy", J=-1.0, T=[1.0, 2.0], sweeps=300, seed=9)
    b = _pt(HEPTAGON, model="xy", J=-1.0, T=[2.0, 1.0], sweeps=300, seed=9)
    assert np.array_equal(a.e, b.e) and np.array_equal(a.acceptance, b.acceptance)
    a.save(tmp_path / "pt.json")
    back = TemperingResult.load(tmp_path / "pt.json")
    assert np.array_equal(back.e, a.e) and back.round_trips == a.round_trips


@pytest.mark.parametrize("kw, match", [
    (dict(beta=[1.0]), "at least two"),
    (dict(beta=[1.0, 1.0]), "distinct"),
    (dict(beta=[1.0, -1.0]), "positive"),
    (dict(T=[1.0, float("nan")]), "NaN"),
    (dict(beta=[1.0, 2.0], T=[1.0, 2.0]), "exactly one"),
    (dict(beta=[1.0, 2.0], exchange_every=0), "exchange_every"),
])
def test_bad_input(kw, match):
    with pytest.raises(ValueError, match=match):
        tempering_mc(HEPTAGON, model="ising", sweeps=10, progress=False, **kw)


def test_cli_tempering(capsys):
    assert main(["spins", "classical", "--model", "ising", "--rings", "1", "-p", "7", "-q", "3", "--J", "-1",
                 "--tempering", "0.8,1.5", "--sweeps", "400", "--seed", "2", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["type"] == "TemperingResult" and len(out["acceptance"]) == 1 and len(out["temperatures"]) == 2
    first = out["temperatures"][0]
    assert list(first)[:3] == ["sites", "e", "e_err"] and first["update"] == "heat-bath"
    for argv in (["--tempering", "0.8"], ["--tempering", "1,1"], ["--T", "1", "--exchange-every", "3"]):
        with pytest.raises(SystemExit) as exc:
            raise SystemExit(main(["spins", "classical", "--model", "ising", "--rings", "1", *argv]))
        assert exc.value.code == 2
        assert capsys.readouterr().err.strip().count("\n") == 0


def test_plots(tmp_path):
    import matplotlib

    matplotlib.use("Agg")
    from hyperlattice.plots.spins_classical import plot_temperature_scan
    from hyperlattice.spins import classical_mc

    flake = hl.ring_lattice(7, 3, 2)
    r = _pt(flake, model="ising", J=-1.0, T=[1.0, 2.0], sweeps=200, seed=1)
    ax = r.plot(observable="U4")
    assert len(ax.lines) >= 1 and "tempering" in ax.get_title()
    ax = r.plot(observable="alignment", by_ring=True)
    assert len(ax.get_legend().get_texts()) == 2                 # one curve per ring
    one = classical_mc(flake, model="ising", beta=0.4, sweeps=200, seed=1, progress=False)
    assert one.plot().get_xlabel() == "ring"
    assert "distance" in one.plot(observable="correlation").get_xlabel()
    plot_temperature_scan([one, *r.chains], observable="e", label="e")
    with pytest.raises(ValueError, match="observable must be one of"):
        one.plot(observable="nope")
    matplotlib.pyplot.close("all")


@pytest.mark.machine_independence
def test_checkpoint_resumes_bit_identically(tmp_path):
    from hyperlattice.bosons import _checkpoint

    kw = dict(model="ising", J=-1.0, T=[1.0, 2.0, 3.0], thermalization=50, seed=5, exchange_every=2)
    full = _pt(HEPTAGON, sweeps=400, **kw)
    _pt(HEPTAGON, sweeps=200, checkpoint=tmp_path, **kw)
    resumed = _pt(HEPTAGON, sweeps=400, checkpoint=tmp_path, **kw)
    assert np.array_equal(resumed.e, full.e) and np.array_equal(resumed.attempts, full.attempts)
    assert resumed.round_trips == full.round_trips
    with pytest.raises(ValueError, match="other parameters"):
        tempering_mc(HEPTAGON, sweeps=400, checkpoint=tmp_path, progress=False, **{**kw, "T": [1.0, 2.5, 3.0]})
    f = tmp_path / "spins_tempering.npz"
    meta, arrays = _checkpoint.read(f)
    arrays["c1_spins"] = arrays["c1_spins"] * 2.0
    _checkpoint.write(f, meta, arrays)
    with pytest.raises(ValueError, match="other than \\+1 and -1"):
        tempering_mc(HEPTAGON, sweeps=500, checkpoint=tmp_path, progress=False, **kw)
