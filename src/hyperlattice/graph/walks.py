r"""Exact closed-walk counts of the infinite {p,q} lattice, and what they prove.

:math:`W_n = \langle o|A^n|o\rangle`, the number of closed walks of length n from a site o, are the
moments of the local density of states of :math:`A` (and, by vertex-transitivity, of the DOS per
site of the infinite lattice). They are counted *exactly* (integers) on a finite flake.

The depth limit (proof)
-----------------------
A flake of R rings (:func:`~hyperlattice.graph.lattice.ring_lattice`) is the subgraph of the
infinite lattice *induced* on its rings 1..R: ring k+1 only adds edges from ring k to ring k+1 and
edges inside ring k+1, never an edge between two sites of rings :math:`\le k`. Every edge changes the
ring index by at most one. A closed walk of length n from o visits only sites at graph distance
:math:`\le \lfloor n/2\rfloor` from o (it must come back), hence only rings :math:`\le r + \lfloor n/2\rfloor`
for o on ring r. So if :math:`r + \lfloor n/2\rfloor \le R`, every closed walk of the infinite lattice
lies in the flake, and every walk of the flake is one of the lattice: the counts agree for

.. math:: n \le 2(R - r) + 1 \qquad(:func:`exact_depth`).

A sharper limit, proven the same way: a walk that leaves the flake must first reach a *deficient*
site (degree < q, i.e. one with a neighbour outside) at graph distance :math:`d_b` from o, step out,
and come back, so its length is at least :math:`2(d_b + 1)`. The counts therefore agree for

.. math:: n \le 2 d_b(o) + 1 \qquad(:func:`exact_depths`, a breadth-first search),

which for the ring-1 site of a {7,3} flake is :math:`4R - 3` instead of :math:`2R - 1` (measured:
R = 2, 3 give 5 and 9, and the next length already differs). :func:`closed_walks` uses it, so
{7,3} walks up to length 49 come from a 13-ring flake.

We count from site 0 with :math:`v_k = A^k e_o` and
:math:`W_{2k} = \langle v_k, v_k\rangle`, :math:`W_{2k+1} = \langle v_k, v_{k+1}\rangle`, in int64 when
:math:`q^{n_{\max}} < 2^{63}` (no entry or sum can then overflow: :math:`W_n \le q^n`), else in Python
integers (exact, slower).

Rigorous bounds on the spectral radius :math:`\rho = \|A\|`
------------------------------------------------------------
The band bottom of :math:`H = -A` on the infinite lattice is :math:`-\rho`.

* Lower: the spectral measure :math:`\mu_o` of :math:`A` at o has :math:`W_n` as moments and its support
  is the whole spectrum (vertex-transitivity); A is non-negative, so :math:`\|A\| = \sup\mathrm{spec}A`.
  Hence :math:`W_{2n}^{1/2n} \le \rho` and :math:`W_{2n}/W_{2n-2} \le \rho^2` for every n; the ratios
  increase with n (Cauchy–Schwarz: :math:`W_{2n}^2 \le W_{2n-2}W_{2n+2}`) and tend to :math:`\rho^2`.
  Also :math:`\rho \ge 2\sqrt{q-1}`: the q-regular tree covers the lattice, every closed walk of the
  tree projects onto a closed walk of the lattice, so :math:`W_n \ge W_n^{\rm tree}` for all n.
* Upper (cited, not proved here): Mohar's Cheeger-type inequality for graphs of degree q,
  :math:`\rho \le \sqrt{q^2 - i_E^2}` (B. Mohar, Linear Algebra Appl. 103, 119 (1988)), with the exact
  edge-isoperimetric constant of the {p,q} tiling
  :math:`i_E = (q-2)\sqrt{1 - 4/((p-2)(q-2))}` (Häggström, Jonasson, Lyons, Ann. Probab. 30, 443
  (2002)). As p → ∞ it gives :math:`2\sqrt{q-1}`, the q-regular tree's exact value. Also
  :math:`\rho < q` (Kesten: the lattice is non-amenable).
* No estimate is extrapolated from the walks: the corrected ratios
  :math:`(W_{2n}/W_{2n-2})(n/(n-1))^{3/2}` (the :math:`n^{-3/2}` law of Gouëzel, J. Amer. Math. Soc. 27,
  893 (2014)) are not yet monotone at the lengths a flake allows (n <= 25 for {7,3}: the heptagons
  enter at n = 7), and fits of them scattered beyond the proven interval. The band-bottom *estimate*
  comes from the densities of states (:mod:`hyperlattice.compare.dos`).

Use as a check of the KPM routes: :func:`chebyshev_from_walks` turns :math:`W_n` into the Chebyshev
moments of :math:`T_n(-A/a)` exactly (rational arithmetic), to compare with
:func:`hyperlattice.graph.kpm.local_dos`, :func:`~hyperlattice.graph.kpm.bulk_dos` and the
trace over a periodic cluster (below its systole).
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass
from fractions import Fraction

import numpy as np

from .. import _validate
from ..results import Result

__all__ = ["closed_walks", "exact_depth", "exact_depths", "boundary_distance", "rings_for_walks", "chebyshev_from_walks", "spectral_radius_bounds",
           "SpectralRadius", "spectral_radius", "isoperimetric_upper_bound"]

_INT64_MAX = 2**63 - 1
#: most walk lengths accepted (the flake's size is the practical limit)
MAX_LENGTH = 200


def exact_depth(rings: int, ring: int) -> int:
    r"""Largest n for which closed-walk counts on ring ``ring`` of an R-ring flake are exact.

    Exact means equal to the infinite lattice's count from a site on that ring. The bound is :math:`2(R - r) + 1`: a closed walk of length n reaches at most
    :math:`\lfloor n/2 \rfloor` rings outwards (see the module docstring for the proof).

    Parameters
    ----------
    rings : int
        Number of rings R >= 1 of the flake.
    ring : int
        The site's ring r, 1 <= r <= R.

    Returns
    -------
    int
        :math:`2(R - r) + 1`.

    Raises
    ------
    ValueError
        If ``rings`` or ``ring`` is out of range.

    See Also
    --------
    exact_depths, boundary_distance

    Examples
    --------
    >>> from hyperlattice.graph.walks import exact_depth
    >>> exact_depth(4, 2)
    5
    """
    rings = _validate.positive_int("rings", rings)
    ring = _validate.integer("ring", ring, minimum=1, maximum=rings)
    return 2 * (rings - ring) + 1


def boundary_distance(lattice, *, site: int | None = None) -> np.ndarray | int:
    """Graph distance of every site of a flake to the nearest deficient site.

    A deficient site has a degree below the lattice's coordination, i.e. a neighbour outside
    the flake. With ``site``: that one site's distance only (a search from it that stops at the
    first deficient site).

    Parameters
    ----------
    lattice : Lattice
        A flake or line graph.
    site : int, optional
        One site (0-based); default None: all sites.

    Returns
    -------
    numpy.ndarray of int64, shape (N,), or int
        The distances in edges, -1 where no deficient site is reachable; an int with ``site``.

    Raises
    ------
    ValueError
        For an invalid lattice or site index.

    See Also
    --------
    exact_depths, hyperlattice.graph.kpm.bulk_dos

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.graph.walks import boundary_distance
    >>> lat = hl.ring_lattice(7, 3, 3)
    >>> boundary_distance(lat)[[0, 7, 40]].tolist(), boundary_distance(lat, site=0)
    ([4, 3, 1], 4)
    """
    _validate.lattice(lattice)
    indptr, indices = lattice.neighbours()
    deficient = np.diff(indptr) < lattice.coordination
    if site is not None:
        site = _validate.site_index("site", site, lattice.sites)
        # written out: it stops at the first deficient site, so it costs the ball around the
        # site, not the flake (csgraph's searches have no stop-at-target)
        seen = np.zeros(lattice.sites, dtype=bool)
        frontier = np.array([site])
        seen[site] = True
        d = 0
        while frontier.shape[0]:
            if np.any(deficient[frontier]):
                return d
            nb = _neighbours_of(indptr, indices, frontier)
            nb = nb[~seen[nb]]
            seen[nb] = True
            frontier = nb
            d += 1
        return -1
    sources = np.flatnonzero(deficient)
    if sources.size == 0:
        return np.full(lattice.sites, -1, dtype=np.int64)
    # a breadth-first search from all deficient sites at once (SciPy's csgraph; min_only keeps
    # the distance to the nearest source)
    from scipy.sparse import csgraph, csr_matrix

    graph = csr_matrix((np.ones(indices.shape[0], dtype=np.int8), indices, indptr),
                       shape=(lattice.sites, lattice.sites))
    d = csgraph.dijkstra(graph, directed=True, indices=sources, unweighted=True, min_only=True)
    return np.where(np.isfinite(d), d, -1).astype(np.int64)


def _neighbours_of(indptr, indices, sites) -> np.ndarray:
    """The distinct neighbours of ``sites`` (CSR), via a boolean mark instead of a sort."""
    starts, ends = indptr[sites], indptr[sites + 1]
    lens = ends - starts
    idx = np.repeat(starts - np.concatenate([[0], np.cumsum(lens)[:-1]]), lens) + np.arange(lens.sum())
    mark = np.zeros(indptr.shape[0] - 1, dtype=bool)
    mark[indices[idx]] = True
    return np.nonzero(mark)[0]


def exact_depths(lattice) -> np.ndarray:
    r"""Per site of a flake, the largest n with :math:`\langle i|A^n|i\rangle` equal to the infinite lattice's.

    The depth is :math:`2 d_b(i) + 1`, :math:`d_b` from :func:`boundary_distance` (proof in the
    module docstring); it is at least :func:`exact_depth` of the site's ring.

    Parameters
    ----------
    lattice : Lattice
        A flake of the {p,q} lattice itself (``kind == "sites"``).

    Returns
    -------
    numpy.ndarray of int64, shape (N,)
        The depth of every site (0-based site order).

    Raises
    ------
    ValueError
        If ``lattice`` is not a site lattice.

    See Also
    --------
    boundary_distance, exact_depth

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.graph.walks import exact_depths
    >>> exact_depths(hl.ring_lattice(7, 3, 3))[:8].tolist()
    [9, 9, 9, 9, 9, 9, 9, 7]
    """
    _validate.lattice(lattice, kind="sites")
    return 2 * boundary_distance(lattice) + 1


def rings_for_walks(p: int, q: int, n_max: int, *, max_sites: int | None = None) -> int:
    """Fewest rings of a {p,q} flake whose site 0 has exact closed walks up to length ``n_max``.

    Checked with :func:`exact_depths` on each flake built: 2, 3, ... rings.

    Parameters
    ----------
    p, q : int
        Hyperbolic Schläfli symbol.
    n_max : int
        Longest walk, 0 to 200.
    max_sites : int, optional
        Refuse flakes with more sites (default: what fits in memory).

    Returns
    -------
    int
        The number of rings.

    Raises
    ------
    ValueError
        For invalid input, or a flake above ``max_sites`` (or the available memory).

    See Also
    --------
    closed_walks

    Examples
    --------
    >>> from hyperlattice.graph.walks import rings_for_walks
    >>> rings_for_walks(7, 3, 8)
    3
    """
    p, q = _validate.pq(p, q)
    n_max = _validate.integer("n_max", n_max, minimum=0, maximum=MAX_LENGTH)
    return _flake_for(p, q, n_max, max_sites).rings


def _flake_for(p: int, q: int, n_max: int, max_sites):
    """The smallest flake (by rings) with ``exact_depths[0] >= n_max``."""
    from .lattice import ring_lattice

    rings = 1
    while True:
        rings += 1
        lat = ring_lattice(p, q, rings, max_sites=max_sites)
        if 2 * boundary_distance(lat, site=0) + 1 >= n_max:
            return lat


def _propagate(indptr: np.ndarray, indices: np.ndarray, v: np.ndarray) -> np.ndarray:
    """A v for a 0/1 adjacency in CSR (int64 or object entries)."""
    gathered = v[indices]
    out = np.add.reduceat(gathered, indptr[:-1]) if gathered.shape[0] else np.zeros_like(v)
    deg = np.diff(indptr)
    if np.any(deg == 0):  # reduceat repeats the next entry on empty rows
        out = np.where(deg == 0, 0, out)
    return out


@functools.lru_cache(maxsize=16)
def _walks_cached(p: int, q: int, n_max: int, max_sites: int | None) -> tuple:
    lat = _flake_for(p, q, n_max, max_sites)
    indptr, indices = lat.neighbours()
    indptr = np.asarray(indptr, np.int64)
    # entries of v_k = A^k e_o are at most q^k and the dots at most q^(2k+2): int64 arithmetic while
    # those bounds fit, exact Python integers for whatever would not (checked before each step)
    v = np.zeros(lat.sites, dtype=np.int64)
    v[0] = 1
    out = [0] * (n_max + 1)
    out[0] = 1
    k = 0
    while 2 * k + 1 <= n_max:
        if v.dtype != object and q ** (k + 1) > _INT64_MAX:
            v = v.astype(object)
        w = _propagate(indptr, indices, v)  # v_{k+1}
        small = w.dtype != object and q ** (2 * k + 2) <= _INT64_MAX
        out[2 * k + 1] = int(np.dot(v, w)) if small else _exact_dot(v, w)
        if 2 * k + 2 <= n_max:
            out[2 * k + 2] = int(np.dot(w, w)) if small else _exact_dot(w, w)
        v = w
        k += 1
    return tuple(out)


def _exact_dot(a: np.ndarray, b: np.ndarray) -> int:
    """Sum of a_i b_i without overflow, for non-negative integer vectors.

    int64 vectors are split into halves of ``s`` bits (each entry < 2**(2s)), so that every partial
    product is below 2**(2s) and every partial sum below 2**(2s) * N <= 2**62; the four int64 dots are
    combined in Python integers. Otherwise (object vectors, or too many bits) a Python-int loop.
    """
    if a.dtype == np.int64 and b.dtype == np.int64 and a.shape[0]:
        top = max(int(a.max()), int(b.max()), 1)
        bits = (top.bit_length() + 1) // 2
        if 2 * bits + a.shape[0].bit_length() <= 62:
            mask = (1 << bits) - 1
            ah, al, bh, bl = a >> bits, a & mask, b >> bits, b & mask
            return ((int(np.dot(ah, bh)) << (2 * bits)) + ((int(np.dot(ah, bl)) + int(np.dot(al, bh))) << bits)
                    + int(np.dot(al, bl)))
    nz = np.nonzero(a)[0]
    return sum(int(x) * int(y) for x, y in zip(a[nz].tolist(), b[nz].tolist()))


def closed_walks(p: int, q: int, n_max: int, *, max_sites: int | None = None) -> np.ndarray:
    r"""Exact numbers :math:`W_n`, n = 0..n_max, of closed walks of length n from a site of the infinite {p,q} lattice.

    :math:`W_n = \langle i|A^n|i\rangle` on the infinite lattice (every site is alike). Counted
    from site 0 of the smallest flake on which :func:`exact_depths` proves them exact (module
    docstring; 13 rings for {7,3} up to n = 49). Cached in-process.

    Parameters
    ----------
    p, q : int
        Hyperbolic Schläfli symbol.
    n_max : int
        Longest walk, 0 <= n_max <= 200 (in practice the flake's size limits it: {7,3} with
        n_max = 49 needs 13 rings, 1.9 million sites, about 3 s).
    max_sites : int, optional
        Refuse flakes with more sites (default: what fits in memory).

    Returns
    -------
    numpy.ndarray
        int64 when :math:`q^{n_{\max}} < 2^{63}` (then nothing can overflow), else an object array of
        Python ints; length n_max + 1.

    Raises
    ------
    ValueError
        For an invalid {p,q} or ``n_max``, or a flake above ``max_sites`` (or the available
        memory).

    See Also
    --------
    spectral_radius, chebyshev_from_walks, rings_for_walks

    Examples
    --------
    >>> from hyperlattice.graph.walks import closed_walks
    >>> closed_walks(7, 3, 8).tolist()
    [1, 0, 3, 0, 15, 0, 87, 6, 543]
    """
    p, q = _validate.pq(p, q)
    n_max = _validate.integer("n_max", n_max, minimum=0, maximum=MAX_LENGTH)
    if max_sites is not None:
        max_sites = _validate.positive_int("max_sites", max_sites)
    out = _walks_cached(p, q, n_max, max_sites)
    if q ** max(n_max, 1) <= _INT64_MAX:
        return np.array(out, dtype=np.int64)
    return np.array(out, dtype=object)


def _walk_list(walks) -> list[int]:
    """Closed-walk counts as Python ints (a non-empty sequence of non-negative integers)."""
    if isinstance(walks, (str, bytes)) or not hasattr(walks, "__len__"):
        raise ValueError("walks must be a sequence of closed-walk counts (non-negative integers).")
    out = []
    for x in list(walks):
        if isinstance(x, (bool, np.bool_)) or not isinstance(x, (int, np.integer)) or x < 0:
            raise ValueError("walks must be a sequence of closed-walk counts (non-negative integers).")
        out.append(int(x))
    if not out:
        raise ValueError("walks must hold at least W_0.")
    return out


def chebyshev_from_walks(walks, scale: float, *, sign: int = -1) -> np.ndarray:
    r"""Chebyshev moments :math:`\mu_n` of :math:`T_n(sA/a)` from exact closed-walk counts.

    :math:`\mu_n = \sum_k c_{nk}\,(s/a)^k W_k` for n <= len - 1, with :math:`c_{nk}` the
    coefficients of :math:`T_n`, computed exactly in rational arithmetic from the integer
    moments :math:`W_k` and rounded once to float64 at the end. ``scale`` a is the float used
    by KPM (taken as the exact rational it is), so the result is the exact value of what KPM
    computes in floating point.

    Parameters
    ----------
    walks : sequence of int
        Closed-walk counts :math:`W_0, W_1, \dots` (non-negative integers), e.g. from
        :func:`closed_walks`.
    scale : float
        The KPM scale a > 0 (:attr:`~hyperlattice.graph.kpm.KPMDos.scale`).
    sign : {-1, 1}, optional
        s = -1 (default) for :math:`H = -A`.

    Returns
    -------
    numpy.ndarray of float64, shape (len(walks),)
        The moments :math:`\mu_n`.

    Raises
    ------
    ValueError
        If ``walks`` is not a non-empty sequence of non-negative integers, ``scale`` is not
        positive, or ``sign`` is not -1 or 1.

    See Also
    --------
    closed_walks, hyperlattice.graph.kpm.kpm_dos

    Examples
    --------
    >>> from hyperlattice.graph.walks import chebyshev_from_walks, closed_walks
    >>> mu = chebyshev_from_walks(closed_walks(7, 3, 8), 3.0)
    >>> [round(m, 6) for m in mu[:5].tolist()]
    [1.0, 0.0, -0.333333, 0.0, -0.185185]
    """
    w = _walk_list(walks)
    a = _validate.positive_real("scale", scale)
    s = _validate.integer("sign", sign, minimum=-1, maximum=1)
    if s == 0:
        raise ValueError("sign must be -1 or 1, got 0.")
    x = Fraction(s) / Fraction(a)
    m = [w[k] * x**k for k in range(len(w))]  # moments of the variable sA/a
    # T_n coefficients by the recurrence T_{n+1} = 2x T_n - T_{n-1}
    out = np.empty(len(w))
    t_prev, t_cur = [1], [0, 1]
    try:
        out[0] = float(m[0])
        if len(w) > 1:
            out[1] = float(m[1])
        for n in range(2, len(w)):
            t_next = [0] * (n + 1)
            for k, c in enumerate(t_cur):
                t_next[k + 1] += 2 * c
            for k, c in enumerate(t_prev):
                t_next[k] -= c
            out[n] = float(sum(c * m[k] for k, c in enumerate(t_next) if c))
            t_prev, t_cur = t_cur, t_next
    except OverflowError:
        # a scale far below the spectrum's extent: the moments of A/a grow like (rho/a)^k
        raise ValueError(f"scale = {a:g} is far below the extent of the spectrum: the Chebyshev moments overflow "
                         "float64; the KPM scale must cover the spectrum (a >= the largest |E|).") from None
    return out


def isoperimetric_upper_bound(p: int, q: int) -> float:
    r"""An upper bound :math:`\sqrt{q^2 - i_E^2}` on :math:`\rho` of the {p,q} lattice.

    Here :math:`i_E = (q-2)\sqrt{1-4/((p-2)(q-2))}` is the exact edge isoperimetric constant
    (Häggström–Jonasson–Lyons 2002), and the bound is Mohar's (1988).

    Parameters
    ----------
    p : int or float
        Face size; ``math.inf`` gives the q-regular tree.
    q : int
        Coordination number.

    Returns
    -------
    float
        The bound on :math:`\rho`, in units of t.

    Raises
    ------
    ValueError
        For a non-hyperbolic {p,q}.

    See Also
    --------
    spectral_radius

    References
    ----------
    .. [1] B. Mohar, "Isoperimetric inequalities, growth, and the spectrum of graphs", Linear
       Algebra Appl. 103, 119 (1988).
    .. [2] O. Häggström, J. Jonasson and R. Lyons, "Explicit isoperimetric constants and phase
       transitions in the random-cluster model", Ann. Probab. 30, 443 (2002).

    Examples
    --------
    >>> from hyperlattice.graph.walks import isoperimetric_upper_bound
    >>> round(isoperimetric_upper_bound(7, 3), 6)
    2.966479
    """
    p, q = _validate.pq(p, q, allow_infinite_p=True)
    frac = 0.0 if math.isinf(p) else 4.0 / ((p - 2) * (q - 2))
    i_e = (q - 2) * math.sqrt(1.0 - frac)
    return math.sqrt(q * q - i_e * i_e)


@dataclass(frozen=True, eq=False, kw_only=True)
class SpectralRadius(Result):
    r"""Proven bounds on :math:`\rho = \|A\|` of the infinite {p,q} lattice (band bottom :math:`-\rho` of
    :math:`H = -A`).

    All bounds are in units of t (:math:`\rho` is the norm of A; the band bottom of :math:`H = -tA` is
    :math:`-t\rho`). :math:`W_n` is the number of closed walks of length n from a site.

    Attributes
    ----------
    p, q : int
        Schläfli symbol.
    n_max : int
        The longest closed walk counted.
    lower_root : float
        :math:`\max_n W_{2n}^{1/2n}` (proven lower bound).
    lower_ratio : float
        :math:`\max_n\sqrt{W_{2n}/W_{2n-2}}` (proven lower bound).
    upper : float
        The cited isoperimetric upper bound (:func:`isoperimetric_upper_bound`), at most q.
    ratios : ndarray, shape (n_max // 2,)
        The sequence :math:`\sqrt{W_{2n}/W_{2n-2}}`, n = 1..n_max/2 (increasing to :math:`\rho`).

    Examples
    --------
    >>> import hyperlattice as hl
    >>> s = hl.spectral_radius(7, 3, 8)
    >>> [round(float(x), 4) for x in s.ratios]
    [1.7321, 2.2361, 2.4083, 2.4983]
    >>> round(s.lower, 4), round(s.upper, 4)       # lower: the tree's 2 sqrt(q - 1) wins here
    (2.8284, 2.9665)
    """

    p: int
    q: int
    n_max: int
    lower_root: float
    lower_ratio: float
    upper: float
    ratios: np.ndarray

    @property
    def lower(self) -> float:
        """The best proven lower bound (walk root, walk ratio, or the covering tree's 2 sqrt(q - 1))."""
        return max(self.lower_root, self.lower_ratio, 2.0 * math.sqrt(self.q - 1))

    def band_bottom_interval(self) -> tuple[float, float]:
        """``(-upper, -lower)``: the interval that provably holds the band bottom of H = -A."""
        return -self.upper, -self.lower

    def summary(self) -> dict:
        return {"p": self.p, "q": self.q, "n_max": self.n_max, "lower": self.lower, "upper": self.upper,
                "band_bottom_interval": list(self.band_bottom_interval())}


def spectral_radius_bounds(walks) -> tuple[float, float]:
    r"""Proven lower bounds on :math:`\rho` from exact closed-walk counts.

    They are :math:`\max_n W_{2n}^{1/2n}` and :math:`\max_n \sqrt{W_{2n}/W_{2n-2}}` (float64
    logarithms of exact integers; the last digit is rounding).

    Parameters
    ----------
    walks : sequence of int
        Closed-walk counts :math:`W_0, W_1, \dots` (non-negative integers).

    Returns
    -------
    root, ratio : float
        The two lower bounds (0.0 when no even count is available).

    Raises
    ------
    ValueError
        If ``walks`` is not a non-empty sequence of non-negative integers.

    See Also
    --------
    spectral_radius

    Examples
    --------
    >>> from hyperlattice.graph.walks import closed_walks, spectral_radius_bounds
    >>> root, ratio = spectral_radius_bounds(closed_walks(7, 3, 8))
    >>> round(root, 6), round(ratio, 6)
    (2.197101, 2.498275)
    """
    w = _walk_list(walks)
    evens = [(n, w[2 * n]) for n in range(1, len(w) // 2 + (len(w) % 2)) if 2 * n < len(w)]
    root = max((math.exp(math.log(c) / (2 * n)) for n, c in evens if c > 0), default=0.0)
    ratio = max((math.sqrt(w[2 * n] / w[2 * n - 2]) for n, c in evens if n >= 1 and w[2 * n - 2] > 0), default=0.0)
    return root, ratio


def spectral_radius(p: int, q: int, n_max: int = 22, *, max_sites: int | None = None) -> SpectralRadius:
    r"""Proven bounds on :math:`\rho(p,q)` from the exact closed walks up to ``n_max`` (module docstring).

    :math:`\rho = \|A\|` of the infinite {p,q} lattice; the band bottom of :math:`H = -A` is
    :math:`-\rho`, in units of t.

    Parameters
    ----------
    p, q : int
        Hyperbolic Schläfli symbol.
    n_max : int, optional
        Longest walk, 6 to 200; default 22.
    max_sites : int, optional
        Refuse flakes with more sites (default: what fits in memory).

    Returns
    -------
    SpectralRadius
        ``lower_root``, ``lower_ratio`` (proven lower bounds), ``upper`` (the isoperimetric
        bound, at most q), ``ratios``, and the property ``lower`` and method
        ``band_bottom_interval()``.

    Raises
    ------
    ValueError
        For invalid input, or a flake above ``max_sites`` (or the available memory).

    See Also
    --------
    closed_walks, isoperimetric_upper_bound

    Examples
    --------
    >>> import hyperlattice as hl
    >>> s = hl.spectral_radius(7, 3, 12)
    >>> round(s.lower, 6), round(s.upper, 6)
    (2.828427, 2.966479)
    >>> [round(x, 6) for x in s.band_bottom_interval()]
    [-2.966479, -2.828427]
    """
    p, q = _validate.pq(p, q)
    n_max = _validate.integer("n_max", n_max, minimum=6, maximum=MAX_LENGTH)
    w = closed_walks(p, q, n_max, max_sites=max_sites)
    root, ratio = spectral_radius_bounds(w)
    upper = min(isoperimetric_upper_bound(p, q), float(q))
    ns = np.arange(1, n_max // 2 + 1)
    ratios = np.sqrt(np.array([int(w[2 * n]) / int(w[2 * n - 2]) for n in ns]))
    return SpectralRadius(p=p, q=q, n_max=n_max, lower_root=root, lower_ratio=ratio, upper=upper, ratios=ratios)


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
