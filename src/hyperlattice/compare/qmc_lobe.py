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
           "SQUARE_TIP_MEAN_FIELD", "load_scan", "xy_qubit_check"]

#: the exact n = 1 tip of the square lattice, (U/t)_c = 16.7424(54): Capogrosso-Sansone et al., PRA 77, 015602 (2008)
SQUARE_TIP_EXACT = (1.0 / 16.7424, 0.0054 / 16.7424**2)
#: mean field on the square lattice: (t/U)_c = (3 - 2 sqrt 2)/z, z = 4
SQUARE_TIP_MEAN_FIELD = (3.0 - 2.0 * math.sqrt(2.0)) / 4.0


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
                 seed: int = 1, iterations: int = 3, mu_start: float | None = None) -> dict:
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

    Returns
    -------
    dict
        ``mu`` (μ±/U), ``mu_err``, ``steps`` (a list of the runs: ``mu``, ``N``, ``N_err``,
        ``kappa``, ``kappa_err``, ``tau_int``, ``converged``), ``sites``, ``t_over_U``, ``beta_t``,
        ``side``, ``sweeps``, ``nmax``.

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
            r = qmc(system, U=U, mu=mu * U, beta=beta, nmax=nmax, t=1.0, sweeps=sweeps, seed=seed + k,
                    progress=False)
        M = r.sites
        target = M + (0.5 if side == "plus" else -0.5)
        N, N_err = r.density * M, r.density_err * M
        slope, slope_err = r.compressibility * M * U, r.compressibility_err * M * U     # dN/d(mu/U)
        steps.append({"mu": mu, "N": N, "N_err": N_err, "kappa": r.compressibility,
                      "kappa_err": r.compressibility_err, "tau_int": dict(r.tau_int), "converged": bool(r.converged),
                      "warnings": [str(w.message) for w in caught]})
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
    return {"mu": estimate, "mu_err": err, "steps": steps, "sites": steps and M, "t_over_U": x, "beta_t": beta,
            "side": side, "sweeps": sweeps, "nmax": nmax}


@dataclasses.dataclass(frozen=True, eq=False)
class QMCLobe(Result):
    r"""QMC lobe boundaries of several graphs with mean field and strong coupling on the same graphs.

    Attributes
    ----------
    rows : list of dict
        One per QMC boundary: ``system``, ``sites``, ``t_over_U``, ``beta_t``, ``side``, ``mu``,
        ``mu_err``, ``mu_mean_field``, ``mu_strong_coupling`` (all μ/U), ``lambda_max``.
    systems : list of dict
        One per graph: ``system``, ``sites``, ``lambda_max``, ``tip_mean_field``,
        ``tip_strong_coupling`` (t/U), and the lines ``t_line``, ``mf_plus``, ``mf_minus``,
        ``sc_plus``, ``sc_minus``.
    infinite_tip_mean_field : float
        The {7,3} mean-field tip through the spectral radius ρ.
    rho : float
        ρ of the infinite {7,3} lattice (the extrapolated band bottom).
    continuum : dict
        ``lambda_max`` (minus the continuum's band bottom, the paper's map) and its mean-field
        ``tip_mean_field``.
    square : dict
        The square-lattice reference: ``exact``, ``exact_err``, ``mean_field``, ``strong_coupling``.
    """

    COLUMNS = (Column("t_over_U", "t_over_U", "1"), Column("mu", "mu", "U"), Column("mu_err", "mu_err", "U"))

    rows: list
    systems: list
    infinite_tip_mean_field: float
    rho: float
    continuum: dict
    square: dict

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
    """A graph from its scan name: ``flake:L``, ``cluster:NAME`` or ``square:L``."""
    from ..graph.clusters import pbc_cluster
    from ..graph.lattice import ring_lattice

    kind, _, arg = spec.partition(":")
    if kind == "flake":
        return ring_lattice(7, 3, int(arg))
    if kind == "cluster":
        return pbc_cluster(7, 3, arg)
    if kind == "square":
        return square_lattice(int(arg))
    raise ValueError(f"unknown system {spec!r}: use flake:L, cluster:NAME or square:L.")


def _continuum_bottom() -> float:
    """The paper's continuum band bottom -3 + (3/4) h^2 of {7,3}: E(lambda = 1), the spectrum's edge."""
    from ..dictionary import energy_from_lambda

    return float(energy_from_lambda(1.0, 7, 3))


def _gap_extrapolation(rows: list) -> dict:
    """The QMC gap mu_+ - mu_- at each t/U with both sides, and its linear extrapolation to zero.

    A finite graph has no transition: its gap stays open. The straight line through the gaps of the
    two largest t/U, continued to zero, is the pseudo-tip of that graph (an estimate with the
    curvature of the gap neglected; NaN with fewer than two points).
    """
    by_x: dict = {}
    for r in rows:
        by_x.setdefault(r["t_over_U"], {})[r["side"]] = r
    gaps = []
    for x in sorted(by_x):
        d = by_x[x]
        if "plus" in d and "minus" in d:
            gaps.append((x, d["plus"]["mu"] - d["minus"]["mu"], math.hypot(d["plus"]["mu_err"], d["minus"]["mu_err"])))
    out = {"qmc_gaps": [list(g) for g in gaps], "tip_qmc_extrapolated": math.nan, "tip_qmc_extrapolated_err": math.nan}
    if len(gaps) >= 2:
        (x1, g1, e1), (x2, g2, e2) = gaps[-2], gaps[-1]
        slope = (g2 - g1) / (x2 - x1)
        if slope < 0:
            xc = x2 - g2 / slope
            # d xc / d g1 and d xc / d g2 of the two-point line
            d1 = -(x2 - xc) / (g1 - g2) if g1 != g2 else math.nan
            d2 = (x1 - xc) / (g1 - g2) if g1 != g2 else math.nan
            out["tip_qmc_extrapolated"] = xc
            out["tip_qmc_extrapolated_err"] = math.hypot(d1 * e1, d2 * e2)
    return out


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
        rows.append({"system": b["system"], "sites": int(b["sites"]), "t_over_U": x, "beta_t": float(b["beta_t"]),
                     "side": b["side"], "mu": float(b["mu"]), "mu_err": float(b["mu_err"]),
                     "mu_mean_field": float(mf_p[0] if plus else mf_m[0]),
                     "mu_strong_coupling": float(sp_[0] if plus else sm_[0]), "lambda_max": lam})
    for sysd in systems:
        sysd.update(_gap_extrapolation([r for r in rows if r["system"] == sysd["system"]]))
        g, _ = info[sysd["system"]]
        beta_t = max((r["beta_t"] for r in rows if r["system"] == sysd["system"]), default=math.nan)
        sysd["beta_t"] = beta_t
        sysd["beta_splitting"] = boundary_offset(g, beta_t)["beta_splitting"] if math.isfinite(beta_t) else math.nan
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
                   square={"exact": SQUARE_TIP_EXACT[0], "exact_err": SQUARE_TIP_EXACT[1],
                           "mean_field": SQUARE_TIP_MEAN_FIELD, "strong_coupling": square_sc})


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
        out["exact"][key] = float(ex[key])
        out["deviation_sigma"][key] = float(abs(v - ex[key]) / e) if e > 0 else (0.0 if v == ex[key] else math.inf)
    return out


# every public function above checks its arguments at the door (issue 19)
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
