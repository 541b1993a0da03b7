"""qmc_memory: the public estimate of a chain's memory, the number behind the engine's refusal and
the sweep task's check before a grid runs."""

from __future__ import annotations

import warnings

import pytest

import hyperlattice as hl
from hyperlattice import _validate
from hyperlattice.bosons import qmc, qmc_memory
from hyperlattice.sweep.engine import expand_grid

HEPTAGON = hl.ring_lattice(7, 3, 1)
KW = dict(U=4.0, mu=1.0, nmax=2)


def test_bytes_grow_linearly_with_beta_and_the_bonds():
    n1, n2, n3 = (qmc_memory(HEPTAGON, beta=b, **KW) for b in (1.0, 2.0, 3.0))
    assert isinstance(n1, int) and 0 < n1 < n2 < n3 < 2**20
    assert n3 - n2 == pytest.approx(n2 - n1, abs=2)
    big = qmc_memory(hl.ring_lattice(7, 3, 3), beta=2.0, **KW)            # 112 sites, 140 bonds
    assert big > 10 * n2
    assert qmc_memory(HEPTAGON, beta=2.0, t=2.0, **KW) > n2               # larger vertex weights


def test_the_engine_refuses_exactly_above_it(monkeypatch):
    from hyperlattice.bosons.sse import _RUNTIME_BYTES

    # the chain's estimate plus the fixed share of the compiled kernels and BLAS
    need = qmc_memory(HEPTAGON, beta=2.0, **KW) + _RUNTIME_BYTES
    monkeypatch.setattr(_validate, "available_memory", lambda: need - 1)
    with pytest.raises(MemoryError, match="operator string"):
        qmc(HEPTAGON, beta=2.0, sweeps=10, thermalization=10, seed=1, progress=False, **KW)
    monkeypatch.setattr(_validate, "available_memory", lambda: need + 1)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")                 # 10 sweeps: the binning warns, as it should
        r = qmc(HEPTAGON, beta=2.0, sweeps=10, thermalization=10, seed=1, progress=False, **KW)
    assert r.sweeps == 10


def test_the_sweep_task_asks_qmc_memory(monkeypatch):
    import hyperlattice.bosons.sse as sse

    grid = {"rings": 1, "nmax": 2, "U": 4.0, "mu": 1.0, "beta": 2.0, "sweeps": 10}
    assert len(expand_grid("qmc", grid)) == 1
    monkeypatch.setattr(sse, "qmc_memory", lambda *a, **k: 10**18)
    with pytest.raises(ValueError, match="allocate") as exc:
        expand_grid("qmc", grid)
    assert "\n" not in str(exc.value)


@pytest.mark.parametrize("kw, match", [
    (dict(beta=0.0), "beta"), (dict(beta=float("nan")), "beta"), (dict(nmax=0), "nmax"), (dict(t=0.0), "t = 0"),
    (dict(t=-1.0), "sign problem"),
])
def test_bad_input_one_sentence(kw, match):
    args = dict(U=1.0, mu=0.0, beta=1.0, nmax=1)
    args.update(kw)
    with pytest.raises(ValueError, match=match) as exc:
        qmc_memory(HEPTAGON, **args)
    assert "\n" not in str(exc.value)
