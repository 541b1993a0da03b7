r"""Graph levels against continuum levels: labels, side by side, their convergence, Z and level counts.

* :func:`continuum_labels` - each graph level's rotation sector k = m mod p (all the lattice knows
  of m) and the continuum level (n, m) it continues, matched inside its sector by energy order,
  with ties reported and the continuum pairs the lattice splits measured;
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

import dataclasses
import math
from dataclasses import dataclass, field

import numpy as np

from .. import _validate
from .._ties import classify, degenerate_groups, eigenvalue_tolerance, stable_order
from ..graph.spectrum import Spectrum
from ..results import Column, Levels, Result, compare_levels


__all__ = [
    "LabelledSpectrum",
    "continuum_labels",
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
# which continuum level each graph level continues
# ----------------------------------------------------------------------------

@dataclass(frozen=True, eq=False, kw_only=True)
class LabelledSpectrum(Spectrum):
    r"""A graph spectrum whose levels carry their rotation sector k and the continuum (n, m) they continue.

    The p-fold rotation multiplies a state of sector k by :math:`e^{2\pi\mathrm i k/p}`, the same
    phase for every angular momentum :math:`m \equiv k \pmod p`: the lattice knows m only modulo p.
    The continuum label of a graph level is assigned by :func:`continuum_labels` (matching inside
    the sector by energy order). The attributes below come in addition to those of
    :class:`~hyperlattice.graph.spectrum.Spectrum`, whose ``n`` and ``m`` here are the continuum
    labels.

    Attributes
    ----------
    n, m : ndarray of int, shape (K,)
        Radial index and signed angular momentum (any integer) of the continuum level each state
        continues. The two states of a continuum pair (n, ±m) that falls into one sector
        (:math:`2m \equiv 0 \pmod p`, e.g. m = ±4 for p = 8) are split by the lattice into its
        cos- and sin-like combinations; the lower one is listed as +m (a convention, as in the
        continuum list, which puts +m first).
    graph_n, graph_m : ndarray of int, shape (K,)
        The graph's own labels: index within the sector, and the signed sector in :math:`(-p/2, p/2]`.
    continuum_energies, continuum_errors : ndarray, shape (K,)
        Energy (units of t) and error bound of the continuum level each state continues (for a
        line graph shifted by 2 - q, since away from its flat band :math:`-A_L = B^TB - 2` has the
        spectrum of :math:`D + A - 2`, i.e. :math:`E + 2 - q` in the interior).
    ambiguous : ndarray of bool, shape (K,)
        True where the assignment is a tie: the continuum level lies within the error bounds of
        another continuum level of the same sector with a different ``(n, |m|)``, or the graph level
        lies within its tolerance of another graph level of the sector that continues a different
        ``(n, |m|)``. The label is then one of the tied ones.
    splittings : tuple of dict
        One per continuum pair (n, ±m) of one sector among the levels: ``n``, ``m`` (= \|m\|),
        ``levels`` (positions of its states in this list; one entry when the partner lies above the
        computed levels), ``splitting`` (:math:`E_{-m} - E_{+m}`, units of t, None without the
        partner), ``relative`` (splitting over the mean \|E\|) and ``resolved`` (whether the
        splitting exceeds the two states' tolerances; False: degenerate within the computation's
        error).
    labels : str
        One sentence on how the labels were assigned (which continuum disk).

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.compare.levels import continuum_labels
    >>> spec = continuum_labels(hl.lowest_levels(hl.ring_lattice(8, 3, 4), 10))
    >>> spec.sector.tolist(), spec.m.tolist()
    ([0, 1, 7, 2, 6, 3, 5, 4, 4, 5], [0, 1, -1, 2, -2, 3, -3, 4, -4, 5])
    >>> s = spec.splittings[0]
    >>> (s["n"], s["m"], s["levels"], s["resolved"]), f"{s['relative']:.2%}"
    ((1, 4, (7, 8), True), '1.22%')
    """

    COLUMNS = (Column("energy", "energies", "t"), Column("n", "n", "1"), Column("m", "m", "1"),
               Column("sector", "sector", "1"), Column("degeneracy", "degeneracy", "1"),
               Column("error", "errors", "t"), Column("continuum_energy", "continuum_energies", "t"),
               Column("ambiguous", "ambiguous", "1"))

    graph_n: np.ndarray
    graph_m: np.ndarray
    continuum_energies: np.ndarray
    continuum_errors: np.ndarray
    ambiguous: np.ndarray
    splittings: tuple = ()
    labels: str = ""

    def _m_is_sector(self) -> bool:
        return False

    def _check_loaded(self) -> str | None:
        why = super()._check_loaded()
        if why is not None:
            return why
        k = len(self)
        for name in ("graph_n", "graph_m", "continuum_energies", "continuum_errors", "ambiguous"):
            if getattr(self, name).shape != (k,):
                return f"{name} must have one entry per level ({k})"
        if np.any((2 * self.graph_m <= -self.p) | (2 * self.graph_m > self.p)):
            return f"graph_m must lie in (-p/2, p/2] = (-{self.p / 2:g}, {self.p / 2:g}]"
        if np.any(np.mod(self.m, self.p) != np.mod(self.graph_m, self.p)):
            return "every continuum m must lie in the level's sector (m = graph_m mod p)"
        return None

    @property
    def sector(self) -> np.ndarray:
        r"""The rotation sector :math:`k = m \bmod p \in \{0, \dots, p-1\}` of each level."""
        return np.mod(self.graph_m, self.p)

    @property
    def degeneracy(self) -> np.ndarray:
        """Degeneracy on the lattice: 2 for the conjugate sectors k, p - k (no field), else 1."""
        if self.flux:
            return np.ones(len(self), dtype=int)
        return np.where((2 * self.graph_m) % self.p == 0, 1, 2)

    def table(self) -> list[dict]:
        """One dict per level: ``energy, n, m, sector, degeneracy, error, continuum_energy, ambiguous``."""
        return [{"energy": float(e), "n": int(n), "m": int(m), "sector": int(k), "degeneracy": int(g),
                 "error": float(r), "continuum_energy": float(c), "ambiguous": bool(a)}
                for e, n, m, k, g, r, c, a in zip(self.energies, self.n, self.m, self.sector, self.degeneracy,
                                                  self.errors, self.continuum_energies, self.ambiguous)]

    def summary(self) -> dict:
        """The ``spectrum`` CLI's JSON: p, q, rings, sites, method, energies, n, m (continuum labels), sector,
        residuals, continuum_energies, ambiguous (positions), split (the split continuum pairs) (+ flux if nonzero)."""
        out = {
            "p": self.p, "q": self.q, "rings": self.rings, "sites": self.sites, "method": self.method,
            "energies": [float(e) for e in self.energies],
            "n": [int(v) for v in self.n], "m": [int(v) for v in self.m],
            "sector": [int(v) for v in self.sector],
            "residuals": [float(r) for r in self.errors],
            "continuum_energies": [float(e) for e in self.continuum_energies],
            "ambiguous": [int(i) for i in np.flatnonzero(self.ambiguous)],
            "split": [dict(s, levels=list(s["levels"])) for s in self.splittings],
        }
        if self.flux != 0.0:
            out["flux"] = float(self.flux)
        return out

    def notes(self) -> list[str]:
        """Sentences on split continuum pairs and ambiguous labels (what the CLI prints under the table)."""
        out = []
        for s in self.splittings:
            where = ", ".join(str(i + 1) for i in s["levels"])
            if s["splitting"] is None:
                out.append(f"level {where} continues one of the continuum pair (n, m) = ({s['n']}, ±{s['m']}) "
                           "(one sector); its partner lies above the levels computed.")
            elif s["resolved"]:
                out.append(f"levels {where}: the lattice splits the continuum pair (n, m) = ({s['n']}, ±{s['m']}) "
                           f"by {s['splitting']:.3g} ({s['relative']:.2%}); +m labels the lower one (a convention).")
            else:
                out.append(f"levels {where}: the continuum pair ({s['n']}, ±{s['m']}) stays degenerate within the "
                           f"computation's error ({s['splitting']:.1e}).")
        amb = np.flatnonzero(self.ambiguous)
        if amb.size:
            out.append("ambiguous continuum label (a tie within the sector) at level"
                       f"{'s' if amb.size > 1 else ''} {', '.join(str(int(i) + 1) for i in amb)}.")
        return out


def _graph_tolerance(spectrum: Spectrum) -> np.ndarray:
    """Error bound of each graph level (:func:`hyperlattice._ties.eigenvalue_tolerance`).

    The rounding term uses the sector block size N/p and the largest computed |E| for ||H|| (for the
    lowest levels of H = -tA, |E_0| is within a few per cent of q|t| >= ||H||); the residual bounds
    the distance to an exact eigenvalue.
    """
    norm = float(np.max(np.abs(spectrum.energies), initial=0.0))
    block = max(spectrum.sites // spectrum.p, 1)
    return np.array([eigenvalue_tolerance(norm, block, float(r) if np.isfinite(r) else 0.0)
                     for r in spectrum.errors])


def _continuum_for(spectrum: Spectrum, radius, dictionary: str, states: int):
    """The ``states`` lowest continuum levels of the flake's disk (with the flake's field)."""
    where = {"rings": spectrum.rings} if radius is None else {"radius": radius}
    if spectrum.flux != 0.0:
        from ..continuum.magnetic import magnetic_levels

        return magnetic_levels(spectrum.p, spectrum.q, levels=states, flux=spectrum.flux, **where)
    from ..continuum.spectrum import continuum_levels

    return continuum_levels(spectrum.p, spectrum.q, levels=states, dictionary=dictionary, **where)


def continuum_labels(spectrum: Spectrum, *, radius: float | None = None, dictionary: str = "paper") -> LabelledSpectrum:
    r"""Give each graph level its rotation sector k and the continuum level (n, m) it continues.

    The lattice knows the angular momentum only modulo p (the sector :math:`k = m \bmod p`). Inside
    one sector no symmetry separates the levels, so they do not cross (von Neumann–Wigner) as the
    lattice deforms into the continuum: the j-th lowest graph level of sector k continues the j-th
    lowest continuum Dirichlet level with :math:`m \equiv k \pmod p` on the disk of the same flake.
    For p = 8 the second level of sector 4 is thus (n, m) = (1, -4), not (2, 4): the lattice splits
    the continuum pair (1, ±4), which falls into one sector, by about 0.1 %.

    Without a field, sectors k and p - k are complex conjugates and exactly degenerate; a pair of them
    cut by the end of the list is completed by the conjugate state, and degenerate states are listed
    as the continuum lists them, +m first (:func:`hyperlattice._ties.stable_order` with the
    continuum labels as keys), so the K states are the same on every machine. Ties are reported in
    ``ambiguous`` (class docstring); every decision on near-equal energies uses the levels' own error
    bounds (residuals and rounding for the graph, the root enclosures for the continuum).

    Parameters
    ----------
    spectrum : Spectrum
        Graph levels with rotation sectors (:func:`~hyperlattice.graph.spectrum.lowest_levels` of a
        ring lattice or its line graph, without a rotation-breaking on-site term).
    radius : float, optional
        Disk radius :math:`L \in (0, 1)` of the continuum; default: the dictionary disk of the
        flake's rings (``eq12``).
    dictionary : {"paper", "improved"}, optional
        The continuum map (and disk) of :func:`~hyperlattice.continuum.spectrum.continuum_levels`;
        with a field the magnetic levels (:func:`~hyperlattice.continuum.magnetic.magnetic_levels`)
        at the same flux are matched instead.

    Returns
    -------
    LabelledSpectrum
        The same states (energies, residuals, eigenvectors), ``n``, ``m`` the continuum labels,
        ``sector``, ``graph_n``, ``graph_m``, the matched continuum energies, ``ambiguous`` and
        ``splittings``.

    Raises
    ------
    ValueError
        If ``spectrum`` is not a graph Spectrum with rotation sectors, or the continuum levels
        needed would cost more than the continuum solvers accept.

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.compare.levels import continuum_labels
    >>> spec = continuum_labels(hl.lowest_levels(hl.ring_lattice(7, 3, 3), 4, sector=0))
    >>> spec.n.tolist(), spec.m.tolist(), spec.sector.tolist()
    ([1, 2, 1, 1], [0, 0, 7, -7], [0, 0, 0, 0])
    """
    if isinstance(spectrum, LabelledSpectrum):
        raise ValueError("these levels already carry continuum labels; pass the graph Spectrum from lowest_levels.")
    if not isinstance(spectrum, Spectrum):
        raise ValueError("continuum_labels takes a graph Spectrum (lowest_levels of a ring lattice or line graph).")
    if spectrum.m is None:
        raise ValueError("these levels have no rotation sectors (an on-site term breaks the rotation), so no "
                         "continuum angular momentum can be assigned.")
    if radius is not None:
        radius = _validate.real("radius", radius)
        if not 0.0 < radius < 1.0:
            raise ValueError(f"the disk radius must lie in (0, 1), got {radius:g}.")
    dictionary = _validate.choice("dictionary", dictionary, ("paper", "improved"))
    p = spectrum.p
    K = len(spectrum)
    gm, gn = spectrum.m.astype(np.int64), spectrum.n.astype(np.int64)
    tol_all = _graph_tolerance(spectrum)
    # the states: those listed, plus the conjugate partner of a pair that the end of the list cut
    rows, conj = list(range(K)), [False] * K
    if spectrum.flux == 0.0 and spectrum.requested_sector is None:
        have = {(int(a), int(b)) for a, b in zip(gm, gn)}
        for i in range(K):
            if (2 * int(gm[i])) % p and (-int(gm[i]), int(gn[i])) not in have:
                rows.append(i)
                conj.append(True)
    rows_a, conj_a = np.array(rows, dtype=np.int64), np.array(conj, dtype=bool)
    e, tol = spectrum.energies[rows_a], tol_all[rows_a]
    sm = np.where(conj_a, -gm[rows_a], gm[rows_a])
    sm = np.where(2 * sm <= -p, sm + p, sm)           # -p/2 is the sector p/2
    sn = gn[rows_a]
    k = np.mod(sm, p)
    # rank of each state within its sector: energy order, ties by the solver's index (a tie whose
    # members continue different levels is reported below)
    rank = np.empty(e.size, dtype=np.int64)
    for kk in np.unique(k):
        sel = np.flatnonzero(k == kk)
        rank[sel[stable_order(e[sel], tol[sel], sn[sel])]] = np.arange(1, sel.size + 1)
    need = {int(kk): int(rank[k == kk].max()) for kk in np.unique(k)}
    # enough continuum states that every sector has one more than the graph needs (its next level
    # decides whether the match is a tie); a quarter more than the graph's count to start with (the
    # continuum's cost grows with the count: a short request is repeated 1.5 times larger)
    states = math.ceil(1.25 * e.size) + p + 1
    while True:
        cont = _continuum_for(spectrum, radius, dictionary, states)
        ck = np.mod(cont.m, p)
        members = {kk: np.flatnonzero(ck == kk) for kk in need}
        if all(members[kk].size > need[kk] for kk in need):
            break
        states = math.ceil(1.5 * states)
    cidx = np.array([members[int(kk)][r - 1] for kk, r in zip(k, rank)], dtype=np.int64)
    cn, cm = cont.n[cidx].astype(np.int64), cont.m[cidx].astype(np.int64)
    cerr = np.nan_to_num(np.asarray(cont.errors, float), nan=0.0, posinf=0.0)
    amb = np.zeros(e.size, dtype=bool)
    for kk, mem in members.items():
        # continuum ties inside the sector between different (n, |m|)
        group = degenerate_groups(cont.energies[mem], cerr[mem])
        key = cont.n[mem] * 100_003 + np.abs(cont.m[mem])
        for i in np.flatnonzero(k == kk):
            j = rank[i] - 1
            amb[i] |= bool(np.any((group == group[j]) & (key != key[j])))
        # graph ties inside the sector between states that continue different (n, |m|)
        sel = np.flatnonzero(k == kk)
        sel = sel[np.argsort(rank[sel])]
        ggroup = degenerate_groups(e[sel], tol[sel])
        gkey = cn[sel] * 100_003 + np.abs(cm[sel])
        for g in np.unique(ggroup):
            inside = sel[ggroup == g]
            if np.unique(gkey[ggroup == g]).size > 1:
                amb[inside] = True
    order = stable_order(e, tol, np.abs(cm), (cm < 0).astype(np.int64), cn)[:K]
    pick = rows_a[order]
    vecs = spectrum.eigenvectors
    if vecs is not None:
        cols = vecs[:, pick]
        if np.any(conj_a[order]):
            cols = np.where(conj_a[order][None, :], np.conj(cols), cols)
        vecs = cols
    e, tol, sm, sn, cn, cm, amb = (a[order] for a in (e, tol, sm, sn, cn, cm, amb))
    splits = []
    if spectrum.flux == 0.0:
        for i in np.flatnonzero((cm > 0) & ((2 * cm) % p == 0)):
            partner = np.flatnonzero((cn == cn[i]) & (cm == -cm[i]))
            item = {"n": int(cn[i]), "m": int(cm[i])}
            if partner.size:
                j = int(partner[0])
                split = float(e[j] - e[i])
                item.update(levels=(int(i), j), splitting=split,
                            relative=abs(split) / max(0.5 * abs(float(e[i] + e[j])), np.finfo(float).tiny),
                            resolved=bool(abs(split) > tol[i] + tol[j]))
            else:
                item.update(levels=(int(i),), splitting=None, relative=None, resolved=None)
            splits.append(item)
        for i in np.flatnonzero((cm < 0) & ((2 * cm) % p == 0)):
            if not np.any((cn == cn[i]) & (cm == -cm[i])):
                splits.append({"n": int(cn[i]), "m": int(-cm[i]), "levels": (int(i),), "splitting": None,
                               "relative": None, "resolved": None})
    disk = f"L = {radius:.6g}" if radius is not None else f"the {spectrum.rings}-ring dictionary disk (eq12)"
    labels = (f"n, m: the continuum level each state continues, the j-th lowest graph level of sector k = m mod p "
              f"matched to the j-th lowest continuum level with m = k mod p on {disk}"
              + (f" at flux f = {spectrum.flux:g}" if spectrum.flux else f" ({dictionary} dictionary)") + ".")
    shift = 0.0
    if spectrum.kind == "line_graph":
        # the line graph's -A_L = B^T B - 2 has the spectrum of D + A - 2 away from its flat band, i.e.
        # E_line = E + 2 - q at the interior coordination q: its states continue the shifted levels
        shift = 2.0 - spectrum.q
    base = {f.name: getattr(spectrum, f.name) for f in dataclasses.fields(Spectrum)}
    base.update(energies=e, n=cn, m=cm, errors=spectrum.errors[pick], eigenvectors=vecs)
    return LabelledSpectrum(**base, graph_n=sn, graph_m=sm, continuum_energies=cont.energies[cidx][order] + shift,
                            continuum_errors=np.asarray(cont.errors, float)[cidx][order], ambiguous=amb,
                            splittings=tuple(splits), labels=labels)


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
        (an on-site term that breaks the rotation). A graph
        :class:`~hyperlattice.graph.spectrum.Spectrum` is compared through the continuum level
        each state continues (:func:`continuum_labels`, kept in ``graph``), not through its
        sector, which gives m only modulo p.

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
        """p, q, methods, error kinds and the level table (+ ``split``: the continuum pairs the lattice
        splits, when the graph side carries continuum labels)."""
        out = {"p": self.graph.p, "q": self.graph.q, "graph_method": self.graph.method,
               "continuum_method": self.continuum.method, "graph_error_kind": self.graph.error_kind,
               "continuum_error_kind": self.continuum.error_kind, "levels": self.table()}
        if isinstance(self.graph, LabelledSpectrum):
            out["split"] = [dict(s, levels=list(s["levels"])) for s in self.graph.splittings]
        return out


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
        (n, m) labels agree level by level. A graph Spectrum is first given the continuum labels
        of the levels its states continue (:func:`continuum_labels`, on the continuum's disk), and
        ``graph`` holds that :class:`LabelledSpectrum`.

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
    if isinstance(graph, Spectrum) and not isinstance(graph, LabelledSpectrum) and graph.m is not None:
        # the graph's m is its sector; compare the continuum level each state continues, on the
        # continuum's own disk
        rings = getattr(continuum, "rings", None)
        graph = continuum_labels(graph, radius=None if rings == graph.rings else getattr(continuum, "radius", None),
                                 dictionary=getattr(continuum, "dictionary", "paper"))
        base = compare_levels(graph, continuum)
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
    # Weyl's law first (a huge cutoff would run for minutes before max_table stopped it):
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


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
