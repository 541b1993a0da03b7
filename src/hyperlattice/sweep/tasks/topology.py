"""The ``topology`` and ``conductance`` tasks: one disorder realization of the local Chern marker at a
flake's centre, or of the two-terminal conductance through two arcs of its edge."""

from __future__ import annotations

from ... import _validate
from ._common import _check_geometry, _lattice

def _topology(p: int = 8, q: int = 3, rings: int = 4, model: str = "qwz", M: float = 1.0, t2: float = 0.2,
              phi: float = 1.5707963267948966, W: float = 0.0, seed: int = 0, moments: int = 256) -> dict:
    import warnings

    from ...errors import ConvergenceWarning
    from ...topology.kpm_marker import centre_marker

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ConvergenceWarning)   # the row carries marker_error instead
        r = centre_marker(_lattice(p, q, rings, False), model, M=M, t2=t2, phi=phi, disorder=W, seed=seed,
                          moments=moments)
    return {"marker": r.marker, "marker_error": r.marker_error, "kitaev": r.kitaev, "gap": r.gap}


def _check_topology(params: dict) -> None:
    _check_geometry(dict(params, line_graph=False), 200_000)
    _validate.choice("model", params["model"], ("qwz", "haldane"))
    for name in ("M", "t2", "phi"):
        _validate.real(name, params[name], minimum=-1e6, maximum=1e6)
    _validate.real("W", params["W"], minimum=0.0, maximum=1e6)
    _validate.integer("seed", params["seed"], minimum=0, maximum=2**63 - 1)
    _validate.integer("moments", params["moments"], minimum=16, maximum=100_000)


#: the conductance task's largest flake (sites): the sparse LU of the {8,3} l = 7 flake (40,328 sites) fits
CONDUCTANCE_SITES_MAX = 100_000


def _conductance(p: int = 8, q: int = 3, rings: int = 4, model: str = "qwz", M: float = 1.0, t2: float = 0.2,
                 phi: float = 1.5707963267948966, W: float = 0.0, seed: int = 0, energy: float = 0.0,
                 coupling: float = 2.0, arc: float = 0.25) -> dict:
    import warnings

    from ...errors import ConvergenceWarning
    from ...topology.transport import conductance

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ConvergenceWarning)   # the row carries the solve's error instead
        g = conductance(_lattice(p, q, rings, False), model, energies=[energy], M=M, t2=t2, phi=phi, disorder=W,
                        seed=seed, coupling=coupling, arc=arc)
    return {"conductance": float(g.conductance[0]), "error": float(g.error[0])}


def _check_conductance(params: dict) -> None:
    _check_geometry(dict(params, line_graph=False), CONDUCTANCE_SITES_MAX)
    _validate.choice("model", params["model"], ("qwz", "haldane", "kane-mele"))
    for name in ("M", "t2", "phi", "energy"):
        _validate.real(name, params[name], minimum=-1e6, maximum=1e6)
    _validate.real("W", params["W"], minimum=0.0, maximum=1e6)
    _validate.integer("seed", params["seed"], minimum=0, maximum=2**63 - 1)
    _validate.real("coupling", params["coupling"], minimum=1e-12, maximum=1e12)
    arc = _validate.real("arc", params["arc"], minimum=1e-6, maximum=0.5)
    if arc >= 0.5:
        raise ValueError("arc must be below one half: the two contacts would overlap.")
