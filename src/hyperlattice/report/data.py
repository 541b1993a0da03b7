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
    """E0, E1, method, m labels and residuals of the ``rings``-ring {7,3} graph (cached).

    Parameters
    ----------
    cache : Cache
        The result cache; the :class:`~hyperlattice.graph.spectrum.Spectrum` is stored under
        ``"graph_levels"`` with the key ``{"p": 7, "q": 3, "rings": rings, "levels": 2}``.
    rings : int
        Number of rings l of the {7,3} flake.
    timings : dict
        Filled in place: ``timings["graph_levels_l<rings>"]`` is the solver's wall-clock time in
        seconds (of the run that computed the spectrum, also on a cache hit).

    Returns
    -------
    dict
        ``"E0"``, ``"E1"`` (the two lowest levels of H = -tA, t = 1), ``"method"`` (the solver that
        ran), ``"m"`` (their angular momenta) and ``"residuals"`` (one per level).

    See Also
    --------
    hyperlattice.graph.spectrum.lowest_levels : the computation.
    continuum_levels : the continuum side of the same table row.

    Examples
    --------
    >>> import tempfile
    >>> from hyperlattice.cache import Cache
    >>> from hyperlattice.report.data import graph_levels
    >>> timings = {}
    >>> with tempfile.TemporaryDirectory() as d:
    ...     row = graph_levels(Cache(d), 2, timings)
    >>> round(row["E0"], 6), round(row["E1"], 6), row["method"], row["m"]
    (-2.636405, -2.283335, 'sector-dense', [0, 1])
    >>> list(timings), max(row["residuals"]) < 1e-12
    (['graph_levels_l2'], True)
    """
    def compute():
        from ..graph.spectrum import lowest_levels

        return lowest_levels(ring_lattice(7, 3, rings), levels=2)

    # the cache stores the Spectrum itself (exact JSON round trip of the result protocol)
    spec = cache.get("graph_levels", {"p": 7, "q": 3, "rings": rings, "levels": 2}, compute)
    timings[f"graph_levels_l{rings}"] = float(spec.timings["total"])
    return {"E0": float(spec.energies[0]), "E1": float(spec.energies[1]), "method": spec.method,
            "m": [int(v) for v in spec.m], "residuals": [float(v) for v in spec.errors]}


def continuum_levels(rings: int) -> dict:
    r"""E0, E1 (``spec1``, ``spec2``), their k, the asymptotes (``spec11``, ``spec17``) and L.

    The continuum side of one row of ``SuppTab1`` for the {7,3} flake of ``rings`` rings, with the
    paper's dictionary (not cached: it takes milliseconds).

    Parameters
    ----------
    rings : int
        Number of rings l; the disk radius L is that of the l-ring flake.

    Returns
    -------
    dict
        ``"E0"``, ``"E1"`` (energies in units of t), ``"k0"``, ``"k1"`` (their k), ``"E0_asym"``,
        ``"E1_asym"`` (the large-disk asymptotes), ``"E_inf"`` (the band edge
        :math:`-q + \frac{q}{4}h^2`) and ``"radius"`` (L, Euclidean radius in the Poincaré disk).

    See Also
    --------
    hyperlattice.continuum.spectrum.continuum_levels, hyperlattice.continuum.spectrum.asymptotic_energies

    Examples
    --------
    >>> from hyperlattice.report.data import continuum_levels
    >>> row = continuum_levels(2)
    >>> {k: round(v, 6) for k, v in row.items()}
    {'E0': -2.570293, 'E1': -2.084519, 'k0': 2.555843, 'k1': 3.879106, 'E0_asym': -2.73753, 'E1_asym': -1.632855, 'E_inf': -2.942952, 'radius': 0.745356}
    """
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

    Parameters
    ----------
    cache : Cache
        The result cache (entry ``"green_compare"``, keyed by rings, omega and source).
    rings : int
        Number of rings l of the {7,3} flake.
    omega : float or complex
        Frequency ω of the Green function, in units of t.
    source : int
        Index of the source site j.
    comparison : GreenComparison, optional
        The result of :func:`~hyperlattice.compare.green.compare_green` for the same inputs, to reuse
        on a cache miss.

    Returns
    -------
    dict
        ``"rel_l2"`` (relative L2 distance of graph and continuum columns, source excluded),
        ``"terms"`` (number of m terms of the ``green36`` sum), ``"tail"`` (estimate of its truncated
        tail), and ``"collapse_graph"``, ``"collapse_continuum"`` (the collapse numbers of
        :func:`~hyperlattice.compare.correlation.collapse_measure` of the real parts of both columns
        against distance).

    Examples
    --------
    >>> import tempfile
    >>> from hyperlattice.cache import Cache
    >>> from hyperlattice.report.data import green_row
    >>> with tempfile.TemporaryDirectory() as d:
    ...     row = green_row(Cache(d), 2, -3.5, 0)
    >>> sorted(row)
    ['collapse_continuum', 'collapse_graph', 'rel_l2', 'tail', 'terms']
    >>> round(row["rel_l2"], 6)
    0.077178
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


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
