r"""Reading a ``device`` sweep back: the realisations of each device merged into an ensemble.

Above the store (it reads a table) and the task registry (whose row format it inverts).
"""

from __future__ import annotations

import numpy as np

from .store import SweepTable, read_table
from .tasks import _point_value, get_task

__all__ = ["merge_device"]


def merge_device(table) -> list:
    """The realisations of a ``device`` sweep merged per device (all parameters but ``seed``).

    Parameters
    ----------
    table : SweepTable, str or path-like
        A sweep's table (:func:`~hyperlattice.sweep.read_table`) or its directory.

    Returns
    -------
    list of DeviceEnsemble
        One per device, in the order of their first rows: mean and spread of ``|S₂₁|²`` and of the
        levels (resonance positions) over the seeds.

    Raises
    ------
    ValueError
        If the table is not a ``device`` sweep.

    Examples
    --------
    >>> import os, tempfile
    >>> from hyperlattice.sweep import run_sweep
    >>> from hyperlattice.sweep.device import merge_device
    >>> where = os.path.join(tempfile.mkdtemp(), "ens")
    >>> grid = {"rings": 2, "ports": "0-1:0.1,30-31:0.1", "sigma_omega": 0.05, "seed": [1, 2, 3], "points": 50}
    >>> _ = run_sweep("device", grid, where, scheduler="serial", progress=False)
    >>> [(e.realizations, e.seeds, e.omega.size) for e in merge_device(where)]
    [(3, (1, 2, 3), 50)]
    """
    from ..device import ensemble_statistics

    if not isinstance(table, SweepTable):
        table = read_table(table)
    if table.metadata.get("task") != "device":
        raise ValueError(f"merge_device reads a device sweep, not a {table.metadata.get('task')!r} sweep.")
    point_keys = [k for k in get_task("device").defaults if k != "seed"]
    groups: dict = {}
    for row in table.rows():
        key = tuple(_point_value(row[k]) for k in point_keys)
        groups.setdefault(key, []).append(row)
    out = []
    for rows in groups.values():
        rows = sorted(rows, key=lambda r: int(r["seed"]))
        params = {k: rows[0][k] for k in point_keys}
        out.append(ensemble_statistics(np.asarray(rows[0]["omega"], float),
                                       [np.asarray(r["s21_abs2"], float) for r in rows],
                                       [np.asarray(r["levels"], float) for r in rows],
                                       seeds=tuple(int(r["seed"]) for r in rows), parameters=params))
    return out


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
