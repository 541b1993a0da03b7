r"""Graph vs continuum Green functions through the dictionary ``eq21``, and the distance collapse.

The graph side is :mod:`hyperlattice.graph.green`, the continuum side
:mod:`hyperlattice.continuum.green`, the maps between them :mod:`hyperlattice.dictionary`.

Dictionary (``eq21``, generalised to {p,q})
-------------------------------------------
Following ``path5``/``path6``: write :math:`G_{ij}` as the Gaussian integral
:math:`\langle\theta_i\theta_j\rangle` with weight
:math:`\exp[-\frac12\sum_{ij}\theta_i(H-\omega)_{ij}\theta_j]`. For a {p,q} lattice the
small-h expansion of the adjacency operator is :math:`A \approx q + \frac q4 h^2\Delta_g`
(``adj26`` with 3 replaced by q: the q neighbours sit at :math:`h e^{\mathrm i(\chi+2\pi k/q)}`,
whose first and second moments vanish), so
:math:`H - \omega \approx -\frac q4 h^2\Delta_g - (\omega + q) = \frac q4 h^2(-\Delta_g - \lambda)`
with :math:`\lambda = 4(\omega+q)/(qh^2)`. With :math:`\sum_i \approx \frac1{\mathcal A}\int dV`
(``eq11``, :math:`\mathcal A` the area per site, :func:`hyperlattice.geometry.site_area`) the
exponent becomes :math:`-\frac12 C'\int dV\,\theta(-\Delta_g-\lambda)\theta` with
:math:`C' = qh^2/(4\mathcal A)`, and by ``path2`` the two-point function is :math:`G/C'`:

.. math:: G_{ij}(\omega) \approx \frac{4\mathcal A}{q h^2}\,
          G\Bigl(z_i, z_j, \lambda = \frac{4(\omega+q)}{qh^2}, L\Bigr),

with :math:`L` from ``eq12``. For {7,3}, :math:`\mathcal A = \pi/28` gives :math:`\pi/(21h^2)`.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from .. import _validate
from ..dictionary import dictionary_parameters
from ..geometry import distance
from ..graph.green import GraphResolvent
from ..graph.lattice import Lattice
from ..results import Column, Result

if TYPE_CHECKING:
    from ..continuum.green import GreenInfo

__all__ = [
    "continuum_column",
    "compare_green",
    "GreenComparison",
    "relative_l2",
]


# ----------------------------------------------------------------------------
# graph vs continuum, ``eq21``
# ----------------------------------------------------------------------------

def continuum_column(lattice: Lattice, omega, source: int, *, tol: float = 1e-12) -> tuple[np.ndarray, GreenInfo]:
    r"""Right-hand side of ``eq21`` at every site i for source j: :math:`\frac{4\mathcal A}{qh^2}G(z_i,z_j,\lambda,L)`.

    Uses :math:`L` of ``eq12`` (``lattice.radius``); sites beyond :math:`L` get the analytic
    continuation of ``green33`` (``extend=True``). The source entry is ``inf`` (coincident
    points).

    Parameters
    ----------
    lattice : Lattice
        A {p,q} site lattice (``ring_lattice``; not a line graph).
    omega : complex
        Lattice frequency (units of t); mapped to :math:`\lambda = 4(\omega+q)/(qh^2)`.
    source : int
        Source site j (0-based).
    tol : float, optional
        Relative tolerance of the continuum series (``continuum_green``). Default 1e-12.

    Returns
    -------
    values : ndarray of complex, shape (N,)
        :math:`\frac{4\mathcal A}{qh^2}G(z_i,z_j,\lambda,L)` for every site i (units of 1/t);
        ``inf`` at the source.
    info : hyperlattice.continuum.green.GreenInfo
        How the continuum Green function was evaluated (method, ``terms``, ``tail_estimate``).

    Raises
    ------
    ValueError
        For a line-graph lattice, a source out of range or a non-finite omega.

    See Also
    --------
    compare_green : the same column against the graph Green function.
    hyperlattice.continuum.green.continuum_green : the continuum Green function.

    References
    ----------
    .. [1] I. Boettcher et al., Phys. Rev. A 102, 032208 (2020), Eq. (19) (source label
       ``eq21``), here for general {p,q} (module docstring).

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.compare.green import continuum_column
    >>> lat = hl.ring_lattice(7, 3, 3)
    >>> values, info = continuum_column(lat, -3.5, 0)
    >>> values.shape, float(values[0].real)
    ((112,), inf)
    >>> print(f"{values[1].real:.6f}")
    0.148490
    """
    from ..continuum.green import continuum_green

    _validate.lattice(lattice, kind="sites")
    source = _validate.site_index("source", source, lattice.sites)
    omega = _validate.complex_number("omega", omega)
    lam, pref = dictionary_parameters(omega, lattice.p, lattice.q)
    vals, info = continuum_green(lattice.z, lattice.z[source], lam, lattice.radius, tol=tol,
                                 extend=True, return_info=True)
    vals = np.asarray(vals, complex)
    out = np.empty_like(vals)
    out.real = pref * vals.real            # part-wise: keeps inf + 0j at the source
    out.imag = pref * vals.imag
    return out, info


def relative_l2(graph, continuum, exclude: int | None = None) -> float:
    r""":math:`\|G^{\rm graph} - G^{\rm cont}\|_2 / \|G^{\rm graph}\|_2` over all sites but ``exclude``.

    Parameters
    ----------
    graph, continuum : array of complex, shape (N,)
        The two columns; ``continuum`` may be infinite at ``exclude`` (the source, where the
        continuum Green function diverges) and must be finite elsewhere.
    exclude : int, optional
        A site left out of both norms (0-based). Default None: all sites.

    Returns
    -------
    float
        The relative L2 distance (dimensionless).

    Raises
    ------
    ValueError
        For arrays of different shapes, non-finite entries outside ``exclude``, or a graph
        column that vanishes (the relative distance is undefined).

    Examples
    --------
    >>> from hyperlattice.compare.green import relative_l2
    >>> round(relative_l2([1, 2, 3], [float("inf"), 2, 3.5], exclude=0), 6)
    0.138675
    """
    g = _validate.complex_array("graph", graph, ndim=1)
    keep = np.ones(g.shape, bool)
    if exclude is not None:
        keep[_validate.site_index("exclude", exclude, g.size)] = False
    try:
        c = np.asarray(continuum, dtype=complex)
    except (TypeError, ValueError, OverflowError):
        raise ValueError("continuum must be an array of (complex) numbers.") from None
    if c.shape != g.shape:
        raise ValueError(f"graph and continuum must have the same shape, got {g.shape} and {c.shape}.")
    _validate.complex_array("continuum (outside the excluded site)", c[keep])
    den = np.linalg.norm(g[keep])
    if den == 0:
        raise ValueError("the graph column vanishes on the compared sites; the relative distance is undefined.")
    return float(np.linalg.norm(g[keep] - c[keep]) / den)


@dataclass(frozen=True, eq=False, kw_only=True)
class GreenComparison(Result):
    r"""Graph column and continuum prediction (``eq21``) for one source and one omega.

    Attributes
    ----------
    p, q, rings : int
        The lattice.
    source : int
        Source site j (0-based).
    omega : complex
        Lattice frequency, in units of t (:math:`H = -tA`, t = 1; G in units of 1/t).
    lam : complex
        :math:`\lambda = 4(\omega+q)/(qh^2)` (``eq21``).
    radius : float
        Euclidean disk radius L in the paper's Poincaré disk (``eq12``).
    prefactor : float
        :math:`4\mathcal A/(qh^2)` (``eq21``).
    graph : ndarray of complex, shape (N,)
        :math:`G_{ij}(\omega)` for all i (``eq20``).
    continuum : ndarray of complex, shape (N,)
        Right-hand side of ``eq21`` for all i; infinite at the source.
    distance : ndarray, shape (N,)
        Hyperbolic distance :math:`d(z_i, z_j)` (``eq4``).
    rel_l2 : float
        :func:`relative_l2` over all sites but the source.
    terms : int
        Number of m terms of the ``green36`` sum.
    tail_estimate : float
        Estimate of the truncated tail of that sum.

    Examples
    --------
    >>> import hyperlattice as hl
    >>> cmp = hl.compare_green(hl.ring_lattice(7, 3, 3), -3.5, 0)
    >>> cmp.graph.shape, f"{cmp.rel_l2:.4f} {cmp.lam.real:.4f} {cmp.prefactor:.4f}"
    ((112,), '0.0706 -8.7645 1.9667')
    >>> [round(x, 4) for x in cmp.collapse()]
    [0.1727, 0.1235]
    """

    #: one row per target site i
    COLUMNS = (Column("distance", "distance", "hyperbolic distance"), Column("graph", "graph", "1/t"),
               Column("continuum", "continuum", "1/t"))

    p: int
    q: int
    rings: int
    source: int
    omega: complex
    lam: complex
    radius: float
    prefactor: float
    graph: np.ndarray = field(repr=False)
    continuum: np.ndarray = field(repr=False)
    distance: np.ndarray = field(repr=False)
    rel_l2: float
    terms: int
    tail_estimate: float

    def summary(self) -> dict:
        """The JSON summary of the ``green`` command: p, q, rings, site, omega, lambda, radius, rel_l2."""
        return {"p": self.p, "q": self.q, "rings": self.rings, "site": self.source,
                "omega": self.omega, "lambda": self.lam, "radius": self.radius,
                "rel_l2": self.rel_l2}

    def collapse(self, width: float | None = None) -> tuple[float, float]:
        """Collapse numbers (:func:`hyperlattice.compare.correlation.collapse_measure`) of the real
        parts of the graph and the continuum column, source excluded: ``(graph, continuum)``.

        Parameters
        ----------
        width : float, optional
            Bin width in the paper's metric (default: that of
            :func:`~hyperlattice.compare.correlation.collapse_measure`).

        Returns
        -------
        graph, continuum : float
            The two collapse numbers.
        """
        from .correlation import collapse_measure

        keep = np.arange(self.graph.shape[0]) != self.source
        return (collapse_measure(self.distance[keep], self.graph[keep].real, width=width),
                collapse_measure(self.distance[keep], self.continuum[keep].real, width=width))


def _same_bonds(H, lattice: Lattice) -> bool:
    """Whether the off-diagonal pattern of ``H`` is the edge set of ``lattice``."""
    n = lattice.sites
    coo = H.tocoo()
    upper = (coo.row < coo.col) & (coo.data != 0)
    have = np.sort(coo.row[upper].astype(np.int64) * n + coo.col[upper])
    e = np.sort(np.asarray(lattice.edges, dtype=np.int64), axis=1)
    want = np.sort(e[:, 0] * n + e[:, 1])
    return have.shape == want.shape and bool(np.array_equal(have, want))


def compare_green(lattice: Lattice, omega, source: int, *, tol: float = 1e-12,
                  resolvent: GraphResolvent | None = None) -> GreenComparison:
    r"""Graph column :math:`G_{\cdot j}(\omega)` against the generalised ``eq21``.

    .. math:: G_{ij}(\omega) \approx \frac{4\mathcal A}{q h^2}\,
              G\Bigl(z_i, z_j, \lambda = \frac{4(\omega+q)}{qh^2}, L\Bigr)

    ``rel_l2`` is the relative L2 distance over all sites except the source.

    Parameters
    ----------
    lattice : Lattice
        A {p,q} site lattice (``ring_lattice``; not a line graph).
    omega : complex
        Lattice frequency (units of t); off the spectrum (give it an imaginary part inside the
        band).
    source : int
        Source site j (0-based; ring 1 first, each ring counterclockwise).
    tol : float, optional
        Relative tolerance of the continuum series. Default 1e-12.
    resolvent : GraphResolvent, optional
        Reuse a factorization of :math:`H - \omega` (several sources at one omega).

    Returns
    -------
    GreenComparison
        ``graph`` (:math:`G_{ij}(\omega)`, ``eq20``) and ``continuum`` (right-hand side of
        ``eq21``, infinite at the source) columns, the hyperbolic ``distance`` to the source,
        ``lam``, ``prefactor``, ``radius`` L and ``rel_l2``.

    Raises
    ------
    ValueError
        For a line-graph lattice, a source out of range or a non-finite omega.

    See Also
    --------
    continuum_column : the continuum side alone.
    relative_l2 : the distance used for ``rel_l2``.

    References
    ----------
    .. [1] I. Boettcher et al., Phys. Rev. A 102, 032208 (2020): the graph Green function
       (label ``eq20``) and its continuum approximation Eq. (19) (label ``eq21``), here for
       general {p,q} (module docstring).

    Examples
    --------
    >>> import hyperlattice as hl
    >>> lat = hl.ring_lattice(7, 3, 3)
    >>> cmp = hl.compare_green(lat, -3.5, 0)
    >>> print(f"{cmp.rel_l2:.4f} {cmp.lam.real:.4f} {cmp.prefactor:.4f}")
    0.0706 -8.7645 1.9667
    """
    _validate.lattice(lattice, kind="sites")
    source = _validate.site_index("source", source, lattice.sites)
    omega = _validate.complex_number("omega", omega)
    if resolvent is None:
        res = GraphResolvent(lattice)
    elif not isinstance(resolvent, GraphResolvent):
        raise ValueError(f"resolvent must be a GraphResolvent of this lattice (or None), got {type(resolvent).__name__}.")
    elif resolvent.n != lattice.sites or not _same_bonds(resolvent.H, lattice):
        raise ValueError(f"resolvent belongs to another lattice ({resolvent.n} sites; this one has {lattice.sites}); "
                         "make it with GraphResolvent(lattice).")
    else:
        res = resolvent
    g = res.column(omega, source)
    c, info = continuum_column(lattice, omega, source, tol=tol)
    lam, pref = dictionary_parameters(omega, lattice.p, lattice.q)
    d = distance(lattice.z, lattice.z[source])
    return GreenComparison(p=lattice.p, q=lattice.q, rings=lattice.rings, source=source, omega=omega,
                           lam=lam, radius=lattice.radius, prefactor=pref, graph=g, continuum=c,
                           distance=d, rel_l2=relative_l2(g, c, exclude=source), terms=info.terms,
                           tail_estimate=info.tail_estimate)


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
