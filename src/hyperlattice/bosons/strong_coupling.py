r"""Strong-coupling (t/U) expansion of the Mott-lobe boundaries on any graph, to third order.

.. math::

    H = -t \sum_{ij} A_{ij}\, a_i^\dagger a_j + \frac U2 \sum_i n_i(n_i-1) - \mu \sum_i n_i

(A symmetric, non-negative, zero diagonal; a flake, a periodic cluster or any weighted graph). In
the Mott state of filling n every site holds n bosons; one extra particle (one hole) at site x is
degenerate at t = 0 over all x, and degenerate perturbation theory in the hopping gives an
effective hopping Hamiltonian for it, a sparse matrix over the sites built from A. Its lowest
eigenvalue, minus the Mott energy to the same order, is the chemical potential at which the Mott
state gives way:

.. math::

    \mu_+ = E_{N+1} - E_N = U\big[n + \lambda_{\min}(P(x))\big], \qquad
    \mu_- = E_N - E_{N-1} = U\big[n - 1 - \lambda_{\min}(R(x))\big], \qquad x = t/U,

and the lobe tip is where :math:`\mu_+ = \mu_-`. With the Schrieffer–Wolff form of third-order
degenerate perturbation theory, :math:`H_{\rm eff} = PVP + PV\mathcal R V P + PV\mathcal R V
\mathcal R VP - \tfrac12\{PV\mathcal R^2VP,\, PVP\}`, and the notation

* :math:`D_2 = \operatorname{diag}(\sum_j A_{ij}^2)` (the degree for a 0/1 graph),
* :math:`A^{(3)} = A\circ A\circ A` (elementwise; = A for a 0/1 graph),
* :math:`E = D_2 A + A D_2`, :math:`T = \operatorname{diag}(A^3)` (closed 3-walks: twice the
  triangles at a site), :math:`A^3_{\rm o} = A^3 - T`,

the matrices are, in units of U (derived here for a general graph; the enumeration of three-hop
processes is in the project notes, and the tests check every coefficient against exact
diagonalisation on weighted graphs with and without triangles, to :math:`O(x^4)`):

.. math::

    P(x) &= -(n+1)\,x A + x^2\Big[\big(3n(n+1) - \tfrac{n(n+2)}2\big)D_2 - n(n+1)A^2\Big]
           + x^3\,P_3, \\
    R(x) &= -n\,x A + x^2\Big[\big(3n(n+1) - \tfrac{(n-1)(n+1)}2\big)D_2 - n(n+1)A^2\Big]
           + x^3\,R_3,

.. math::

    P_3 &= -n(n+1)(3n+2)\,(A^3_{\rm o} - E + A^{(3)}) - \tfrac{n(n+1)(n+2)}{2}(E - 2A^{(3)})
          + 2n(n+1)^2 (E - A^{(3)}) \\
        &\quad + \tfrac{n+1}{2}\Big[2n(n+1)A^3 - \big(3n(n+1) - \tfrac{n(n+2)}4\big)E\Big]
          + \Big[3n(n+1)(2n+1) - n(n+1)(n+2) - \tfrac{n^2(n+2)}4\Big] T, \\
    R_3 &= -n(n+1)(3n+1)\,(A^3_{\rm o} - E + A^{(3)}) - \tfrac{(n-1)n(n+1)}{2}(E - 2A^{(3)})
          + 2n^2(n+1)(E - A^{(3)}) \\
        &\quad + \tfrac n2\Big[2n(n+1)A^3 - \big(3n(n+1) - \tfrac{n^2-1}4\big)E\Big]
          + \Big[3n(n+1)(2n+1) - (n-1)n(n+1) - \tfrac{(n-1)(n+1)^2}4\Big] T .

For n = 1 and a 0/1 graph: :math:`P = -2xA + x^2(\tfrac92 D - 2A^2) + x^3(-6A^3_{\rm o} +
\tfrac{39}4 E - 12A + \tfrac{61}4 T)` and :math:`R = -xA + x^2(6D - 2A^2) + x^3(-6A^3_{\rm o} + 9E
- 12A + 20T)`. The terms proportional to the number of bonds (vacuum fluctuations away from the
defect) cancel between the defect and the Mott energy, so the matrices are local: the expansion
holds on a finite flake, boundary included, and on every periodic cluster.

The regular hypercubic lattice (coordination z = 2d, no triangles) has the uniform vector as the
lowest eigenvector, and the boundaries reduce to the closed forms of Freericks and Monien:

.. math::

    \mu_+/U &= n - z(n+1)x + x^2\big[(3n(n+1) - \tfrac{n(n+2)}2) z - n(n+1) z^2\big] + x^3 p_3(z), \\
    \mu_-/U &= n - 1 + z n x - x^2\big[(3n(n+1) - \tfrac{n^2-1}2) z - n(n+1) z^2\big] - x^3 r_3(z),

with :math:`p_3, r_3` the row sums of :math:`P_3, R_3` (n = 1: :math:`p_3 = -6z^3 + 39z^2/2 - 12z`,
:math:`r_3 = -6z^3 + 18z^2 - 12z`); :func:`hypercubic_boundaries` evaluates them. In d = 1 the gap
is :math:`\Delta/U = 1 - 6x + 5x^2 + 6x^3`.

References
----------
* J. K. Freericks and H. Monien, Phys. Rev. B 53, 2691 (1996): strong-coupling expansion of
  the Bose–Hubbard phase diagram to third order in t/U (hypercubic lattices).
* J. K. Freericks and H. Monien, Europhys. Lett. 26, 545 (1994).
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

__all__ = ["StrongCouplingLobe", "excitation_matrices", "excitation_energies", "strong_coupling_lobe",
           "strong_coupling_tip", "hypercubic_boundaries"]

#: dense eigensolver up to this many sites (Lanczos is faster above; measured on {7,3} flakes)
_DENSE_SITES = 40


def _graph_adjacency(system) -> tuple[sp.csr_matrix, str]:
    from .meanfield import _adjacency, _system_label

    a = _adjacency(system).tocsr().astype(np.float64)
    if a.diagonal().any():
        raise ValueError("the adjacency matrix must have a zero diagonal (no on-site hopping).")
    a.eliminate_zeros()
    a.sort_indices()
    return a, _system_label(system)


def _filling(n) -> int:
    return _validate.integer("filling", n, minimum=1, maximum=1000)


def _order(order) -> int:
    return _validate.integer("order", order, minimum=1, maximum=3)


def excitation_matrices(system, filling: int = 1) -> dict:
    r"""The coefficient matrices of the particle and hole effective Hamiltonians, order by order.

    Parameters
    ----------
    system : Lattice, Cluster or sparse matrix
        A flake, a periodic cluster, or a square symmetric adjacency matrix (non-negative weights,
        zero diagonal).
    filling : int, optional
        The Mott lobe n >= 1. Default 1.

    Returns
    -------
    dict
        ``"particle"`` and ``"hole"``: lists ``[M1, M2, M3]`` of scipy.sparse CSR matrices with
        :math:`P(x) = x M_1 + x^2 M_2 + x^3 M_3` (and R(x) likewise), x = t/U, energies in units of
        U (the module docstring gives them); ``"sites"``, ``"label"``.

    Raises
    ------
    ValueError
        If ``system`` is not a graph the package knows or ``filling`` < 1.

    Examples
    --------
    >>> import numpy as np, scipy.sparse as sp
    >>> from hyperlattice.bosons.strong_coupling import excitation_matrices
    >>> ring = sp.csr_matrix(np.roll(np.eye(6), 1, 1) + np.roll(np.eye(6), -1, 1))   # 6-site ring
    >>> m = excitation_matrices(ring)
    >>> [float(M.sum(axis=1)[0, 0]) for M in m["particle"]], [float(M.sum(axis=1)[0, 0]) for M in m["hole"]]
    ([-4.0, 1.0, 6.0], [-2.0, 4.0, 0.0])
    """
    a, label = _graph_adjacency(system)
    n = _filling(filling)
    m = a.shape[0]
    _validate.require_memory(f"the third-order hopping matrices of a {m:,}-site graph",
                             40.0 * 4 * (a.nnz * max(1.0, a.nnz / max(m, 1)) ** 2 + m))
    a2 = (a @ a).tocsr()
    a3 = (a2 @ a).tocsr()
    d2 = np.asarray(a.multiply(a).sum(axis=1)).ravel()
    D2 = sp.diags(d2)
    T = sp.diags(a3.diagonal())
    a3o = (a3 - T).tocsr()
    E = (D2 @ a + a @ D2).tocsr()
    Q = a.multiply(a).multiply(a).tocsr()
    eye = sp.identity(m, format="csr")
    del eye
    p1 = -(n + 1) * a
    p2 = (3 * n * (n + 1) - n * (n + 2) / 2.0) * D2 - n * (n + 1) * a2
    p3 = (-n * (n + 1) * (3 * n + 2) * (a3o - E + Q) - n * (n + 1) * (n + 2) / 2.0 * (E - 2 * Q)
          + 2 * n * (n + 1) ** 2 * (E - Q)
          + (n + 1) / 2.0 * (2 * n * (n + 1) * a3 - (3 * n * (n + 1) - n * (n + 2) / 4.0) * E)
          + (3 * n * (n + 1) * (2 * n + 1) - n * (n + 1) * (n + 2) - n * n * (n + 2) / 4.0) * T)
    r1 = -n * a
    r2 = (3 * n * (n + 1) - (n - 1) * (n + 1) / 2.0) * D2 - n * (n + 1) * a2
    r3 = (-n * (n + 1) * (3 * n + 1) * (a3o - E + Q) - (n - 1) * n * (n + 1) / 2.0 * (E - 2 * Q)
          + 2 * n * n * (n + 1) * (E - Q)
          + n / 2.0 * (2 * n * (n + 1) * a3 - (3 * n * (n + 1) - (n * n - 1) / 4.0) * E)
          + (3 * n * (n + 1) * (2 * n + 1) - (n - 1) * n * (n + 1) - (n - 1) * (n + 1) ** 2 / 4.0) * T)
    fix = [lambda M: sp.csr_matrix(M, dtype=np.float64)]
    return {"particle": [fix[0](p1), fix[0](p2), fix[0](p3)], "hole": [fix[0](r1), fix[0](r2), fix[0](r3)],
            "sites": m, "label": label}


def _lowest(mat: sp.csr_matrix, v0=None) -> tuple[float, np.ndarray]:
    m = mat.shape[0]
    if not np.any(mat.data):          # t = 0: the zero matrix (ARPACK refuses a zero operator)
        return 0.0, np.full(m, 1.0 / np.sqrt(m))
    if m <= _DENSE_SITES:
        w, v = np.linalg.eigh(mat.toarray())
        return float(w[0]), v[:, 0]
    import scipy.sparse.linalg as spla

    # shift so that the wanted end is the largest magnitude: Lanczos on -(M - c) with c >= max eig
    c = float(abs(mat).sum(axis=1).max())
    op = (c * sp.identity(m, format="csr") - mat).tocsr()
    w, v = spla.eigsh(op, k=1, which="LA", tol=1e-12, v0=v0, maxiter=20 * m)
    lam = c - float(w[0])
    vec = v[:, 0]
    res = float(np.linalg.norm(mat @ vec - lam * vec))
    if res > 1e-8 * max(1.0, abs(lam)):
        warnings.warn(f"strong-coupling lowest eigenvalue: Lanczos residual {res:.1e}.", ConvergenceWarning,
                      stacklevel=3)
    return lam, vec


def _energies(mats: dict, x: np.ndarray, order: int, n: int) -> tuple[np.ndarray, np.ndarray]:
    mu_p = np.empty(x.shape)
    mu_m = np.empty(x.shape)
    vp = vh = None
    for k, xv in enumerate(x):
        P = sum(xv ** (j + 1) * mats["particle"][j] for j in range(order))
        R = sum(xv ** (j + 1) * mats["hole"][j] for j in range(order))
        lp, vp = _lowest(sp.csr_matrix(P), vp)
        lh, vh = _lowest(sp.csr_matrix(R), vh)
        mu_p[k] = n + lp
        mu_m[k] = n - 1 - lh
    return mu_p, mu_m


def excitation_energies(system, t_over_U, *, filling: int = 1, order: int = 3) -> tuple[np.ndarray, np.ndarray]:
    r"""The lobe boundaries :math:`\mu_\pm/U` of the strong-coupling expansion at given t/U.

    Parameters
    ----------
    system : Lattice, Cluster or sparse matrix
        The graph (see :func:`excitation_matrices`).
    t_over_U : array_like of float
        Hopping values, each >= 0.
    filling : int, optional
        n >= 1. Default 1.
    order : int, optional
        1, 2 or 3 (terms kept in t/U). Default 3.

    Returns
    -------
    mu_plus, mu_minus : ndarray
        :math:`\mu_+/U` (particle: lowest eigenvalue of :math:`n + P(x)`) and :math:`\mu_-/U`
        (:math:`n - 1 - \lambda_{\min} R(x)`), of the shape of ``t_over_U``.

    Raises
    ------
    ValueError
        If an argument is out of range.

    Examples
    --------
    >>> import numpy as np, scipy.sparse as sp
    >>> from hyperlattice.bosons.strong_coupling import excitation_energies
    >>> ring = sp.csr_matrix(np.roll(np.eye(8), 1, 1) + np.roll(np.eye(8), -1, 1))
    >>> mp, mm = excitation_energies(ring, [0.0, 0.1])
    >>> [round(float(v), 6) for v in mp], [round(float(v), 6) for v in mm]
    ([1.0, 0.616], [0.0, 0.16])
    """
    n = _filling(filling)
    order = _order(order)
    x = _validate.real_array("t_over_U", t_over_U)
    if x.size and (np.any(x < 0)):
        raise ValueError("t_over_U must be >= 0.")
    mats = excitation_matrices(system, n)
    shape = x.shape
    mp, mm = _energies(mats, x.ravel(), order, n)
    return mp.reshape(shape), mm.reshape(shape)


def _tip(mats: dict, n: int, order: int, x_max: float, points: int = 25) -> tuple[float, float]:
    """First zero of the gap mu_+ - mu_- in (0, x_max], by a grid then bisection; NaN if none."""
    from scipy.optimize import brentq

    xs = np.linspace(0.0, x_max, points + 1)[1:]
    mp, mm = _energies(mats, xs, order, n)
    gap = mp - mm
    idx = np.flatnonzero(gap <= 0)
    if idx.size == 0:
        return math.nan, math.nan
    i = int(idx[0])
    lo = xs[i - 1] if i > 0 else 0.0
    hi = xs[i]

    def g(xv):
        a, b = _energies(mats, np.array([xv]), order, n)
        return float(a[0] - b[0])

    xc = brentq(g, lo, hi, xtol=1e-10, rtol=1e-10)
    a, b = _energies(mats, np.array([xc]), order, n)
    return float(xc), float(0.5 * (a[0] + b[0]))


@dataclasses.dataclass(frozen=True, eq=False)
class StrongCouplingLobe(Result):
    r"""The Mott lobe of filling n from the strong-coupling expansion on one graph.

    Attributes
    ----------
    label : str
        The system.
    sites : int
        Graph size.
    filling, order : int
        n and the order in t/U kept.
    t_over_U, mu_plus, mu_minus : ndarray
        The boundaries :math:`\mu_\pm/U` on a grid of t/U (energies in units of U).
    tip_t_over_U, tip_mu_over_U : float
        Where :math:`\mu_+ = \mu_-` (NaN if the series' gap does not close on the grid's range).

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.bosons.strong_coupling import strong_coupling_lobe
    >>> lobe = strong_coupling_lobe(hl.ring_lattice(7, 3, 2), [0.0, 0.05])
    >>> [round(float(v), 4) for v in lobe.mu_plus], [round(float(v), 4) for v in lobe.mu_minus]
    ([1.0, 0.7336], [0.0, 0.1258])
    """

    COLUMNS = (Column("t_over_U", "t_over_U", "1"), Column("mu_plus", "mu_plus", "U"),
               Column("mu_minus", "mu_minus", "U"))

    label: str
    sites: int
    filling: int
    order: int
    t_over_U: np.ndarray
    mu_plus: np.ndarray
    mu_minus: np.ndarray
    tip_t_over_U: float
    tip_mu_over_U: float

    def summary(self) -> dict:
        return {"label": self.label, "sites": self.sites, "filling": self.filling, "order": self.order,
                "tip_t_over_U": self.tip_t_over_U, "tip_mu_over_U": self.tip_mu_over_U}


def strong_coupling_lobe(system, t_over_U=None, *, filling: int = 1, order: int = 3) -> StrongCouplingLobe:
    r"""The strong-coupling Mott lobe of a graph: :math:`\mu_\pm(t)` and its tip.

    Parameters
    ----------
    system : Lattice, Cluster or sparse matrix
        The graph (see :func:`excitation_matrices`).
    t_over_U : array_like of float, optional
        Grid of t/U (each >= 0); default 41 points from 0 up to the tip.
    filling : int, optional
        n >= 1. Default 1.
    order : int, optional
        1, 2 or 3. Default 3.

    Returns
    -------
    StrongCouplingLobe
        The boundaries on the grid and the tip where :math:`\mu_+ = \mu_-` (searched on
        (0, 0.5/n] in t/U; NaN when the truncated series' gap does not close there).

    Raises
    ------
    ValueError
        If an argument is out of range.

    See Also
    --------
    hyperlattice.bosons.meanfield.mott_lobe : the mean-field lobe.

    References
    ----------
    .. [1] J. K. Freericks and H. Monien, Phys. Rev. B 53, 2691 (1996).

    Examples
    --------
    >>> import numpy as np, scipy.sparse as sp
    >>> from hyperlattice.bosons.strong_coupling import strong_coupling_lobe
    >>> ring = sp.csr_matrix(np.roll(np.eye(12), 1, 1) + np.roll(np.eye(12), -1, 1))
    >>> round(strong_coupling_lobe(ring, [0.1]).tip_t_over_U, 4)      # 1 - 6x + 5x^2 + 6x^3 = 0
    0.2153
    """
    n = _filling(filling)
    order = _order(order)
    mats = excitation_matrices(system, n)
    xc, mc = _tip(mats, n, order, 0.5 / n)
    if t_over_U is None:
        top = xc if math.isfinite(xc) else 0.5 / n
        x = np.linspace(0.0, top, 41)
    else:
        x = _validate.real_array("t_over_U", t_over_U, ndim=1)
        if x.size == 0 or np.any(x < 0):
            raise ValueError("t_over_U must be a non-empty list of values >= 0.")
    mp, mm = _energies(mats, x, order, n)
    return StrongCouplingLobe(label=mats["label"], sites=mats["sites"], filling=n, order=order, t_over_U=x,
                              mu_plus=mp, mu_minus=mm, tip_t_over_U=xc, tip_mu_over_U=mc)


def strong_coupling_tip(system, *, filling: int = 1, order: int = 3) -> tuple[float, float]:
    r"""The lobe tip :math:`((t/U)_c, \mu_c/U)` of the strong-coupling expansion on a graph.

    Parameters
    ----------
    system : Lattice, Cluster or sparse matrix
        The graph.
    filling : int, optional
        n >= 1. Default 1.
    order : int, optional
        1, 2 or 3. Default 3.

    Returns
    -------
    tuple of float
        :math:`(t/U)_c` and :math:`\mu_c/U` where :math:`\mu_+ = \mu_-`, NaN when the truncated
        series' gap does not close for t/U <= 0.5/n.

    Raises
    ------
    ValueError
        If an argument is out of range.

    Examples
    --------
    >>> import numpy as np, scipy.sparse as sp
    >>> from hyperlattice.bosons.strong_coupling import strong_coupling_tip
    >>> ring = sp.csr_matrix(np.roll(np.eye(12), 1, 1) + np.roll(np.eye(12), -1, 1))
    >>> [round(v, 4) for v in strong_coupling_tip(ring, order=1)]      # 1 - 6x = 0
    [0.1667, 0.3333]
    """
    n = _filling(filling)
    order = _order(order)
    return _tip(excitation_matrices(system, n), n, order, 0.5 / n)


def hypercubic_boundaries(dimension: int, t_over_U, *, filling: int = 1, order: int = 3
                          ) -> tuple[np.ndarray, np.ndarray]:
    r"""Closed-form :math:`\mu_\pm/U` on the d-dimensional hypercubic lattice (z = 2d).

    The row sums of the particle and hole matrices (the uniform vector is the lowest eigenvector
    of a translation-invariant lattice without triangles); Freericks and Monien's third-order
    boundaries, written with the coordination z.

    Parameters
    ----------
    dimension : int
        d >= 1.
    t_over_U : array_like of float
        Hopping values >= 0.
    filling : int, optional
        n >= 1. Default 1.
    order : int, optional
        1, 2 or 3. Default 3.

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
    >>> from hyperlattice.bosons.strong_coupling import hypercubic_boundaries
    >>> mp, mm = hypercubic_boundaries(2, [0.05])
    >>> round(float(mp[0]), 6), round(float(mm[0]), 6)
    (0.55, 0.238)
    """
    d = _validate.integer("dimension", dimension, minimum=1, maximum=1000)
    n = _filling(filling)
    order = _order(order)
    x = _validate.real_array("t_over_U", t_over_U)
    if x.size and np.any(x < 0):
        raise ValueError("t_over_U must be >= 0.")
    z = 2.0 * d
    # row sums of the matrices of excitation_matrices for a z-regular graph without triangles:
    # A -> z, A^2 -> z^2, D2 -> z, A^3_o -> z^3, E -> 2 z^2, A^(3) -> z, T -> 0
    a, a2, d2, a3o, E, Q = z, z * z, z, z ** 3, 2 * z * z, z
    p = [-(n + 1) * a,
         (3 * n * (n + 1) - n * (n + 2) / 2.0) * d2 - n * (n + 1) * a2,
         (-n * (n + 1) * (3 * n + 2) * (a3o - E + Q) - n * (n + 1) * (n + 2) / 2.0 * (E - 2 * Q)
          + 2 * n * (n + 1) ** 2 * (E - Q) + (n + 1) / 2.0 * (2 * n * (n + 1) * a3o
                                                           - (3 * n * (n + 1) - n * (n + 2) / 4.0) * E))]
    r = [-n * a,
         (3 * n * (n + 1) - (n - 1) * (n + 1) / 2.0) * d2 - n * (n + 1) * a2,
         (-n * (n + 1) * (3 * n + 1) * (a3o - E + Q) - (n - 1) * n * (n + 1) / 2.0 * (E - 2 * Q)
          + 2 * n * n * (n + 1) * (E - Q) + n / 2.0 * (2 * n * (n + 1) * a3o
                                                       - (3 * n * (n + 1) - (n * n - 1) / 4.0) * E))]
    mp = n + sum(p[j] * x ** (j + 1) for j in range(order))
    mm = n - 1 - sum(r[j] * x ** (j + 1) for j in range(order))
    return np.asarray(mp, dtype=float), np.asarray(mm, dtype=float)


# every public function above checks its arguments at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
