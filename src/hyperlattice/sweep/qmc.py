r"""Reading a qmc sweep back: the independent chains of each grid point merged into one result.

Above the store (it reads a table) and the task registry (whose row format it inverts).
"""

from __future__ import annotations

import numpy as np

from .store import SweepTable, read_table
from .tasks import _NOTES_SEP, _QMC_GREEN, _QMC_SCALARS, _QMC_STIFFNESS, _QMC_TAUS, _point_value, get_task

__all__ = ["merge_qmc"]


def merge_qmc(table) -> list:
    """The chains of a ``qmc`` sweep merged per grid point (all parameters but ``seed``).

    Parameters
    ----------
    table : SweepTable, str or path-like
        A sweep's table (:func:`~hyperlattice.sweep.read_table`) or its directory.

    Returns
    -------
    list of QMCResult
        One result per point, in the order of the points' first rows, from
        :func:`hyperlattice.bosons.merge_chains` of that point's chains (``chains``, ``seeds``).
        ``seconds`` is 0 and ``green_matrix`` None (a row stores neither).

    Raises
    ------
    ValueError
        If the table is not a ``qmc`` sweep.

    Examples
    --------
    >>> import os, tempfile
    >>> from hyperlattice.sweep import run_sweep
    >>> from hyperlattice.sweep.qmc import merge_qmc
    >>> where = os.path.join(tempfile.mkdtemp(), "lobe")
    >>> grid = {"rings": 1, "nmax": 2, "U": 8.0, "mu": [2.0, 4.0], "beta": 1.0, "sweeps": 1000, "seed": [1, 2]}
    >>> _ = run_sweep("qmc", grid, where, scheduler="serial", progress=False)
    >>> [(r.mu, r.chains, r.seeds) for r in merge_qmc(where)]
    [(2.0, 2, (1, 2)), (4.0, 2, (1, 2))]
    """
    from ..bosons import merge_chains
    from ..bosons.sse import QMCResult

    if not isinstance(table, SweepTable):
        table = read_table(table)
    if table.metadata.get("task") != "qmc":
        raise ValueError(f"merge_qmc reads a qmc sweep, not a {table.metadata.get('task')!r} sweep.")
    point_keys = [k for k in get_task("qmc").defaults if k != "seed"]
    groups: dict = {}
    for row in table.rows():
        tau = {k: float(row[f"tau_{k}"]) for k in _QMC_TAUS}
        st = _stiffness(row, tau)
        r = QMCResult(
            U=float(row["U"]), mu=float(row["mu"]), t=float(row["t"]), beta=float(row["beta"]),
            nmax=int(row["nmax"]), seed=int(row["seed"]), seeds=(int(row["seed"]),), chains=1,
            tau_int=tau, converged=bool(row["converged"]),
            notes=tuple(n for n in str(row["notes"]).split(_NOTES_SEP) if n),
            site_density=np.asarray(row["site_density"], float),
            site_density_err=np.asarray(row["site_density_err"], float),
            bonds=np.column_stack([np.asarray(row["bond_i"], np.int64), np.asarray(row["bond_j"], np.int64)]),
            # the task's graphs (flakes, clusters) have unit adjacency: every coupling is t
            bond_hopping=np.full(len(row["bond_i"]), float(row["t"])),
            bond_kinetic=np.asarray(row["bond_kinetic"], float),
            bond_kinetic_err=np.asarray(row["bond_kinetic_err"], float), seconds=0.0,
            sweeps=int(row["sweeps"]), thermalization=int(row["thermalization_sweeps"]), green_matrix=None,
            **{k: (np.asarray(row[k], float) if len(row[k]) else None) for k in _QMC_GREEN},
            **{k: row[k] for k in _QMC_SCALARS}, **st)
        groups.setdefault(tuple(_point_value(row[k]) for k in point_keys), []).append(r)
    return [merge_chains(chains) for chains in groups.values()]


def _stiffness(row, tau: dict) -> dict:
    """The stiffness fields of a QMCResult from a row (tables written before they were stored: none)."""
    d = int(row["stiffness_dim"]) if "stiffness_dim" in row else 0
    if d == 0:
        return {"stiffness_note": str(row["stiffness_note"]) if "stiffness_note" in row
                else "not stored in this sweep's table."}
    tau["stiffness"] = float(row["tau_stiffness"])
    out = {k: float(row[k]) for k in _QMC_STIFFNESS}
    for k in ("stiffness", "stiffness_err"):
        out[k] = np.asarray(row[k], float).reshape(d, d)
    out["stiffness_note"] = ""
    return out


from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
