r"""The n = 1 Mott lobe from quantum Monte Carlo against mean field and the strong-coupling expansion.

On a finite graph of M sites the Mott state of filling 1 (N = M) gives way to one extra particle at
:math:`\mu_+ = E_0(M+1) - E_0(M)` and to one hole at :math:`\mu_- = E_0(M) - E_0(M-1)`. The
grand-canonical QMC (:func:`hyperlattice.bosons.qmc`) measures :math:`\langle N\rangle(\mu)`: the
boundaries are where :math:`\langle N\rangle = M \pm \tfrac12` (the middle of the step from M to
M ± 1). At temperature T the step has a width ~T and its middle is shifted by about
:math:`T \ln g` when g particle (hole) levels lie within T of the lowest; the shift vanishes once
βt exceeds the inverse spacing of the lowest particle levels (:func:`boundary_offset` states it
for the graph's own first-order particle band). Each boundary is located by Newton steps on
:math:`\langle N\rangle - (M\pm\tfrac12)` with the slope :math:`d\langle N\rangle/d\mu = \beta\,
\mathrm{var}\,N = M\kappa` that the same run measures, starting from the third-order
strong-coupling value; its error propagates the QMC errors of ⟨N⟩ and κ.

Compared on the same graph: Gutzwiller mean field (exact within mean field for a uniform μ: the
boundary :math:`\lambda_{\max} t/U = y(1-y)/(1+y)`, :mod:`hyperlattice.bosons.meanfield`) and the
third-order strong-coupling expansion (:mod:`hyperlattice.bosons.strong_coupling`); for the
infinite {7,3} lattice the mean-field tip through the spectral radius ρ. A periodic L × L square
lattice (:func:`square_lattice`) is the engine check against the known square-lattice tip
(t/U)_c = 0.05974 (Capogrosso-Sansone, Söyler, Prokof'ev and Svistunov, PRA 77, 015602 (2008)).

Where mean field stands: on the square lattice mean field puts the tip at
:math:`(t/U)_c = (3-2\sqrt2)/4 = 0.0429`, 28 % below the exact 0.0597; on a {7,3} lattice the
graph's own λ_max enters instead of the coordination.
"""

from __future__ import annotations

import dataclasses
import json
import math
import warnings

import numpy as np
import scipy.sparse as sp

from .. import _validate
from ..results import Column, Result

__all__ = ["square_lattice", "square_lattice_windings", "mean_field_boundaries", "qmc_boundary", "QMCLobe", "qmc_lobe", "SQUARE_TIP_EXACT",
           "CUBIC_TIP_EXACT",
           "gap_tip", "size_extrapolation", "combine_steps", "LINEAR_WINDOW", "system_spec",
           "SQUARE_TIP_MEAN_FIELD", "load_scan", "xy_qubit_check"]

#: the exact n = 1 tip of the square lattice, (U/t)_c = 16.7424(54): Capogrosso-Sansone et al., PRA 77, 015602 (2008)
SQUARE_TIP_EXACT = (1.0 / 16.7424, 0.0054 / 16.7424**2)
#: mean field on the square lattice: (t/U)_c = (3 - 2 sqrt 2)/z, z = 4
SQUARE_TIP_MEAN_FIELD = (3.0 - 2.0 * math.sqrt(2.0)) / 4.0
#: the exact n = 1 tip of the simple cubic lattice (z = 6), (U/t)_c = 29.34(2): Capogrosso-Sansone,
#: Prokof'ev and Svistunov, PRB 75, 134302 (2007); mean field there is (3 - 2 sqrt 2)/6
CUBIC_TIP_EXACT = (1.0 / 29.34, 0.02 / 29.34**2)


def square_lattice(L: int) -> sp.csr_matrix:
    r"""Adjacency of the periodic L × L square lattice (a torus, coordination 4).

    Parameters
    ----------
    L : int
        Linear size, 3 to 4096 (L >= 3 keeps the four neighbours distinct).

    Returns
    -------
    scipy.sparse.csr_matrix
        (L², L²) symmetric 0/1 matrix; site (i, j) is ``i * L + j``.

    Raises
    ------
    ValueError
        If L is out of range.

    Examples
    --------
    >>> from hyperlattice.compare.qmc_lobe import square_lattice
    >>> A = square_lattice(4)
    >>> A.shape, int(A.sum(axis=1).min()), int(A.sum(axis=1).max()), (A != A.T).nnz
    ((16, 16), 4, 4, 0)
    """
    L = _validate.integer("L", L, minimum=3, maximum=4096)
    idx = np.arange(L * L).reshape(L, L)
    rows = np.concatenate([idx.ravel(), idx.ravel()])
    cols = np.concatenate([np.roll(idx, 1, 0).ravel(), np.roll(idx, 1, 1).ravel()])
    a = sp.csr_matrix((np.ones(rows.size), (rows, cols)), shape=(L * L, L * L))
    return (a + a.T).tocsr()


def square_lattice_windings(L: int) -> tuple[np.ndarray, np.ndarray]:
    r"""Windings of the bonds of the periodic L × L square lattice (:func:`square_lattice`).

    The directed bond from site (i, j) to (i + 1, j) has winding (1, 0) when it crosses the seam
    (i = L − 1, i + 1 → 0) and (0, 0) otherwise; (i, j) → (i, j + 1) likewise (0, 1) at j = L − 1.
    The sum along a closed walk is then its winding around the two cycles of the torus, so a
    QMC configuration's total :math:`W = (W_x, W_y)` counts how often the world lines wind
    around each direction: pass the result as ``windings=`` to :func:`hyperlattice.bosons.qmc`
    for the superfluid stiffness :math:`\rho_s = \langle W_x^2 + W_y^2\rangle/(2\beta)`.

    Parameters
    ----------
    L : int
        Linear size, 3 to 4096 (as :func:`square_lattice`).

    Returns
    -------
    edges : ndarray of int64, shape (2L², 2)
        The bonds (i < j, site (x, y) is ``x * L + y``).
    windings : ndarray of int64, shape (2L², 2)
        The winding of the directed bond ``edges[k, 0] -> edges[k, 1]``.

    Raises
    ------
    ValueError
        If L is out of range.

    Examples
    --------
    >>> from hyperlattice.compare.qmc_lobe import square_lattice_windings
    >>> edges, w = square_lattice_windings(3)
    >>> edges.shape, int(abs(w).sum(axis=0)[0]), int(abs(w).sum(axis=0)[1])
    ((18, 2), 3, 3)
    """
    L = _validate.integer("L", L, minimum=3, maximum=4096)
    idx = np.arange(L * L).reshape(L, L)
    src = np.concatenate([idx.ravel(), idx.ravel()])
    dst = np.concatenate([np.roll(idx, -1, 0).ravel(), np.roll(idx, -1, 1).ravel()])
    w = np.zeros((2 * L * L, 2), dtype=np.int64)
    w[: L * L, 0] = (idx // L == L - 1).ravel()            # (x, y) -> (x + 1, y) across the seam
    w[L * L:, 1] = (idx % L == L - 1).ravel()              # (x, y) -> (x, y + 1) across the seam
    flip = src > dst
    w[flip] *= -1
    edges = np.stack([np.minimum(src, dst), np.maximum(src, dst)], axis=1).astype(np.int64)
    order = np.argsort(edges[:, 0] * L * L + edges[:, 1], kind="stable")
    return edges[order], w[order]


def mean_field_boundaries(lambda_max: float, t_over_U) -> tuple[np.ndarray, np.ndarray]:
    r"""Mean-field :math:`\mu_\pm/U` of the n = 1 lobe at given t/U (NaN beyond the tip).

    The two roots of :math:`\lambda_{\max}x = y(1-y)/(1+y)`, :math:`y = \mu/U`, x = t/U:
    :math:`y_\pm = \tfrac12[(1-\lambda x) \pm \sqrt{(1-\lambda x)^2 - 4\lambda x}]`.

    Parameters
    ----------
    lambda_max : float
        Largest adjacency eigenvalue of the graph (ρ for the infinite lattice), > 0.
    t_over_U : array_like of float
        Values >= 0.

    Returns
    -------
    mu_plus, mu_minus : ndarray
        In units of U.

    Raises
    ------
    ValueError
        If an argument is out of range.

    Examples
    --------
    >>> from hyperlattice.compare.qmc_lobe import mean_field_boundaries
    >>> mp, mm = mean_field_boundaries(4.0, [0.0, 0.02])
    >>> [round(float(v), 6) for v in mp], [round(float(v), 6) for v in mm]
    ([1.0, 0.822767], [0.0, 0.097233])
    """
    lam = _validate.positive_real("lambda_max", lambda_max)
    x = _validate.real_array("t_over_U", t_over_U)
    if x.size and np.any(x < 0):
        raise ValueError("t_over_U must be >= 0.")
    b = 1.0 - lam * x
    disc = b * b - 4.0 * lam * x
    ok = (disc >= 0) & (b > 0)
    r = np.sqrt(np.where(ok, disc, 0.0))
    return np.where(ok, 0.5 * (b + r), np.nan), np.where(ok, 0.5 * (b - r), np.nan)


def boundary_offset(system, beta_t: float) -> dict:
    r"""How far below the lowest particle levels a temperature reaches (a finite-T statement).

    The first-order particle band is :math:`-2tA`: its two lowest levels are split by
    :math:`\delta = 2t(\lambda_1 - \lambda_2)`. The step of :math:`\langle N\rangle(\mu)` is that of
    the ground state when :math:`\beta\delta \gg 1`; this returns δ/t and βδ.

    Parameters
    ----------
    system : Lattice, Cluster or sparse matrix
        The graph.
    beta_t : float
        βt > 0.

    Returns
    -------
    dict
        ``"splitting_over_t"`` and ``"beta_splitting"``.

    Raises
    ------
    ValueError
        If an argument is out of range.

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.compare.qmc_lobe import boundary_offset
    >>> off = boundary_offset(hl.ring_lattice(7, 3, 1), 10.0)
    >>> round(off["splitting_over_t"], 6), round(off["beta_splitting"], 4)
    (1.506041, 15.0604)
    """
    from ..bosons.meanfield import _adjacency

    b = _validate.positive_real("beta_t", beta_t)
    a = _adjacency(system)
    m = a.shape[0]
    if m <= 2000:
        w = np.linalg.eigvalsh(a.toarray())[::-1][:2]
    else:
        import scipy.sparse.linalg as spla

        w = np.sort(spla.eigsh(a, k=2, which="LA", tol=1e-10)[0])[::-1]
    d = 2.0 * float(w[0] - w[1]) if m > 1 else math.inf
    return {"splitting_over_t": d, "beta_splitting": b * d}


def qmc_boundary(system, t_over_U: float, side: str, *, beta_t: float = 10.0, sweeps: int = 2000, nmax: int = 3,
                 seed: int = 1, iterations: int = 3, mu_start: float | None = None,
                 thermalization: int | None = None) -> dict:
    r"""One boundary :math:`\mu_\pm/U` of the n = 1 lobe on a finite graph from QMC (Newton on ⟨N⟩).

    Parameters
    ----------
    system : Lattice, Cluster or sparse matrix
        The graph (t = 1 on its bonds).
    t_over_U : float
        x = t/U > 0.
    side : {"plus", "minus"}
        The particle (⟨N⟩ = M + 1/2) or hole (⟨N⟩ = M − 1/2) boundary.
    beta_t : float, optional
        βt. Default 10.
    sweeps : int, optional
        QMC sweeps per Newton step. Default 2000.
    nmax : int, optional
        Occupation cutoff (3 is exact to O((t/U)^4) for the n = 1 lobe). Default 3.
    seed : int, optional
        Seed of the first run (step k uses seed + k). Default 1.
    iterations : int, optional
        Newton steps, 1 to 10. Default 3.
    mu_start : float, optional
        Starting μ/U; default the third-order strong-coupling value.
    thermalization : int, optional
        Thermalisation sweeps of each run (default that of :func:`~hyperlattice.bosons.qmc`).

    Returns
    -------
    dict
        ``mu`` (μ±/U), ``mu_err``, ``steps`` (a list of the runs: ``mu``, ``N``, ``N_err``,
        ``kappa``, ``kappa_err``, ``tau_int``, ``converged``), ``sites``, ``t_over_U``, ``beta_t``,
        ``side``, ``sweeps``, ``nmax``, ``converged`` (False when a run that entered the
        estimate, or the last run when none did, has a binning error off its plateau, halves
        that disagree or a string that filled up: the boundary's error bar is then in doubt) and
        ``notes`` (those runs' reasons).

    Raises
    ------
    ValueError
        If an argument is out of range.
    """
    from ..bosons import qmc
    from ..bosons.strong_coupling import excitation_energies

    x = _validate.positive_real("t_over_U", t_over_U)
    side = _validate.choice("side", side, ("plus", "minus"))
    beta = _validate.positive_real("beta_t", beta_t)
    sweeps = _validate.integer("sweeps", sweeps, minimum=10, maximum=10**9)
    iterations = _validate.integer("iterations", iterations, minimum=1, maximum=10)
    U = 1.0 / x
    if mu_start is None:
        mp, mm = excitation_energies(system, [x])
        mu = float(mp[0] if side == "plus" else mm[0])
    else:
        mu = _validate.real("mu_start", mu_start)
    steps = []
    estimate = err = math.nan
    for k in range(iterations):
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            # only N and N^2 are needed: the one-body density matrix (worm estimator) is not measured
            r = qmc(system, U=U, mu=mu * U, beta=beta, nmax=nmax, t=1.0, sweeps=sweeps, seed=seed + k,
                    thermalization=thermalization, measure_green=False, progress=False)
        M = r.sites
        target = M + (0.5 if side == "plus" else -0.5)
        N, N_err = r.density * M, r.density_err * M
        slope, slope_err = r.compressibility * M * U, r.compressibility_err * M * U     # dN/d(mu/U)
        steps.append({"mu": mu, "N": N, "N_err": N_err, "kappa": r.compressibility, "seconds": r.seconds,
                      "kappa_err": r.compressibility_err, "tau_int": dict(r.tau_int), "converged": bool(r.converged),
                      "warnings": [str(w.message) for w in caught], "notes": list(r.notes)})
        delta = N - target
        # the step is clipped to a few temperatures: the linearisation holds within ~T of the step
        limit = 3.0 / (beta * U)
        if slope > 0:
            step = -delta / slope
        else:
            step = math.copysign(limit, -delta)
        step = max(-limit, min(limit, step))
        estimate = mu + step
        if slope > 0 and abs(step) < limit:
            err = math.hypot(N_err / slope, delta * slope_err / slope**2)
        else:
            err = math.nan
        mu = estimate
    comb, comb_err, used = combine_steps(steps, side, M, x, beta)
    if used:
        estimate, err = comb, comb_err
    # the runs behind the estimate: those inside the linear window, else the last Newton step
    behind = [s_ for s_ in steps if abs(s_["N"] - (M + (0.5 if side == "plus" else -0.5))) < LINEAR_WINDOW
              and s_["kappa"] > 0 and s_["N_err"] > 0] if used else steps[-1:]
    converged = all(s_["converged"] for s_ in behind)
    notes = sorted({n for s_ in behind if not s_["converged"] for n in s_["notes"]})
    return {"mu": estimate, "mu_err": err, "steps": steps, "sites": steps and M, "t_over_U": x, "beta_t": beta,
            "side": side, "sweeps": sweeps, "nmax": nmax, "steps_used": used, "converged": bool(converged),
            "notes": notes}


#: graphs below this size stay out of the size extrapolation: the heptagon and the l = 2 flake (35
#: sites) have their pseudo-tips at t/U > 0.12, twice the lattice's, far from any scaling form
MIN_SITES_EXTRAPOLATION = 50

#: a Newton step's run enters the boundary estimate when its <N> is within this of M +- 1/2: for a
#: two-level step (a logistic in mu) the straight line then misplaces the middle by < 0.04 T
LINEAR_WINDOW = 0.15


def combine_steps(steps: list, side: str, sites: int, t_over_U: float, beta_t: float) -> tuple[float, float, int]:
    r"""The boundary from every Newton run whose ⟨N⟩ lies near M ± 1/2 (weighted mean of their estimates).

    Each run at :math:`\mu_k` gives :math:`\mu_k - (\langle N\rangle_k - N^*)/(\beta M\kappa_k)`;
    runs with :math:`|\langle N\rangle_k - N^*| <` :data:`LINEAR_WINDOW` (where the straight line is
    accurate to a small fraction of T) are averaged with weights from their errors (⟨N⟩ and κ).

    Parameters
    ----------
    steps : list of dict
        The ``steps`` of :func:`qmc_boundary` (``mu``, ``N``, ``N_err``, ``kappa``, ``kappa_err``).
    side : {"plus", "minus"}
    sites : int
    t_over_U, beta_t : float

    Returns
    -------
    mu, mu_err : float
        μ±/U and its error (NaN, NaN when no run qualifies).
    used : int
        How many runs entered.

    Raises
    ------
    ValueError
        If an argument is out of range.

    Examples
    --------
    >>> from hyperlattice.compare.qmc_lobe import combine_steps
    >>> st = [{"mu": 0.50, "N": 10.55, "N_err": 0.02, "kappa": 0.05, "kappa_err": 0.001},
    ...       {"mu": 0.49, "N": 10.45, "N_err": 0.02, "kappa": 0.05, "kappa_err": 0.001}]
    >>> mu, err, used = combine_steps(st, "plus", 10, 0.1, 5.0)
    >>> round(mu, 4), used
    (0.495, 2)
    """
    side = _validate.choice("side", side, ("plus", "minus"))
    M = _validate.integer("sites", sites, minimum=1, maximum=10**9)
    x = _validate.positive_real("t_over_U", t_over_U)
    beta = _validate.positive_real("beta_t", beta_t)
    target = M + (0.5 if side == "plus" else -0.5)
    U = 1.0 / x
    est, wts = [], []
    for s_ in steps:
        delta = s_["N"] - target
        slope, slope_err = s_["kappa"] * M * U, s_["kappa_err"] * M * U
        if abs(delta) >= LINEAR_WINDOW or not slope > 0 or not s_["N_err"] > 0:
            continue
        e = math.hypot(s_["N_err"] / slope, delta * slope_err / slope**2)
        est.append(s_["mu"] - delta / slope)
        wts.append(1.0 / e**2)
    if not est:
        return math.nan, math.nan, 0
    w = np.array(wts)
    mu = float(np.dot(w, est) / w.sum())
    err = float(1.0 / math.sqrt(w.sum()))
    if len(est) > 1:
        # the runs must agree: a scatter larger than their errors widens the error (Birge ratio)
        chi2 = float(np.dot(w, (np.array(est) - mu) ** 2))
        err *= max(1.0, math.sqrt(chi2 / (len(est) - 1)))
    return mu, err, len(est)


@dataclasses.dataclass(frozen=True, eq=False)
class QMCLobe(Result):
    r"""QMC lobe boundaries of several graphs with mean field and strong coupling on the same graphs.

    Attributes
    ----------
    rows : list of dict
        One per QMC boundary: ``system``, ``sites``, ``t_over_U``, ``beta_t``, ``nmax``, ``side``, ``mu``,
        ``mu_err``, ``mu_mean_field``, ``mu_strong_coupling`` (all μ/U), ``lambda_max``.
    systems : list of dict
        One per graph: ``system``, ``sites``, ``lambda_max``, ``tip_mean_field``,
        ``tip_strong_coupling`` (t/U), the lines ``t_line``, ``mf_plus``, ``mf_minus``,
        ``sc_plus``, ``sc_minus``, ``splitting_over_t`` (δ/t of :func:`boundary_offset`) and
        ``tips``: one dict per (``beta_t``, ``nmax``) with the QMC ``gaps`` (t/U, Δ, error) and the
        pseudo-tips of :func:`gap_tip` (``tip``, ``tip_err``: Δ² form; ``tip_linear``,
        ``tip_linear_err``), ``chi2``, ``dof``, ``beta_splitting``.
    infinite_tip_mean_field : float
        The {7,3} mean-field tip through the spectral radius ρ.
    rho : float
        ρ of the infinite {7,3} lattice (the extrapolated band bottom).
    continuum : dict
        ``lambda_max`` (minus the continuum's band bottom, the paper's map) and its mean-field
        ``tip_mean_field``.
    square : dict
        The square-lattice reference: ``exact``, ``exact_err``, ``mean_field``, ``strong_coupling``;
        and the simple cubic one: ``cubic_exact``, ``cubic_exact_err``, ``cubic_mean_field``.
    finite_size : list of dict
        Per ``kind`` ("cluster" or "flake") and ``beta_t`` with two or more sizes: the pseudo-tips
        extrapolated in 1/M (``tip``, ``tip_err``) and in :math:`1/\sqrt M` (``tip_sqrt_form``),
        ``systematic`` their difference, ``sites``; ``slope`` and ``slope_sqrt_form`` (c of each
        form), ``chi2``, ``chi2_sqrt_form`` and ``dof`` (sizes − 2: with three or more sizes χ²
        tests the form; the errors are widened by √(χ²/dof) when that exceeds 1).
    """

    COLUMNS = (Column("t_over_U", "t_over_U", "1"), Column("mu", "mu", "U"), Column("mu_err", "mu_err", "U"))

    rows: list
    systems: list
    infinite_tip_mean_field: float
    rho: float
    continuum: dict
    square: dict
    finite_size: list = dataclasses.field(default_factory=list)

    def summary(self) -> dict:
        return {"rows": self.rows, "infinite_tip_mean_field": self.infinite_tip_mean_field, "square": self.square,
                "systems": [{k: v for k, v in s.items() if not isinstance(v, list)} if isinstance(s, dict) else s
                            for s in self.systems]}

    def _row_values(self, key: str) -> np.ndarray:
        return np.array([float(r[key]) if isinstance(r, dict) else math.nan for r in self.rows], dtype=float)

    @property
    def t_over_U(self) -> np.ndarray:
        """t/U of each QMC boundary point (the table's first column)."""
        return self._row_values("t_over_U")

    @property
    def mu(self) -> np.ndarray:
        """mu/U of each QMC boundary point."""
        return self._row_values("mu")

    @property
    def mu_err(self) -> np.ndarray:
        """The error bar of ``mu`` (units of U)."""
        return self._row_values("mu_err")


def _system(spec: str):
    """A graph from its scan name: ``flake:L``, ``cluster:NAME`` or ``square:L`` ({7,3}), or with the
    lattice first, ``{p,q}:flake:L`` and ``{p,q}:cluster:NAME`` (``hyperlattice bosons lobe``)."""
    from ..graph.clusters import pbc_cluster
    from ..graph.lattice import ring_lattice

    p, q = 7, 3
    if spec.startswith("{"):
        head, _, spec = spec.partition("}:")
        try:
            p, q = (int(v) for v in head[1:].split(","))
        except ValueError:
            raise ValueError(f"unknown system {head + '}:' + spec!r}: use {{p,q}}:flake:L or {{p,q}}:cluster:NAME.") from None
    kind, _, arg = spec.partition(":")
    if kind == "flake":
        return ring_lattice(p, q, int(arg))
    if kind == "cluster":
        return pbc_cluster(p, q, arg)
    if kind == "square":
        return square_lattice(int(arg))
    raise ValueError(f"unknown system {spec!r}: use flake:L, cluster:NAME or square:L.")


def system_spec(p: int, q: int, *, rings: int | None = None, cluster: str | None = None) -> str:
    """The scan name of a {p,q} flake or cluster (``flake:L``, ``cluster:NAME`` for {7,3}, else
    ``{p,q}:flake:L``, ``{p,q}:cluster:NAME``), as :func:`qmc_lobe` reads it back.

    Parameters
    ----------
    p, q : int
        The lattice.
    rings : int, optional
        A flake of this many rings.
    cluster : str, optional
        A periodic cluster's name (exactly one of ``rings`` and ``cluster``).

    Returns
    -------
    str

    Raises
    ------
    ValueError
        If an argument is out of range.

    Examples
    --------
    >>> from hyperlattice.compare.qmc_lobe import system_spec
    >>> system_spec(7, 3, rings=3), system_spec(8, 3, cluster="PSL(2,7)")
    ('flake:3', '{8,3}:cluster:PSL(2,7)')
    """
    p, q = _validate.pq(p, q)
    if (rings is None) == (cluster is None):
        raise ValueError("give exactly one of rings and cluster.")
    if rings is not None:
        body = f"flake:{_validate.integer('rings', rings, minimum=1)}"
    else:
        if not isinstance(cluster, str) or not cluster:
            raise ValueError(f"cluster must be a cluster's name, got {_validate._shown(cluster)}.")
        body = f"cluster:{cluster}"
    return body if (p, q) == (7, 3) else f"{{{p},{q}}}:{body}"


def _continuum_bottom() -> float:
    """The paper's continuum band bottom -3 + (3/4) h^2 of {7,3}: E(lambda = 1), the spectrum's edge."""
    from ..dictionary import energy_from_lambda

    return float(energy_from_lambda(1.0, 7, 3))


def gap_tip(t_over_U, gap, gap_err, *, form: str = "sqrt") -> dict:
    r"""The pseudo-tip of a finite graph: its Mott gap :math:`\Delta = \mu_+ - \mu_-` continued to zero.

    A finite graph has no transition and keeps a gap; near the tip of the infinite lattice the gap
    closes as :math:`\Delta \propto (x_c - x)^{z\nu}` (x = t/U). Mean field (Gutzwiller) has
    :math:`z\nu = 1/2`: its gap is :math:`\Delta^2 = (1-\lambda x)^2 - 4\lambda x`, a straight line in
    x up to a term :math:`\lambda^2x^2` that is 3 % of the linear term at the tip. ``form="sqrt"``
    fits :math:`\Delta^2 = a + bx` (the mean-field form), ``form="linear"`` fits
    :math:`\Delta = a + bx` (zν = 1); both by weighted least squares, :math:`x_c = -a/b`. Because
    the gap curve is concave in x, the straight line in Δ overshoots the tip and the one in Δ²
    (convex) undershoots it: the two bracket it when the exponent lies between 1/2 and 1.

    Parameters
    ----------
    t_over_U, gap, gap_err : array_like of float
        At least two points with gap > 0 and gap_err > 0 (units of U).
    form : {"sqrt", "linear", "power"}, optional
        The fitted form (default "sqrt"). ``"power"`` fits :math:`\Delta = A(x_c - x)^{p}` with the
        exponent p = zν free (at least four points).

    Returns
    -------
    dict
        ``tip`` (x_c), ``tip_err`` (from the fit's covariance, scaled by :math:`\sqrt{\chi^2/\nu}`
        when that exceeds 1), ``chi2``, ``dof``, ``slope``, ``points``, ``form``; for "power" also
        ``exponent`` and ``exponent_err``. ``tip`` is NaN when the gap does not decrease with x
        (or the power fit fails).

    Raises
    ------
    ValueError
        If the arrays differ in length, hold non-finite values, or fewer than two usable points.

    Examples
    --------
    >>> from hyperlattice.compare.qmc_lobe import gap_tip
    >>> r = gap_tip([0.05, 0.06, 0.07], [0.6, 0.5, 0.4], [0.01, 0.01, 0.01], form="linear")
    >>> round(r["tip"], 6), r["dof"]
    (0.11, 1)
    """
    form = _validate.choice("form", form, ("sqrt", "linear", "power"))
    x = _validate.real_array("t_over_U", t_over_U)
    g = _validate.real_array("gap", gap)
    e = _validate.real_array("gap_err", gap_err)
    if not (x.shape == g.shape == e.shape) or x.ndim != 1:
        raise ValueError("t_over_U, gap and gap_err must be 1-d arrays of one length.")
    if not (np.all(np.isfinite(x)) and np.all(np.isfinite(g)) and np.all(np.isfinite(e))):
        raise ValueError("t_over_U, gap and gap_err must be finite.")
    keep = (g > 0) & (e > 0)
    x, g, e = x[keep], g[keep], e[keep]
    if x.size < 2 or np.unique(x).size < 2:
        raise ValueError("the gap extrapolation needs at least two points at different t/U with gap > 0.")
    if form == "power":
        return _power_fit(x, g, e)
    y, s = (g * g, 2.0 * g * e) if form == "sqrt" else (g, e)
    w = 1.0 / s**2
    X = np.stack([np.ones_like(x), x], axis=1)
    cov = np.linalg.inv(X.T @ (X * w[:, None]))
    a, b = cov @ (X.T @ (w * y))
    chi2 = float(np.sum(w * (y - a - b * x) ** 2))
    dof = int(x.size - 2)
    if dof > 0 and chi2 / dof > 1.0:
        cov = cov * (chi2 / dof)
    out = {"form": form, "points": int(x.size), "chi2": chi2, "dof": dof, "slope": float(b),
           "tip": math.nan, "tip_err": math.nan}
    if b < 0:
        xc = -a / b
        grad = np.array([-1.0 / b, a / b**2])          # d xc / d(a, b)
        out["tip"] = float(xc)
        out["tip_err"] = float(math.sqrt(max(grad @ cov @ grad, 0.0)))
    return out


def _power_fit(x: np.ndarray, g: np.ndarray, e: np.ndarray) -> dict:
    """Delta = A (x_c - x)^p by weighted least squares, started from the straight-line fit."""
    from scipy.optimize import curve_fit

    if np.unique(x).size < 4:
        raise ValueError("the power-law gap fit needs at least four points at different t/U.")
    out = {"form": "power", "points": int(x.size), "chi2": math.nan, "dof": int(x.size - 3), "slope": math.nan,
           "tip": math.nan, "tip_err": math.nan, "exponent": math.nan, "exponent_err": math.nan}
    lin = gap_tip(x, g, e, form="linear")
    if not math.isfinite(lin["tip"]):
        return out
    xmax = float(x.max())

    def model(xx, amp, xc, p):
        return amp * np.clip(xc - xx, 1e-12, None) ** p

    p0 = (-lin["slope"], max(lin["tip"], xmax * (1 + 1e-6)), 1.0)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            par, cov = curve_fit(model, x, g, p0=p0, sigma=e, absolute_sigma=True, maxfev=20000,
                                 bounds=([0.0, xmax * (1 + 1e-9), 0.05], [np.inf, np.inf, 5.0]))
    except (RuntimeError, ValueError):
        return out
    chi2 = float(np.sum(((g - model(x, *par)) / e) ** 2))
    if out["dof"] > 0 and chi2 / out["dof"] > 1.0:
        cov = cov * (chi2 / out["dof"])
    err = np.sqrt(np.clip(np.diag(cov), 0.0, None))
    if not np.all(np.isfinite(err)):
        return out
    out.update({"chi2": chi2, "tip": float(par[1]), "tip_err": float(err[1]), "exponent": float(par[2]),
                "exponent_err": float(err[2]), "slope": -float(par[0])})
    return out


def size_extrapolation(sites, tip, tip_err, *, power: float = 1.0) -> dict:
    r"""Extrapolate pseudo-tips to the infinite graph: :math:`x_c(M) = x_\infty + c\,M^{-p}`.

    Weighted least squares over the graphs (with two graphs the line passes through both and the
    error is the propagated one).

    Parameters
    ----------
    sites : array_like of int
        Graph sizes M (at least two different).
    tip, tip_err : array_like of float
        Pseudo-tips and their errors (> 0).
    power : float, optional
        p > 0 (default 1: corrections in 1/M).

    Returns
    -------
    dict
        ``tip`` (:math:`x_\infty`), ``tip_err``, ``slope`` (c), ``power``, ``chi2``, ``dof``, ``sites``.

    Raises
    ------
    ValueError
        If the arrays differ in length or hold fewer than two sizes.

    Examples
    --------
    >>> from hyperlattice.compare.qmc_lobe import size_extrapolation
    >>> r = size_extrapolation([100, 400], [0.07, 0.064], [0.001, 0.001])
    >>> round(r["tip"], 6), round(r["tip_err"], 6)
    (0.062, 0.001374)
    """
    m = _validate.real_array("sites", sites)
    v = _validate.real_array("tip", tip)
    e = _validate.real_array("tip_err", tip_err)
    p = _validate.positive_real("power", power)
    if not (m.shape == v.shape == e.shape) or m.ndim != 1:
        raise ValueError("sites, tip and tip_err must be 1-d arrays of one length.")
    if np.unique(m).size < 2 or np.any(m <= 0) or np.any(~np.isfinite(v)) or np.any(~(e > 0)):
        raise ValueError("the size extrapolation needs at least two sizes with finite tips and errors > 0.")
    u = m ** (-p)
    w = 1.0 / e**2
    X = np.stack([np.ones_like(u), u], axis=1)
    cov = np.linalg.inv(X.T @ (X * w[:, None]))
    a, c = cov @ (X.T @ (w * v))
    chi2 = float(np.sum(w * (v - a - c * u) ** 2))
    dof = int(m.size - 2)
    if dof > 0 and chi2 / dof > 1.0:
        cov = cov * (chi2 / dof)
    return {"tip": float(a), "tip_err": float(math.sqrt(cov[0, 0])), "slope": float(c), "power": p, "chi2": chi2,
            "dof": dof, "sites": [int(k) for k in m]}


def _gaps(rows: list) -> list:
    """(beta_t, nmax, [(x, gap, err), ...]) for each temperature and cutoff of one graph's rows."""
    by: dict = {}
    for r in rows:
        by.setdefault((r["beta_t"], r.get("nmax", 3)), {}).setdefault(r["t_over_U"], {})[r["side"]] = r
    out = []
    for (beta, nmax), xs in sorted(by.items()):
        gaps = []
        for x in sorted(xs):
            d = xs[x]
            if "plus" in d and "minus" in d:
                gaps.append((x, d["plus"]["mu"] - d["minus"]["mu"], math.hypot(d["plus"]["mu_err"],
                                                                                d["minus"]["mu_err"])))
        out.append((beta, nmax, gaps))
    return out


def _gap_extrapolation(rows: list) -> list:
    r"""The pseudo-tips of one graph, one dict per (beta t, nmax) with at least two gaps.

    Both straight lines (Δ² and Δ against t/U, :func:`gap_tip`) through the three largest t/U,
    where the gap is smallest; the pseudo-tip is their midpoint and its error adds half their
    difference (the unknown exponent zν, between the mean-field 1/2 and 1) to the statistical
    errors. With four or more points the free power law gives zν as a diagnostic.
    """
    tips = []
    for beta, nmax, gaps in _gaps(rows):
        gaps = [gp for gp in gaps if math.isfinite(gp[1]) and math.isfinite(gp[2]) and gp[1] > 0 and gp[2] > 0]
        d = {"beta_t": beta, "nmax": nmax, "gaps": [list(gp) for gp in gaps], "tip": math.nan, "tip_err": math.nan,
             "tip_sqrt": math.nan, "tip_sqrt_err": math.nan, "tip_linear": math.nan, "tip_linear_err": math.nan,
             "chi2_sqrt": math.nan, "chi2_linear": math.nan, "dof": 0, "exponent": math.nan,
             "exponent_err": math.nan, "tip_power": math.nan, "tip_power_err": math.nan}
        if len(gaps) >= 2:
            use = gaps[-3:]
            xs, gs, es = (np.array(c) for c in zip(*use))
            sq = gap_tip(xs, gs, es, form="sqrt")
            li = gap_tip(xs, gs, es, form="linear")
            d.update({"tip_sqrt": sq["tip"], "tip_sqrt_err": sq["tip_err"], "chi2_sqrt": sq["chi2"], "dof": sq["dof"],
                      "tip_linear": li["tip"], "tip_linear_err": li["tip_err"], "chi2_linear": li["chi2"],
                      "fit_points": [u[0] for u in use]})
            if math.isfinite(sq["tip"]) and math.isfinite(li["tip"]):
                d["tip"] = 0.5 * (sq["tip"] + li["tip"])
                d["tip_err"] = math.sqrt(0.25 * (sq["tip_err"] ** 2 + li["tip_err"] ** 2)
                                         + (0.5 * (li["tip"] - sq["tip"])) ** 2)
        if len(gaps) >= 4:
            xs, gs, es = (np.array(c) for c in zip(*gaps))
            pw = gap_tip(xs, gs, es, form="power")
            d.update({"exponent": pw["exponent"], "exponent_err": pw["exponent_err"], "tip_power": pw["tip"],
                      "tip_power_err": pw["tip_err"]})
        tips.append(d)
    return tips


def load_scan(path) -> dict:
    """The stored scan (JSON written by benchmarks/qmc_lobe_scan.py): ``{"meta": ..., "boundaries": [...]}``."""
    p = _validate.input_path("path", path, suffixes=(".json",))
    with open(p, encoding="utf-8") as fh:
        data = json.load(fh)
    if not isinstance(data, dict) or "boundaries" not in data:
        raise ValueError(f"{p} is not a QMC lobe scan (no 'boundaries').")
    return data


def qmc_lobe(scan: dict, *, points: int = 41) -> QMCLobe:
    r"""Assemble a QMC lobe scan with mean field and strong coupling on the same graphs.

    Parameters
    ----------
    scan : dict
        From :func:`load_scan` (or built by :func:`qmc_boundary` runs): ``boundaries`` is a list of
        the dicts :func:`qmc_boundary` returns, each with a ``system`` spec
        (``flake:L``, ``cluster:NAME``, ``square:L``).
    points : int, optional
        Points of the mean-field and strong-coupling lines. Default 41.

    Returns
    -------
    QMCLobe

    Raises
    ------
    ValueError
        If the scan is malformed.
    """
    from ..bosons.meanfield import largest_adjacency_eigenvalue, lobe_tip
    from ..bosons.strong_coupling import excitation_energies, strong_coupling_tip

    if not isinstance(scan, dict) or not isinstance(scan.get("boundaries"), list):
        raise ValueError("scan must be a dict with a list of 'boundaries'.")
    points = _validate.integer("points", points, minimum=3, maximum=10_000)
    specs = []
    for b in scan["boundaries"]:
        if b["system"] not in specs:
            specs.append(b["system"])
    systems, info = [], {}
    for spec in specs:
        g = _system(spec)
        lam = float(largest_adjacency_eigenvalue(g))
        tip_sc = strong_coupling_tip(g)[0]
        tip_mf = lobe_tip(lam)[1]
        top = max(tip_sc if math.isfinite(tip_sc) else 0.0, tip_mf) * 1.05
        # the mean-field tip itself is on the grid, so that the drawn lobe closes
        xs = np.union1d(np.linspace(0.0, top, points), [tip_mf * (1.0 - 1e-12)])
        sp_, sm_ = excitation_energies(g, xs)
        mf_p, mf_m = mean_field_boundaries(lam, xs)
        sites = int(g.shape[0]) if sp.issparse(g) else int(g.sites)
        info[spec] = (g, lam)
        systems.append({"system": spec, "sites": sites, "lambda_max": lam, "tip_mean_field": tip_mf,
                        "tip_strong_coupling": tip_sc, "t_line": xs.tolist(), "mf_plus": mf_p.tolist(),
                        "mf_minus": mf_m.tolist(), "sc_plus": sp_.tolist(), "sc_minus": sm_.tolist()})
    rows = []
    for b in sorted(scan["boundaries"], key=lambda b: (specs.index(b["system"]), b["t_over_U"], b["side"])):
        g, lam = info[b["system"]]
        x = float(b["t_over_U"])
        sp_, sm_ = excitation_energies(g, [x])
        mf_p, mf_m = mean_field_boundaries(lam, [x])
        plus = b["side"] == "plus"
        mu_b, mu_e = float(b["mu"]), float(b["mu_err"])
        if b.get("steps") and all(k in b["steps"][0] for k in ("N", "N_err", "kappa", "kappa_err")):
            c_mu, c_err, used = combine_steps(b["steps"], b["side"], int(b["sites"]), x, float(b["beta_t"]))
            if used:
                mu_b, mu_e = c_mu, c_err
        rows.append({"system": b["system"], "sites": int(b["sites"]), "t_over_U": x, "beta_t": float(b["beta_t"]),
                     "nmax": int(b.get("nmax", 3)), "side": b["side"], "mu": mu_b,
                     "converged": bool(b.get("converged", all(st.get("converged", True) for st in b.get("steps", [])))),
                     "mu_err": mu_e,
                     "mu_mean_field": float(mf_p[0] if plus else mf_m[0]),
                     "mu_strong_coupling": float(sp_[0] if plus else sm_[0]), "lambda_max": lam})
    for sysd in systems:
        g, _ = info[sysd["system"]]
        tips = _gap_extrapolation([r for r in rows if r["system"] == sysd["system"]])
        for d in tips:
            d["beta_splitting"] = boundary_offset(g, d["beta_t"])["beta_splitting"]
        sysd["tips"] = tips
        sysd["splitting_over_t"] = boundary_offset(g, 1.0)["splitting_over_t"]
    # the infinite lattice from the periodic clusters (no boundary): x_c(M) = x_inf + c/M, and with
    # c/sqrt(M) as the alternative form (the difference is a systematic error of the extrapolation)
    finite_size = []
    betas = sorted({d["beta_t"] for s_ in systems for d in s_["tips"]})
    for beta in betas:
        for kind in ("cluster", "flake"):
            pts = sorted((s_["sites"], d["tip"], d["tip_err"]) for s_ in systems if s_["system"].startswith(kind + ":")
                   if s_["sites"] >= MIN_SITES_EXTRAPOLATION
                   for d in s_["tips"] if d["beta_t"] == beta and d["nmax"] == 3 and math.isfinite(d["tip"])
                   and d["tip_err"] > 0)
            if len({p_[0] for p_ in pts}) < 2:
                continue
            m_, v_, e_ = zip(*pts)
            one = size_extrapolation(m_, v_, e_, power=1.0)
            half = size_extrapolation(m_, v_, e_, power=0.5)
            finite_size.append({"kind": kind, "beta_t": beta, "sites": one["sites"], "tip": one["tip"],
                                "tip_err": one["tip_err"], "tip_sqrt_form": half["tip"],
                                "tip_sqrt_form_err": half["tip_err"],
                                "systematic": abs(one["tip"] - half["tip"]), "slope": one["slope"],
                                "slope_sqrt_form": half["slope"], "chi2": one["chi2"],
                                "chi2_sqrt_form": half["chi2"], "dof": one["dof"]})
    from .limits import band_bottom   # the report's route to rho (extrapolated band bottom)

    rho = float(band_bottom(7, 3, schur_window=None).rho)
    tip_inf = float(lobe_tip(rho)[1])
    square_sc = strong_coupling_tip(square_lattice(4))[0]
    # the continuum's band bottom: the paper's map E = -q + (q/4) h^2 lambda at lambda = 1, where the
    # spectrum of -Delta_g on the hyperbolic plane (curvature -4) starts; its mean-field tip is the
    # continuum's reading of the same formula
    lam_cont = -float(_continuum_bottom())
    continuum = {"lambda_max": lam_cont, "tip_mean_field": float(lobe_tip(lam_cont)[1])}
    return QMCLobe(rows=rows, systems=systems, infinite_tip_mean_field=tip_inf, rho=rho, continuum=continuum,
                   finite_size=finite_size, square={"exact": SQUARE_TIP_EXACT[0], "exact_err": SQUARE_TIP_EXACT[1],
                           "mean_field": SQUARE_TIP_MEAN_FIELD, "strong_coupling": square_sc,
                           "cubic_exact": CUBIC_TIP_EXACT[0], "cubic_exact_err": CUBIC_TIP_EXACT[1],
                           "cubic_mean_field": (3.0 - 2.0 * math.sqrt(2.0)) / 6.0})


def xy_qubit_check(rings: int = 2, omega_q: float = -3.5, g: float = 0.5, *, ring: int = 1, mu: float = 0.0,
                   beta_J: float = 10.0, sweeps: int = 4000, seed: int = 3) -> dict:
    r"""Hard-core bosons (the XY model) on the exchange couplings of qubits, QMC against exact.

    Qubits on every site of ring ``ring`` of an ℓ-ring {7,3} flake (one rotation orbit, so every
    qubit has the same Lamb shift and a uniform chemical potential is exact) with the exchange
    :math:`J_{kl}` of :func:`hyperlattice.graph.qubits.spin_model`; the spin model
    :math:`H = -\sum_{k\neq l} J_{kl}\sigma_k^+\sigma_l^- - \mu\sum_k n_k` (all-to-all, J > 0: no
    sign problem) at inverse temperature :math:`\beta = \beta_J / J_{\max}`, by QMC with nmax = 1 and by
    :func:`hyperlattice.bosons.exact_thermal`.

    Parameters
    ----------
    rings, ring : int, optional
        Flake size and the ring holding the qubits. Default 2, 1 (7 qubits).
    omega_q, g : float, optional
        Qubit frequency (below the band) and coupling, units of t. Default -3.5, 0.5.
    mu : float, optional
        Chemical potential of the excitations (the frame), units of t, within 10 J_max of 0.
        Default 0.
    beta_J : float, optional
        Inverse temperature in units of the largest exchange, :math:`\beta J_{\max}`. Default 10.
    sweeps : int, optional
        QMC sweeps. Default 4000.
    seed : int, optional
        QMC seed. Default 3.

    Returns
    -------
    dict
        ``qubits``, ``J_max``, ``beta_J``, and for ``qmc`` and ``exact``: ``energy``, ``density``,
        ``compressibility`` (with ``_err`` for QMC), ``deviation_sigma`` (per observable).

    Raises
    ------
    ValueError
        If an argument is out of range.
    """
    from ..bosons import exact_thermal, qmc
    from ..graph.lattice import ring_lattice
    from ..graph.qubits import spin_model

    lat = ring_lattice(7, 3, _validate.integer("rings", rings, minimum=1, maximum=6))
    ring = _validate.integer("ring", ring, minimum=1, maximum=lat.rings)
    sites = np.flatnonzero(np.asarray(lat.ring) == ring)
    model = spin_model(lat, sites.tolist(), omega_q, g)
    J = np.array(model.couplings)
    np.fill_diagonal(J, 0.0)
    A = sp.csr_matrix(J)
    beta = _validate.positive_real("beta_J", beta_J) / float(J.max())
    mu = _validate.real("mu", mu)
    if abs(mu) > 10.0 * float(J.max()):
        # the check is about the XY model's own scale; far outside it the system is empty or full
        raise ValueError(f"mu must lie within 10 J_max = {10.0 * float(J.max()):.4g} of 0 for this check, got {mu:g}.")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        r = qmc(A, U=0.0, mu=mu, beta=beta, nmax=1, t=1.0, sweeps=sweeps, seed=seed, progress=False)
    ex = exact_thermal(A, U=0.0, mu=mu, beta=beta, nmax=1, t=1.0)
    out = {"qubits": int(sites.size), "J_max": float(J.max()), "beta": beta, "beta_J": float(beta * J.max()),
           "lamb_shift_spread": float(np.ptp(model.lamb_shift)),
           "qmc": {}, "exact": {}, "deviation_sigma": {}, "warnings": [str(w.message) for w in caught]}
    for key in ("energy", "density", "compressibility"):
        v, e = getattr(r, key), getattr(r, key + "_err")
        out["qmc"][key], out["qmc"][key + "_err"] = float(v), float(e)
        out["exact"][key] = float(getattr(ex, key))
        out["deviation_sigma"][key] = float(abs(v - getattr(ex, key)) / e) if e > 0 else (0.0 if v == getattr(ex, key) else math.inf)
    return out


# every public function above checks its arguments at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
