"""The ``qmc`` task: one Markov chain of the Bose–Hubbard quantum Monte Carlo (SSE) on a flake or a cluster."""

from __future__ import annotations

import math

import numpy as np

from ... import _validate
from ._common import _NOTES_SEP, _check_chain_graph, _check_chain_length, _qmc_system, _quietly

#: the fields of a QMCResult a ``qmc`` row stores under their own names (the rest: see _qmc)
_QMC_SCALARS = ("system", "sites", "energy", "energy_err", "density", "density_err",
                "compressibility", "compressibility_err", "bins", "bin_size", "mean_operators", "string_length",
                "loops_per_sweep", "condensate_fraction", "condensate_fraction_err", "distance_kind")
#: the 1-d arrays of the equal-time Green function by distance class (empty when not measured)
_QMC_GREEN = ("green_distance", "green", "green_err", "green_pairs")
_QMC_TAUS = ("energy", "density", "compressibility")
#: the stiffness scalars of a ``qmc`` row (nan without winding numbers: an open flake)
_QMC_STIFFNESS = ("rho_s", "rho_s_err", "stiffness_geometric", "stiffness_geometric_err")


def _qmc(p: int = 7, q: int = 3, rings: int = 3, cluster: str | None = None, nmax: int = 2, U: float = 10.0,
         t: float = 1.0, mu: float = 5.0, beta: float = 4.0, sweeps: int = 5000, thermalization: int | None = None,
         seed: int = 0) -> dict:
    from ...bosons import QMCWarning, qmc

    r = _quietly(QMCWarning, qmc, _qmc_system(p, q, rings, cluster), U=U, mu=mu, beta=beta, nmax=nmax, t=t,
                 sweeps=sweeps, thermalization=thermalization, seed=seed, progress=False)
    row = {k: getattr(r, k) for k in _QMC_SCALARS}
    # an output never reuses a parameter's name (the table holds both): the thermalisation actually run
    row["thermalization_sweeps"] = int(r.thermalization)
    row.update({f"tau_{k}": float(r.tau_int.get(k, math.nan)) for k in _QMC_TAUS})
    row["converged"] = bool(r.converged)
    row["notes"] = _NOTES_SEP.join(r.notes)
    row["site_density"] = np.asarray(r.site_density, float)
    row["site_density_err"] = np.asarray(r.site_density_err, float)
    row["bond_i"] = np.asarray(r.bonds, np.int64)[:, 0]
    row["bond_j"] = np.asarray(r.bonds, np.int64)[:, 1]
    row["bond_kinetic"] = np.asarray(r.bond_kinetic, float)
    row["bond_kinetic_err"] = np.asarray(r.bond_kinetic_err, float)
    for k in _QMC_GREEN:     # G(d) by distance class; the full matrix (2-d) is not a table column
        v = getattr(r, k)
        row[k] = np.zeros(0) if v is None else np.asarray(v, float)
    # the superfluid stiffness from the winding numbers (a periodic cluster): the D x D tensor row by
    # row (a column holds 1-d arrays), D in ``stiffness_dim``; empty, 0 and nan on a flake
    row.update({k: float(getattr(r, k)) for k in _QMC_STIFFNESS})
    row["tau_stiffness"] = float(r.tau_int.get("stiffness", math.nan))
    row["stiffness_dim"] = 0 if r.stiffness is None else int(r.stiffness.shape[0])
    for k in ("stiffness", "stiffness_err"):
        v = getattr(r, k)
        row[k] = np.zeros(0) if v is None else np.asarray(v, float).ravel()
    row["stiffness_note"] = r.stiffness_note
    return row


def _check_qmc(params: dict) -> None:
    p, q = _check_chain_graph(params)
    _validate.positive_int("nmax", params["nmax"], maximum=1000)
    beta = _check_chain_length(params, ("U", "t", "mu"), positive_beta=True)
    if params["t"] == 0:
        raise ValueError("t = 0 leaves no bond term; the sites are independent.")
    # the operator string grows with beta * bonds: the engine's own estimate refuses a point that will
    # not fit, before the grid runs
    from ...bosons.sse import qmc_memory

    need = qmc_memory(_qmc_system(p, q, params["rings"], params["cluster"]), U=float(params["U"]),
                      mu=float(params["mu"]), beta=beta, nmax=int(params["nmax"]), t=float(params["t"]))
    try:
        _validate.require_memory(f"the SSE operator string at beta = {beta:g}", need)
    except MemoryError as exc:
        raise ValueError(str(exc)) from None
