r"""Second Chern numbers and spin Chern numbers of Abelian Bloch bands on closed surfaces.

On a cluster of genus g the Abelian Bloch Hamiltonian :math:`H(k)` of a model lives on the
2g-torus (:mod:`hyperlattice.topology.surfaces`). For g >= 2 every choice of four momenta
:math:`(k_a, k_b, k_c, k_d)` (the others at 0) is a 4-subtorus, and the occupied bands define a
vector bundle over it with the second Chern character

.. math:: C_2 = \frac{1}{8\pi^2}\int \mathrm{tr}\, F\wedge F
              = \frac{1}{4\pi^2}\int d^4k\;\mathrm{tr}\,(F_{ab}F_{cd} - F_{ac}F_{bd} + F_{ad}F_{bc}),

the "second Chern number" of the four-dimensional quantum Hall effect (Qi, Hughes and Zhang,
PRB 78, 195424 (2008), eq. 27, there written :math:`\frac{1}{32\pi^2}\int\epsilon^{\mu\nu\rho\sigma}
\mathrm{tr}F_{\mu\nu}F_{\rho\sigma}`). It is an integer on the 4-torus; for a bundle whose first
Chern numbers :math:`C_{ab}` do not vanish it contains their square, :math:`C_2 = \mathrm{Pf}\,C^{(abcd)}
- c_2`, with :math:`c_2` the second Chern class and :math:`\mathrm{Pf}\,C^{(abcd)} = C_{ab}C_{cd}
- C_{ac}C_{bd} + C_{ad}C_{bc}` (:math:`\int c_1^2/2` on the 4-torus). Both numbers are reported.

Method (gauge invariant, no choice of eigenvector phases): the non-Abelian Berry curvature of
the occupied bands at each k is the projector formula (Avron, Seiler and Simon, PRL 51, 51
(1983)) :math:`F_{\mu\nu} = i P[\partial_\mu P, \partial_\nu P]P`, evaluated from the exact
derivatives :math:`\partial_\mu H = \sum i w_\mu B e^{ik\cdot w}` by first-order perturbation
theory: in the eigenbasis, :math:`X_\mu = \langle m|\partial_\mu H|n\rangle/(E_n - E_m)` (m empty, n
occupied) and :math:`F_{\mu\nu} = i(X_\mu^\dagger X_\nu - X_\nu^\dagger X_\mu)`, an occ x occ
Hermitian matrix whose trace is the Abelian curvature with the sign of
:mod:`~hyperlattice.topology.surfaces` (:math:`F = \partial_a A_b - \partial_b A_a`, :math:`A =
i\langle u|\nabla u\rangle`; square-lattice QWZ at M = 1 has C = -1). The integrand is smooth and
periodic where the gap is open, so the equispaced n^4 rule (the trapezoid rule on the torus)
converges exponentially in n (Trefethen and Weideman, SIAM Rev. 56, 385 (2014)); the grid grows
by 4 per direction until two successive values agree within ``tol``, and the last difference is
the stated error. The smallest direct gap over every grid point used is reported, and a gap at
or below the eigensolver's rounding is refused.

The spin Chern number (Sheng, Weng, Sheng and Haldane, PRL 97, 036808 (2006)) of Kane–Mele
without Rashba coupling: :math:`s_z` is conserved, the spin-up block is Haldane with phase
:math:`\phi` and the spin-down block Haldane with :math:`-\phi`; each block is half filled, and
:math:`C^s_{ab} = (C^\uparrow_{ab} - C^\downarrow_{ab})/2` on every 2-subtorus. Time reversal
maps one block onto the other (:math:`C^\downarrow = -C^\uparrow`), so :math:`C^s = C^\uparrow`
and the :math:`\mathbb Z_2` index of the 2-subtorus :math:`(a, b)` is :math:`C^\uparrow_{ab} \bmod 2`
(Kane and Mele, PRL 95, 146802 (2005), in the :math:`s_z`-conserving case).
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from .. import _validate
from ..errors import ConvergenceError
from ..results import Result
from .models import MODELS, ModelTerms, PlaneGraph, model_terms

__all__ = ["SecondChern", "SpinChern", "dirac4_torus", "kubo_chern", "second_chern", "spin_chern",
           "product_terms", "particle_hole", "chern2_density"]

_SX = np.array([[0, 1], [1, 0]], dtype=np.complex128)
_SY = np.array([[0, -1j], [1j, 0]], dtype=np.complex128)
_SZ = np.array([[1, 0], [0, -1]], dtype=np.complex128)
_ID = np.eye(2, dtype=np.complex128)

#: the five anticommuting 4 x 4 Dirac matrices of :func:`dirac4_torus` (Gamma_1..4, Gamma_5 the mass)
GAMMA = (np.kron(_SX, _SX), np.kron(_SX, _SY), np.kron(_SX, _SZ), np.kron(_SY, _ID), np.kron(_SZ, _ID))

#: largest number of k points diagonalised at once (memory ~ K * rows^2 * 16 B * 8)
_CHUNK = 4096


def dirac4_torus(m: float) -> ModelTerms:
    r"""The lattice Dirac model on the Euclidean 4-torus, the reference of :func:`second_chern`.

    :math:`H(k) = \sum_{\mu=1}^4 \sin k_\mu\,\Gamma_\mu + (m + \sum_\mu \cos k_\mu)\,\Gamma_5` (Qi,
    Hughes and Zhang, PRB 78, 195424 (2008), eq. 39; four bands, two occupied): on-site
    :math:`m\Gamma_5`, and a hop :math:`\tfrac12(\Gamma_5 - i\Gamma_\mu)` to the next cell in
    direction :math:`\mu`. The gap closes at m = 0, +-2, +-4; :func:`second_chern` gives
    :math:`C_2 = -1, 3, -3, 1` in the four gapped intervals (-4, -2), (-2, 0), (0, 2), (2, 4) and 0 outside
    (with the curvature sign of the module docstring).

    Parameters
    ----------
    m : float
        The mass, finite.

    Returns
    -------
    ModelTerms
        One site, four orbitals, windings in :math:`\mathbb Z^4`.

    Examples
    --------
    >>> from hyperlattice.topology.closed import dirac4_torus
    >>> t = dirac4_torus(-1.0)
    >>> t.orbitals, t.windings.shape
    (4, (8, 4))
    """
    m = _validate.real("m", m, minimum=-1e6, maximum=1e6)
    blocks, winds = [], []
    for mu in range(4):
        b = 0.5 * (GAMMA[4] - 1j * GAMMA[mu])
        w = np.zeros(4, dtype=np.int64)
        w[mu] = 1
        blocks += [b, b.conj().T]
        winds += [w, -w]
    return ModelTerms(model="dirac4", orbitals=4, onsite=(m * GAMMA[4])[None].astype(np.complex128),
                      tail=np.zeros(8, dtype=np.int64), head=np.zeros(8, dtype=np.int64),
                      blocks=np.array(blocks, dtype=np.complex128), windings=np.array(winds, dtype=np.int64),
                      parameters={"m": m})


def product_terms(a: ModelTerms, b: ModelTerms) -> ModelTerms:
    r"""The model :math:`H_a(k_a)\otimes 1 + 1\otimes H_b(k_b)` on the product of two tori (one site each).

    Its lowest band is the tensor product of the lowest bands of a and b, a line bundle with
    :math:`C_2 = C_a C_b` (its Chern character :math:`c_1^2/2`): the check of :func:`second_chern`
    on a bundle whose second Chern number comes only from first Chern numbers.

    Parameters
    ----------
    a, b : ModelTerms
        Models on tori with one site (e.g. ``model_terms(square_torus(), "qwz")``).

    Returns
    -------
    ModelTerms
        One site, ``a.orbitals * b.orbitals`` orbitals, windings in :math:`\mathbb Z^{2g_a + 2g_b}`.

    Examples
    --------
    >>> from hyperlattice.topology.models import model_terms, square_torus
    >>> from hyperlattice.topology.closed import product_terms
    >>> q = model_terms(square_torus(), "qwz", M=1.0)
    >>> product_terms(q, q).windings.shape
    (8, 4)
    """
    for t in (a, b):
        if not isinstance(t, ModelTerms):
            raise ValueError(f"expected ModelTerms, got {type(t).__name__}.")
        if t.sites != 1 or t.windings.shape[1] == 0:
            raise ValueError("product_terms needs models on tori with one site.")
    da, db = a.orbitals, b.orbitals
    ga, gb = a.windings.shape[1], b.windings.shape[1]
    blocks = [np.kron(x, np.eye(db)) for x in a.blocks] + [np.kron(np.eye(da), y) for y in b.blocks]
    winds = np.zeros((len(blocks), ga + gb), dtype=np.int64)
    winds[: len(a.blocks), :ga] = a.windings
    winds[len(a.blocks):, ga:] = b.windings
    onsite = np.kron(a.onsite[0], np.eye(db)) + np.kron(np.eye(da), b.onsite[0])
    n = len(blocks)
    return ModelTerms(model=f"{a.model}x{b.model}", orbitals=da * db, onsite=onsite[None].astype(np.complex128),
                      tail=np.zeros(n, dtype=np.int64), head=np.zeros(n, dtype=np.int64),
                      blocks=np.array(blocks, dtype=np.complex128), windings=winds,
                      parameters={"a": a.parameters, "b": b.parameters})


# ----------------------------------------------------------------------------
# the curvature engine
# ----------------------------------------------------------------------------

class _Bloch:
    """H(k) and its derivatives for many k at once, from a sparse scatter of the hop blocks."""

    def __init__(self, terms: ModelTerms):
        d, n = terms.orbitals, terms.sites
        self.rows = R = n * d
        a, b = np.meshgrid(np.arange(d), np.arange(d), indexing="ij")
        r = (terms.tail[:, None, None] * d + a[None]).ravel()
        c = (terms.head[:, None, None] * d + b[None]).ravel()
        h = np.repeat(np.arange(len(terms.tail)), d * d)
        self.scatter = sp.csr_matrix((terms.blocks.ravel(), (r * R + c, h)), shape=(R * R, len(terms.tail)))
        on = np.zeros((R, R), dtype=np.complex128)
        for i in range(n):
            on[i * d:(i + 1) * d, i * d:(i + 1) * d] = terms.onsite[i]
        self.onsite = on
        self.w = terms.windings.astype(float)

    def h(self, kk: np.ndarray, dirs) -> tuple[np.ndarray, list[np.ndarray]]:
        R = self.rows
        phase = np.exp(1j * (kk @ self.w.T))                      # (K, hops)
        H = (self.scatter @ phase.T).T.reshape(-1, R, R) + self.onsite
        dH = [(self.scatter @ (1j * self.w[:, mu][None] * phase).T).T.reshape(-1, R, R) for mu in dirs]
        return H, dH


def _curvatures(bloch: _Bloch, kk: np.ndarray, dirs, occ: int):
    """F_{mu nu} (occ x occ) for the pairs of ``dirs`` at the points kk; also the smallest gap and rounding."""
    H, dH = bloch.h(kk, dirs)
    e, v = np.linalg.eigh(H)
    gap = e[:, occ] - e[:, occ - 1]
    vo, vu = v[:, :, :occ], v[:, :, occ:]
    den = e[:, None, :occ] - e[:, occ:, None]                     # (K, empty, occ): E_n - E_m
    X = [np.einsum("kim,kij,kjn->kmn", vu.conj(), d, vo, optimize=True) / den for d in dH]
    F = {}
    for i, j in itertools.combinations(range(len(dirs)), 2):
        xy = np.einsum("kmn,kmp->knp", X[i].conj(), X[j], optimize=True)
        F[i, j] = 1j * (xy - np.conj(np.swapaxes(xy, 1, 2)))
    tol = 50 * H.shape[-1] * np.finfo(float).eps * max(1.0, float(np.max(np.abs(e))))
    return F, float(gap.min()), tol


def _grid(n: int, g2: int, dirs) -> np.ndarray:
    ks = 2 * np.pi * np.arange(n) / n
    mesh = np.meshgrid(*([ks] * len(dirs)), indexing="ij")
    kk = np.zeros((n ** len(dirs), g2))
    for a, m in zip(dirs, mesh):
        kk[:, a] = m.ravel()
    return kk


def _occupied(terms: ModelTerms, occupied) -> int:
    R = terms.sites * terms.orbitals
    if occupied is None:
        return R // 2
    return _validate.integer("occupied", occupied, minimum=1, maximum=R - 1)


def _terms_of(system, model, params) -> tuple[ModelTerms, str, int]:
    from ..graph.clusters import Cluster

    if isinstance(system, ModelTerms):
        if system.windings.shape[1] == 0:
            raise ValueError("these model terms are on an open graph: no Bloch Hamiltonian.")
        return system, system.model, system.windings.shape[1] // 2
    if isinstance(system, Cluster):
        model = _validate.choice("model", model, MODELS)
        return model_terms(system, model, **params), system.name, system.genus
    if isinstance(system, PlaneGraph):
        if not system.periodic:
            raise ValueError("a Chern number needs a closed surface (a cluster or a torus), not an open flake.")
        model = _validate.choice("model", model, MODELS)
        return model_terms(system, model, **params), f"{system.name} torus", 1
    raise ValueError(f"expected a Cluster, a torus PlaneGraph or ModelTerms, got {type(system).__name__}.")


def kubo_chern(system, model: str = "qwz", *, occupied=None, grid: int = 24, **params) -> np.ndarray:
    r"""First Chern numbers :math:`C_{ab}` on all 2-subtori from the projector (Kubo) curvature, unrounded.

    The cross-check of the Fukui–Hatsugai–Suzuki numbers of
    :func:`~hyperlattice.topology.surfaces.cluster_chern` by the curvature of this module (same
    sign), integrated on an n x n grid.

    Parameters
    ----------
    system : Cluster, PlaneGraph (torus) or ModelTerms
        A closed surface and a model, or model terms with windings.
    model : str, optional
        The model when ``system`` is a graph (default qwz).
    occupied : int, optional
        Bands below the Fermi level (default half of them).
    grid : int, optional
        Points per direction (default 24).
    **params
        Model parameters (M, t2, phi, rashba) when ``system`` is a graph.

    Returns
    -------
    numpy.ndarray of float, shape (2g, 2g)
        Antisymmetric.

    Examples
    --------
    >>> from hyperlattice.topology import square_torus
    >>> from hyperlattice.topology.closed import kubo_chern
    >>> round(float(kubo_chern(square_torus(), "qwz", M=1.0)[0, 1]), 6)
    -1.0
    """
    terms, _, _ = _terms_of(system, model, params)
    occ = _occupied(terms, occupied)
    n = _validate.integer("grid", grid, minimum=4, maximum=512)
    g2 = terms.windings.shape[1]
    bloch = _Bloch(terms)
    out = np.zeros((g2, g2))
    for a, b in itertools.combinations(range(g2), 2):
        kk = _grid(n, g2, (a, b))
        total = 0.0
        for s in range(0, len(kk), _CHUNK):
            F, gap, tol = _curvatures(bloch, kk[s:s + _CHUNK], (a, b), occ)
            if gap <= tol:
                raise ValueError(f"the gap closes on the grid of subtorus ({a}, {b}); the Chern number is undefined.")
            total += float(np.einsum("kii->", F[0, 1]).real)
        out[a, b] = total * 2 * np.pi / n ** 2
        out[b, a] = -out[a, b]
    return out


@dataclass(frozen=True, eq=False, kw_only=True)
class SecondChern(Result):
    r"""Second Chern numbers of the occupied Abelian bands on the 4-subtori of the 2g-torus.

    Attributes
    ----------
    model : str
        The model.
    name : str
        The cluster or torus.
    genus : int
        g (2g momenta).
    subtori : ndarray of int64, shape (S, 4)
        The four momentum indices of each 4-subtorus (the other momenta at 0).
    chern2 : ndarray of int64, shape (S,)
        :math:`C_2 = \frac{1}{8\pi^2}\int\mathrm{tr}F\wedge F` rounded.
    chern2_raw : ndarray of float, shape (S,)
        The integral on the finest grid.
    error : ndarray of float, shape (S,)
        Difference of the last two grids (the stated error of ``chern2_raw``).
    pfaffian : ndarray of int64, shape (S,)
        :math:`C_{ab}C_{cd} - C_{ac}C_{bd} + C_{ad}C_{bc}` of the first Chern numbers of the same
        bundle on the faces of the subtorus (:math:`\int c_1^2/2`).
    c2 : ndarray of int64, shape (S,)
        The second Chern class :math:`\mathrm{Pf} - C_2`.
    gap : float
        Smallest direct gap over every grid point used.
    grid : ndarray of int64, shape (S,)
        Final points per direction of each subtorus.
    occupied : int
        Bands below the Fermi level.

    Examples
    --------
    >>> from hyperlattice.topology.closed import dirac4_torus, second_chern
    >>> res = second_chern(dirac4_torus(-3.0), tol=0.01)
    >>> res.chern2.tolist(), res.pfaffian.tolist()
    ([-1], [0])
    """

    NOT_TABULAR = "one row per 4-subtorus; see summary()"

    model: str
    name: str
    genus: int
    subtori: np.ndarray
    chern2: np.ndarray
    chern2_raw: np.ndarray
    error: np.ndarray
    pfaffian: np.ndarray
    c2: np.ndarray
    gap: float
    grid: np.ndarray
    occupied: int

    def summary(self) -> dict:
        """The CLI's JSON view."""
        return {"model": self.model, "cluster": self.name, "genus": self.genus,
                "subtori": self.subtori.tolist(), "chern2": self.chern2.tolist(),
                "chern2_raw": self.chern2_raw.tolist(), "chern2_error": self.error.tolist(),
                "chern2_pfaffian": self.pfaffian.tolist(), "c2": self.c2.tolist(), "chern2_gap": self.gap,
                "chern2_grid": self.grid.tolist(), "occupied": self.occupied}


def _second_chern_subtorus(bloch, g2, dirs, occ, n):
    """C2 and the six first Chern numbers of one 4-subtorus on an n^4 grid; smallest gap."""
    kk = _grid(n, g2, dirs)
    c2 = 0.0
    c1 = np.zeros((4, 4))
    gmin = np.inf
    for s in range(0, len(kk), _CHUNK):
        F, gap, tol = _curvatures(bloch, kk[s:s + _CHUNK], dirs, occ)
        if gap <= tol:
            raise ValueError(f"the gap closes on the {n}^4 grid of subtorus {tuple(dirs)} (smallest gap {gap:.2e}): "
                             "the second Chern number is undefined here.")
        gmin = min(gmin, gap)

        def tr(x, y):
            return float(np.einsum("kij,kji->", x, y).real)
        c2 += tr(F[0, 1], F[2, 3]) - tr(F[0, 2], F[1, 3]) + tr(F[0, 3], F[1, 2])
        for (i, j), f in F.items():
            c1[i, j] += float(np.einsum("kii->", f).real)
    h = 2 * np.pi / n
    c2 *= h ** 4 / (4 * np.pi ** 2)
    # a first Chern number integrated over the whole 4-subtorus: divide by the (2 pi)^2 of the other two momenta
    c1 *= h ** 4 / (2 * np.pi) / (2 * np.pi) ** 2
    return c2, c1, gmin


def second_chern(system, model: str = "qwz", *, occupied=None, grid: int = 8, max_grid: int = 24,
                 tol: float = 1e-3, **params) -> SecondChern:
    r"""Second Chern numbers of the occupied Abelian bands on every 4-subtorus (see the module docstring).

    Parameters
    ----------
    system : Cluster, PlaneGraph (torus) or ModelTerms
        A closed surface of genus >= 2 and a model, or model terms with at least four momenta
        (e.g. :func:`dirac4_torus`).
    model : str, optional
        The model when ``system`` is a graph (default qwz).
    occupied : int, optional
        Bands below the Fermi level (default half of them).
    grid : int, optional
        Starting points per direction (default 8).
    max_grid : int, optional
        The grid grows by 4 until two successive values agree within ``tol`` (default up to 24).
    tol : float, optional
        Agreement of two successive grids (default 1e-3).
    **params
        Model parameters (M, t2, phi, rashba) when ``system`` is a graph.

    Returns
    -------
    SecondChern

    Raises
    ------
    ValueError
        Fewer than four momenta, bad parameters, a gap that closes on a grid, or a grid that
        does not fit in memory.
    ConvergenceError
        If two successive grids still differ by more than ``tol`` at ``max_grid``, or the value
        is not within 0.05 of an integer.

    Examples
    --------
    >>> from hyperlattice.topology.closed import dirac4_torus, second_chern
    >>> second_chern(dirac4_torus(3.0), tol=0.01).chern2.tolist()
    [1]
    """
    from ..graph.solvers import single_threaded_blas

    terms, name, genus = _terms_of(system, model, params)
    occ = _occupied(terms, occupied)
    g2 = terms.windings.shape[1]
    if g2 < 4:
        raise ValueError(f"a second Chern number needs at least four momenta (genus >= 2), got {g2}.")
    grid = _validate.integer("grid", grid, minimum=4, maximum=64)
    max_grid = _validate.integer("max_grid", max_grid, minimum=grid, maximum=64)
    tol = _validate.real("tol", tol, minimum=1e-12, maximum=0.5)
    R = terms.sites * terms.orbitals
    _validate.require_memory("one chunk of Bloch Hamiltonians", 12 * 16.0 * R * R * _CHUNK)
    subtori = list(itertools.combinations(range(g2), 4))
    bloch = _Bloch(terms)
    raw, err, pf, grids, gaps = [], [], [], [], []
    with single_threaded_blas():
        for dirs in subtori:
            n = grid
            prev, _, gap = _second_chern_subtorus(bloch, g2, dirs, occ, n)
            if grid + 4 > max_grid:
                raise ValueError(f"max_grid = {max_grid} leaves no room to check convergence beyond grid = {grid} "
                                 "(need max_grid >= grid + 4).")
            while True:
                n += 4
                cur, c1, g = _second_chern_subtorus(bloch, g2, dirs, occ, n)
                gap = min(gap, g)
                if abs(cur - prev) < tol:
                    break
                if n + 4 > max_grid:
                    raise ConvergenceError(f"the second Chern number of subtorus {dirs} changes by "
                                           f"{abs(cur - prev):.1e} between the last grids (above tol = {tol:g}) "
                                           f"at max_grid = {max_grid}.")
                prev = cur
            if abs(cur - round(cur)) > 0.05:
                raise ConvergenceError(f"the second Chern number of subtorus {dirs} converged to {cur:.4f}, not "
                                       "an integer: a gap is too small for the grid.")
            c1i = np.rint(c1).astype(np.int64)
            raw.append(cur)
            err.append(abs(cur - prev))
            pf.append(int(c1i[0, 1] * c1i[2, 3] - c1i[0, 2] * c1i[1, 3] + c1i[0, 3] * c1i[1, 2]))
            grids.append(n)
            gaps.append(gap)
    ch2 = np.rint(raw).astype(np.int64)
    pf = np.array(pf, dtype=np.int64)
    return SecondChern(model=terms.model, name=name, genus=genus, subtori=np.array(subtori, dtype=np.int64),
                       chern2=ch2, chern2_raw=np.array(raw), error=np.array(err), pfaffian=pf, c2=pf - ch2,
                       gap=float(min(gaps)), grid=np.array(grids, dtype=np.int64), occupied=occ)


# ----------------------------------------------------------------------------
# why the {p,3} models have C2 = 0: a particle-hole symmetry of class D
# ----------------------------------------------------------------------------

def particle_hole(terms: ModelTerms, *, tol: float = 1e-9):
    r"""A local antiunitary :math:`\mathcal C = U K` with :math:`\mathcal C H(k)\mathcal C^{-1} = -H(-k)`, if any.

    Solves the linear conditions on a block-diagonal :math:`U = \oplus_i U_i` (one d x d block
    per site): :math:`U_i O_i^* = -O_i U_i` for every on-site block and :math:`U_t B^* = -B U_h`
    for every hop (tail t, head h); their solutions form a vector space, whose null-space basis
    (SVD) is scanned for a unitary member. Such a :math:`\mathcal C` maps the occupied bands at k
    onto the complex conjugate of the empty bands at -k. With :math:`\mathcal C^2 = +1` the model is
    in class D, whose entry for four dimensions in the periodic table is 0 (Schnyder, Ryu,
    Furusaki and Ludwig, PRB 78, 195125 (2008); Kitaev, AIP Conf. Proc. 1134, 22 (2009)): the
    second Chern density is odd, :math:`\mathrm{tr}F\wedge F(-k) = -\mathrm{tr}F\wedge F(k)`
    (:func:`chern2_density`), so :math:`C_2 = 0` on every 4-subtorus, while first Chern numbers
    (class D in two dimensions: :math:`\mathbb Z`) survive.

    Parameters
    ----------
    terms : ModelTerms
        A model (at most 4,096 unknowns: sites x d^2).
    tol : float, optional
        Singular values below ``tol`` times the largest count as zero (default 1e-9).

    Returns
    -------
    dict or None
        None when no unitary solution exists; else ``{"unitary": U (sites, d, d), "square": +1 or
        -1}`` (:math:`\mathcal C^2 = U U^*`).

    Raises
    ------
    ValueError
        For more unknowns than 4,096.

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.topology.models import model_terms
    >>> from hyperlattice.topology.closed import dirac4_torus, particle_hole
    >>> particle_hole(model_terms(hl.pbc_cluster(8, 3, "bolza"), "qwz", M=1.0))["square"]
    1
    >>> particle_hole(dirac4_torus(-3.0)) is None
    True
    """
    if not isinstance(terms, ModelTerms):
        raise ValueError(f"expected ModelTerms, got {type(terms).__name__}.")
    tol = _validate.real("tol", tol, minimum=1e-15, maximum=1e-2)
    n, d = terms.sites, terms.orbitals
    nv = n * d * d
    if nv > 4096:
        raise ValueError(f"particle_hole solves for {nv} unknowns; at most 4,096 (sites x orbitals^2).")
    eye = np.eye(d)
    idx = np.arange(nv).reshape(n, d * d)
    rows = []
    # row-major vec: vec(U A) = kron(I, A^T) vec(U), vec(A U) = kron(A, I) vec(U)
    for i in range(n):
        a = np.zeros((d * d, nv), dtype=np.complex128)
        a[:, idx[i]] = np.kron(eye, terms.onsite[i].conj().T) + np.kron(terms.onsite[i], eye)
        rows.append(a)
    for t, h, b in zip(terms.tail, terms.head, terms.blocks):
        a = np.zeros((d * d, nv), dtype=np.complex128)
        a[:, idx[t]] += np.kron(eye, b.conj().T)
        a[:, idx[h]] += np.kron(b, eye)
        rows.append(a)
    A = np.vstack(rows)
    _, sv, vh = np.linalg.svd(A)
    sv = np.concatenate([sv, np.zeros(vh.shape[0] - len(sv))])
    null = vh[sv <= tol * max(1.0, float(sv.max()))].conj()
    for v in null:
        U = v.reshape(n, d, d)
        uu = np.einsum("nij,nkj->nik", U, U.conj())
        scale = uu[:, 0, 0].real
        if np.any(scale <= tol) or not np.allclose(uu, scale[:, None, None] * eye[None], atol=1e-8):
            continue
        U = U / np.sqrt(scale)[:, None, None]
        sq = np.einsum("nij,njk->nik", U, U.conj())
        if np.allclose(sq, eye[None], atol=1e-8):
            return {"unitary": U, "square": 1}
        if np.allclose(sq, -eye[None], atol=1e-8):
            return {"unitary": U, "square": -1}
    return None


def chern2_density(system, model: str = "qwz", *, dirs=(0, 1, 2, 3), k=None, occupied=None, **params) -> np.ndarray:
    r"""The second Chern density :math:`\mathrm{tr}(F_{ab}F_{cd} - F_{ac}F_{bd} + F_{ad}F_{bc})` at momenta k.

    The integrand of :func:`second_chern` on the 4-subtorus ``dirs`` (its integral times
    :math:`1/4\pi^2` is :math:`C_2`), for checking parities such as the one of
    :func:`particle_hole`.

    Parameters
    ----------
    system : Cluster, PlaneGraph (torus) or ModelTerms
        As :func:`second_chern`.
    model : str, optional
        The model when ``system`` is a graph.
    dirs : sequence of four int, optional
        The momenta of the 4-subtorus (default the first four).
    k : array_like, shape (K, 4)
        Points on the subtorus (radians).
    occupied : int, optional
        Bands below the Fermi level (default half).
    **params
        Model parameters when ``system`` is a graph.

    Returns
    -------
    numpy.ndarray of float, shape (K,)

    Examples
    --------
    >>> import numpy as np
    >>> from hyperlattice.topology.closed import chern2_density, dirac4_torus
    >>> k = np.array([[0.3, 1.1, 2.0, 0.7]])
    >>> bool(abs(chern2_density(dirac4_torus(-3.0), k=k)[0] - chern2_density(dirac4_torus(-3.0), k=-k)[0]) < 1e-9)
    True
    """
    terms, _, _ = _terms_of(system, model, params)
    occ = _occupied(terms, occupied)
    g2 = terms.windings.shape[1]
    dirs = tuple(_validate.int_list("dirs", dirs, minimum=0, maximum=g2 - 1))
    if len(dirs) != 4 or len(set(dirs)) != 4:
        raise ValueError(f"dirs must be four different momentum indices, got {dirs}.")
    k = _validate.real_array("k", k, ndim=2)
    if k.shape[1] != 4:
        raise ValueError(f"k must have shape (K, 4), got {k.shape}.")
    kk = np.zeros((len(k), g2))
    kk[:, list(dirs)] = k
    F, gap, tol = _curvatures(_Bloch(terms), kk, dirs, occ)
    if gap <= tol:
        raise ValueError("the gap closes at one of the points k.")

    def tr(x, y):
        return np.einsum("kij,kji->k", x, y).real
    return tr(F[0, 1], F[2, 3]) - tr(F[0, 2], F[1, 3]) + tr(F[0, 3], F[1, 2])


# ----------------------------------------------------------------------------
# spin Chern numbers (Kane-Mele without Rashba)
# ----------------------------------------------------------------------------

@dataclass(frozen=True, eq=False, kw_only=True)
class SpinChern(Result):
    r"""Spin Chern numbers of the :math:`s_z`-conserving Kane–Mele model on a closed surface.

    Attributes
    ----------
    name : str
        The cluster or torus.
    genus : int
        g.
    chern_up, chern_down : ndarray of int64, shape (2g, 2g)
        First Chern matrices of the half-filled spin-up and spin-down blocks.
    spin_chern : ndarray of int64, shape (2g, 2g)
        :math:`(C^\uparrow - C^\downarrow)/2` (integer: time reversal makes :math:`C^\downarrow =
        -C^\uparrow`, checked).
    z2 : ndarray of int64, shape (2g, 2g)
        :math:`C^\uparrow \bmod 2` on every 2-subtorus.
    gap : float
        Smallest direct gap of either block on the grids.
    parameters : dict
        M, t2, phi.

    Examples
    --------
    >>> from hyperlattice.topology import honeycomb_torus
    >>> from hyperlattice.topology.closed import spin_chern
    >>> res = spin_chern(honeycomb_torus(), M=0.1, t2=0.2)
    >>> int(res.spin_chern[0, 1]), int(res.z2[0, 1])
    (1, 1)
    """

    NOT_TABULAR = "matrices of Chern numbers"

    name: str
    genus: int
    chern_up: np.ndarray
    chern_down: np.ndarray
    spin_chern: np.ndarray
    z2: np.ndarray
    gap: float
    parameters: dict

    def summary(self) -> dict:
        """The CLI's JSON view."""
        return {"cluster": self.name, "genus": self.genus, "chern_up": self.chern_up.tolist(),
                "chern_down": self.chern_down.tolist(), "spin_chern": self.spin_chern.tolist(),
                "z2": self.z2.tolist(), "spin_gap": self.gap}


def spin_chern(system, *, M: float = 0.0, t2: float = 0.2, phi: float = np.pi / 2, grid: int = 12,
               max_grid: int = 96) -> SpinChern:
    r"""Spin Chern numbers and the :math:`\mathbb Z_2` index of Kane–Mele without Rashba on a closed surface.

    Parameters
    ----------
    system : Cluster or PlaneGraph
        A {p,3} cluster with even p, or the honeycomb torus.
    M, t2, phi : float, optional
        Sublattice mass, second-neighbour amplitude and phase (as in
        :func:`~hyperlattice.topology.models.model_terms`).
    grid, max_grid : int, optional
        The grids of :func:`~hyperlattice.topology.surfaces.cluster_chern`.

    Returns
    -------
    SpinChern

    Raises
    ------
    ValueError
        As :func:`~hyperlattice.topology.surfaces.cluster_chern` (a gap that closes, a graph that
        is not bipartite of degree 3).

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.topology.closed import spin_chern
    >>> spin_chern(hl.pbc_cluster(8, 3, "bolza"), M=0.0, t2=0.3).gap > 0
    True
    """
    from .surfaces import cluster_chern

    up = cluster_chern(system, "haldane", M=M, t2=t2, phi=phi, grid=grid, max_grid=max_grid)
    dn = cluster_chern(system, "haldane", M=M, t2=t2, phi=-phi, grid=grid, max_grid=max_grid)
    if not np.array_equal(up.chern, -dn.chern):
        raise ConvergenceError("the spin-down Chern numbers are not minus the spin-up ones (time reversal): "
                               "a grid is too coarse.")
    return SpinChern(name=up.name, genus=up.genus, chern_up=up.chern, chern_down=dn.chern,
                     spin_chern=(up.chern - dn.chern) // 2, z2=np.mod(up.chern, 2), gap=min(up.gap, dn.gap),
                     parameters=dict(M=float(M), t2=float(t2), phi=float(phi)))


from .._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
