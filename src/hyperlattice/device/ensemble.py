"""Ensembles of fabricated devices: mean and spread of ``|S₂₁|²`` and of the resonance positions.

The realisations run as a sweep (the ``device`` task of :mod:`hyperlattice.sweep.tasks`, a grid
over ``seed``, on Dask when worth it); :func:`hyperlattice.sweep.device.merge_device` reads the
table back into a :class:`DeviceEnsemble`. :func:`ensemble_statistics` is the arithmetic, here so
that it is one function whatever ran the realisations.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from .. import _validate
from ..results import Column, Result

__all__ = ["DeviceEnsemble", "ensemble_statistics"]


@dataclass(frozen=True, eq=False, kw_only=True)
class DeviceEnsemble(Result):
    r"""Mean and spread of ``|S₂₁|²`` over fabricated devices, and of each resonance position.

    Attributes
    ----------
    omega : ndarray
        Frequencies (the user's units).
    mean : ndarray
        Mean ``|S₂₁|²`` over the realisations.
    spread : ndarray
        Standard deviation of ``|S₂₁|²`` over the realisations (ddof = 1; 0 for one realisation).
    level_mean : ndarray
        Mean of the k-th lowest level of H over the realisations.
    level_spread : ndarray
        Its standard deviation (ddof = 1).
    realizations : int
        Number of devices.
    seeds : tuple of int
        Their seeds.
    parameters : dict
        The device parameters shared by the realisations.

    Examples
    --------
    >>> import numpy as np
    >>> from hyperlattice.device import ensemble_statistics
    >>> ens = ensemble_statistics(np.array([0.0, 1.0]), [np.array([0.1, 0.2]), np.array([0.3, 0.2])],
    ...                           [np.array([-1.0, 1.0]), np.array([-1.2, 1.0])], seeds=(1, 2))
    >>> [round(float(x), 3) for x in ens.mean], [round(float(x), 3) for x in ens.level_spread]
    ([0.2, 0.2], [0.141, 0.0])
    """

    COLUMNS: ClassVar[tuple] = (Column("omega", "omega", "user's frequency unit"), Column("mean", "mean", "1"),
                                Column("spread", "spread", "1"))

    omega: np.ndarray
    mean: np.ndarray
    spread: np.ndarray
    level_mean: np.ndarray
    level_spread: np.ndarray
    realizations: int
    seeds: tuple = ()
    parameters: dict | None = None


def ensemble_statistics(omega, powers, levels, *, seeds=(), parameters: dict | None = None) -> DeviceEnsemble:
    """Mean and spread of ``|S₂₁|²`` and of the sorted levels over realisations.

    Parameters
    ----------
    omega : array_like
        The common frequency grid.
    powers : sequence of array_like
        ``|S₂₁|²`` of each realisation on ``omega``.
    levels : sequence of array_like
        The levels of each realisation (sorted here), all of one length.
    seeds : sequence of int, optional
        The realisations' seeds.
    parameters : dict, optional
        The shared device parameters.

    Returns
    -------
    DeviceEnsemble

    Examples
    --------
    >>> import numpy as np
    >>> from hyperlattice.device import ensemble_statistics
    >>> ensemble_statistics([0.0], [[0.5]], [[1.0]]).realizations
    1
    """
    w = _validate.real_array("omega", omega, ndim=1)
    if not isinstance(powers, (list, tuple)) or not isinstance(levels, (list, tuple)) or not powers:
        raise ValueError("powers and levels must be non-empty lists, one entry per realisation.")
    if len(powers) != len(levels):
        raise ValueError(f"{len(powers)} traces but {len(levels)} level lists; give one of each per realisation.")
    p = np.asarray([_validate.real_array("powers", x, ndim=1) for x in powers])
    if p.ndim != 2 or p.shape[1] != w.size:
        raise ValueError(f"every trace must have the {w.size} points of omega.")
    lv = [np.sort(_validate.real_array("levels", x, ndim=1)) for x in levels]
    if len({x.size for x in lv}) != 1:
        raise ValueError("every realisation must have the same number of levels.")
    lv = np.asarray(lv)
    r = p.shape[0]
    ddof = 1 if r > 1 else 0
    return DeviceEnsemble(omega=w, mean=p.mean(axis=0), spread=p.std(axis=0, ddof=ddof), level_mean=lv.mean(axis=0),
                          level_spread=lv.std(axis=0, ddof=ddof), realizations=int(r),
                          seeds=tuple(int(s) for s in seeds), parameters=dict(parameters or {}))


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
