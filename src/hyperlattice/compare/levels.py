r"""Graph levels against continuum levels: side by side, their convergence, Z and level counts.

* :func:`levels_side_by_side` - a graph spectrum and continuum levels (both
  :class:`~hyperlattice.results.Levels`) level by level (``SuppTab1``, ``spec1``, ``spec2``);
* :func:`relative_error_trend` - the signed relative error :math:`(E_{\rm graph} -
  E_{\rm cont})/|E_{\rm graph}|` of one level as the number of rings grows: where it changes
  sign, whether it then grows monotonically and where it saturates (an Aitken estimate). This
  is the open question of App. ``AppSpec``: "we are not able to test whether the relative error
  between :math:`E_{0,1}` and :math:`E_{0,1}^{(\rm cont)}` decreases as :math:`\ell\to\infty`";
* :func:`graph_levels_below`, :func:`continuum_levels_below` - every level below an energy
  cutoff with its degeneracy, and :func:`partition_functions` - the partition functions
  :math:`Z = \sum_n\Theta(-E_n)e^{-\beta E_n}` and :math:`Z'` of the inset of ``Fig2``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .. import _validate
from .._ties import classify, stable_order
from ..results import Column, Levels, Result, compare_levels


__all__ = [
    "LevelComparison",
    "levels_side_by_side",
    "RelativeErrorTrend",
    "relative_error_trend",
    "LevelCount",
    "graph_levels_below",
    "continuum_levels_below",
    "PartitionComparison",
    "partition_functions",
]


# ----------------------------------------------------------------------------
# graph and continuum levels side by side
# ----------------------------------------------------------------------------

@dataclass(frozen=True, eq=False, kw_only=True)
class LevelComparison(Result):
    r"""A graph spectrum and continuum levels, level by level (``SuppTab1``, ``spec1``, ``spec2``).

    Attributes
    ----------
    graph, continuum : Levels
        The two level lists as given.
    relative_difference : ndarray, shape (K,)
        :math:`(E_{\rm graph} - E_{\rm cont})/|E_{\rm graph}|` of the first K = min(len) levels.
    labels_agree : ndarray of bool, shape (K,), or None
        Whether level k carries the same (n, m) on both sides; None if either side has no m
        (an on-site term that breaks the rotation).

    Notes
    -----
    Energies on both sides are in units of t.

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.compare.levels import levels_side_by_side
    >>> cmp = levels_side_by_side(hl.lowest_levels(hl.ring_lattice(7, 3, 2), 2),
    ...                           hl.continuum_levels(7, 3, rings=2, levels=2))
    >>> [round(float(x), 4) for x in cmp.relative_difference], cmp.labels_agree.tolist()
    ([-0.0251, -0.0871], [True, True])
    """

    graph: Levels
    continuum: Levels
    relative_difference: np.ndarray
    labels_agree: np.ndarray | None

    COLUMNS = (Column("E_graph", "E_graph", "t"), Column("E_continuum", "E_continuum", "t"),
               Column("relative_difference", "relative_difference", "1"),
               Column("n_graph", "n_graph", "1"), Column("m_graph", "m_graph", "1"),
               Column("n_continuum", "n_continuum", "1"), Column("m_continuum", "m_continuum", "1"),
               Column("labels_agree", "labels_agree", "1"),
               Column("graph_error", "graph_error", "t"), Column("continuum_error", "continuum_error", "t"))

    def __len__(self) -> int:
        return int(self.relative_difference.shape[0])

    def _first(self, side: Levels, name: str) -> np.ndarray | None:
        # the first K levels of one side (the columns of the table)
        a = getattr(side, name)
        return None if a is None else a[:len(self)]

    E_graph = property(lambda self: self._first(self.graph, "energies"), doc="Graph energies of the K levels.")
    E_continuum = property(lambda self: self._first(self.continuum, "energies"),
                           doc="Continuum energies of the K levels.")
    n_graph = property(lambda self: self._first(self.graph, "n"), doc="Graph radial indices.")
    m_graph = property(lambda self: self._first(self.graph, "m"), doc="Graph angular momenta (None without).")
    n_continuum = property(lambda self: self._first(self.continuum, "n"), doc="Continuum radial indices.")
    m_continuum = property(lambda self: self._first(self.continuum, "m"), doc="Continuum angular momenta.")
    graph_error = property(lambda self: self._first(self.graph, "errors"), doc="Graph errors (residuals).")
    continuum_error = property(lambda self: self._first(self.continuum, "errors"), doc="Continuum error bounds.")

    def table(self) -> list[dict]:
        """One dict per level: energies, (n, m) labels and errors of both sides, relative difference."""
        g, c = self.graph.table(), self.continuum.table()
        return [{"level": k, "E_graph": g[k]["energy"], "E_continuum": c[k]["energy"],
                 "relative_difference": float(self.relative_difference[k]),
                 "n_graph": g[k]["n"], "m_graph": g[k]["m"], "n_continuum": c[k]["n"], "m_continuum": c[k]["m"],
                 "labels_agree": None if self.labels_agree is None else bool(self.labels_agree[k]),
                 "graph_error": g[k]["error"], "continuum_error": c[k]["error"]}
                for k in range(len(self))]

    def summary(self) -> dict:
        """p, q, methods, error kinds and the level table."""
        return {"p": self.graph.p, "q": self.graph.q, "graph_method": self.graph.method,
                "continuum_method": self.continuum.method, "graph_error_kind": self.graph.error_kind,
                "continuum_error_kind": self.continuum.error_kind, "levels": self.table()}


def levels_side_by_side(graph: Levels, continuum: Levels) -> LevelComparison:
    r"""Put a graph spectrum and continuum levels side by side, level by level.

    Parameters
    ----------
    graph : Levels
        Graph levels (:func:`hyperlattice.graph.spectrum.lowest_levels`), residual errors.
    continuum : Levels
        Continuum Dirichlet levels of the disk of radius L (``spec1``, ``spec2``), energy error
        bounds; both lists ascending, a :math:`\pm m` pair listed twice (+m first).

    Returns
    -------
    LevelComparison
        The first min(len) levels of both, with the relative difference and whether the
        (n, m) labels agree level by level.

    Raises
    ------
    ValueError
        If either argument is not a :class:`~hyperlattice.results.Levels` or their {p,q} differ.

    See Also
    --------
    hyperlattice.results.compare_levels : the same comparison as a plain dict.

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.compare.levels import levels_side_by_side
    >>> graph = hl.lowest_levels(hl.ring_lattice(7, 3, 2), 2)
    >>> cont = hl.continuum_levels(7, 3, rings=2, levels=2)
    >>> cmp = levels_side_by_side(graph, cont)
    >>> [round(float(x), 4) for x in cmp.relative_difference]
    [-0.0251, -0.0871]
    """
    base = compare_levels(graph, continuum)  # checks both are Levels
    if (graph.p, graph.q) != (continuum.p, continuum.q):
        raise ValueError(f"the graph levels are for {{{graph.p},{graph.q}}}, the continuum levels for "
                         f"{{{continuum.p},{continuum.q}}}; compare the same tiling.")
    k = base["levels"]
    agree = None
    if graph.m is not None and continuum.m is not None:
        agree = (graph.m[:k] == continuum.m[:k]) & (graph.n[:k] == continuum.n[:k])
    return LevelComparison(graph=graph, continuum=continuum,
                           relative_difference=np.asarray(base["relative_difference"], float),
                           labels_agree=agree)


# ----------------------------------------------------------------------------
# the open question: how the relative error behaves as l grows
# ----------------------------------------------------------------------------

@dataclass(frozen=True, eq=False, kw_only=True)
class RelativeErrorTrend(Result):
    r"""The signed graph-continuum relative error of one level against the number of rings.

    Attributes
    ----------
    level : str
        Which level (``"E0"``, ``"E1"``).
    rings : ndarray of int
        Numbers of rings l, increasing.
    relative_error : ndarray
        :math:`(E_{\rm graph} - E_{\rm cont})/|E_{\rm graph}|` at each l (negative: the graph
        level lies below the continuum level).
    sign_change : ndarray of int, shape (2,), or None
        ``[l_a, l_b]``: consecutive rings between which the error changes sign for the last
        time; None if it never does.
    rising : bool or None
        At that sign change: True if the error goes from below zero to above (the graph level
        moves from below to above the continuum level), False for the reverse, None without a
        sign change.
    monotone : bool
        Whether after the last sign change the magnitude of the error grows strictly over at
        least three rings.
    increments : ndarray, shape (2,) or (0,)
        When ``monotone``: the last two increments :math:`(d_1, d_2)` of the error (signed);
        otherwise empty.
    aitken_limit : float
        When ``monotone`` with shrinking increments :math:`|d_2| < |d_1|`: Aitken's
        :math:`\Delta^2` estimate :math:`x - d_2^2/(d_2 - d_1)` of the limit from the last three
        values; NaN otherwise.
    magnitude_decreasing : bool
        Whether :math:`|{\rm error}|` decreases strictly over the whole range.

    Examples
    --------
    >>> from hyperlattice.compare.levels import relative_error_trend
    >>> trend = relative_error_trend([2, 3, 4], [-2.6, -2.7, -2.75], [-2.5, -2.72, -2.76])
    >>> [round(float(x), 4) for x in trend.relative_error]
    [-0.0385, 0.0074, 0.0036]
    >>> trend.sign_change.tolist(), trend.rising, trend.monotone, trend.magnitude_decreasing
    ([2, 3], True, False, True)
    """

    COLUMNS = (Column("rings", "rings", "1"), Column("relative_error", "relative_error", "1"))

    level: str
    rings: np.ndarray
    relative_error: np.ndarray
    sign_change: np.ndarray | None
    rising: bool | None
    monotone: bool
    increments: np.ndarray
    aitken_limit: float
    magnitude_decreasing: bool

    @property
    def saturates(self) -> bool:
        """Monotone growth with shrinking increments toward a finite (Aitken) limit."""
        return bool(self.monotone and math.isfinite(self.aitken_limit))

    def summary(self) -> dict:
        """All fields as plain JSON (lists, no type tags)."""
        return super().summary()


def relative_error_trend(rings, graph, continuum, *, level: str = "E0") -> RelativeErrorTrend:
    r"""How the relative error between a graph level and its continuum level behaves as l grows.

    The open question of App. ``AppSpec``: does
    :math:`(E_{\rm graph} - E_{\rm cont})/|E_{\rm graph}|` (``SuppTab1``) keep decreasing as
    :math:`\ell\to\infty`? The answer is read off the data: the last sign change, whether the
    magnitude then grows monotonically, and, when its increments shrink, Aitken's
    :math:`\Delta^2` extrapolation of the limit from the last three values.

    Parameters
    ----------
    rings : array of int
        Numbers of rings l, strictly increasing.
    graph, continuum : array of float
        The level (E0, E1, ...) of the graph and of the continuum disk at each l.
    level : str, optional
        Name of the level, carried into the result. Default ``"E0"``.

    Returns
    -------
    RelativeErrorTrend
        ``relative_error`` at each l, the last ``sign_change`` ``[l_a, l_b]`` (None if none) and
        its direction ``rising``, ``monotone``, the last ``increments`` and ``aitken_limit``.

    Raises
    ------
    ValueError
        If ``rings`` is empty or not strictly increasing integers, the arrays do not match,
        ``level`` is not a name, or a graph energy is zero.

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.compare.levels import relative_error_trend
    >>> from hyperlattice.compare.limits import reference_levels
    >>> rings, E0, E1 = reference_levels(7, 3)
    >>> rings, E0 = rings[:8], E0[:8]
    >>> cont = [hl.continuum_levels(7, 3, rings=int(x), levels=1).energies[0] for x in rings]
    >>> trend = relative_error_trend(rings, E0, cont)
    >>> trend.sign_change.tolist(), trend.rising, trend.monotone
    ([5, 6], True, True)
    >>> [round(float(x), 4) for x in trend.relative_error[-3:]]
    [0.0001, 0.0004, 0.0005]
    """
    ell = _validate.real_array("rings", rings, ndim=1)
    if ell.size == 0:
        raise ValueError("rings must not be empty.")
    if np.any(ell != np.round(ell)) or np.any(np.diff(ell) <= 0):
        raise ValueError("rings must be strictly increasing integers.")
    g = _validate.real_array("graph", graph, shape=ell.shape)
    c = _validate.real_array("continuum", continuum, shape=ell.shape)
    if not isinstance(level, str):
        raise ValueError(f"level must be a name such as 'E0', got {level!r}.")
    if np.any(g == 0):
        raise ValueError("a graph energy is zero; the relative error is undefined there.")
    ell = ell.astype(np.int64)
    rel = (g - c) / np.abs(g)
    changes = np.nonzero(np.diff(np.sign(rel)) != 0)[0]
    sign_change, rising, monotone = None, None, False
    increments, limit = np.zeros(0), float("nan")
    if changes.size:
        i = int(changes[-1])
        sign_change = ell[i:i + 2].copy()
        rising = bool(rel[i + 1] > rel[i])
        tail = rel[i + 1:]
        monotone = bool(tail.size >= 3 and np.all(np.diff(np.abs(tail)) > 0))
        if monotone:
            d1, d2 = tail[-2] - tail[-3], tail[-1] - tail[-2]
            increments = np.array([d1, d2])
            if abs(d2) < abs(d1):
                limit = float(tail[-1] - d2 * d2 / (d2 - d1))
    return RelativeErrorTrend(level=level, rings=ell, relative_error=rel, sign_change=sign_change, rising=rising,
                              monotone=monotone, increments=increments, aitken_limit=limit,
                              magnitude_decreasing=bool(np.all(np.diff(np.abs(rel)) < 0)))


# ----------------------------------------------------------------------------
# levels below a cutoff, partition functions (``Fig2`` inset)
# ----------------------------------------------------------------------------

@dataclass(frozen=True, eq=False, kw_only=True)
class LevelCount(Result):
    r"""Every level below an energy cutoff with its degeneracy.

    What the partition functions of the ``Fig2`` inset and the counting function
    :math:`\mathcal N(E) = \#\{\text{states with } E_n \le E\}` sum over.

    Attributes
    ----------
    side : str
        ``"graph"`` or ``"continuum"``.
    p, q : int
        Schläfli symbol.
    rings : int or None
        Number of rings of the lattice (or the one that fixes L by ``eq12``).
    radius : float
        Euclidean disk radius L in the paper's Poincaré disk (``eq12`` for a lattice).
    cutoff : float
        Only levels with :math:`E < {\rm cutoff}` are listed, decided robustly: a level within
        ``tolerance`` of the cutoff is neither listed nor hidden but counted in ``at_cutoff``.
    energies : ndarray
        Ascending, in units of t (as ``cutoff`` and ``tolerance``); a degenerate continuum pair
        :math:`\pm m` is listed once.
    degeneracy : ndarray of int
        States per entry: 1 for a graph eigenvalue (listed once per state) and a continuum
        m = 0 level, 2 for a continuum :math:`\pm m` pair.
    n, m : ndarray of int or None
        Continuum labels (radial index, :math:`|m|`); None for the graph.
    description : str
        How the levels were obtained.
    at_cutoff : int
        States whose computed energy lies within ``tolerance`` of the cutoff: their side of it
        is rounding noise (it differs between BLAS kernels), so they are reported here instead
        of being sorted by the sign of that noise. For a graph and cutoff 0 these are the zero
        modes of the flake (two for the {7,3} flake with l = 4).
    tolerance : float
        The largest error bound of a listed energy (graph: :func:`~hyperlattice.graph.spectrum.
        full_spectrum_tolerance`; continuum: the Dirichlet roots' energy error bounds).

    Examples
    --------
    >>> from hyperlattice.compare.levels import continuum_levels_below
    >>> below = continuum_levels_below(7, 3, rings=2)
    >>> below.states, below.degeneracy[:3].tolist(), below.counting([-2.5, -2.0]).tolist()
    (10, [1, 2, 2], [1, 3])
    >>> [round(float(z), 4) for z in below.partition_function([0.0, 1.0])]
    [10.0, 48.96]
    """

    COLUMNS = (Column("energy", "energies", "t"), Column("degeneracy", "degeneracy", "1"),
               Column("n", "n", "1"), Column("m", "m", "1"))

    side: str
    p: int
    q: int
    rings: int | None
    radius: float
    cutoff: float
    energies: np.ndarray
    degeneracy: np.ndarray
    n: np.ndarray | None
    m: np.ndarray | None
    description: str
    at_cutoff: int = 0
    tolerance: float = 0.0

    @property
    def states(self) -> int:
        """Number of states below the cutoff (degenerate levels counted with multiplicity)."""
        return int(self.degeneracy.sum())

    def counting(self, energy) -> np.ndarray:
        r"""The counting function :math:`\mathcal N(E)`: states with :math:`E_n \le E`, for each E.

        Parameters
        ----------
        energy : float or array_like
            Energies E in units of t.

        Returns
        -------
        numpy.ndarray of int
            :math:`\mathcal N(E)` for each E (degeneracies counted).
        """
        e = _validate.real_array("energy", energy)
        cum = np.concatenate([[0], np.cumsum(self.degeneracy)])
        return cum[np.searchsorted(self.energies, e, side="right")]

    def partition_function(self, beta) -> np.ndarray:
        r""":math:`Z(\beta) = \sum_n g_n e^{-\beta E_n}` over the listed levels, for each beta.

        Parameters
        ----------
        beta : float or array_like
            Inverse temperatures :math:`\beta \ge 0` in units of 1/t.

        Returns
        -------
        numpy.ndarray
            :math:`Z(\beta)` for each beta.

        Raises
        ------
        ValueError
            If beta is negative or Z overflows double precision (then use :meth:`log_partition_function`).
        """
        b = _check_beta(beta)
        with np.errstate(over="ignore"):  # an overflow is reported below as a ValueError
            z = (self.degeneracy[None, :] * np.exp(-b[:, None] * self.energies[None, :])).sum(axis=1)
        if not np.all(np.isfinite(z)):
            raise ValueError(f"Z overflows double precision for beta up to {b.max():g}; use "
                             "log_partition_function.")
        return z

    def log_partition_function(self, beta) -> np.ndarray:
        r""":math:`\ln Z(\beta)`, computed shifted by the lowest level so that it never overflows.

        Parameters
        ----------
        beta : float or array_like
            Inverse temperatures :math:`\beta \ge 0` in units of 1/t.

        Returns
        -------
        numpy.ndarray
            :math:`\ln Z(\beta)` for each beta.
        """
        b = _check_beta(beta)
        if self.energies.size == 0:
            return np.full(b.shape, -np.inf)
        e0 = self.energies[0]
        return -b * e0 + np.log((self.degeneracy[None, :] *
                                 np.exp(-b[:, None] * (self.energies[None, :] - e0))).sum(axis=1))


def _check_beta(beta) -> np.ndarray:
    b = _validate.real_array("beta", beta, ndim=(0, 1))
    if np.any(b < 0):
        raise ValueError("beta (the inverse temperature) must be non-negative.")
    return np.atleast_1d(b)


def graph_levels_below(lattice, cutoff: float = 0.0) -> LevelCount:
    r"""All eigenvalues of :math:`H = -A` on ``lattice`` below ``cutoff`` (``Fig2`` inset: 0).

    The full spectrum (:func:`hyperlattice.graph.spectrum.full_spectrum_tolerance`, a dense
    computation per rotation sector) with each eigenvalue listed once per state. Levels within
    the eigensolver's error bound of the cutoff are not listed but counted in ``at_cutoff``
    (at cutoff 0: the flake's exact zero modes), so the count is the same on every machine.

    Parameters
    ----------
    lattice : Lattice
        A {p,q} site flake (``ring_lattice``).
    cutoff : float, optional
        Energy cutoff (units of t). Default 0.

    Returns
    -------
    LevelCount
        ``energies`` below the cutoff (ascending, once per state, ``degeneracy`` 1), the number
        of ``states``, ``at_cutoff`` (states within ``tolerance`` of the cutoff) and the disk
        ``radius`` L of the flake.

    Raises
    ------
    ValueError
        For a line-graph lattice or a non-finite cutoff.

    See Also
    --------
    continuum_levels_below, partition_functions

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.compare.levels import graph_levels_below
    >>> below = graph_levels_below(hl.ring_lattice(7, 3, 2))
    >>> below.states, below.at_cutoff
    (16, 1)
    """
    from ..graph.spectrum import full_spectrum_tolerance

    lattice = _validate.lattice(lattice, kind="sites")
    cutoff = _validate.real("cutoff", cutoff)
    e, tol = full_spectrum_tolerance(lattice)
    below, at, _ = classify(e, cutoff, tol)
    e = e[below]
    return LevelCount(side="graph", p=lattice.p, q=lattice.q, rings=lattice.rings, radius=lattice.radius,
                      cutoff=cutoff, energies=e, degeneracy=np.ones(e.size, dtype=np.int64), n=None, m=None,
                      description="all eigenvalues of H = -A (dense, per rotation sector)",
                      at_cutoff=int(np.count_nonzero(at)), tolerance=float(tol))


#: Most levels :func:`continuum_levels_below` counts, by Weyl's estimate before any root is found:
#: the {7,3} disk of 4 rings has ~150 below E = 0 (2.5 s), that of 5 rings ~400 (over 100 s).
MAX_LEVELS_BELOW = 300
#: Largest (n, m) table of Dirichlet roots :func:`continuum_levels_below` computes before it refuses.
MAX_TABLE = 50_000


def continuum_levels_below(p: int = 7, q: int = 3, *, rings=None, radius=None, cutoff: float = 0.0,
                           max_table: int = MAX_TABLE) -> LevelCount:
    r"""All Dirichlet levels :math:`E_{nm}` (``spec1``, ``spec2``) of the disk below ``cutoff``.

    :math:`E_{nm}` grows with n and with :math:`|m|`, so the table n = 1..n_max,
    m = 0..m_max holds every level below the cutoff as soon as its last row and last column
    lie above it; the table is enlarged until they do. A level with :math:`m \ne 0` is the
    degenerate pair :math:`\pm m` (degeneracy 2).

    Parameters
    ----------
    p, q : int, optional
        Schläfli symbol, :math:`(p-2)(q-2) > 4`. Default {7,3}.
    rings : int, optional
        The disk of radius L of the ``rings``-ring lattice (``eq12``).
    radius : float, optional
        L itself, 0 < L < 1. Give ``rings`` or ``radius``, not both.
    cutoff : float, optional
        Energy cutoff (units of t; 0 in the ``Fig2`` inset: "we limit the sums to negative
        energies"). Default 0.
    max_table : int, optional
        Largest number of (n, m) roots computed; a cutoff that needs more is refused.

    Returns
    -------
    LevelCount
        ``energies`` below the cutoff (ascending, a :math:`\pm m` pair once) with their
        ``degeneracy`` (1 for m = 0, 2 otherwise), the labels ``n`` and ``m`` (:math:`|m|`), and
        the number of ``states``.

    Raises
    ------
    ValueError
        For bad input, or when the levels below the cutoff need a table larger than ``max_table``.

    See Also
    --------
    graph_levels_below, partition_functions

    Examples
    --------
    >>> from hyperlattice.compare.levels import continuum_levels_below
    >>> below = continuum_levels_below(7, 3, rings=2)
    >>> below.states, below.degeneracy[:3].tolist()
    (10, [1, 2, 2])
    >>> [round(float(e), 4) for e in below.energies[:3]]
    [-2.5703, -2.0845, -1.5368]
    """
    from ..continuum.spectrum import dirichlet_levels, disk_argument
    from ..dictionary import lambda_from_energy

    p, q = _validate.pq(p, q)
    cutoff = _validate.real("cutoff", cutoff)
    max_table = _validate.positive_int("max_table", max_table)
    # Weyl's law first (issue 19: a huge cutoff ran for minutes before max_table stopped it):
    # N(lambda) ~ A lambda / (4 pi), A = pi L^2 / (1 - L^2) the disk's area in the metric of eq3
    L, _ = disk_argument(radius, p=p, q=q, rings=rings)
    lam = float(lambda_from_energy(min(cutoff, 1e300), p, q).real) if cutoff > -q else 0.0
    weyl = max(lam, 0.0) * (L * L / ((1.0 - L) * (1.0 + L))) / 4.0
    if weyl / 2 > max_table:
        raise ValueError(f"about {weyl:.3g} Dirichlet levels lie below {cutoff:g} on this disk (Weyl's law): "
                         f"more than max_table = {max_table:,} roots; lower the cutoff or raise max_table.")
    if weyl > MAX_LEVELS_BELOW:
        raise ValueError(f"about {weyl:.3g} Dirichlet levels lie below {cutoff:g} on this disk (Weyl's law); "
                         f"at most {MAX_LEVELS_BELOW:,} are counted (the root table search grows too slow "
                         "beyond); lower the cutoff or use a smaller disk.")
    n_max, m_max = 6, 12
    while True:
        if n_max * (m_max + 1) > max_table:
            raise ValueError(f"the levels below {cutoff:g} need more than max_table = {max_table:,} Dirichlet "
                             "roots; lower the cutoff or raise max_table.")
        tab = dirichlet_levels(p, q, radius=radius, rings=rings, n_max=n_max, m_max=m_max)
        e = tab.energies  # e[n - 1, m]
        # the table's last row and column must lie above the cutoff beyond their error bounds
        if np.all(e[:, -1] - tab.errors[:, -1] > cutoff) and np.all(e[-1, :] - tab.errors[-1, :] > cutoff):
            break
        n_max, m_max = n_max + 4, m_max + 8
    err = np.asarray(tab.errors, dtype=float)
    below, at, _ = classify(e, cutoff, err)
    n_idx, m_idx = np.nonzero(below)
    energies = e[n_idx, m_idx]
    # ascending energy; degenerate levels (within their error bounds) by (n, m), not by rounding
    order = stable_order(energies, err[n_idx, m_idx], n_idx, m_idx)
    m = m_idx[order]
    at_states = int(np.sum(np.where(np.nonzero(at)[1] == 0, 1, 2)))
    return LevelCount(side="continuum", p=p, q=q, rings=None if rings is None else int(rings), radius=tab.radius,
                      cutoff=cutoff, energies=energies[order], degeneracy=np.where(m == 0, 1, 2), n=n_idx[order] + 1,
                      m=m, description=f"Dirichlet roots of spec2 on a {n_max} x {m_max + 1} (n, m) table",
                      at_cutoff=at_states, tolerance=float(err[n_idx, m_idx].max(initial=0.0)))


@dataclass(frozen=True, eq=False, kw_only=True)
class PartitionComparison(Result):
    r"""Graph and continuum partition functions over negative energies (inset of ``Fig2``).

    :math:`Z = \sum_n\Theta(-E_n)e^{-\beta E_n}` over the graph levels and
    :math:`Z' = \sum_n\Theta(-E^{(\rm cont)}_n)e^{-\beta E^{(\rm cont)}_n}` over the disk's states.
    ``graph_zero_modes`` counts the graph states within ``graph_tolerance`` (the eigensolver's
    error bound) of the cutoff: left out of Z and reported, never sorted by the sign of rounding.

    Attributes
    ----------
    rings : int or None
        Rings of the lattice (and of the disk by ``eq12``).
    beta : ndarray
        Inverse temperatures, units of 1/t.
    z_graph, z_continuum : ndarray
        Z and Z' at each beta.
    e0_graph : float
        Lowest graph level, units of t.
    graph_states, continuum_states : int
        States summed on each side.
    graph_zero_modes : int
        Graph states within ``graph_tolerance`` of the cutoff (left out of Z).
    graph_tolerance : float
        The graph eigenvalues' error bound, units of t.

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.compare.levels import (continuum_levels_below, graph_levels_below,
    ...                                          partition_functions)
    >>> z = partition_functions(graph_levels_below(hl.ring_lattice(7, 3, 2)),
    ...                         continuum_levels_below(7, 3, rings=2), [0.0, 1.0])
    >>> z.graph_states, z.continuum_states, z.graph_zero_modes, round(z.e0_graph, 4)
    (16, 10, 1, -2.6364)
    >>> [round(float(x), 4) for x in z.z_graph], [round(float(x), 4) for x in z.z_continuum]
    ([16.0, 86.2311], [10.0, 48.96])
    """

    COLUMNS = (Column("beta", "beta", "1/t"), Column("z_graph", "z_graph", "1"),
               Column("z_continuum", "z_continuum", "1"))

    rings: int | None
    beta: np.ndarray
    z_graph: np.ndarray
    z_continuum: np.ndarray
    e0_graph: float
    graph_states: int
    continuum_states: int
    graph_zero_modes: int = 0
    graph_tolerance: float = 0.0


def partition_functions(graph: LevelCount, continuum: LevelCount, beta) -> PartitionComparison:
    r"""Z and Z' of the ``Fig2`` inset from the levels below the cutoff of both sides.

    :math:`Z = \sum_n\Theta(-E_n)e^{-\beta E_n}`, each level counted with its degeneracy.

    Parameters
    ----------
    graph : LevelCount
        From :func:`graph_levels_below`, with at least one level.
    continuum : LevelCount
        From :func:`continuum_levels_below`.
    beta : float or array_like of float
        Inverse temperatures :math:`\beta \ge 0` (units of 1/t).

    Returns
    -------
    PartitionComparison
        ``beta``, ``z_graph`` and ``z_continuum`` (one per beta), the graph ground state
        ``e0_graph``, the state counts and the graph zero modes left out.

    Raises
    ------
    ValueError
        If an argument is not a LevelCount, the graph has no level below the cutoff, or a beta
        is negative.

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.compare.levels import (continuum_levels_below, graph_levels_below,
    ...                                          partition_functions)
    >>> z = partition_functions(graph_levels_below(hl.ring_lattice(7, 3, 2)),
    ...                         continuum_levels_below(7, 3, rings=2), [0.0, 1.0])
    >>> [round(float(x), 4) for x in z.z_graph], [round(float(x), 4) for x in z.z_continuum]
    ([16.0, 86.2311], [10.0, 48.96])
    """
    if not isinstance(graph, LevelCount) or not isinstance(continuum, LevelCount):
        raise ValueError("partition_functions takes two LevelCount results (graph_levels_below, "
                         "continuum_levels_below).")
    if graph.energies.size == 0:
        raise ValueError("the graph has no level below the cutoff.")
    b = _check_beta(beta)
    return PartitionComparison(rings=graph.rings, beta=b, z_graph=graph.partition_function(b),
                               z_continuum=continuum.partition_function(b), e0_graph=float(graph.energies.min()),
                               graph_states=graph.states, continuum_states=continuum.states,
                               graph_zero_modes=graph.at_cutoff, graph_tolerance=graph.tolerance)


# every public function above checks its annotated argument types at the door (issue 19)
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
