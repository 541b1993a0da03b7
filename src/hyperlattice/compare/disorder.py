r"""Disorder ensembles on the graph, and the graph average against the SCBA in the continuum.

Observables (per realization :func:`realization_observables`, pooled by :func:`disorder_ensemble`):

* the level-spacing ratio :math:`r_n = \min(s_n, s_{n+1})/\max(s_n, s_{n+1})`,
  :math:`s_n = E_{n+1} - E_n` (Oganesyan & Huse, PRB 75, 155111 (2007)), which needs no unfolding
  of the density of states; its mean is :data:`GOE_R` = 0.5307 for extended, level-repelling states
  (large-N GOE, Atas et al., PRL 110, 084101 (2013)) and :data:`POISSON_R` = :math:`2\ln2-1` =
  0.3863 for localized ones. Ratios are binned by the energy of the middle level into windows;
* the density of states per site (histogram, averaged over realizations);
* the inverse participation ratio :math:`\sum_i|\psi_i|^4` of the eigenstates, in the same windows
  (:math:`\sim 1/N` extended, :math:`O(1)` localized);
* the averaged Green function :math:`\langle G_{ij}(\omega)\rangle` against the hyperbolic distance
  :math:`d(z_i, z_j)` (:func:`green_ensemble`), compared with the SCBA (:func:`compare_scba`):
  on the graph (the exact diagonal self-energy :math:`\Sigma_i = w^2[(H_0-\omega-\Sigma)^{-1}]_{ii}`,
  :func:`graph_scba`) and in the continuum (:mod:`hyperlattice.continuum.scba` through ``eq21``).

Without the rotation symmetry each realization is one dense diagonalisation of the whole
:math:`N\times N` matrix (see :mod:`hyperlattice.graph.disorder`), run on one BLAS thread so that
a realization gives the same bits in any process (the sweep engine relies on this).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import scipy.linalg as sla

from .. import _validate
from ..dictionary import dictionary_parameters
from ..geometry import distance
from ..graph.disorder import MODELS, _system, disorder, disordered_hamiltonian, onsite_variance
from ..graph.lattice import Lattice
from ..results import Column, Result


__all__ = ["GOE_R", "POISSON_R", "spacing_ratios", "inverse_participation", "default_windows",
           "realization_observables", "DisorderEnsemble", "disorder_ensemble", "RScan", "r_scan",
           "DisorderGreen", "green_ensemble", "graph_scba", "SCBAComparison", "compare_scba"]

#: mean spacing ratio of the large-N Gaussian orthogonal ensemble (Atas et al., PRL 110, 084101 (2013))
GOE_R = 0.5307
#: mean spacing ratio of uncorrelated (Poisson) levels, 2 ln 2 - 1
POISSON_R = 2.0 * math.log(2.0) - 1.0
#: dense diagonalisation only up to this many sites (8 N^2 bytes for the matrix and as much for vectors)
DENSE_MAX = 12_000
MAX_REALIZATIONS = 1_000_000
#: spacings below this fraction of the mean spacing count as exact degeneracies (r undefined)
_DEGENERATE = 1e-9


def _single_thread():
    from ..graph.solvers import single_threaded_blas

    return single_threaded_blas()


def spacing_ratios(energies, *, window=None) -> tuple[np.ndarray, np.ndarray]:
    r"""Spacing ratios :math:`r_n` of a spectrum and the energy of each middle level.

    Parameters
    ----------
    energies : array_like of float
        Eigenvalues (any order; sorted here).
    window : (float, float), optional
        Keep only ratios whose middle level lies in ``[lo, hi)``.

    Returns
    -------
    r, e_mid : ndarray
        Ratios in [0, 1] and the middle energies. Triples with both spacings below
        ``1e-9`` times the mean spacing (exact degeneracies, e.g. the clean flake's m, p - m pairs
        and the line graph's flat band) are left out: their ratio is 0/0. Fewer than three
        levels give empty arrays.

    Raises
    ------
    ValueError
        If ``energies`` is not a finite 1-d array or ``window`` is not two numbers.

    References
    ----------
    .. [1] V. Oganesyan and D. A. Huse, Phys. Rev. B 75, 155111 (2007).

    Examples
    --------
    >>> from hyperlattice.compare.disorder import spacing_ratios
    >>> r, e_mid = spacing_ratios([0.0, 1.0, 3.0, 4.0])
    >>> r.tolist(), e_mid.tolist()
    ([0.5, 0.5], [1.0, 3.0])
    """
    e = np.sort(_validate.real_array("energies", energies, ndim=1))
    if e.size < 3:
        return np.zeros(0), np.zeros(0)
    s = np.diff(e)
    mean = (e[-1] - e[0]) / (e.size - 1)
    lo, hi = s[:-1], s[1:]
    big = np.maximum(lo, hi)
    keep = big > _DEGENERATE * max(mean, np.finfo(float).tiny)
    r = np.where(keep, np.minimum(lo, hi) / np.where(keep, big, 1.0), 0.0)
    mid = e[1:-1]
    if window is not None:
        w = _validate.real_array("window", window, shape=(2,))
        keep &= (mid >= w[0]) & (mid < w[1])
    return r[keep], mid[keep]


def inverse_participation(vectors) -> np.ndarray:
    r"""Inverse participation ratio :math:`\sum_i |\psi_i|^4` of each column of ``vectors``.

    About 1/N for a state extended over N sites, of order 1 for a localized one.

    Parameters
    ----------
    vectors : array_like, shape (N, K)
        Normalised eigenvectors, one per column (real or complex).

    Returns
    -------
    ndarray of float, shape (K,)
        The inverse participation ratio of each column.

    Raises
    ------
    ValueError
        If ``vectors`` is not a 2-d array.

    Examples
    --------
    >>> import numpy as np
    >>> from hyperlattice.compare.disorder import inverse_participation
    >>> inverse_participation(np.eye(3)).tolist()
    [1.0, 1.0, 1.0]
    >>> inverse_participation(np.full((4, 1), 0.5)).tolist()
    [0.25]
    """
    v = np.asarray(vectors)
    if v.ndim != 2:
        raise ValueError(f"vectors must be a 2-d array (one eigenvector per column), got shape {v.shape}.")
    a = np.abs(v) ** 2
    return np.einsum("ij,ij->j", a, a)


def default_windows(q: int) -> np.ndarray:
    """Energy window edges ``[-inf, -2q/3, -q/3, 0, q/3, 2q/3, inf]`` (six windows, all levels counted).

    Parameters
    ----------
    q : int
        Coordination number of the lattice (>= 3); the clean band lies in :math:`[-q, q]`
        (units of t).

    Returns
    -------
    ndarray of float, shape (7,)
        The window edges, increasing, with infinite outer ends.

    Raises
    ------
    ValueError
        If ``q`` is not an integer in the allowed range.

    Examples
    --------
    >>> from hyperlattice.compare.disorder import default_windows
    >>> default_windows(3).tolist()
    [-inf, -2.0, -1.0, 0.0, 1.0, 2.0, inf]
    """
    q = _validate.integer("q", q, minimum=3, maximum=_validate.PQ_MAX)
    inner = np.linspace(-q, q, 7)[1:-1]
    return np.concatenate([[-np.inf], inner, [np.inf]])


def _dos_edges(q: int, strength: float, bins: int) -> np.ndarray:
    half = q + 0.5 * strength + 0.5
    return np.linspace(-half, half, bins + 1)


def _edges(name: str, edges) -> np.ndarray:
    # window edges may be +-inf (the default's outer windows), so not _validate.real_array
    if isinstance(edges, (str, bytes, bool)) or edges is None:
        raise ValueError(f"{name} must be at least two increasing numbers.")
    try:
        e = np.asarray(edges)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be at least two increasing numbers.") from None
    if e.dtype.kind not in "iuf":
        raise ValueError(f"{name} must be at least two increasing numbers.")
    e = e.astype(float)
    if e.ndim != 1 or e.size < 2 or np.any(np.isnan(e)) or np.any(np.diff(e) <= 0):
        raise ValueError(f"{name} must be at least two increasing numbers.")
    return e


def _check_size(lattice: Lattice) -> None:
    if lattice.sites > DENSE_MAX:
        raise ValueError(f"a disorder realization is a dense diagonalisation of all {lattice.sites:,} sites "
                         f"(the rotation symmetry is gone); the limit is {DENSE_MAX:,}.")


def realization_observables(lattice: Lattice, model: str = "box", strength: float = 1.0, *, seed: int = 0,
                            realization: int = 0, omega0: float | None = None, windows=None,
                            dos_bins: int = 60, ipr: bool = True) -> dict:
    r"""All spectral observables of one disorder realization (the unit of work of a sweep).

    Parameters
    ----------
    lattice : Lattice or Cluster
        A flake (``ring_lattice``, sites or line graph) or a periodic cluster, at most
        :data:`DENSE_MAX` sites (each realization is one dense diagonalisation).
    model : str, optional
        Disorder model of :func:`hyperlattice.graph.disorder.disorder` (``"box"``, ...).
        Default ``"box"``.
    strength : float, optional
        W (or sigma for the resonator model), units of t. Default 1.
    seed : int, optional
        Seed of the ensemble. Default 0.
    realization : int, optional
        Index of the realization within the ensemble of ``seed`` (0-based). Default 0.
    omega0 : float, optional
        Resonator frequency of the resonator model (see
        :func:`hyperlattice.graph.disorder.disorder`).
    windows : array_like, optional
        Energy window edges, increasing (default :func:`default_windows`).
    dos_bins : int, optional
        Number of histogram bins of the density of states. Default 60.
    ipr : bool, optional
        Compute eigenvectors for the inverse participation ratios (about 2x the time).
        Default True.

    Returns
    -------
    dict
        ``r_sum, r_count`` (all ratios), ``r_mean`` (nan if none), ``r_window_sum``,
        ``r_window_count`` (per window of ``windows``), ``ipr_window_sum``, ``ipr_window_count``
        (per window, eigenstates counted by energy; zeros if ``ipr`` is False), ``dos_counts``
        (histogram over :func:`_dos_edges`), ``e_min``, ``e_max``. Sums and counts, so that
        realizations pool exactly.

    Raises
    ------
    ValueError
        For bad input, or a lattice of more than :data:`DENSE_MAX` sites.

    See Also
    --------
    disorder_ensemble : pools these rows over realizations.

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.compare.disorder import realization_observables
    >>> row = realization_observables(hl.ring_lattice(7, 3, 3), "box", 1.0, seed=1)
    >>> row["r_count"]
    110
    >>> print(f"{row['r_mean']:.4f}")
    0.5292
    """
    lattice = _system(lattice)
    _check_size(lattice)
    win = default_windows(lattice.q) if windows is None else _edges("windows", windows)
    dos_bins = _validate.positive_int("dos_bins", dos_bins, maximum=100_000)
    ipr = _validate.flag("ipr", ipr)
    dis = disorder(lattice, model, strength, seed=seed, realization=realization, omega0=omega0)
    h = disordered_hamiltonian(lattice, dis).toarray()
    with _single_thread():
        if ipr:
            e, v = sla.eigh(h, driver="evd")
        else:
            e = sla.eigh(h, eigvals_only=True, driver="evd")
    r, mid = spacing_ratios(e)
    k = win.size - 1
    idx = np.searchsorted(win, mid, side="right") - 1
    ok = (idx >= 0) & (idx < k)
    r_wsum = np.bincount(idx[ok], weights=r[ok], minlength=k)[:k]
    r_wcnt = np.bincount(idx[ok], minlength=k)[:k]
    if ipr:
        p = inverse_participation(v)
        ie = np.searchsorted(win, e, side="right") - 1
        ok = (ie >= 0) & (ie < k)
        i_wsum = np.bincount(ie[ok], weights=p[ok], minlength=k)[:k]
        i_wcnt = np.bincount(ie[ok], minlength=k)[:k]
    else:
        i_wsum, i_wcnt = np.zeros(k), np.zeros(k, dtype=np.int64)
    dos, _ = np.histogram(e, bins=_dos_edges(lattice.q, dis.strength if model != "resonator"
                                             else 2.0 * dis.strength * (omega0 or 0.0), dos_bins))
    return {"r_sum": float(r.sum()), "r_count": int(r.size), "r_mean": float(r.mean()) if r.size else math.nan,
            "r_window_sum": r_wsum.astype(float), "r_window_count": r_wcnt.astype(np.int64),
            "ipr_window_sum": i_wsum.astype(float), "ipr_window_count": i_wcnt.astype(np.int64),
            "dos_counts": dos.astype(np.int64), "e_min": float(e[0]), "e_max": float(e[-1])}


@dataclass(frozen=True, eq=False, kw_only=True)
class DisorderEnsemble(Result):
    r"""Disorder-averaged spectral observables of one lattice at one strength.

    ``r_mean`` pools every ratio of every realization; ``r_err`` is the standard error from the
    scatter of the per-realization means (with one realization: the scatter of the ratios over
    :math:`\sqrt n`, which ignores their weak correlation). Window arrays follow ``windows``
    (edges); ``dos`` is the density of states per site and unit energy on ``dos_edges``.

    Attributes
    ----------
    p, q, rings : int
        The lattice.
    kind : str
        ``"sites"`` or ``"line_graph"``.
    sites : int
        Number of sites N.
    model : str
        Disorder model (:data:`hyperlattice.graph.disorder.MODELS`).
    W : float
        Strength: W in units of t, or the relative spread sigma of the resonator model.
    seed : int
        Seed of the draws (realization k is a pure function of seed and k).
    realizations : int
        Number of realizations.
    omega0 : float or None
        :math:`\omega_0/t` of the resonator model.
    r_mean, r_err : float
        Mean spacing ratio over all realizations and its standard error.
    r_count : int
        Number of ratios pooled.
    windows : ndarray
        Edges of the energy windows (units of t; open outer ends are -inf / inf).
    r_window, r_window_count, ipr_window : ndarray
        Per window: mean ratio, number of ratios, mean inverse participation ratio.
    dos_edges : ndarray
        Histogram edges of the density of states, units of t.
    dos : ndarray
        Density of states per site and unit energy (units of 1/t).
    r_realization : ndarray, shape (realizations,)
        Mean ratio of each realization.

    Examples
    --------
    >>> import hyperlattice as hl
    >>> ens = hl.disorder_ensemble(hl.ring_lattice(7, 3, 3), 2.0, realizations=3, seed=1)
    >>> ens.model, ens.W, ens.r_count, ens.windows.tolist()
    ('box', 2.0, 330, [-inf, -2.0, -1.0, 0.0, 1.0, 2.0, inf])
    >>> print(f"{ens.r_mean:.4f} +- {ens.r_err:.4f}")
    0.5434 +- 0.0136
    """

    #: one row per energy window; an open end of the outer windows is -inf / inf here (null in JSON)
    COLUMNS = (Column("window_low", "window_low", "t"), Column("window_high", "window_high", "t"),
               Column("r", "r_window", "1"), Column("r_count", "r_window_count", "1"),
               Column("ipr", "ipr_window", "1"))

    p: int
    q: int
    rings: int
    kind: str
    sites: int
    model: str
    W: float
    seed: int
    realizations: int
    omega0: float | None
    r_mean: float
    r_err: float
    r_count: int
    windows: np.ndarray = field(repr=False)
    r_window: np.ndarray = field(repr=False)
    r_window_count: np.ndarray = field(repr=False)
    ipr_window: np.ndarray = field(repr=False)
    dos_edges: np.ndarray = field(repr=False)
    dos: np.ndarray = field(repr=False)
    r_realization: np.ndarray = field(repr=False)

    @property
    def window_low(self) -> np.ndarray:
        """Lower edge of each energy window (-inf for the first)."""
        return self.windows[:-1]

    @property
    def window_high(self) -> np.ndarray:
        """Upper edge of each energy window (inf for the last)."""
        return self.windows[1:]

    def summary(self) -> dict:
        """The ``disorder`` command's JSON: W, realizations, seed, r_mean, r_err (the contract) and more."""
        return {"W": self.W, "realizations": self.realizations, "seed": self.seed, "r_mean": self.r_mean,
                "r_err": self.r_err, "r_count": self.r_count, "model": self.model, "p": self.p, "q": self.q,
                "rings": self.rings, "kind": self.kind, "sites": self.sites, "goe": GOE_R, "poisson": POISSON_R,
                # each window as [low, high]; null is an open end (the outer windows), so the
                # list holds numbers and nulls only
                "windows": [[None if np.isinf(lo) else float(lo), None if np.isinf(hi) else float(hi)]
                            for lo, hi in zip(self.windows[:-1], self.windows[1:])],
                "r_window": self.r_window.tolist(),
                "ipr_window": self.ipr_window.tolist()}


def _pool(p, q, rings, kind, sites, model, strength, seed, realizations, omega0, rows, windows, dos_edges):
    r_sum = np.array([row["r_sum"] for row in rows])
    r_cnt = np.array([row["r_count"] for row in rows])
    total = int(r_cnt.sum())
    r_mean = float(r_sum.sum() / total) if total else math.nan
    per = np.array([row["r_mean"] for row in rows])
    if len(rows) >= 2:
        good = per[np.isfinite(per)]
        r_err = float(np.std(good, ddof=1) / math.sqrt(good.size)) if good.size >= 2 else math.nan
    else:
        r_err = math.nan
    wsum = np.sum([row["r_window_sum"] for row in rows], axis=0)
    wcnt = np.sum([row["r_window_count"] for row in rows], axis=0)
    isum = np.sum([row["ipr_window_sum"] for row in rows], axis=0)
    icnt = np.sum([row["ipr_window_count"] for row in rows], axis=0)
    with np.errstate(invalid="ignore", divide="ignore"):
        r_win = np.where(wcnt > 0, wsum / np.maximum(wcnt, 1), np.nan)
        ipr_win = np.where(icnt > 0, isum / np.maximum(icnt, 1), np.nan)
    counts = np.sum([row["dos_counts"] for row in rows], axis=0)
    dos = counts / (len(rows) * sites * np.diff(dos_edges))
    return DisorderEnsemble(p=p, q=q, rings=rings, kind=kind, sites=sites, model=model, W=strength, seed=seed,
                            realizations=realizations, omega0=omega0, r_mean=r_mean, r_err=r_err, r_count=total,
                            windows=windows, r_window=r_win, r_window_count=wcnt, ipr_window=ipr_win,
                            dos_edges=dos_edges, dos=dos, r_realization=per)


def disorder_ensemble(lattice: Lattice, strength: float = 1.0, realizations: int = 10, *, seed: int = 0,
                      model: str = "box", omega0: float | None = None, windows=None, dos_bins: int = 60,
                      ipr: bool = True, rows: list[dict] | None = None, progress=None) -> DisorderEnsemble:
    r"""Average :func:`realization_observables` over realizations ``range(realizations)`` of ``seed``.

    Parameters
    ----------
    lattice : Lattice or Cluster
        A flake (``ring_lattice``, sites or line graph) or a periodic cluster, at most
        :data:`DENSE_MAX` sites (each realization is one dense diagonalisation).
    strength : float, optional
        W (or sigma for the resonator model), units of t, see
        :func:`hyperlattice.graph.disorder.disorder`. Default 1.
    realizations : int, optional
        Number of realizations, 1 to 1 000 000. Default 10.
    seed : int, optional
        Seed of the ensemble (realization k is the same in any process). Default 0.
    model : str, optional
        Disorder model (``"box"``, ``"gaussian"``, ``"resonator"``, ...), see
        :func:`hyperlattice.graph.disorder.disorder`. Default ``"box"``.
    omega0 : float, optional
        Resonator frequency of the resonator model, see
        :func:`hyperlattice.graph.disorder.disorder`.
    windows : array_like, optional
        Energy window edges (default :func:`default_windows`).
    dos_bins : int, optional
        Number of histogram bins of the density of states. Default 60.
    ipr : bool, optional
        Compute eigenvectors for the inverse participation ratios (about 2x the time).
        Default True.
    rows : list of dict, optional
        Precomputed per-realization results (e.g. read from a sweep table) instead of computing.
    progress : bool, None or callable
        A bar over the realizations on stderr (:mod:`hyperlattice._progress`; None: when stderr is a
        terminal), or a function receiving one-line messages.

    Returns
    -------
    DisorderEnsemble
        ``r_mean`` (all ratios pooled) with ``r_err``, the per-window ``r_window`` and
        ``ipr_window`` on ``windows``, the density of states per site ``dos`` on ``dos_edges``,
        and the per-realization means ``r_realization``.

    Raises
    ------
    ValueError
        For bad input, a lattice of more than :data:`DENSE_MAX` sites, or ``rows`` that are not
        ``realizations`` rows of :func:`realization_observables` for this lattice, windows and
        ``dos_bins``.

    See Also
    --------
    realization_observables : one realization.
    r_scan : the mean ratio against W.

    Examples
    --------
    >>> import hyperlattice as hl
    >>> lat = hl.ring_lattice(7, 3, 3)
    >>> ens = hl.disorder_ensemble(lat, 2.0, realizations=3, seed=1)
    >>> ens.r_count
    330
    >>> print(f"{ens.r_mean:.4f} +- {ens.r_err:.4f}")
    0.5434 +- 0.0136
    """
    lattice = _system(lattice)
    _check_size(lattice)
    model = _validate.choice("model", model, MODELS)
    realizations = _validate.positive_int("realizations", realizations, maximum=MAX_REALIZATIONS)
    win = default_windows(lattice.q) if windows is None else _edges("windows", windows)
    dos_bins = _validate.positive_int("dos_bins", dos_bins, maximum=100_000)
    dis0 = disorder(lattice, model, strength, seed=seed, realization=0, omega0=omega0)  # validates all
    progress = _validate.progress("progress", progress)
    if rows is None:
        from .._progress import progress_bar

        rows = []
        with progress_bar(realizations, "disorder", unit="realization", progress=progress) as bar:
            for k in range(realizations):
                rows.append(realization_observables(lattice, model, strength, seed=seed, realization=k,
                                                    omega0=omega0, windows=win, dos_bins=dos_bins, ipr=ipr))
                bar.update()
    else:
        rows = _rows(rows, realizations)
    spread = dis0.strength if model != "resonator" else 2.0 * dis0.strength * dis0.omega0
    try:
        return _pool(lattice.p, lattice.q, getattr(lattice, "rings", 0), getattr(lattice, "kind", "cluster"),
                 lattice.sites, model, dis0.strength,
                 dis0.seed, realizations, dis0.omega0, rows, win, _dos_edges(lattice.q, spread, dos_bins))
    except (TypeError, ValueError, IndexError) as exc:
        # rows of another lattice, window set or bin count: their arrays do not line up
        raise ValueError(f"rows do not match this ensemble (another lattice, windows or dos_bins?): {exc}"
                         .split("\n")[0]) from None


#: the keys a precomputed realization row must carry (see realization_observables)
_ROW_KEYS = ("r_sum", "r_count", "r_mean", "r_window_sum", "r_window_count", "ipr_window_sum",
             "ipr_window_count", "dos_counts")


def _rows(rows, realizations: int) -> list:
    if not isinstance(rows, (list, tuple)):
        raise ValueError(f"rows must be a list of dicts from realization_observables, got {type(rows).__name__}.")
    if len(rows) != realizations:
        raise ValueError(f"got {len(rows)} rows for {realizations} realizations.")
    for k, row in enumerate(rows):
        if not isinstance(row, dict):
            raise ValueError(f"rows[{k}] must be a dict from realization_observables, got {type(row).__name__}.")
        missing = [key for key in _ROW_KEYS if key not in row]
        if missing:
            raise ValueError(f"rows[{k}] lacks {', '.join(missing)} (not a realization_observables result).")
    return list(rows)


@dataclass(frozen=True, eq=False, kw_only=True)
class RScan(Result):
    """Mean spacing ratio against the disorder strength (one ensemble per strength).

    Attributes
    ----------
    p, q, rings, sites : int
        The lattice.
    model : str
        Disorder model.
    seed, realizations : int
        Seed and realizations per strength.
    window : ndarray, shape (2,)
        Energy window of the ratios, units of t (``[-inf, inf]``: the whole spectrum).
    W : ndarray
        The strengths, units of t.
    r_mean, r_err : ndarray
        Mean spacing ratio and its standard error at each strength (NaN where none fell in
        the window or fewer than two realizations contributed).

    Examples
    --------
    >>> import hyperlattice as hl
    >>> scan = hl.r_scan(hl.ring_lattice(7, 3, 3), [0.5, 4.0], realizations=2, window=None)
    >>> scan.W.tolist(), [round(float(r), 4) for r in scan.r_mean]
    ([0.5, 4.0], [0.3959, 0.4593])
    """

    COLUMNS = (Column("W", "W", "t"), Column("r_mean", "r_mean", "1"), Column("r_err", "r_err", "1"))

    p: int
    q: int
    rings: int
    sites: int
    model: str
    seed: int
    realizations: int
    window: np.ndarray
    W: np.ndarray
    r_mean: np.ndarray
    r_err: np.ndarray

    def summary(self) -> dict:
        """Every field in the plain JSON view, with ``window`` as ``[low, high]`` and null for an open
        end (``window=None``: the whole spectrum), the convention of :meth:`DisorderEnsemble.summary`."""
        out = super().summary()
        out["window"] = [None if np.isinf(v) else float(v) for v in self.window]
        return out


def r_scan(lattice: Lattice, strengths, realizations: int = 10, *, seed: int = 0, model: str = "box",
           window=(-1.0, 1.0)) -> RScan:
    r"""Mean spacing ratio :math:`\langle r\rangle` against W (ratios whose middle level lies in ``window``).

    The default :math:`|E| < 1` is the band centre, away from the band edges and the tails of
    boundary states, for weak disorder; ``window=None`` takes the whole spectrum (needed at strong
    disorder, where the levels spread over :math:`[-W/2, W/2]`). ``r_err`` is the standard error of
    the per-realization window means.

    Parameters
    ----------
    lattice : Lattice or Cluster
        A flake (``ring_lattice``, sites or line graph) or a periodic cluster, at most
        :data:`DENSE_MAX` sites (each realization is one dense diagonalisation).
    strengths : array_like of float
        Disorder strengths W >= 0 (units of t), one ensemble each.
    realizations : int, optional
        Realizations per strength, 1 to 1 000 000. Default 10.
    seed : int, optional
        Seed of the ensembles. Default 0.
    model : str, optional
        Disorder model, see :func:`hyperlattice.graph.disorder.disorder`. Default ``"box"``.
    window : (float, float) or None, optional
        ``(lo, hi)`` with lo < hi, units of t: keep ratios whose middle level lies in
        ``[lo, hi)``. Default ``(-1, 1)``; None for the whole spectrum.

    Returns
    -------
    RScan
        ``W``, ``r_mean`` and ``r_err`` (arrays over the strengths; NaN where no ratio fell in
        the window or fewer than two realizations contributed), and the ``window`` edges.

    Raises
    ------
    ValueError
        For bad input, an empty or negative list of strengths, a window with lo >= hi, or a
        lattice of more than :data:`DENSE_MAX` sites.

    See Also
    --------
    disorder_ensemble : all observables at one strength.
    GOE_R, POISSON_R : the two limits of the mean ratio.

    Examples
    --------
    >>> import hyperlattice as hl
    >>> lat = hl.ring_lattice(7, 3, 3)
    >>> scan = hl.r_scan(lat, [0.5, 4.0], realizations=2, window=None)
    >>> [round(float(r), 4) for r in scan.r_mean]
    [0.3959, 0.4593]
    """
    lattice = _system(lattice)
    _check_size(lattice)
    realizations = _validate.positive_int("realizations", realizations, maximum=MAX_REALIZATIONS)
    model = _validate.choice("model", model, MODELS)
    ws = _validate.real_array("strengths", strengths, ndim=1)
    if ws.size == 0 or np.any(ws < 0):
        raise ValueError("strengths must be a non-empty list of numbers >= 0.")
    if window is None:
        edges = np.array([-np.inf, np.inf])
    else:
        edges = _validate.real_array("window", window, shape=(2,))
        if not edges[0] < edges[1]:
            raise ValueError("window must be (lo, hi) with lo < hi.")
    means, errs = [], []
    for w in ws:
        rows = [realization_observables(lattice, model, float(w), seed=seed, realization=k, windows=edges, ipr=False)
                for k in range(realizations)]
        s = np.array([row["r_window_sum"][0] for row in rows])
        c = np.array([row["r_window_count"][0] for row in rows])
        means.append(float(s.sum() / c.sum()) if c.sum() else math.nan)
        per = s[c > 0] / c[c > 0]
        errs.append(float(np.std(per, ddof=1) / math.sqrt(per.size)) if per.size >= 2 else math.nan)
    return RScan(p=lattice.p, q=lattice.q, rings=getattr(lattice, "rings", 0), sites=lattice.sites, model=model, seed=seed,
                 realizations=realizations, window=edges, W=ws, r_mean=np.array(means), r_err=np.array(errs))


# ----------------------------------------------------------------------------
# Green functions: the ensemble average and the SCBA
# ----------------------------------------------------------------------------

@dataclass(frozen=True, eq=False, kw_only=True)
class DisorderGreen(Result):
    r"""Disorder-averaged column :math:`\langle G_{ij}(\omega)\rangle` for source j.

    ``mean`` averages the realizations and their mirror images :math:`V \to -V` (antithetic
    pairs: unbiased for symmetric distributions, and the odd orders of the Born series cancel
    exactly in every pair, which leaves the :math:`W^2` term without first-order noise);
    ``err`` is the standard error of the mean over pairs. ``clean`` is the W = 0 column.

    Attributes
    ----------
    p, q, rings : int
        The lattice.
    model : str
        Disorder model.
    W : float
        Strength, units of t.
    variance : float
        On-site variance :math:`\langle V^2\rangle` (:math:`W^2/12` for the box), units of :math:`t^2`.
    seed, realizations : int
        Seed and number of realizations.
    omega : complex
        Frequency, units of t.
    source : int
        Source site j (0-based).
    distance : ndarray, shape (N,)
        Hyperbolic distance of each site to the source (paper's metric).
    clean, mean, err : ndarray, shape (N,)
        The clean column, the disorder average and its standard error (units of 1/t).

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.compare.disorder import green_ensemble
    >>> ge = green_ensemble(hl.ring_lattice(7, 3, 3), -2.9 + 0.2j, 1.0, realizations=4)
    >>> ge.mean.shape, round(ge.variance, 6)
    ((112,), 0.083333)
    >>> print(f"{abs(ge.mean[0]):.4f} {abs(ge.clean[0]):.4f}")
    0.6640 0.6660
    """

    COLUMNS = (Column("distance", "distance", "hyperbolic distance"), Column("clean", "clean", "1/t"),
               Column("mean", "mean", "1/t"), Column("err", "err", "1/t"))

    p: int
    q: int
    rings: int
    model: str
    W: float
    variance: float
    seed: int
    realizations: int
    omega: complex
    source: int
    distance: np.ndarray = field(repr=False)
    clean: np.ndarray = field(repr=False)
    mean: np.ndarray = field(repr=False)
    err: np.ndarray = field(repr=False)


def _omega_upper(omega) -> complex:
    om = _validate.complex_number("omega", omega)
    if om.imag <= 0:
        raise ValueError(f"omega must have a positive imaginary part (retarded, off the spectrum), got {om:g}.")
    return om


def _column(h, omega: complex, source: int) -> np.ndarray:
    r"""Column ``source`` of :math:`(H-\omega)^{-1}` by sparse LU (graph/factor; the fill-in is small)."""
    from ..graph.factor import factorize

    n = h.shape[0]
    rhs = np.zeros(n, complex)
    rhs[source] = 1.0
    return factorize(h, omega, pivoting=True, what=f"H - omega of a disordered {n:,}-site lattice").solve(rhs)


def green_ensemble(lattice: Lattice, omega, strength: float, realizations: int = 20, *, seed: int = 0,
                   source: int = 0, model: str = "box") -> DisorderGreen:
    r"""Average the column :math:`G_{\cdot j}(\omega)` over antithetic pairs of realizations.

    Parameters
    ----------
    lattice : Lattice
        A flake (sites kind: the distances are those of the Poincaré disk).
    omega : complex
        Frequency (units of t) with Im omega > 0 (retarded, off the spectrum).
    strength : float
        W of the on-site model (box or gaussian), units of t.
    realizations : int, optional
        Number of pairs (2 x realizations solves). Default 20.
    seed : int, optional
        Seed of the ensemble. Default 0.
    source : int, optional
        Source site j (0-based). Default 0.
    model : {"box", "gaussian"}, optional
        The on-site distribution. Default ``"box"``.

    Returns
    -------
    DisorderGreen
        ``mean`` (the averaged column :math:`\langle G_{ij}(\omega)\rangle`, units of 1/t) with
        its standard error ``err`` (NaN for one pair), the clean column ``clean``, the hyperbolic
        ``distance`` of each site to the source and the on-site ``variance``.

    Raises
    ------
    ValueError
        For bad input, a line-graph or cluster lattice, Im omega <= 0, or more than
        :data:`DENSE_MAX` sites.

    See Also
    --------
    compare_scba : the average against the SCBA.

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.compare.disorder import green_ensemble
    >>> lat = hl.ring_lattice(7, 3, 3)
    >>> ge = green_ensemble(lat, -2.9 + 0.2j, 1.0, realizations=4)
    >>> print(f"{abs(ge.mean[0]):.4f} {abs(ge.clean[0]):.4f}")
    0.6640 0.6660
    """
    _validate.lattice(lattice, kind="sites")
    _check_size(lattice)
    om = _omega_upper(omega)
    model = _validate.choice("model", model, ("box", "gaussian"))
    realizations = _validate.positive_int("realizations", realizations, maximum=MAX_REALIZATIONS)
    source = _validate.site_index("source", source, lattice.sites)
    import scipy.sparse as sp

    h0 = disordered_hamiltonian(lattice, disorder(lattice, model, 0.0, seed=seed))
    with _single_thread():
        g0 = _column(h0, om, source)
        cols = []
        for k in range(realizations):
            v = sp.diags(disorder(lattice, model, strength, seed=seed, realization=k).onsite)
            cols.append(0.5 * (_column(h0 + v, om, source) + _column(h0 - v, om, source)))
    cols = np.array(cols)
    mean = cols.mean(axis=0)
    err = cols.std(axis=0, ddof=1) / math.sqrt(realizations) if realizations > 1 else np.full(mean.shape, np.nan)
    return DisorderGreen(p=lattice.p, q=lattice.q, rings=lattice.rings, model=model, W=float(strength),
                         variance=onsite_variance(model, strength), seed=int(seed), realizations=realizations,
                         omega=om, source=source, distance=distance(lattice.z, lattice.z[source]), clean=g0,
                         mean=mean, err=err)


def graph_scba(lattice: Lattice, omega, variance: float, *, tol: float = 1e-12, max_iter: int = 2000,
               damping: float = 1.0) -> tuple[np.ndarray, int]:
    r"""The SCBA on the graph: :math:`\Sigma_i = w^2[(H_0 - \omega - \Sigma)^{-1}]_{ii}`, per site.

    Plain fixed-point iteration (``damping = 1``) converges in 6-40 steps for w^2 <= 1.3 at
    :math:`\omega = -2.9 + 0.2i` (the map contracts by about :math:`w^2|G|^2`); lower ``damping``
    for stronger disorder. Its first order, :math:`\Sigma_i = w^2 G^{(0)}_{ii}(\omega)`,
    is exact second-order perturbation theory; :math:`(H_0-\omega-\Sigma)^{-1}` then predicts
    :math:`\langle G\rangle`.

    Parameters
    ----------
    lattice : Lattice or Cluster
        A flake (``ring_lattice``, sites or line graph) or a periodic cluster, at most
        :data:`DENSE_MAX` sites (each realization is one dense diagonalisation).
    omega : complex
        Frequency (units of t) with Im omega > 0.
    variance : float
        On-site variance :math:`w^2 \ge 0` (units of :math:`t^2`; :math:`W^2/12` for the box
        model).
    tol : float, optional
        Stop when the update is below ``tol`` times ``max(1, max |Sigma|)``; 1e-15 to 1e-2.
        Default 1e-12.
    max_iter : int, optional
        Largest number of iterations. Default 2000.
    damping : float, optional
        Mixing of the new self-energy, in (0, 1]. Default 1 (plain iteration).

    Returns
    -------
    sigma : ndarray of complex, shape (N,)
        The self-energy :math:`\Sigma_i` of every site (units of t).
    iterations : int
        Iterations used.

    Raises
    ------
    ValueError
        For bad input, Im omega <= 0, or more than :data:`DENSE_MAX` sites.
    hyperlattice.errors.ConvergenceError
        If the damped fixed-point iteration does not reach ``tol`` (the residual is stated).

    See Also
    --------
    hyperlattice.continuum.scba.scba : the continuum SCBA.
    compare_scba

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.compare.disorder import graph_scba
    >>> sigma, iterations = graph_scba(hl.ring_lattice(7, 3, 3), -2.9 + 0.2j, 1 / 12)
    >>> iterations
    11
    >>> print(f"{sigma[0].real:.5f} {sigma[0].imag:.5f}")
    0.04691 0.02732
    """
    from ..errors import ConvergenceError

    lattice = _system(lattice)
    _check_size(lattice)
    om = _omega_upper(omega)
    w2 = _validate.real("variance", variance, minimum=0.0, maximum=1e12)
    tol = _validate.real("tol", tol, minimum=1e-15, maximum=1e-2)
    max_iter = _validate.positive_int("max_iter", max_iter, maximum=100_000)
    damping = _validate.damping("damping", damping, tol, 100_000) if w2 > 0 else \
        _validate.real("damping", damping, minimum=0.0, maximum=1.0, open_min=True)
    h0 = disordered_hamiltonian(lattice, disorder(lattice, "box", 0.0)).toarray().astype(complex)
    n = lattice.sites
    sigma = np.zeros(n, complex)
    with _single_thread():
        for it in range(1, max_iter + 1):
            a = h0.copy()
            a[np.diag_indices(n)] -= om + sigma
            target = w2 * np.diag(np.linalg.inv(a))
            res = float(np.max(np.abs(target - sigma))) if n else 0.0
            if res <= tol * max(1.0, float(np.max(np.abs(sigma))) if n else 1.0):
                return target, it
            sigma = (1.0 - damping) * sigma + damping * target
    raise ConvergenceError(f"the graph SCBA did not converge in {max_iter} iterations (residual {res:.1e}).")


@dataclass(frozen=True, eq=False, kw_only=True)
class SCBAComparison(Result):
    r"""Graph ensemble average against the SCBA, one row per W.

    Columns (arrays over W): ``variance`` :math:`W^2/12`; ``rel_clean``, ``rel_graph_scba``,
    ``rel_continuum_scba``: relative L2 distance (source excluded) of the ensemble average from the
    clean column, from the graph SCBA prediction and from the continuum SCBA prediction (``eq21`` at
    :math:`\tilde\omega`); ``rel_noise``: the statistical error of the average on the same scale;
    ``sigma_graph`` (site average of the graph SCBA self-energy over the interior, rings < l),
    ``sigma_continuum``; ``born_ratio``: :math:`\|\langle G\rangle - G_0\|/\|w^2 G_0 \mathrm{diag}(G_0) G_0\|`
    projected on the latter (1 in the weak-disorder limit).

    Attributes
    ----------
    p, q, rings : int
        The lattice.
    omega : complex
        Frequency, units of t.
    source : int
        Source site j (0-based).
    seed, realizations : int
        Seed and realizations per strength.
    W, variance : ndarray
        Box widths (units of t) and :math:`W^2/12` (units of :math:`t^2`).
    rel_clean, rel_graph_scba, rel_continuum_scba, rel_noise : ndarray
        Relative L2 distances described above.
    born_ratio : ndarray
        The Born projection described above.
    sigma_graph, sigma_continuum : ndarray of complex
        SCBA self-energies, units of t.
    continuum_floor : float
        The same relative distance at W = 0 (clean graph against ``eq21``): the part of the
        disagreement that is the clean dictionary's, not the SCBA's.

    Examples
    --------
    >>> import hyperlattice as hl
    >>> cmp = hl.compare_scba(hl.ring_lattice(7, 3, 3), -2.9 + 0.2j, [1.0], realizations=4)
    >>> print(f"{cmp.rel_clean[0]:.4f} {cmp.rel_graph_scba[0]:.4f} {cmp.continuum_floor:.4f}")
    0.1926 0.0567 0.0993
    """

    COLUMNS = (Column("W", "W", "t"), Column("variance", "variance", "t^2"),
               Column("rel_clean", "rel_clean", "1"), Column("rel_graph_scba", "rel_graph_scba", "1"),
               Column("rel_continuum_scba", "rel_continuum_scba", "1"), Column("rel_noise", "rel_noise", "1"),
               Column("born_ratio", "born_ratio", "1"), Column("sigma_graph", "sigma_graph", "t"),
               Column("sigma_continuum", "sigma_continuum", "t"))

    p: int
    q: int
    rings: int
    omega: complex
    source: int
    seed: int
    realizations: int
    W: np.ndarray
    variance: np.ndarray
    rel_clean: np.ndarray
    rel_graph_scba: np.ndarray
    rel_continuum_scba: np.ndarray
    rel_noise: np.ndarray
    born_ratio: np.ndarray
    sigma_graph: np.ndarray
    sigma_continuum: np.ndarray
    continuum_floor: float

    def rows(self) -> list[dict]:
        """One dict per W (for tables)."""
        return [{"W": float(self.W[i]), "variance": float(self.variance[i]), "rel_clean": float(self.rel_clean[i]),
                 "rel_graph_scba": float(self.rel_graph_scba[i]),
                 "rel_continuum_scba": float(self.rel_continuum_scba[i]), "rel_noise": float(self.rel_noise[i]),
                 "born_ratio": float(self.born_ratio[i]), "sigma_graph": complex(self.sigma_graph[i]),
                 "sigma_continuum": complex(self.sigma_continuum[i])} for i in range(self.W.size)]


def _rel(a: np.ndarray, b: np.ndarray, keep: np.ndarray) -> float:
    return float(np.linalg.norm(a[keep] - b[keep]) / np.linalg.norm(a[keep]))


def compare_scba(lattice: Lattice, omega, strengths, realizations: int = 20, *, seed: int = 0,
                 source: int = 0) -> SCBAComparison:
    r"""Box-disorder ensemble average of :math:`G_{\cdot j}(\omega)` against the graph and continuum SCBA.

    The continuum prediction is :math:`\frac{4\mathcal A}{qh^2}G(z_i, z_j, \lambda(\tilde\omega), L)`
    with :math:`\tilde\omega` from :func:`hyperlattice.continuum.scba.scba`; ``continuum_floor``
    is the same distance at W = 0 (clean graph against ``eq21``), the part of the disagreement
    that is the clean dictionary's and not the SCBA's.

    Parameters
    ----------
    lattice : Lattice
        A flake (sites kind), at most :data:`DENSE_MAX` sites.
    omega : complex
        Frequency (units of t) with Im omega > 0.
    strengths : array_like of float
        Box widths W > 0 (units of t), one ensemble each.
    realizations : int, optional
        Antithetic pairs per strength (:func:`green_ensemble`). Default 20.
    seed : int, optional
        Seed of the ensembles. Default 0.
    source : int, optional
        Source site j (0-based). Default 0.

    Returns
    -------
    SCBAComparison
        Arrays over W: ``variance``, the relative distances ``rel_clean``, ``rel_graph_scba``,
        ``rel_continuum_scba`` and ``rel_noise``, ``born_ratio``, ``sigma_graph`` and
        ``sigma_continuum``; and ``continuum_floor``.

    Raises
    ------
    ValueError
        For bad input, a line-graph or cluster lattice, Im omega <= 0, an empty list of
        strengths or one <= 0, or more than :data:`DENSE_MAX` sites.
    hyperlattice.errors.ConvergenceError
        If the graph or continuum SCBA does not converge.

    See Also
    --------
    green_ensemble, graph_scba, hyperlattice.continuum.scba.scba

    References
    ----------
    .. [1] I. Boettcher et al., Phys. Rev. A 102, 032208 (2020), Eq. (19) (source label
       ``eq21``) for the continuum column.

    Examples
    --------
    >>> import hyperlattice as hl
    >>> lat = hl.ring_lattice(7, 3, 3)
    >>> cmp = hl.compare_scba(lat, -2.9 + 0.2j, [1.0], realizations=4)
    >>> print(f"{cmp.rel_clean[0]:.4f} {cmp.rel_graph_scba[0]:.4f} {cmp.born_ratio[0]:.3f}")
    0.1926 0.0567 0.829
    """
    from ..continuum.green import continuum_green
    from ..continuum.scba import scba

    _validate.lattice(lattice, kind="sites")
    om = _omega_upper(omega)
    ws = _validate.real_array("strengths", strengths, ndim=1)
    if ws.size == 0 or np.any(ws <= 0):
        raise ValueError("strengths must be a non-empty list of numbers > 0.")
    source = _validate.site_index("source", source, lattice.sites)
    keep = np.arange(lattice.sites) != source
    h0 = disordered_hamiltonian(lattice, disorder(lattice, "box", 0.0)).toarray()
    with _single_thread():
        g0_full = sla.inv(h0.astype(complex) - om * np.eye(lattice.sites))
    g0 = g0_full[:, source]
    born_dir = g0_full @ (np.diag(g0_full) * g0)      # G0 diag(G0) G0 e_j: the W^2 coefficient / w^2
    interior = lattice.ring < lattice.rings

    def continuum_column(w: complex) -> np.ndarray:
        lam, pref = dictionary_parameters(w, lattice.p, lattice.q)
        vals = np.asarray(continuum_green(lattice.z, lattice.z[source], lam, lattice.radius, extend=True), complex)
        out = np.empty_like(vals)
        out.real = pref * vals.real        # part-wise: keeps inf + 0j at the source (excluded anyway)
        out.imag = pref * vals.imag
        return out

    floor = _rel(g0, continuum_column(om), keep)
    out = {k: [] for k in ("variance", "rel_clean", "rel_graph_scba", "rel_continuum_scba", "rel_noise",
                           "born_ratio", "sigma_graph", "sigma_continuum")}
    for w in ws:
        ens = green_ensemble(lattice, om, float(w), realizations, seed=seed, source=source)
        w2 = ens.variance
        sig, _ = graph_scba(lattice, om, w2)
        a = h0.astype(complex)
        a[np.diag_indices_from(a)] -= om + sig
        rhs = np.zeros(lattice.sites, complex)
        rhs[source] = 1.0
        pred = np.linalg.solve(a, rhs)
        cs = scba(om, w2, lattice.p, lattice.q)
        delta = ens.mean - g0
        out["variance"].append(w2)
        out["rel_clean"].append(_rel(ens.mean, g0, keep))
        out["rel_graph_scba"].append(_rel(ens.mean, pred, keep))
        out["rel_continuum_scba"].append(_rel(ens.mean, continuum_column(cs.omega_shifted), keep))
        out["rel_noise"].append(float(np.linalg.norm(ens.err[keep]) / np.linalg.norm(ens.mean[keep])))
        bd = w2 * born_dir
        out["born_ratio"].append(float((np.vdot(bd[keep], delta[keep]) / np.vdot(bd[keep], bd[keep])).real))
        out["sigma_graph"].append(complex(np.mean(sig[interior])))
        out["sigma_continuum"].append(cs.self_energy)
    return SCBAComparison(p=lattice.p, q=lattice.q, rings=lattice.rings, omega=om, source=source, seed=int(seed),
                          realizations=int(realizations), W=ws, continuum_floor=floor,
                          **{k: np.array(v) for k, v in out.items()})


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
