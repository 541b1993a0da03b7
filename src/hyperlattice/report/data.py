"""What the report needs from the package, fetched through the cache where it is expensive.

Each function calls the public API and returns plain JSON values (what the cache stores); the
physics lives in :mod:`hyperlattice.graph`, :mod:`hyperlattice.continuum` and
:mod:`hyperlattice.compare`.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from ..cache import Cache
from ..graph.lattice import ring_lattice

if TYPE_CHECKING:
    from ..compare.green import GreenComparison

__all__ = ["graph_levels", "continuum_levels", "green_row"]


def graph_levels(cache: Cache, rings: int, timings: dict) -> dict:
    """E0, E1, method, m labels and residuals of the ``rings``-ring {7,3} graph (cached)."""
    def compute():
        from ..graph.spectrum import lowest_levels

        return lowest_levels(ring_lattice(7, 3, rings), levels=2)

    # the cache stores the Spectrum itself (exact JSON round trip of the result protocol)
    spec = cache.get("graph_levels", {"p": 7, "q": 3, "rings": rings, "levels": 2}, compute)
    timings[f"graph_levels_l{rings}"] = float(spec.timings["total"])
    return {"E0": float(spec.energies[0]), "E1": float(spec.energies[1]), "method": spec.method,
            "m": [int(v) for v in spec.m], "residuals": [float(v) for v in spec.errors]}


def continuum_levels(rings: int) -> dict:
    """E0, E1 (``spec1``, ``spec2``), their k, the asymptotes (``spec11``, ``spec17``) and L."""
    from ..continuum.spectrum import asymptotic_energies, continuum_levels as levels

    spec = levels(7, 3, rings=rings, levels=2)
    asym = asymptotic_energies(7, 3, rings=rings)
    return {"E0": float(spec.energies[0]), "E1": float(spec.energies[1]), "k0": float(spec.k[0]),
            "k1": float(spec.k[1]), "E0_asym": asym["E0"], "E1_asym": asym["E1"], "E_inf": asym["E_inf"],
            "radius": spec.radius}


def green_row(cache: Cache, rings: int, omega, source: int, comparison: GreenComparison | None = None) -> dict:
    """rel_l2, m terms, tail estimate and collapse numbers of the ``eq21`` comparison (cached).

    ``comparison``, when given, is the already computed comparison for these inputs (the
    figure's); it is used instead of computing it again on a cache miss.
    """
    def compute() -> dict:
        from ..compare.green import compare_green

        cmp = comparison if comparison is not None else compare_green(ring_lattice(7, 3, rings), omega, source)
        collapse_graph, collapse_continuum = cmp.collapse()
        return {"rel_l2": cmp.rel_l2, "terms": cmp.terms, "tail": cmp.tail_estimate,
                "collapse_graph": collapse_graph, "collapse_continuum": collapse_continuum}

    key = {"rings": rings, "omega": [omega.real, omega.imag] if isinstance(omega, complex) else omega,
           "source": source}
    return cache.get("green_compare", key, compute)


# every public function above checks its annotated argument types at the door (issue 19)
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
