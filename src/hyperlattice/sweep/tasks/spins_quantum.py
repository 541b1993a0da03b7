"""The ``spins_quantum`` task: one Markov chain of the spin-1/2 XXZ quantum Monte Carlo (SSE)."""

from __future__ import annotations

import math

import numpy as np

from ... import _validate
from ._common import _NOTES_SEP, _check_chain_graph, _check_chain_length, _qmc_system, _quietly

#: the scalars of an XXZResult a ``spins_quantum`` row stores under their own names
_XXZ_SCALARS = ("system", "sites", "bipartite", "e", "e_err", "c", "c_err", "chi_u", "chi_u_err", "mz", "mz_err",
                "s_pi", "s_pi_err", "binder", "binder_err", "rho_s", "rho_s_err", "bins", "bin_size",
                "mean_operators", "energy_estimator")


def _spins_quantum(p: int = 8, q: int = 3, rings: int = 2, cluster: str | None = None, J: float = 1.0,
                   Delta: float = 1.0, h: float = 0.0, beta: float = 4.0, sweeps: int = 5000,
                   thermalization: int | None = None, seed: int = 0) -> dict:
    from ...spins.quantum import XXZWarning, xxz_qmc

    r = _quietly(XXZWarning, xxz_qmc, _qmc_system(p, q, rings, cluster), J=J, Delta=Delta, h=h, beta=beta,
                 sweeps=sweeps, thermalization=thermalization, seed=seed, progress=False)
    row = {k: getattr(r, k) for k in _XXZ_SCALARS}
    row["thermalization_sweeps"] = int(r.thermalization)
    row.update({f"tau_{k}": float(r.tau_int.get(k, math.nan)) for k in ("energy", "chi_u", "s_pi", "stiffness")})
    row["converged"] = bool(r.converged)
    row["notes"] = _NOTES_SEP.join(r.notes)
    for k in ("site_sz", "site_sz_err", "site_stag", "site_stag_err", "ring_stag", "ring_stag_err"):
        v = getattr(r, k)
        row[k] = np.zeros(0) if v is None else np.asarray(v, float)
    return row


def _check_spins_quantum(params: dict) -> None:
    p, q = _check_chain_graph(params)
    _check_chain_length(params, ("J", "Delta", "h"), positive_beta=True)
    if params["J"] == 0:
        raise ValueError("J = 0 leaves free spins in a field (no bond term); use a nonzero J.")
    if params["J"] > 0 and params["cluster"] is None and p % 2:
        raise ValueError(f"an antiferromagnet (J > 0) on a graph with an odd cycle is frustrated and gives the "
                         f"quantum Monte Carlo a sign problem (the {{{p},{q}}} flake has {p}-gons).")
