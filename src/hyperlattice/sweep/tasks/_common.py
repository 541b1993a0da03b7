"""What the sweep tasks share: the built flakes (cached per process), the geometry check, the systems of the
Monte Carlo tasks and the separator of a chain's notes."""

from __future__ import annotations

import functools

from ... import _validate

@functools.lru_cache(maxsize=8)
def _lattice(p: int, q: int, rings: int, line: bool):
    from ...graph.lattice import line_graph, ring_lattice

    lat = ring_lattice(p, q, rings)
    return line_graph(lat) if line else lat


def _sites(p, q, rings, line) -> int:
    from ...graph.lattice import edge_count, site_count

    return edge_count(p, q, rings) if line else site_count(p, q, rings)


def _check_geometry(params: dict, dense_max: int) -> None:
    p, q = _validate.pq(params["p"], params["q"])
    rings = _validate.positive_int("rings", params["rings"], maximum=40)
    line = _validate.flag("line_graph", params["line_graph"])
    n = _sites(p, q, rings, line)
    if n > dense_max:
        raise ValueError(f"the {{{p},{q}}} {'line graph' if line else 'flake'} of {rings} rings has {n:,} sites; "
                         f"this task is a dense computation limited to {dense_max:,}.")


#: separates the notes of a chain in the ``notes`` column
_NOTES_SEP = " | "


def _qmc_system(p: int, q: int, rings: int, cluster):
    if cluster is None:
        return _lattice(p, q, rings, False)
    from ...graph.clusters import pbc_cluster

    return pbc_cluster(p, q, cluster)


def _point_value(v):
    """A hashable, exact stand-in of a parameter value (floats by repr)."""
    return repr(v) if isinstance(v, float) else v


def _check_chain_graph(params: dict) -> tuple[int, int]:
    """(p, q) of a Monte Carlo task's graph: a flake of ``rings`` or a known periodic ``cluster``."""
    p, q = _validate.pq(params["p"], params["q"])
    if params["cluster"] is None:
        _validate.positive_int("rings", params["rings"], maximum=40)
    else:
        from ...graph.clusters import pbc_cluster

        pbc_cluster(p, q, params["cluster"])        # refuses an unknown name in one sentence
    return p, q


def _check_chain_length(params: dict, couplings: tuple = (), positive_beta: bool = False) -> float | None:
    """A Monte Carlo task's real ``couplings``, its beta (> 0, returned) when ``positive_beta``, its sweeps,
    thermalisation sweeps and seed."""
    for name in couplings:
        _validate.real(name, params[name])
    beta = None
    if positive_beta:
        beta = _validate.real("beta", params["beta"])
        if not beta > 0:
            raise ValueError(f"beta must be positive, got {beta!r}.")
    _validate.positive_int("sweeps", params["sweeps"])
    if params["thermalization"] is not None:
        _validate.integer("thermalization", params["thermalization"], minimum=0)
    _validate.integer("seed", params["seed"], minimum=0)
    return beta


def _quietly(warning: type, chain, *args, **kwargs):
    """``chain(*args, **kwargs)`` with its warnings of class ``warning`` silenced: the row keeps what a
    warning says (``converged`` and ``notes``)."""
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", warning)
        return chain(*args, **kwargs)
