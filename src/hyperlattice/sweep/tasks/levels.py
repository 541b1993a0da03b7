"""The ``levels`` task: the lowest levels of a flake with flux."""

from __future__ import annotations

import math

import numpy as np

from ... import _validate
from ._common import _check_geometry, _lattice

def _levels(p: int = 7, q: int = 3, rings: int = 4, line_graph: bool = False, flux: float = 0.0,
            levels: int = 2) -> dict:
    from ...graph.spectrum import lowest_levels

    spec = lowest_levels(_lattice(p, q, rings, line_graph), levels, flux=flux)
    e = np.asarray(spec.energies, float)
    return {"E": e, "E0": float(e[0]), "E1": float(e[1]) if e.size > 1 else math.nan, "method": spec.method}


def _check_levels(params: dict) -> None:
    _check_geometry(params, 5_000_000)
    _validate.real("flux", params["flux"])
    _validate.positive_int("levels", params["levels"], maximum=1000)
