"""The ``spins`` task: one Markov chain of a classical spin model on a flake or a cluster."""

from __future__ import annotations

import math

import numpy as np

from ... import _validate
from ._common import _NOTES_SEP, _check_chain_graph, _check_chain_length, _qmc_system, _quietly

#: the scalar observables of a ``spins`` row, each with its ``_err``
_SPINS_SCALARS = ("e", "c", "m", "m2", "m_abs", "U4", "chi", "m2_s", "m_abs_s", "U4_s", "chi_s")


def _spins(p: int = 7, q: int = 3, rings: int = 3, cluster: str | None = None, model: str = "ising",
           J: float = 1.0, h: float = 0.0, T: float = 2.0, sweeps: int = 5000, thermalization: int | None = None,
           seed: int = 0, update: str = "auto") -> dict:
    from ...spins.classical import SpinWarning, classical_mc

    r = _quietly(SpinWarning, classical_mc, _qmc_system(p, q, rings, cluster), model=model, T=T, J=J, h=h,
                 sweeps=sweeps, thermalization=thermalization, seed=seed, update=update, measure_correlation=False,
                 progress=False)
    row = {"sites": int(r.sites), "update_used": r.update}
    for k in _SPINS_SCALARS:
        row[k] = float(getattr(r, k))
        row[k + "_err"] = float(getattr(r, k + "_err"))
    row.update({f"tau_{k}": float(r.tau_int.get(k, math.nan)) for k in ("e", "m2")})
    row["converged"] = bool(r.converged)
    row["notes"] = _NOTES_SEP.join(r.notes)
    for k in ("ring_energy", "ring_alignment", "ring_alignment_err", "ring_m"):     # bulk against boundary
        v = getattr(r, k)
        row[k] = np.zeros(0) if v is None else np.asarray(v, float)
    return row


def _check_spins(params: dict) -> None:
    p, q = _check_chain_graph(params)
    from ...spins.classical import MODELS, classical_mc_memory

    _validate.choice("model", params["model"], tuple(MODELS))
    _validate.choice("update", params["update"], ("auto", "wolff", "swendsen-wang", "local"))
    T = _validate.real("T", params["T"])
    if not T > 0:
        raise ValueError(f"T must be positive, got {T!r}.")
    _check_chain_length(params, ("J", "h"))
    need = classical_mc_memory(_qmc_system(p, q, params["rings"], params["cluster"]), model=params["model"],
                               measure_correlation=False)
    try:
        _validate.require_memory("the classical spin chain", need)
    except MemoryError as exc:
        raise ValueError(str(exc)) from None
