r"""Below the band: the lattice propagator as a positive-definite solve, and circuit-QED qubits.

Qubits of frequency :math:`\omega_q` below the photon band, each coupled with strength g to one
site (of a {p,q} lattice, or of its line graph, the resonator array of the devices), in the
single-excitation sector:

.. math:: \mathcal H = \begin{pmatrix} H & gB \\ gB^T & \omega_q \mathbb 1_K \end{pmatrix},
          \qquad H = -tA,\quad B_{j_k k} = 1,

(rotating-wave Jaynes–Cummings lattice, one excitation). Eliminating the photons exactly (Schur
complement) gives the qubit block :math:`\omega_q - g^2 B^T G(E) B` with
:math:`G(E) = (H - E)^{-1}` (``eq20``). Hence

* **bound state** of one qubit on site :math:`j_0`: :math:`E_b` solves
  :math:`E - \omega_q + g^2 G_{j_0j_0}(E) = 0`, unique below the band bottom :math:`E_0` (the left
  side increases monotonically from :math:`-\infty` to :math:`+\infty` on :math:`(-\infty, E_0)`), and
  the photon amplitude is :math:`\phi = g\,G(E_b)e_{j_0}` (qubit amplitude :math:`-1` before
  normalization). To leading order in g, :math:`E_b \approx \omega_q - g^2G_{j_0j_0}(\omega_q)` and
  :math:`\phi \propto G_{\cdot j_0}(\omega_q)`; the normalized profiles differ by :math:`O(g^2)`
  because :math:`E_b - \omega_q = O(g^2)`.
* **effective spin model** to order :math:`g^2`:
  :math:`H_{\rm spin} = \sum_{kl} h_{kl}\sigma_k^+\sigma_l^-`,
  :math:`h = \omega_q\mathbb 1 - g^2 B^TG(\omega_q)B`, i.e. a Lamb shift
  :math:`-g^2G_{j_kj_k}(\omega_q)` and the exchange

  .. math:: H_{\rm spin} \ni -\sum_{k<l} J_{kl}(\sigma_k^+\sigma_l^- + \mathrm{h.c.}),
            \qquad J_{kl} = g^2 G_{j_kj_l}(\omega_q) > 0

  (below the band every entry of :math:`G` is positive). Bienias, Boettcher, Belyansky, Kollár
  and Gorshkov, PRL 128, 013601 (2022) study these bound states and exchange couplings.

The solves use :class:`BelowBandResolvent`: one sparse :math:`LDL^T` factorization per frequency
(fill-reducing order and elimination tree once per lattice, numeric factorization in numba), whose
pivot signs give the inertia of :math:`H - \omega` (Sylvester's law): all pivots positive proves
:math:`\omega < E_0`, so "below the band" is checked exactly, at no extra cost. It is shared with
:mod:`hyperlattice.compare.boundary` (the boundary correlators of the massive scalar).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from .. import _validate
from ..errors import ConvergenceError
from ..geometry import distance
from ..results import Result
from .lattice import Lattice
from .operators import hamiltonian

if TYPE_CHECKING:
    from matplotlib.axes import Axes

__all__ = [
    "BelowBandResolvent",
    "qubit_hamiltonian",
    "BoundState",
    "bound_state",
    "SpinModel",
    "spin_model",
    "MAX_QUBITS",
]

#: largest number of qubits of one spin model (its coupling matrix is dense, K x K)
MAX_QUBITS = 20_000
_NEWTON_MAX = 60


def _real_omega(name: str, omega) -> float:
    """A real frequency: complex values with a zero imaginary part are accepted."""
    if isinstance(omega, (complex, np.complexfloating)):
        w = _validate.complex_number(name, omega)
        if w.imag != 0:
            raise ValueError(f"{name} must be real (a frequency below the band), got {w}.")
        return w.real
    return _validate.real(name, omega)


def _angular_dissection(adj: sp.csr_matrix, angle: np.ndarray, leaf: int = 32) -> np.ndarray:
    """Nested-dissection order of a flake by recursive median splits in angle (cuts along radial geodesics).

    The separator of a split is the set of sites of one half adjacent to the other half; it is ordered
    after both halves. Hyperbolic flakes are tree-like: a radial cut crosses about two sites per ring, so
    the separators stay small (measured <= 20 sites at l = 10) and the fill of the factor stays near linear.
    """
    n = adj.shape[0]
    out: list[np.ndarray] = []
    stack: list[tuple[np.ndarray, bool]] = [(np.arange(n), False)]
    in_q = np.zeros(n)
    while stack:                       # iterative post-order: (P, Q, S) -> P, Q, then S
        region, emit = stack.pop()
        if emit or region.size <= leaf:
            out.append(region)
            continue
        srt = np.argsort(angle[region], kind="stable")
        half = region.size // 2
        P, Q = region[srt[:half]], region[srt[half:]]
        in_q[Q] = 1.0
        touch = (adj[P] @ in_q) > 0
        in_q[Q] = 0.0
        # pushed in reverse: P first, then Q, then the separator
        stack.append((P[touch], True))
        stack.append((Q, False))
        stack.append((P[~touch], False))
    return np.concatenate(out) if out else np.arange(0)


def _fill_reducing_order(adj: sp.csr_matrix, angle: np.ndarray) -> np.ndarray:
    """Sites of degree <= 2 first (eliminating one only joins its two neighbours), then an angular
    nested dissection of the rest on the graph in which those chains are contracted."""
    adj = sp.csr_matrix(adj, dtype=float)
    adj.data[:] = 1.0
    deg = np.diff(adj.indptr)
    low = np.flatnonzero(deg <= 2)
    rest = np.flatnonzero(deg > 2)
    if rest.size == 0:
        return np.argsort(angle, kind="stable")
    low = low[np.argsort(angle[low], kind="stable")]
    a_rr = adj[rest][:, rest]
    a_rl = adj[rest][:, low]
    a_ll = adj[low][:, low]
    # chains of one or two low-degree sites contracted (longer chains: a little extra fill, still exact)
    g = (a_rr + a_rl @ a_rl.T + a_rl @ a_ll @ a_rl.T).tocsr()
    return np.concatenate([low, rest[_angular_dissection(g, angle[rest])]])


_KERNELS: dict = {}


def _ldl_kernels() -> dict:
    """Numba kernels of a simplicial LDL^T (up-looking, elimination tree), compiled on first use, cached on disk."""
    if _KERNELS:
        return _KERNELS
    import numba

    @numba.njit(cache=True)
    def symbolic(n, ap, ai):                     # pragma: no cover - compiled
        parent = np.full(n, -1, np.int64)
        flag = np.empty(n, np.int64)
        lnz = np.zeros(n, np.int64)
        for k in range(n):
            flag[k] = k
            for p in range(ap[k], ap[k + 1]):
                i = ai[p]
                if i < k:
                    while flag[i] != k:
                        if parent[i] == -1:
                            parent[i] = k
                        lnz[i] += 1
                        flag[i] = k
                        i = parent[i]
        lp = np.zeros(n + 1, np.int64)
        for k in range(n):
            lp[k + 1] = lp[k] + lnz[k]
        return parent, lp

    @numba.njit(cache=True)
    def numeric(n, ap, ai, ax, shift, parent, lp):   # pragma: no cover - compiled
        # (A - shift) = L D L^T, row by row; stops at the first pivot that is not > 0
        li = np.empty(lp[n], np.int64)
        lx = np.empty(lp[n])
        d = np.empty(n)
        y = np.zeros(n)
        pattern = np.empty(n, np.int64)
        flag = np.empty(n, np.int64)
        lnz = np.zeros(n, np.int64)
        for k in range(n):
            top = n
            flag[k] = k
            y[k] = -shift
            for p in range(ap[k], ap[k + 1]):
                i = ai[p]
                if i > k:
                    continue
                y[i] += ax[p]
                ln = 0
                while flag[i] != k:
                    pattern[ln] = i
                    ln += 1
                    flag[i] = k
                    i = parent[i]
                while ln > 0:
                    top -= 1
                    ln -= 1
                    pattern[top] = pattern[ln]
            dk = y[k]
            y[k] = 0.0
            while top < n:
                i = pattern[top]
                top += 1
                yi = y[i]
                y[i] = 0.0
                p2 = lp[i] + lnz[i]
                for p in range(lp[i], p2):
                    y[li[p]] -= lx[p] * yi
                lki = yi / d[i]
                dk -= lki * yi
                li[p2] = k
                lx[p2] = lki
                lnz[i] += 1
            d[k] = dk
            if not dk > 0.0:
                return li, lx, d, k
        return li, lx, d, -1

    @numba.njit(cache=True)
    def solve(n, lp, li, lx, d, x):              # pragma: no cover - compiled
        for c in range(x.shape[1]):
            for j in range(n):
                xj = x[j, c]
                if xj != 0.0:
                    for p in range(lp[j], lp[j + 1]):
                        x[li[p], c] -= lx[p] * xj
            for j in range(n):
                x[j, c] /= d[j]
            for j in range(n - 1, -1, -1):
                s = x[j, c]
                for p in range(lp[j], lp[j + 1]):
                    s -= lx[p] * x[li[p], c]
                x[j, c] = s
        return x

    _KERNELS.update(symbolic=symbolic, numeric=numeric, solve=solve)
    return _KERNELS


class BelowBandResolvent:
    r""":math:`G(\omega) = (H - \omega)^{-1}` for real :math:`\omega` below the spectrum of :math:`H`.

    Parameters
    ----------
    system : Lattice
        The lattice (``kind`` ``"sites"`` or ``"line_graph"``); :math:`H = -tA`.
    t : float
        Hopping (default 1).
    method : {"ldl", "superlu"}
        ``"ldl"`` (default): a fill-reducing order computed once per lattice (sites of degree <= 2
        first, then nested dissection along radial geodesics), its elimination tree once, and per
        :math:`\omega` a numeric :math:`LDL^T` without pivoting (numba). ``"superlu"``: SuperLU in
        symmetric mode with diagonal pivots, COLAMD order (the first version; 5-10x slower).

    Notes
    -----
    **Below the band, proved.** For a symmetric matrix, :math:`H - \omega = LDL^T` with every pivot
    :math:`D_{kk} > 0` is positive definite (Sylvester's law of inertia), i.e. :math:`\omega < E_0`;
    conversely an LDL^T without pivoting of a positive-definite matrix never meets a pivot
    :math:`\le 0`. So "below the band" is checked exactly, by the factorization itself. When a pivot
    :math:`\le 0` appears the SuperLU route runs once more to count the levels at or below
    :math:`\omega` for the error message.

    **Accuracy.** :math:`H - \omega` is then a nonsingular M-matrix (off-diagonal entries
    :math:`\le 0`): its :math:`L` has entries :math:`\le 0` below the diagonal and the triangular
    solves for a right-hand side :math:`e_j \ge 0` add terms of one sign only, so every entry of the
    column, down to :math:`G_{ij} \sim 10^{-21}` across an :math:`\ell = 10` flake, comes with a small
    *relative* error (measured 2e-13 against ``spsolve``). Krylov solvers (CG, multi-shift CG) give a
    small *normwise* residual and cannot resolve these entries; the boundary fit needs them.

    Cost at :math:`\ell = 10` ({7,3}, 105,875 sites): order and elimination tree about 1 s once,
    about 0.07 s per :math:`\omega`, 0.01 s per solve (``benchmarks/bench_boundary.py``).
    """

    def __init__(self, system: Lattice, *, t: float = 1.0, method: str = "ldl") -> None:
        lat = _validate.lattice(system)
        t = _validate.positive_real("the hopping t", t)
        self.method = _validate.choice("method", method, ("ldl", "superlu"))
        self.lattice = lat
        self.H = hamiltonian(lat, t=t).tocsc().astype(float)
        self.n = self.H.shape[0]
        self._lu = None
        self._omega = None
        self._sym = None            # (perm, inverse perm, ap, ai, ax, parent, lp): once per lattice
        self._ldl = None            # (omega, li, lx, d)

    # -- SuperLU route (also the level count when omega is not below the band) --
    def factor(self, omega) -> spla.SuperLU:
        """SuperLU factorization of :math:`H - \\omega` (cached for the last omega); ValueError above :math:`E_0`."""
        omega = _real_omega("omega", omega)
        if self._lu is not None and self._omega == omega:
            return self._lu
        M = (self.H - omega * sp.identity(self.n, format="csc")).tocsc()
        try:
            lu = spla.splu(M, permc_spec="COLAMD", diag_pivot_thresh=0.0,
                           options={"SymmetricMode": True})
        except RuntimeError:        # SuperLU: exactly singular
            raise ValueError(f"omega = {omega:g} is an eigenvalue of H: the propagator does not exist there.") \
                from None
        piv = lu.U.diagonal()
        below = int(np.count_nonzero(piv <= 0))
        # symmetric mode may still swap rows when a diagonal pivot is exactly zero: then the
        # inertia argument does not hold and we say so instead of guessing
        if not np.array_equal(lu.perm_r, lu.perm_c):
            raise ValueError(f"omega = {omega:g}: the factorization of H - omega needed off-diagonal pivots; "
                             "omega is not safely below the band.")
        if below:
            raise ValueError(f"omega = {omega:g} is not below the band: {below} level(s) of H lie at or below it "
                             "(the propagator below the band needs omega < E0, the lattice BF bound).")
        self._lu, self._omega = lu, omega
        return lu

    # -- LDL^T route --
    def _symbolic(self) -> tuple:
        if self._sym is None:
            k = _ldl_kernels()
            z = getattr(self.lattice, "z", None)
            angle = np.angle(np.asarray(z)) if z is not None and len(z) == self.n else np.arange(self.n, dtype=float)
            perm = _fill_reducing_order(self.H.tocsr(), angle)
            inv = np.empty(self.n, np.int64)
            inv[perm] = np.arange(self.n)
            hp = self.H[perm][:, perm].tocsc()
            hp.sort_indices()
            ap, ai = hp.indptr.astype(np.int64), hp.indices.astype(np.int64)
            parent, lp = k["symbolic"](self.n, ap, ai)
            self._sym = (perm, inv, ap, ai, np.ascontiguousarray(hp.data, float), parent, lp)
        return self._sym

    def _ldl_factor(self, omega: float) -> tuple:
        if self._ldl is not None and self._ldl[0] == omega:
            return self._ldl
        perm, inv, ap, ai, ax, parent, lp = self._symbolic()
        li, lx, d, bad = _ldl_kernels()["numeric"](self.n, ap, ai, ax, float(omega), parent, lp)
        if bad >= 0:
            # not positive definite: omega is at or above E0. Let the SuperLU route count the levels
            # (and raise); if it finds none (a pivot <= 0 within rounding of E0), say so plainly.
            self.factor(omega)
            raise ValueError(f"omega = {omega:g} is not safely below the band: the LDL^T factorization of "
                             "H - omega met a pivot <= 0 (omega within rounding of E0).")
        self._ldl = (omega, li, lx, d)
        return self._ldl

    def columns(self, omega, sources) -> np.ndarray:
        r"""Columns :math:`G_{\cdot j}(\omega)` for the given sources, real array ``(N, k)``."""
        src = _validate.site_indices("sources", sources, self.n)
        omega = _real_omega("omega", omega)
        if self.method == "superlu":
            lu = self.factor(omega)
            rhs = np.zeros((self.n, src.size))
            rhs[src, np.arange(src.size)] = 1.0
            out = lu.solve(rhs)
        else:
            _, li, lx, d = self._ldl_factor(omega)
            perm, inv, _, _, _, _, lp = self._sym
            x = np.zeros((self.n, src.size))
            x[inv[src], np.arange(src.size)] = 1.0
            _ldl_kernels()["solve"](self.n, lp, li, lx, d, x)
            out = x[inv]
        if not np.all(np.isfinite(out)):
            raise ValueError(f"omega = {omega}: the solve overflowed (omega within rounding of E0).")
        return out

    def column(self, omega, source) -> np.ndarray:
        r"""One column :math:`G_{\cdot j}(\omega)`, shape ``(N,)``."""
        source = _validate.site_index("source", source, self.n)
        return self.columns(omega, [source])[:, 0]


def _sites(lat: Lattice, sites) -> np.ndarray:
    if np.isscalar(sites) or (isinstance(sites, np.ndarray) and sites.ndim == 0):
        sites = [sites]
    idx = _validate.site_indices("sites", sites, lat.sites)
    if idx.size == 0:
        raise ValueError("give at least one qubit site.")
    if idx.size > MAX_QUBITS:
        raise ValueError(f"at most {MAX_QUBITS} qubits are supported (their couplings form a dense matrix), "
                         f"got {idx.size}.")
    if np.unique(idx).size != idx.size:
        raise ValueError("each site carries at most one qubit; the sites contain repeats.")
    return idx


def qubit_hamiltonian(lattice: Lattice, sites, omega_q, g, *, t: float = 1.0) -> sp.csr_matrix:
    r"""The single-excitation Hamiltonian :math:`\begin{pmatrix} H & gB\\ gB^T & \omega_q\end{pmatrix}`
    (module docstring), sparse, shape ``(N + K, N + K)``; photons first, then the K qubits."""
    lat = _validate.lattice(lattice)
    idx = _sites(lat, sites)
    omega_q = _validate.real("omega_q", omega_q)
    g = _validate.real("g", g)
    H = hamiltonian(lat, t=_validate.positive_real("the hopping t", t)).astype(float)
    k = idx.size
    B = sp.csr_matrix((np.full(k, g), (idx, np.arange(k))), shape=(lat.sites, k))
    return sp.bmat([[H, B], [B.T, omega_q * sp.identity(k)]], format="csr")


@dataclass(frozen=True, eq=False, kw_only=True)
class BoundState(Result):
    r"""The photon bound state of one qubit below the band, exact and to leading order in g.

    Attributes
    ----------
    p, q, rings : int
    kind : str
        ``"sites"`` or ``"line_graph"``.
    site : int
        The qubit's site :math:`j_0`.
    omega_q, g : float
        Qubit frequency and coupling.
    energy : float
        Exact bound-state energy :math:`E_b` (root of :math:`E - \omega_q + g^2G_{j_0j_0}(E)`).
    energy_leading : float
        :math:`\omega_q - g^2G_{j_0j_0}(\omega_q)`.
    qubit_weight : float
        :math:`|a|^2` of the normalized eigenvector (the rest is photonic).
    photon : ndarray, shape (N,)
        Exact photon profile :math:`\propto G_{\cdot j_0}(E_b)`, unit norm, positive.
    leading : ndarray, shape (N,)
        Leading-order profile :math:`\propto G_{\cdot j_0}(\omega_q)`, unit norm.
    profile_error : float
        :math:`\|\text{photon} - \text{leading}\|_2` (:math:`O(g^2)`).
    residual : float
        :math:`\|\mathcal H v - E_b v\|` of the full normalized eigenvector.
    distance : ndarray, shape (N,)
        Hyperbolic distance of each site from the qubit (paper's metric).
    size : float
        :math:`\langle d\rangle = \sum_i |\phi_i|^2 d_i`, the mean distance of the photon from the qubit.
    decay_length : float
        :math:`\xi` of :math:`G \propto e^{-d/\xi}`, fitted to :math:`\ln\phi` against d over the sites
        between 2 and 6 edge lengths from the qubit that are at least 3 edge lengths inside the
        outer ring (NaN when there are fewer than 10 such sites).
    """

    p: int
    q: int
    rings: int
    kind: str
    site: int
    omega_q: float
    g: float
    energy: float
    energy_leading: float
    qubit_weight: float
    photon: np.ndarray = field(repr=False)
    leading: np.ndarray = field(repr=False)
    profile_error: float
    residual: float
    distance: np.ndarray = field(repr=False)
    size: float
    decay_length: float

    def summary(self) -> dict:
        """Scalars only: p, q, rings, kind, site, omega_q, g, energy, energy_leading, qubit_weight,
        profile_error, residual, size, decay_length."""
        keys = ("p", "q", "rings", "kind", "site", "omega_q", "g", "energy", "energy_leading", "qubit_weight",
                "profile_error", "residual", "size", "decay_length")
        return {k: getattr(self, k) for k in keys}

    def plot(self, ax=None) -> Axes:
        """|photon| (exact) and the leading-order profile against hyperbolic distance, log scale."""
        import matplotlib.pyplot as plt

        if ax is None:
            _, ax = plt.subplots()
        ax.semilogy(self.distance, self.photon, ".", ms=3, label="exact bound state")
        ax.semilogy(self.distance, self.leading, ".", ms=1.5, label=r"$\propto G_{ij_0}(\omega_q)$")
        ax.set_xlabel("hyperbolic distance from the qubit")
        ax.set_ylabel("photon amplitude")
        ax.legend()
        return ax


def _decay_length(lat: Lattice, d: np.ndarray, profile: np.ndarray) -> float:
    """Fit ln(profile) = a - d/xi over 2 d0 <= d <= 6 d0, away from the outer rings (edge effects)."""
    d0 = lat.d0
    inner = lat.ring <= lat.rings - 3
    sel = inner & (d >= 2 * d0) & (d <= 6 * d0) & (profile > 0)
    if np.count_nonzero(sel) < 10:
        return math.nan
    slope = np.polyfit(d[sel], np.log(profile[sel]), 1)[0]
    return float(-1.0 / slope) if slope < 0 else math.nan


def bound_state(lattice: Lattice, site: int, omega_q, g, *, t: float = 1.0,
                resolvent: BelowBandResolvent | None = None, tol: float = 1e-13) -> BoundState:
    r"""The single-excitation bound state of one qubit on ``site``, exact and to leading order.

    Parameters
    ----------
    lattice : Lattice
        Sites or line graph (the resonators).
    site : int
        The qubit's site.
    omega_q : float
        Qubit frequency, below the band (:math:`\omega_q < E_0`).
    g : float
        Coupling, :math:`g \ne 0`.
    t : float
        Hopping.
    resolvent : BelowBandResolvent, optional
        Reuse a resolvent of the same lattice.
    tol : float
        Relative tolerance of the Newton iteration for :math:`E_b`.

    Returns
    -------
    BoundState

    Raises
    ------
    ValueError
        Bad input, :math:`\omega_q` not below the band.
    ConvergenceError
        If the Newton iteration for :math:`E_b` does not converge (not expected: the secular
        function is increasing and convex, so Newton from :math:`\omega_q` converges monotonically).
    """
    lat = _validate.lattice(lattice)
    site = _validate.site_index("site", site, lat.sites)
    omega_q = _real_omega("omega_q", omega_q)
    g = _validate.real("g", g)
    if g == 0:
        raise ValueError("g must be nonzero (at g = 0 the qubit does not dress the photons).")
    tol = _validate.real("tol", tol, minimum=1e-15, maximum=1e-3)
    res = resolvent if resolvent is not None else BelowBandResolvent(lat, t=t)
    g2 = g * g
    col0 = res.column(omega_q, site)              # refuses omega_q above E0
    e_lead = omega_q - g2 * col0[site]
    # Newton on f(E) = E - omega_q + g^2 G_jj(E): G_jj(E) = sum_n psi_n(j)^2/(E_n - E) is increasing
    # and convex below the band, so f is too (f' = 1 + g^2 (G^2)_jj). Started at E = omega_q, where
    # f = g^2 G_jj > 0, the tangent of a convex increasing function lands between the root and the
    # current point: the iterates decrease monotonically to E_b and never leave the band gap.
    E = omega_q
    col = col0
    for _ in range(_NEWTON_MAX):
        f = E - omega_q + g2 * col[site]
        fp = 1.0 + g2 * float(col @ col)
        E_new = E - f / fp
        col = res.column(E_new, site)
        if abs(E_new - E) <= tol * max(1.0, abs(E_new)):
            E = E_new
            break
        E = E_new
    else:
        raise ConvergenceError(f"the bound-state energy did not converge in {_NEWTON_MAX} Newton steps "
                               f"(last E = {E:.15g}).")
    phi = g * col
    norm2 = float(phi @ phi) + 1.0
    v = np.concatenate([phi, [-1.0]]) / math.sqrt(norm2)
    Hq = qubit_hamiltonian(lat, [site], omega_q, g, t=t)
    residual = float(np.linalg.norm(Hq @ v - E * v))
    photon = np.abs(phi) / math.sqrt(float(phi @ phi))
    lead = col0 / np.linalg.norm(col0)
    d = distance(lat.z, lat.z[site])
    size = float(np.sum(photon**2 * d))
    return BoundState(p=lat.p, q=lat.q, rings=lat.rings, kind=lat.kind, site=site, omega_q=omega_q, g=g,
                      energy=float(E), energy_leading=float(e_lead), qubit_weight=1.0 / norm2, photon=photon,
                      leading=lead, profile_error=float(np.linalg.norm(photon - lead)), residual=residual,
                      distance=d, size=size, decay_length=_decay_length(lat, d, photon))


@dataclass(frozen=True, eq=False, kw_only=True)
class SpinModel(Result):
    r"""The effective XY spin model of K qubits to order :math:`g^2` (module docstring).

    :math:`H_{\rm spin} = \sum_{kl} h_{kl}\sigma_k^+\sigma_l^-` with :math:`h = \omega_q - g^2 B^TG(\omega_q)B`:
    diagonal :math:`\omega_q + \delta\omega_k` (Lamb shift :math:`\delta\omega_k = -g^2G_{j_kj_k}`),
    off-diagonal :math:`-J_{kl}`, :math:`J_{kl} = g^2G_{j_kj_l}(\omega_q)`.

    Attributes
    ----------
    p, q, rings : int
    kind : str
    sites : ndarray of int, shape (K,)
        Lattice sites of the qubits.
    omega_q, g : float
    couplings : ndarray, shape (K, K)
        :math:`J_{kl}` (zero diagonal).
    lamb_shift : ndarray, shape (K,)
    distance : ndarray, shape (K, K)
        Hyperbolic distances between the qubits.
    """

    p: int
    q: int
    rings: int
    kind: str
    sites: np.ndarray
    omega_q: float
    g: float
    couplings: np.ndarray = field(repr=False)
    lamb_shift: np.ndarray = field(repr=False)
    distance: np.ndarray = field(repr=False)

    def matrix(self, threshold: float = 0.0) -> sp.csr_matrix:
        r"""The single-excitation matrix :math:`h` (K x K, scipy CSR); couplings with
        :math:`|J| < \text{threshold}\cdot\max|J|` dropped (0 keeps all)."""
        threshold = _validate.real("threshold", threshold, minimum=0.0, maximum=1.0)
        J = np.array(self.couplings)
        if J.size and threshold > 0:
            J[np.abs(J) < threshold * np.abs(J).max()] = 0.0
        h = sp.csr_matrix(-J)
        h = h + sp.diags(self.omega_q + np.asarray(self.lamb_shift))
        return h.tocsr()

    def edges(self, threshold: float = 0.0) -> list[tuple[int, int, float]]:
        r"""Edge list ``[(k, l, J_kl), ...]`` with k < l (qubit indices 0..K-1; ``sites[k]`` is the
        lattice site), couplings with :math:`|J| < \text{threshold}\cdot\max|J|` dropped."""
        threshold = _validate.real("threshold", threshold, minimum=0.0, maximum=1.0)
        J = np.asarray(self.couplings)
        k, l = np.triu_indices(J.shape[0], 1)
        vals = J[k, l]
        keep = np.abs(vals) >= threshold * (np.abs(vals).max() if vals.size else 0.0)
        return [(int(a), int(b), float(v)) for a, b, v in zip(k[keep], l[keep], vals[keep])]

    def summary(self) -> dict:
        """p, q, rings, kind, qubits, omega_q, g, the largest coupling and the Lamb-shift range."""
        J = np.asarray(self.couplings)
        off = J[~np.eye(J.shape[0], dtype=bool)] if J.size else J
        return {"p": self.p, "q": self.q, "rings": self.rings, "kind": self.kind, "qubits": int(len(self.sites)),
                "omega_q": self.omega_q, "g": self.g, "max_coupling": float(off.max()) if off.size else 0.0,
                "lamb_shift_min": float(np.min(self.lamb_shift)), "lamb_shift_max": float(np.max(self.lamb_shift))}


def spin_model(lattice: Lattice, sites, omega_q, g, *, t: float = 1.0,
               resolvent: BelowBandResolvent | None = None) -> SpinModel:
    r"""Effective exchange :math:`J_{kl} = g^2G_{j_kj_l}(\omega_q)` and Lamb shifts of qubits on ``sites``.

    One factorization and K solves (each column gives a row of J).

    Raises
    ------
    ValueError
        Bad or repeated sites, :math:`\omega_q` not below the band, more than :data:`MAX_QUBITS`.
    """
    lat = _validate.lattice(lattice)
    idx = _sites(lat, sites)
    omega_q = _real_omega("omega_q", omega_q)
    g = _validate.real("g", g)
    res = resolvent if resolvent is not None else BelowBandResolvent(lat, t=t)
    G = np.empty((idx.size, idx.size))
    chunk = max(1, int(2**26 // (8 * lat.sites)))      # (N, chunk) right-hand sides within ~64 MB
    for a in range(0, idx.size, chunk):
        cols = res.columns(omega_q, idx[a:a + chunk])
        G[:, a:a + chunk] = cols[idx]
    G = 0.5 * (G + G.T)     # symmetric up to rounding of the solves
    J = g * g * G
    lamb = -np.diag(J).copy()
    np.fill_diagonal(J, 0.0)
    d = distance(lat.z[idx][:, None], lat.z[idx][None, :])
    return SpinModel(p=lat.p, q=lat.q, rings=lat.rings, kind=lat.kind, sites=idx, omega_q=omega_q, g=g,
                     couplings=J, lamb_shift=lamb, distance=d)


# every public function above checks its annotated argument types at the door (issue 19)
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
