r"""Site-decoupled (Gutzwiller) mean field of the Bose–Hubbard model and its Mott lobes.

.. math::

    H = -t \sum_{\langle ij\rangle} (a_i^\dagger a_j + \mathrm{h.c.})
        + \frac{U}{2} \sum_i n_i (n_i - 1) - \mu \sum_i n_i

Decoupling every bond, :math:`a_i^\dagger a_j \to \psi_i^* a_j + a_i^\dagger \psi_j - \psi_i^*\psi_j`
with :math:`\psi_i = \langle a_i \rangle`, leaves one local Hamiltonian per site,

.. math::

    h_i = \frac U2 n(n-1) - \mu n - \phi_i (a^\dagger + a), \qquad
    \phi_i = t \sum_j A_{ij} \psi_j ,

whose ground state gives :math:`\psi_i` back (real and non-negative for t > 0: the
self-consistency is a monotone map, iterated here from the largest order parameter down to its
largest fixed point). The graph enters only through its adjacency A: on a flake the outer-ring
sites have fewer neighbours and the order parameter is inhomogeneous.

The Mott lobes
--------------
Linearising the self-consistency about :math:`\psi = 0` in the Mott state of filling n gives
:math:`\psi = t\, g_n(\mu)\, A \psi`, with the atomic susceptibility (second-order perturbation
theory in :math:`\phi`; Fisher, Weichman, Grinstein and Fisher, PRB 40, 546 (1989); van Oosten,
van der Straten and Stoof, PRA 63, 053601 (2001), Eq. 9)

.. math:: U g_n(\mu) = \frac{n+1}{n - \mu/U} + \frac{n}{\mu/U - (n-1)}, \qquad n - 1 < \mu/U < n .

The Mott state is unstable where :math:`t\, \lambda_{\max}\, g_n(\mu) = 1`, with
:math:`\lambda_{\max}` the largest eigenvalue of A. The criterion is exact within mean field for
any graph with a uniform :math:`\mu` (the susceptibility is the same on every site), so the
inhomogeneous flake needs nothing but its :math:`\lambda_{\max} = -E_0(\ell)/t`, which tends to the
spectral radius :math:`\rho` of the infinite lattice (2.9412 for {7,3}), *not* to the
coordination q = 3 that a homogeneous or Bethe-lattice mean field would use; a periodic cluster is
q-regular and has :math:`\lambda_{\max} = q` exactly. With :math:`y = \mu/U - (n-1)` the boundary
is :math:`\lambda_{\max} t_c / U = y(1-y)/(n+y)`, maximal at :math:`y = \sqrt{n(n+1)} - n`: the
lobe tip :math:`\lambda_{\max} t_c/U = (\sqrt{n+1} - \sqrt n)^2` (3 - 2√2 = 0.1716 for n = 1).

Continuum side
--------------
Through the paper's dictionary :math:`-tA \to -qt - t'\Delta_g` (``t' = (q/4) h^2 t``,
``mu' = mu + q t``), so :math:`\lambda_{\max} \to q - (t'/t)\,\lambda_D(L)`, with :math:`\lambda_D`
the lowest Dirichlet eigenvalue of :math:`-\Delta_g` on the disk that represents the flake: the
continuum's :math:`-E_0` (:func:`hyperlattice.continuum_levels`). Its lobes are the lattice's
formula with that :math:`\lambda_{\max}`; :func:`mott_lobes` tabulates both.
"""

from __future__ import annotations

import dataclasses
import math
import warnings

import numpy as np
import scipy.sparse as sp

from .. import _validate
from ..errors import ConvergenceWarning
from ..results import Column, Result

__all__ = ["atomic_susceptibility", "lobe_boundary", "lobe_tip", "largest_adjacency_eigenvalue", "MottLobe",
           "mott_lobe", "GutzwillerState", "gutzwiller", "selfconsistent_boundary", "MottLobeTable",
           "mott_lobes"]


# ----------------------------------------------------------------------------
# the atomic limit and the lobe formula
# ----------------------------------------------------------------------------

def _filling(n) -> int:
    return _validate.integer("filling", n, minimum=1, maximum=10**6)


def atomic_susceptibility(mu_over_U, filling: int = 1) -> float | np.ndarray:
    r""":math:`U g_n(\mu)`, the dimensionless atomic susceptibility of the Mott state of filling n.

    Parameters
    ----------
    mu_over_U : float or array
        Chemical potential in units of U; the Mott state of filling n is the atomic ground state
        for :math:`n - 1 < \mu/U < n`.
    filling : int
        n >= 1.

    Returns
    -------
    float or ndarray
        :math:`(n+1)/(n - \mu/U) + n/(\mu/U - n + 1)`; NaN outside the open interval.

    Raises
    ------
    ValueError
        If ``mu_over_U`` is not finite or ``filling`` is not an integer >= 1.

    References
    ----------
    .. [1] M. P. A. Fisher, P. B. Weichman, G. Grinstein and D. S. Fisher, Phys. Rev. B 40, 546
       (1989).
    .. [2] D. van Oosten, P. van der Straten and H. T. C. Stoof, Phys. Rev. A 63, 053601 (2001),
       Eq. (9).

    Examples
    --------
    >>> from hyperlattice.bosons.meanfield import atomic_susceptibility
    >>> [round(float(g), 6) for g in atomic_susceptibility([0.25, 0.5, 1.5])]
    [6.666667, 6.0, nan]
    """
    n = _filling(filling)
    x = _validate.real_array("mu_over_U", mu_over_U) if np.ndim(mu_over_U) else np.asarray(
        _validate.real("mu_over_U", mu_over_U))
    inside = (x > n - 1) & (x < n)
    with np.errstate(divide="ignore", invalid="ignore"):
        g = np.where(inside, (n + 1) / (n - x) + n / (x - (n - 1)), np.nan)
    return float(g) if g.ndim == 0 else g


def lobe_boundary(lambda_max: float, mu_over_U, filling: int = 1) -> float | np.ndarray:
    r""":math:`t_c/U` at which the Mott state of filling n becomes unstable: :math:`1/(\lambda_{\max} U g_n)`.

    Parameters
    ----------
    lambda_max : float
        Largest eigenvalue of the adjacency matrix (> 0).
    mu_over_U : float or array
        Chemical potentials in units of U; NaN outside :math:`(n-1, n)`.
    filling : int, optional
        n >= 1. Default 1.

    Returns
    -------
    float or ndarray
        :math:`t_c/U` at each :math:`\mu/U` (NaN outside the lobe's interval).

    Raises
    ------
    ValueError
        If ``lambda_max`` is not positive, ``mu_over_U`` not finite or ``filling`` < 1.

    See Also
    --------
    mott_lobe : the whole boundary with its tip.

    References
    ----------
    .. [1] M. P. A. Fisher, P. B. Weichman, G. Grinstein and D. S. Fisher, Phys. Rev. B 40, 546
       (1989).
    .. [2] D. van Oosten, P. van der Straten and H. T. C. Stoof, Phys. Rev. A 63, 053601 (2001),
       Eq. (9).

    Examples
    --------
    >>> from hyperlattice.bosons.meanfield import lobe_boundary
    >>> [round(float(x), 6) for x in lobe_boundary(3.0, [0.0, 0.5, 0.9])]
    [nan, 0.055556, 0.015789]
    """
    lam = _validate.positive_real("lambda_max", lambda_max)
    g = np.asarray(atomic_susceptibility(mu_over_U, filling))
    out = 1.0 / (lam * g)
    return float(out) if out.ndim == 0 else out


def lobe_tip(lambda_max: float, filling: int = 1) -> tuple[float, float]:
    r"""The tip of the Mott lobe of filling n: :math:`(\mu/U, t_c/U)` in closed form.

    :math:`\mu/U = n - 1 + \sqrt{n(n+1)} - n` and :math:`\lambda_{\max} t_c/U = (\sqrt{n+1} - \sqrt n)^2`.

    Parameters
    ----------
    lambda_max : float
        Largest eigenvalue of the adjacency matrix (> 0).
    filling : int, optional
        n >= 1. Default 1.

    Returns
    -------
    mu_over_U, t_c_over_U : float
        The tip's chemical potential and hopping, both in units of U.

    Raises
    ------
    ValueError
        If ``lambda_max`` is not positive or ``filling`` < 1.

    References
    ----------
    .. [1] M. P. A. Fisher, P. B. Weichman, G. Grinstein and D. S. Fisher, Phys. Rev. B 40, 546
       (1989).
    .. [2] D. van Oosten, P. van der Straten and H. T. C. Stoof, Phys. Rev. A 63, 053601 (2001),
       Eq. (9).

    Examples
    --------
    >>> from hyperlattice.bosons.meanfield import lobe_tip
    >>> [round(x, 6) for x in lobe_tip(3.0)], [round(x, 6) for x in lobe_tip(3.0, 2)]
    ([0.414214, 0.057191], [1.44949, 0.033674])
    """
    lam = _validate.positive_real("lambda_max", lambda_max)
    n = _filling(filling)
    y = math.sqrt(n * (n + 1)) - n
    return n - 1 + y, (math.sqrt(n + 1) - math.sqrt(n)) ** 2 / lam


# ----------------------------------------------------------------------------
# the graph: its adjacency and lambda_max
# ----------------------------------------------------------------------------

def _adjacency(system) -> sp.csr_matrix:
    """The adjacency matrix of a Lattice, a Cluster or a symmetric sparse/dense 0/1 matrix."""
    if sp.issparse(system) or isinstance(system, np.ndarray):
        mat = sp.csr_matrix(system, dtype=np.float64)
        if mat.shape[0] != mat.shape[1] or mat.shape[0] == 0:
            raise ValueError(f"the adjacency matrix must be square and non-empty, got shape {mat.shape}.")
        if not np.all(np.isfinite(mat.data)) or np.any(mat.data < 0):
            raise ValueError("the adjacency matrix must have finite non-negative entries.")
        if abs(mat - mat.T).max() if mat.nnz else 0.0:
            raise ValueError("the adjacency matrix must be symmetric.")
        return mat
    if hasattr(system, "adjacency") and callable(getattr(system, "adjacency")):   # a Cluster
        return sp.csr_matrix(system.adjacency(), dtype=np.float64)
    if hasattr(system, "ring_offsets") and hasattr(system, "neighbours"):           # a Lattice
        from ..graph.operators import adjacency

        return sp.csr_matrix(adjacency(system), dtype=np.float64)
    raise ValueError(f"system must be a Lattice, a Cluster or an adjacency matrix, got {_validate._shown(system)}.")


def _system_label(system) -> str:
    if hasattr(system, "ring_offsets") and hasattr(system, "rings"):
        return f"{{{system.p},{system.q}}} flake, l = {system.rings}"
    if hasattr(system, "name") and hasattr(system, "p"):
        return f"{{{system.p},{system.q}}} cluster {system.name}"
    return "graph"


def largest_adjacency_eigenvalue(system) -> float:
    r""":math:`\lambda_{\max}` of the adjacency matrix: :math:`-E_0/t` of the hopping Hamiltonian.

    A flake or its line graph (a :class:`~hyperlattice.Lattice`) goes through
    :func:`hyperlattice.lowest_levels` (its rotation sectors); a q-regular graph (a periodic
    cluster) has :math:`\lambda_{\max} = q` exactly (Perron–Frobenius: the constant vector) and
    returns the integer; any other graph gets a Lanczos estimate with its residual checked.

    Parameters
    ----------
    system : Lattice, Cluster or sparse matrix
        A flake or line graph, a periodic cluster, or a square symmetric adjacency matrix with
        finite non-negative entries.

    Returns
    -------
    float
        :math:`\lambda_{\max}` (an int for a q-regular cluster).

    Raises
    ------
    ValueError
        If ``system`` is of another type, or the matrix is not square, non-empty, symmetric with
        finite non-negative entries.

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.bosons.meanfield import largest_adjacency_eigenvalue
    >>> round(largest_adjacency_eigenvalue(hl.ring_lattice(7, 3, 2)), 6)
    2.636405
    """
    if hasattr(system, "ring_offsets"):
        from ..graph.spectrum import lowest_levels

        return float(-lowest_levels(system, 1).energies[0])
    a = _adjacency(system)
    deg = np.asarray(a.sum(axis=1)).ravel()
    if np.all(deg == deg[0]) and np.all((a.data == 1.0)):
        # regular graph: the constant vector is the Perron vector (for a connected graph, and the
        # largest eigenvalue equals the degree for any regular graph)
        return float(deg[0])
    n = a.shape[0]
    if n <= 400:
        return float(np.linalg.eigvalsh(a.toarray())[-1])
    import scipy.sparse.linalg as spla

    vals, vecs = spla.eigsh(a, k=1, which="LA", tol=1e-12, v0=np.ones(n))
    res = np.linalg.norm(a @ vecs[:, 0] - vals[0] * vecs[:, 0])
    if res > 1e-8 * max(1.0, abs(vals[0])):
        warnings.warn(f"lambda_max of the graph: Lanczos residual {res:.1e}.", ConvergenceWarning, stacklevel=2)
    return float(vals[0])


# ----------------------------------------------------------------------------
# the lobe of one system
# ----------------------------------------------------------------------------

@dataclasses.dataclass(frozen=True, eq=False)
class MottLobe(Result):
    r"""The Mott lobe of filling n of one system in the (μ/U, t/U) plane (mean field).

    Attributes
    ----------
    label : str
        The system (e.g. ``"{7,3} flake, l = 5"``, ``"infinite {7,3} lattice"``, ``"continuum, l = 5"``).
    lambda_max : float
        Largest adjacency eigenvalue used (or its continuum counterpart); the hopping term
        :math:`-tA` reaches :math:`-t\lambda_{\max}`.
    filling : int
        n.
    mu_over_U, t_c_over_U : ndarray
        The boundary :math:`t_c(\mu)/U` on a grid of :math:`\mu/U` in :math:`(n-1, n)`
        (dimensionless: energies in units of U).
    tip_mu_over_U, tip_t_over_U : float
        The lobe tip (closed form, :func:`lobe_tip`).

    Examples
    --------
    >>> from hyperlattice.bosons.meanfield import mott_lobe
    >>> lobe = mott_lobe(3.0, points=5)
    >>> lobe.mu_over_U.tolist(), [round(float(t), 6) for t in lobe.t_c_over_U]
    ([0.0, 0.25, 0.5, 0.75, 1.0], [0.0, 0.05, 0.055556, 0.035714, 0.0])
    >>> round(lobe.tip_mu_over_U, 6), round(lobe.tip_t_over_U, 6)
    (0.414214, 0.057191)
    """

    COLUMNS = (Column("t_over_U", "t_c_over_U", "1"), Column("mu_over_U", "mu_over_U", "1"))

    label: str
    lambda_max: float
    filling: int
    mu_over_U: np.ndarray
    t_c_over_U: np.ndarray
    tip_mu_over_U: float
    tip_t_over_U: float

    def summary(self) -> dict:
        return {"label": self.label, "lambda_max": self.lambda_max, "filling": self.filling,
                "mu_over_U": self.mu_over_U.tolist(), "t_c_over_U": self.t_c_over_U.tolist(),
                "tip_mu_over_U": self.tip_mu_over_U, "tip_t_over_U": self.tip_t_over_U}


def mott_lobe(lambda_max: float, filling: int = 1, points: int = 201, *, label: str = "") -> MottLobe:
    r"""The mean-field Mott lobe of filling n for a graph with largest adjacency eigenvalue :math:`\lambda_{\max}`.

    Parameters
    ----------
    lambda_max : float
        From :func:`largest_adjacency_eigenvalue` (a flake's :math:`-E_0/t`, q for a periodic
        cluster, :math:`\rho` for the infinite lattice).
    filling : int, optional
        n >= 1. Default 1.
    points : int, optional
        Grid points in :math:`\mu/U`; the end points :math:`n-1, n` (where :math:`t_c = 0`)
        included. Default 201.
    label : str, optional
        Name of the system, carried by the result.

    Returns
    -------
    MottLobe
        ``mu_over_U`` (grid on :math:`[n-1, n]`) and ``t_c_over_U`` (the boundary, from
        :func:`lobe_boundary`, 0 at the ends), the tip ``tip_mu_over_U``, ``tip_t_over_U``,
        ``lambda_max``, ``filling`` and ``label``.

    Raises
    ------
    ValueError
        If ``lambda_max`` is not positive, ``filling`` < 1, ``points`` out of range or ``label``
        not a string.

    See Also
    --------
    mott_lobes : lobes of many systems.

    References
    ----------
    .. [1] M. P. A. Fisher, P. B. Weichman, G. Grinstein and D. S. Fisher, Phys. Rev. B 40, 546
       (1989).
    .. [2] D. van Oosten, P. van der Straten and H. T. C. Stoof, Phys. Rev. A 63, 053601 (2001),
       Eq. (9).

    Examples
    --------
    >>> from hyperlattice.bosons.meanfield import mott_lobe
    >>> lobe = mott_lobe(3.0, points=5)
    >>> lobe.mu_over_U.tolist()
    [0.0, 0.25, 0.5, 0.75, 1.0]
    >>> [round(float(t), 6) for t in lobe.t_c_over_U], round(lobe.tip_t_over_U, 6)
    ([0.0, 0.05, 0.055556, 0.035714, 0.0], 0.057191)
    """
    lam = _validate.positive_real("lambda_max", lambda_max)
    n = _filling(filling)
    points = _validate.integer("points", points, minimum=3, maximum=10**6)
    if not isinstance(label, str):
        raise ValueError(f"label must be a string, got {_validate._shown(label)}.")
    mu = np.linspace(n - 1, n, points)
    tc = np.zeros(points)
    tc[1:-1] = lobe_boundary(lam, mu[1:-1], n)
    tip = lobe_tip(lam, n)
    return MottLobe(label=label or f"lambda_max = {lam:.6g}", lambda_max=lam, filling=n, mu_over_U=mu,
                    t_c_over_U=tc, tip_mu_over_U=tip[0], tip_t_over_U=tip[1])


# ----------------------------------------------------------------------------
# the self-consistent Gutzwiller state
# ----------------------------------------------------------------------------

_KERNEL: dict = {}


#: sites from which the parallel kernel pays for its thread start-up (measured: a 16-site cluster
#: iterates 8x faster serially; the l = 12 flake 1.8x faster in parallel on 2 cores)
_PARALLEL_SITES = 20_000
#: largest t/U and -mu/U the Gutzwiller iteration takes (beyond: the GP limit, or the empty lattice)
_MAX_RATIO = 1e6
#: smallest nonzero |t|/U and |mu|/U (below, the scaled values lose their bits: U = 1e308 with
#: mu = 0.5 gave a positive energy)
_MIN_RATIO = 1e-150
#: largest mean filling mu/U for which the occupation cutoff is chosen (nmax = 2 mu/U + 3 <= 200)
_MAX_FILLING = 98


def _local_kernel(parallel: bool = False):
    """numba kernel: the ground state of every site's tridiagonal local Hamiltonian (compiled once)."""
    key = "parallel" if parallel else "serial"
    if key in _KERNEL:
        return _KERNEL[key]
    import numba

    @numba.njit(cache=True, parallel=parallel)
    def local_states(phi, phi_prev, U, mu, nmax, psi_out, dens_out, e_out):  # pragma: no cover - compiled
        m = nmax + 1
        n = phi.shape[0]
        chunks = max(1, min(n, 256))
        d = np.empty(m)
        for k in range(m):
            d[k] = 0.5 * U * k * (k - 1) - mu * k
        sq = np.sqrt(np.arange(m) * 1.0)
        for c in numba.prange(chunks):
            e = np.empty(m)       # e[k] couples k-1 and k
            cc = np.empty(m)
            w = np.empty(m)
            v = np.empty(m)
            for i in range(c * n // chunks, (c + 1) * n // chunks):
                f = phi[i]
                e[0] = 0.0
                for k in range(1, m):
                    e[k] = -f * sq[k]
                # Gershgorin bracket, then Sturm bisection: lo stays below the lowest level
                lo = d[0] - abs(e[1]) if m > 1 else d[0]
                hi = d[0] + abs(e[1]) if m > 1 else d[0]
                for k in range(1, m):
                    r = abs(e[k]) + (abs(e[k + 1]) if k + 1 < m else 0.0)
                    lo = min(lo, d[k] - r)
                    hi = max(hi, d[k] + r)
                hi = min(hi, d[0])          # the lowest level lies below every diagonal entry
                for k in range(1, m):
                    hi = min(hi, d[k])
                scale = max(abs(lo), abs(hi), U)
                # warm start: the lowest level moves by at most |d phi| ||a + a^dag|| <= 2 sqrt(nmax) |d phi|
                # (Weyl); the bracket is used only when the Sturm counts confirm it
                if phi_prev[i] == phi_prev[i]:
                    width = 2.0 * sq[m - 1] * abs(f - phi_prev[i]) + 1e-12 * scale
                    wlo = e_out[i] - width
                    whi = e_out[i] + width
                    if wlo > lo and whi < hi:
                        ok = True
                        for trial in range(2):
                            x = wlo if trial == 0 else whi
                            piv = d[0] - x
                            below = piv < 0.0
                            k = 1
                            while k < m and not below:
                                if piv == 0.0:
                                    piv = 1e-300
                                piv = d[k] - x - e[k] * e[k] / piv
                                below = piv < 0.0
                                k += 1
                            if (trial == 0 and below) or (trial == 1 and not below):
                                ok = False
                        if ok:
                            lo = wlo
                            hi = whi
                while hi - lo > 1e-10 * scale:
                    x = 0.5 * (lo + hi)
                    piv = d[0] - x
                    below = piv < 0.0
                    k = 1
                    while k < m and not below:
                        if piv == 0.0:
                            piv = 1e-300
                        piv = d[k] - x - e[k] * e[k] / piv
                        below = piv < 0.0
                        k += 1
                    if below:
                        hi = x
                    else:
                        lo = x
                # inverse iteration at s just below the lowest level (H - s positive definite: the
                # tridiagonal LDL^T needs no pivoting); each step shrinks the other components by
                # (E0 - s) / (E1 - s) <~ 1e-10 scale / gap
                s = lo - 1e-10 * scale
                for k in range(m):
                    v[k] = 1.0
                for _ in range(2):
                    den = d[0] - s
                    cc[0] = (e[1] / den) if m > 1 else 0.0
                    w[0] = v[0] / den
                    for k in range(1, m):
                        den = d[k] - s - e[k] * cc[k - 1]
                        cc[k] = (e[k + 1] / den) if k + 1 < m else 0.0
                        w[k] = (v[k] - e[k] * w[k - 1]) / den
                    for k in range(m - 2, -1, -1):
                        w[k] -= cc[k] * w[k + 1]
                    nrm = 0.0
                    for k in range(m):
                        nrm += w[k] * w[k]
                    nrm = np.sqrt(nrm)
                    for k in range(m):
                        v[k] = w[k] / nrm
                a = 0.0
                nn = 0.0
                ray = d[0] * v[0] * v[0]
                for k in range(1, m):
                    a += sq[k] * v[k - 1] * v[k]
                    nn += k * v[k] * v[k]
                    ray += d[k] * v[k] * v[k] + 2.0 * e[k] * v[k - 1] * v[k]
                psi_out[i] = abs(a)     # the ground state of a real symmetric h has one sign
                dens_out[i] = nn
                e_out[i] = ray

    _KERNEL[key] = local_states
    return local_states


@dataclasses.dataclass(frozen=True, eq=False)
class GutzwillerState(Result):
    r"""A self-consistent site-decoupled mean-field state.

    Attributes
    ----------
    label : str
        What the graph is (e.g. ``"{7,3} flake, l = 2"``).
    t, mu, U : float
        The model's parameters (any common unit; hopping term :math:`-tA`).
    nmax : int
        Local occupation cutoff.
    psi : ndarray
        Order parameter :math:`\psi_i = \langle a_i\rangle` per site (real, >= 0 for t > 0).
    density : ndarray
        :math:`\langle n_i\rangle` per site.
    energy : float
        Mean-field energy :math:`\sum_i \epsilon_i + \sum_i \phi_i\psi_i` (the grand potential at μ).
    iterations : int
        Self-consistency iterations taken.
    residual : float
        :math:`\max_i |\psi_i - F_i(\psi)|` of the last iteration.
    converged : bool
        Whether the residual met the tolerance.
    cutoff_weight : float
        Largest weight of the occupation ``nmax`` on any site (small means the cutoff is harmless).

    Notes
    -----
    Site-indexed arrays follow the graph's order (0-based, ring by ring for a flake).

    Examples
    --------
    >>> import numpy as np
    >>> import hyperlattice as hl
    >>> from hyperlattice.bosons.meanfield import gutzwiller
    >>> sf = gutzwiller(hl.ring_lattice(7, 3, 2), 0.1, 0.5)          # t = 0.1 U, mu = 0.5 U
    >>> sf.label, sf.converged, sf.superfluid, round(float(np.max(sf.psi)), 6)
    ('{7,3} flake, l = 2', True, True, 0.822718)
    """

    #: one row per site
    COLUMNS = (Column("psi", "psi", "sqrt(bosons)"), Column("density", "density", "bosons"))

    label: str
    t: float
    mu: float
    U: float
    nmax: int
    psi: np.ndarray
    density: np.ndarray
    energy: float
    iterations: int
    residual: float
    converged: bool
    cutoff_weight: float

    @property
    def superfluid(self) -> bool:
        """True when the order parameter exceeds the iteration's own resolution (10x its residual)."""
        return bool(np.max(self.psi) > 10.0 * max(self.residual, 1e-12))

    def summary(self) -> dict:
        return {"label": self.label, "t": self.t, "mu": self.mu, "U": self.U, "nmax": self.nmax,
                "sites": int(self.psi.shape[0]), "psi_max": float(np.max(self.psi)),
                "psi_mean": float(np.mean(self.psi)), "density_mean": float(np.mean(self.density)),
                "energy_per_site": self.energy / self.psi.shape[0], "iterations": self.iterations,
                "residual": self.residual, "converged": self.converged, "superfluid": self.superfluid,
                "cutoff_weight": self.cutoff_weight}


def gutzwiller(system, t: float, mu: float, U: float = 1.0, *, nmax: int | None = None, tol: float = 1e-10,
               max_iter: int = 100_000, psi0=None) -> GutzwillerState:
    r"""The self-consistent site-decoupled mean-field ground state on a graph.

    Parameters
    ----------
    system : Lattice, Cluster or sparse matrix
        The graph (its adjacency A).
    t, mu, U : float
        Hopping (>= 0), chemical potential and on-site interaction (> 0), one unit.
    nmax : int, optional
        Occupation cutoff per site; default ``max(4, 2 ceil(mu/U) + 3)``. The result reports the
        largest weight of the top occupation (``cutoff_weight``): raise nmax if it is not small.
    tol : float
        Stop when :math:`\max_i|\psi_i - F_i(\psi)| \le` tol (F the local ground-state map).
    max_iter : int
        Iteration cap; a :class:`~hyperlattice.errors.ConvergenceWarning` states the residual
        reached when it is hit (slow convergence is expected very close to a lobe boundary,
        where the map's contraction rate tends to 1).
    psi0 : array, optional
        Start; default :math:`\sqrt{\bar n}` on every site, above the largest fixed point, so that
        the monotone iteration descends to the stable (largest) solution.

    Returns
    -------
    GutzwillerState
        The order parameter ``psi`` and ``density`` per site, the mean-field ``energy``,
        ``iterations``, ``residual``, ``converged`` and ``cutoff_weight``.

    Raises
    ------
    ValueError
        For bad input (t < 0, U <= 0, a bad ``psi0`` or system).

    Warns
    -----
    ConvergenceWarning
        If ``max_iter`` is reached before ``tol`` (the residual is stated).

    See Also
    --------
    mott_lobe : where :math:`\psi = 0` becomes unstable.

    References
    ----------
    .. [1] M. P. A. Fisher, P. B. Weichman, G. Grinstein and D. S. Fisher, Phys. Rev. B 40, 546
       (1989).
    .. [2] D. van Oosten, P. van der Straten and H. T. C. Stoof, Phys. Rev. A 63, 053601 (2001),
       Eq. (9).

    Examples
    --------
    Beyond the lobe (superfluid) and inside it (Mott, :math:`\psi = 0`, one boson per site):

    >>> import numpy as np
    >>> import hyperlattice as hl
    >>> from hyperlattice.bosons.meanfield import gutzwiller
    >>> lat = hl.ring_lattice(7, 3, 2)
    >>> sf = gutzwiller(lat, 0.1, 0.5)
    >>> sf.converged, round(float(np.max(sf.psi)), 6)
    (True, 0.822718)
    >>> mott = gutzwiller(lat, 0.01, 0.5)
    >>> bool(np.max(mott.psi) < 1e-8), round(float(np.mean(mott.density)), 6)
    (True, 1.0)
    """
    a = _adjacency(system)
    n_sites = a.shape[0]
    t = _validate.real("t", t, minimum=0.0)
    mu = _validate.real("mu", mu)
    U = _validate.positive_real("U", U)
    tol = _validate.solver_tolerance("tol", tol)
    max_iter = _validate.integer("max_iter", max_iter, minimum=1, maximum=10**8)
    # the problem depends on t/U and mu/U only: solved in units of U (U = 1e308 divided by zero
    # inside, 1e-308 overflowed), energies multiplied back at the end; the ratios are checked here,
    # in the physics' words, before any work
    if t / U > _MAX_RATIO:
        raise ValueError(f"t = {t:g} is more than {_MAX_RATIO:g} U: far in the weakly interacting regime, where "
                         "the occupation cutoff of the Gutzwiller states cannot hold the condensate "
                         "(use the Gross-Pitaevskii equation, hyperlattice.bosons.gp).")
    for name, value in (("t", t), ("mu", mu)):
        if value != 0 and abs(value) / U < _MIN_RATIO:
            raise ValueError(f"{name} = {value:g} is less than {_MIN_RATIO:g} U, too small to resolve beside U in "
                             f"float64 arithmetic; give {name} = 0 or a larger value.")
    if mu / U < -_MAX_RATIO:
        raise ValueError(f"mu = {mu:g} is below -{_MAX_RATIO:g} U: the ground state there is the empty lattice "
                         "(no bosons for mu < -q t); give mu within a few U of the Mott lobes.")
    if nmax is None:
        filling = max(mu, 0.0) / U
        if filling > _MAX_FILLING:
            raise ValueError(f"mu = {mu:g} is {filling:.3g} U: the mean filling would be about {filling:.3g} bosons "
                             f"per site, more than the {_MAX_FILLING} that the Gutzwiller states hold (200 occupations); "
                             "at such fillings use the Gross-Pitaevskii equation (hyperlattice.bosons.gp).")
        nmax = max(4, 2 * math.ceil(filling) + 3)
    nmax = _validate.integer("nmax", nmax, minimum=1, maximum=200)
    _validate.require_memory("the Gutzwiller iteration", 8.0 * n_sites * 12 + 12.0 * a.nnz)
    if psi0 is None:
        psi = np.full(n_sites, math.sqrt(max(1.0, mu / U + 1.0)))
    else:
        psi = _validate.real_array("psi0", psi0, shape=(n_sites,)).copy()
    given = (t, mu, U)
    scale, t, mu, U = U, t / U, mu / U, 1.0
    kernel = _local_kernel(n_sites >= _PARALLEL_SITES)
    new = np.empty(n_sites)
    dens = np.empty(n_sites)
    eps = np.empty(n_sites)
    phi_prev = np.full(n_sites, np.nan)      # no warm start in the first sweep
    residual = math.inf
    it = 0
    for it in range(1, max_iter + 1):
        phi = t * (a @ psi)
        kernel(phi, phi_prev, U, mu, nmax, new, dens, eps)
        phi_prev = phi
        residual = float(np.max(np.abs(new - psi)))
        psi, new = new, psi
        if residual <= tol:
            break
    converged = residual <= tol
    if not converged:
        warnings.warn(f"Gutzwiller iteration: residual {residual:.1e} after {it} iterations, above tol = "
                      f"{tol:.1e} (close to a lobe boundary the iteration slows down).", ConvergenceWarning,
                      stacklevel=2)
    phi = t * (a @ psi)
    kernel(phi, phi_prev, U, mu, nmax, new, dens, eps)
    energy = float(np.sum(eps) + np.dot(phi, psi)) * scale
    if not math.isfinite(energy):
        raise ValueError(f"the Gutzwiller energy at U = {scale:g} lies beyond the range of float64 numbers; "
                         "give U, t and mu in a smaller unit.")
    # weight of the top occupation: from the local ground states at the final field
    top = _top_weight(phi, U, mu, nmax)
    t, mu, U = given
    return GutzwillerState(label=_system_label(system), t=t, mu=mu, U=U, nmax=nmax, psi=psi.copy(),
                           density=dens.copy(), energy=energy, iterations=it, residual=residual,
                           converged=converged, cutoff_weight=top)


def _top_weight(phi: np.ndarray, U: float, mu: float, nmax: int) -> float:
    """Largest weight of |nmax> in the local ground states (dense eigh on the distinct fields)."""
    fields = np.unique(np.round(phi, 12))
    if fields.size > 2000:
        fields = np.quantile(phi, np.linspace(0, 1, 2000))
    k = np.arange(nmax + 1)
    worst = 0.0
    for f in fields:
        h = np.diag(0.5 * U * k * (k - 1) - mu * k) - f * (np.diag(np.sqrt(k[1:]), 1) + np.diag(np.sqrt(k[1:]), -1))
        _, v = np.linalg.eigh(h)
        worst = max(worst, float(v[-1, 0] ** 2))
    return worst


def selfconsistent_boundary(system, mu_over_U: float, *, tol: float = 1e-8, t_tol: float = 1e-4,
                            nmax: int | None = None, max_iter: int = 200_000) -> float:
    r""":math:`t_c/U` at one :math:`\mu/U` from the nonlinear self-consistency alone (no linearisation).

    Bisection on t/U between the atomic limit and twice the linear prediction: a point counts as
    superfluid when the converged order parameter exceeds :math:`\sqrt{\mathrm{tol}}` (the
    order parameter grows as :math:`\sqrt{t - t_c}` past the boundary, so the threshold
    resolves t - t_c to about tol). Used to check :func:`lobe_boundary`; as tol and t_tol shrink
    the two agree (the test suite measures it).

    Parameters
    ----------
    system : Lattice, Cluster or sparse matrix
        The graph, as in :func:`gutzwiller`.
    mu_over_U : float
        Chemical potential in units of U, inside the lobe of filling 1 (0 < mu/U < 1).
    tol : float, optional
        Tolerance of each :func:`gutzwiller` run (> 0); the superfluid threshold is
        :math:`\sqrt{\mathrm{tol}}`. Default 1e-8.
    t_tol : float, optional
        Relative width (> 0) of the final bisection interval. Default 1e-4.
    nmax : int, optional
        Occupation cutoff of the mean-field runs (default as in :func:`gutzwiller`).
    max_iter : int, optional
        Iteration cap of each run. Default 200 000.

    Returns
    -------
    float
        :math:`t_c/U`.

    Raises
    ------
    ValueError
        For bad input or a :math:`\mu/U` outside (0, 1).

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.bosons.meanfield import lobe_boundary, selfconsistent_boundary
    >>> tc = selfconsistent_boundary(hl.ring_lattice(7, 3, 1), 0.5, tol=1e-6, t_tol=1e-3)
    >>> round(tc, 4), round(float(lobe_boundary(2.0, 0.5)), 4)
    (0.0832, 0.0833)
    """
    mu_over_U = _validate.real("mu_over_U", mu_over_U)
    tol = _validate.solver_tolerance("tol", tol)
    t_tol = _validate.positive_real("t_tol", t_tol)
    lam = largest_adjacency_eigenvalue(system)
    guess = lobe_boundary(lam, mu_over_U)
    if not math.isfinite(guess):
        raise ValueError(f"mu_over_U = {mu_over_U} is not inside a Mott lobe of filling 1 (0 < mu/U < 1).")
    lo, hi = 0.0, 2.0 * guess
    threshold = math.sqrt(tol)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ConvergenceWarning)
        while hi - lo > t_tol * guess:
            mid = 0.5 * (lo + hi)
            st = gutzwiller(system, mid, mu_over_U, 1.0, nmax=nmax, tol=tol, max_iter=max_iter)
            if float(np.max(st.psi)) > threshold:
                hi = mid
            else:
                lo = mid
    return 0.5 * (lo + hi)


# ----------------------------------------------------------------------------
# lobes of many systems: flakes, clusters, the infinite lattice and the continuum
# ----------------------------------------------------------------------------

@dataclasses.dataclass(frozen=True, eq=False)
class MottLobeTable(Result):
    r"""Mott lobes of one filling for flakes, periodic clusters, the infinite lattice and the continuum.

    Attributes
    ----------
    p, q, filling : int
        Schläfli symbol and the filling n.
    lobes : list of MottLobe
        In the order of ``kinds``.
    kinds : list of str
        ``"flake"``, ``"continuum"``, ``"cluster"`` or ``"infinite"`` per lobe.
    rings : list of int or None
        l of a flake and of its continuum disk; None otherwise.

    Examples
    --------
    >>> from hyperlattice.bosons.meanfield import mott_lobes
    >>> table = mott_lobes(7, 3, rings=(2,), infinite=False, points=5)
    >>> table.kinds, table.rings
    (['flake', 'continuum'], [2, 2])
    >>> [(r["label"], round(r["lambda_max"], 4), round(r["tip_t_over_U"], 4)) for r in table.rows()]
    [('flake ℓ = 2', 2.6364, 0.0651), ('continuum ℓ = 2', 2.5703, 0.0668)]
    """

    p: int
    q: int
    filling: int
    lobes: list
    kinds: list
    rings: list

    def rows(self) -> list[dict]:
        """One row per system: label, kind, l, lambda_max, tip μ/U and t_c/U."""
        return [{"label": lobe.label, "kind": kind, "rings": ell, "lambda_max": lobe.lambda_max,
                 "tip_mu_over_U": lobe.tip_mu_over_U, "tip_t_over_U": lobe.tip_t_over_U}
                for lobe, kind, ell in zip(self.lobes, self.kinds, self.rings)]

    def summary(self) -> dict:
        return {"p": self.p, "q": self.q, "filling": self.filling, "rows": self.rows()}


def mott_lobes(p: int = 7, q: int = 3, rings=(3, 4, 5, 6, 8, 10, 12), *, filling: int = 1, clusters=(),
               infinite: bool = True, continuum: bool = True, points: int = 201) -> MottLobeTable:
    r"""Mean-field Mott lobes of filling n for flakes of several l, their continuum disks, periodic clusters and the infinite lattice.

    Parameters
    ----------
    p, q : int, optional
        Schläfli symbol, :math:`(p-2)(q-2) > 4`. Default {7,3}.
    rings : sequence of int, optional
        Flakes; :math:`\lambda_{\max} = -E_0(\ell)` from :func:`hyperlattice.lowest_levels`.
    filling : int, optional
        n >= 1. Default 1.
    clusters : sequence of str, optional
        Names from :func:`hyperlattice.list_clusters` (:math:`\lambda_{\max} = q`).
    infinite : bool
        Add the infinite lattice, :math:`\lambda_{\max} = \rho` (the extrapolated band bottom of
        :func:`hyperlattice.compare.limits.band_bottom`; {7,3} only has stored levels — other {p,q}
        skip it).
    continuum : bool
        Add the continuum counterpart of every flake: :math:`\lambda_{\max} = -E_0^{\rm cont}(\ell)`
        from :func:`hyperlattice.continuum_levels` (the paper's dictionary on the Dirichlet disk).
    points : int
        Grid of each lobe.

    Returns
    -------
    MottLobeTable
        ``lobes`` (one :class:`MottLobe` each) with their ``kinds`` and ``rings``; ``rows()``
        gives label, kind, l, lambda_max and the tip of each.

    Raises
    ------
    ValueError
        If {p,q} is not hyperbolic, ``clusters`` is not a list of names, or an argument is out
        of range.

    See Also
    --------
    mott_lobe, largest_adjacency_eigenvalue

    Examples
    --------
    >>> from hyperlattice.bosons.meanfield import mott_lobes
    >>> table = mott_lobes(7, 3, rings=(2,), infinite=False, points=21)
    >>> table.kinds, table.rings
    (['flake', 'continuum'], [2, 2])
    >>> [round(row["tip_t_over_U"], 6) for row in table.rows()]
    [0.065078, 0.066752]
    """
    p, q = _validate.pq(p, q)
    ells = _validate.int_list("rings", rings, minimum=1, maximum=40)
    if isinstance(clusters, str):
        clusters = [clusters]
    if not isinstance(clusters, (list, tuple)) or not all(isinstance(c, str) for c in clusters):
        raise ValueError(f"clusters must be a list of cluster names (strings), got {_validate._shown(clusters)}.")
    names = list(clusters)
    infinite = _validate.flag("infinite", infinite)
    continuum = _validate.flag("continuum", continuum)
    lobes, kinds, ring_col = [], [], []
    from ..graph.lattice import ring_lattice

    for ell in ells:
        lam = largest_adjacency_eigenvalue(ring_lattice(p, q, ell))
        lobes.append(mott_lobe(lam, filling, points, label=f"flake ℓ = {ell}"))
        kinds.append("flake")
        ring_col.append(ell)
        if continuum:
            from ..continuum.spectrum import continuum_levels

            e0 = float(continuum_levels(p, q, rings=ell, levels=1).energies[0])
            if -e0 > 0:
                lobes.append(mott_lobe(-e0, filling, points, label=f"continuum ℓ = {ell}"))
                kinds.append("continuum")
                ring_col.append(ell)
    for name in names:
        from ..graph.clusters import pbc_cluster

        cl = pbc_cluster(p, q, name)
        lam = largest_adjacency_eigenvalue(cl)
        lobes.append(mott_lobe(lam, filling, points, label=f"cluster {cl.name} ({cl.sites} sites)"))
        kinds.append("cluster")
        ring_col.append(None)
    if infinite:
        try:
            from ..compare.limits import band_bottom

            rho = band_bottom(p, q, schur_window=None).rho
        except ValueError:
            rho = None
        if rho is not None:
            lobes.append(mott_lobe(rho, filling, points, label=f"infinite lattice (ρ = {rho:.5f})"))
            kinds.append("infinite")
            ring_col.append(None)
    return MottLobeTable(p=p, q=q, filling=_filling(filling), lobes=lobes, kinds=kinds, rings=ring_col)


# every public function above checks its arguments at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
