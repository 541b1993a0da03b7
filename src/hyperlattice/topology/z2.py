r"""The :math:`\mathbb Z_2` index of time-reversal-symmetric bands on closed surfaces (Kane–Mele with Rashba).

With Rashba coupling :math:`s_z` is not conserved, so the spin Chern numbers of
:func:`~hyperlattice.topology.closed.spin_chern` (one Chern number per :math:`s_z` block) no
longer apply. Time reversal :math:`\Theta = i s_y K` still holds: :math:`H(-k) = s_y H(k)^* s_y` for
the Abelian Bloch Hamiltonian on the 2g-torus (checked at random momenta, refused when broken). On
every 2-subtorus :math:`(k_a, k_b)` whose other 2g - 2 momenta sit at time-reversal-invariant
values (each 0 or :math:`\pi`), the occupied bands carry a :math:`\mathbb Z_2` index; there are
:math:`\binom{2g}{2}\,2^{2g-2}` of them.

Method: the Wilson loop (Yu, Qi, Bernevig, Fang and Dai, PRB 84, 075119 (2011)). For
:math:`k_a` from 0 to :math:`\pi` the occupied bands are transported once around :math:`k_b`,
:math:`W(k_a) = \prod_j V(k_a, k_{b,j})^\dagger V(k_a, k_{b,j+1})`; its eigenphases are the
Wannier centres along b. Time reversal pairs them at :math:`k_a = 0, \pi`; the index is the
parity of the number of times the centres cross a reference line over the half torus. The line
is the middle of the largest gap between the centres at each step (Soluyanov and Vanderbilt,
PRB 83, 235401 (2011)), so no fixed line has to avoid the centres. The Bloch Hamiltonian carries
the phases :math:`e^{ik\cdot w}` on the hops only, so :math:`H(k + 2\pi e_b) = H(k)` and the loop
closes without an embedding phase. The grid (points per direction) doubles until it resolves the
bands (every overlap of neighbouring Bloch states along :math:`k_b` has singular values of at
least :data:`MIN_OVERLAP`, and no Wannier centre lands within :data:`MIN_CLEARANCE` of the
half-width of the largest gap from the previous step's reference line, where the count would be
ambiguous) and the next grid gives the same indices; the smallest direct gap over every momentum used is reported and a gap at the
eigensolver's rounding is refused.

Checks (``tests/test_topology_z2.py``): without Rashba the index equals the spin Chern number mod
2 of :func:`~hyperlattice.topology.closed.spin_chern`; on the honeycomb torus it follows Kane and
Mele's phase diagram (PRL 95, 146802 (2005)): 1 for :math:`|\lambda_v| < 3\sqrt3\lambda_{SO}` at
:math:`\lambda_R = 0`, the gap closing at :math:`\lambda_R = 2\sqrt3\lambda_{SO}` for
:math:`\lambda_v = 0` (PRL 95, 226801 (2005)). The package's Kane–Mele parameters are
:math:`\lambda_v` = ``M``, :math:`\lambda_{SO}` = ``t2`` (at :math:`\phi = \pi/2`),
:math:`\lambda_R` = ``rashba``, t = ``t1`` = 1.
"""

from __future__ import annotations

import itertools
import warnings
from dataclasses import dataclass

import numpy as np

from .. import _validate
from ..errors import ConvergenceError
from ..results import Result
from .models import ModelTerms, PlaneGraph, model_terms

__all__ = ["Z2Index", "z2_index", "wilson_phases", "time_reversal_error"]

_SY = np.array([[0, -1j], [1j, 0]], dtype=np.complex128)

#: largest Bloch Hamiltonian (rows) the Wilson loops diagonalise
MAX_ROWS = 2000
#: time reversal counts as broken above this relative error
TR_TOL = 1e-9
#: a grid resolves the bands when every overlap of neighbouring k_b has singular values above this ...
MIN_OVERLAP = 0.3
#: ... and no Wannier centre comes closer than this fraction of the gap's half-width to the reference line
MIN_CLEARANCE = 0.1


class _Bloch:
    """H(k) = sum_w e^{i k.w} M_w, the hops grouped by their winding (vectorised over k)."""

    def __init__(self, terms: ModelTerms):
        n, d = terms.sites, terms.orbitals
        rows = n * d
        w, inv = np.unique(terms.windings, axis=0, return_inverse=True)
        inv = np.asarray(inv).ravel()
        mats = np.zeros((len(w), n, d, n, d), dtype=np.complex128)
        np.add.at(mats, (inv, terms.tail, slice(None), terms.head), terms.blocks)
        mats = mats.reshape(len(w), rows, rows)
        onsite = np.zeros((n, d, n, d), dtype=np.complex128)
        onsite[np.arange(n), :, np.arange(n), :] = terms.onsite
        self.w = w.astype(float)
        self.mats = mats
        self.onsite = onsite.reshape(rows, rows)
        self.rows = rows
        self.scale = float(np.abs(mats).sum(axis=(0, 2)).max() + np.abs(self.onsite).sum(axis=1).max())

    def __call__(self, k: np.ndarray) -> np.ndarray:
        ph = np.exp(1j * (k @ self.w.T))                          # (K, W)
        return self.onsite[None] + np.einsum("kw,wij->kij", ph, self.mats)


def _terms(system, M, t2, phi, rashba) -> tuple[ModelTerms, str, int]:
    if isinstance(system, ModelTerms):
        terms, name = system, system.model
    else:
        from ..graph.clusters import Cluster

        if not (isinstance(system, Cluster) or (isinstance(system, PlaneGraph) and system.periodic)):
            raise ValueError(f"z2_index needs a closed surface (a Cluster or a Euclidean torus), got "
                             f"{type(system).__name__}.")
        terms = model_terms(system, "kane-mele", M=M, t2=t2, phi=phi, rashba=rashba)
        name = system.name
    g2 = terms.windings.shape[1]
    if g2 < 2:
        raise ValueError("these model terms are on an open graph: the Z2 index needs a closed surface.")
    if terms.orbitals % 2:
        raise ValueError("time reversal i s_y K needs two spin states per site (the kane-mele model).")
    if terms.sites * terms.orbitals > MAX_ROWS:
        raise ValueError(f"a Bloch Hamiltonian of {terms.sites * terms.orbitals:,} rows is refused "
                         f"(at most {MAX_ROWS:,}).")
    return terms, name, g2


def time_reversal_error(terms: ModelTerms, samples: int = 8, seed: int = 0) -> float:
    r"""Largest :math:`\|s_y H(k)^* s_y - H(-k)\|_{\max} / \|H\|` over random momenta (0 for a time-reversal-symmetric model).

    Parameters
    ----------
    terms : ModelTerms
        A two-spin model on a closed surface.
    samples : int, optional
        Random momenta tried (default 8).
    seed : int, optional
        Their seed.

    Returns
    -------
    float

    Examples
    --------
    >>> from hyperlattice.topology import honeycomb_torus, model_terms
    >>> from hyperlattice.topology.z2 import time_reversal_error
    >>> time_reversal_error(model_terms(honeycomb_torus(), "kane-mele", M=0.1, rashba=0.05)) < 1e-12
    True
    """
    terms, _, g2 = _terms(terms, 0, 0, 0, 0)
    samples = _validate.integer("samples", samples, minimum=1, maximum=1000)
    seed = _validate.integer("seed", seed, minimum=0, maximum=2**63 - 1)
    bloch = _Bloch(terms)
    k = np.random.default_rng(seed).uniform(-np.pi, np.pi, (samples, g2))
    S = np.kron(np.eye(terms.sites), _SY)
    lhs = S[None] @ np.conj(bloch(k)) @ S[None]
    return float(np.abs(lhs - bloch(-k)).max() / max(bloch.scale, 1e-300))


def wilson_phases(terms: ModelTerms, a: int, b: int, fixed=None, *, grid: int = 16) -> tuple[np.ndarray, np.ndarray, float]:
    r"""Wannier centres along :math:`k_b` (Wilson-loop eigenphases) for :math:`k_a` from 0 to :math:`\pi`.

    Parameters
    ----------
    terms : ModelTerms
        A model on a closed surface (half filling).
    a, b : int
        The two momenta of the 2-subtorus (distinct, below 2g).
    fixed : array_like of float, shape (2g,), optional
        The other momenta (entries a and b are ignored); default all 0.
    grid : int, optional
        Points of :math:`k_b` around the loop, and steps of :math:`k_a` over :math:`[0, \pi]`
        (default 16).

    Returns
    -------
    ka : ndarray, shape (grid + 1,)
    phases : ndarray, shape (grid + 1, occupied)
        Eigenphases of :math:`W(k_a)` in :math:`(-\pi, \pi]`, sorted at each :math:`k_a`.
    gap : float
        Smallest direct gap at half filling over the momenta used.

    Examples
    --------
    >>> from hyperlattice.topology import honeycomb_torus, model_terms
    >>> from hyperlattice.topology.z2 import wilson_phases
    >>> ka, ph, gap = wilson_phases(model_terms(honeycomb_torus(), "kane-mele", M=0.1), 0, 1, grid=8)
    >>> ph.shape, gap > 0.1
    ((9, 2), True)
    """
    terms, _, g2 = _terms(terms, 0, 0, 0, 0)
    a = _validate.integer("a", a, minimum=0, maximum=g2 - 1)
    b = _validate.integer("b", b, minimum=0, maximum=g2 - 1)
    if a == b:
        raise ValueError("a and b must be two different momenta.")
    grid = _validate.integer("grid", grid, minimum=4, maximum=1024)
    base = np.zeros(g2) if fixed is None else _validate.real_array("fixed", fixed)
    if base.shape != (g2,):
        raise ValueError(f"fixed must have {g2} components, got shape {base.shape}.")
    bloch = _Bloch(terms)
    occ = bloch.rows // 2
    ka, phases, gap, _, _ = _wilson(bloch, a, b, base, grid, occ)
    return ka, phases, gap


def _wilson(bloch: _Bloch, a, b, base, grid, occ):
    from ..graph.solvers import single_threaded_blas

    ka = np.linspace(0.0, np.pi, grid + 1)
    kb = 2 * np.pi * np.arange(grid) / grid
    k = np.tile(base, (len(ka) * grid, 1))
    k[:, a] = np.repeat(ka, grid)
    k[:, b] = np.tile(kb, len(ka))
    with single_threaded_blas():
        e, v = np.linalg.eigh(bloch(k))
    gap = float((e[:, occ] - e[:, occ - 1]).min())
    indirect = float(e[:, occ].min() - e[:, occ - 1].max())
    V = v[:, :, :occ].reshape(len(ka), grid, bloch.rows, occ)
    nxt = np.roll(V, -1, axis=1)
    ov = np.einsum("agri,agrj->agij", V.conj(), nxt)        # <u(k_j)|u(k_j+1)>, the last one closes the loop
    W = np.broadcast_to(np.eye(occ, dtype=np.complex128), (len(ka), occ, occ)).copy()
    smin = 1.0
    for j in range(grid):
        # the polar part of each overlap (its unitary factor) keeps the product well conditioned
        u, sv, vh = np.linalg.svd(ov[:, j])
        smin = min(smin, float(sv.min()))
        W = W @ (u @ vh)
    phases = np.sort(np.angle(np.linalg.eigvals(W)), axis=1)
    return ka, phases, gap, indirect, bool(smin >= MIN_OVERLAP)


def _wrap(x):
    return np.angle(np.exp(1j * np.asarray(x)))


def _gap_middle(ph: np.ndarray) -> tuple[float, float]:
    s = np.sort(ph)
    gaps = np.diff(np.concatenate([s, [s[0] + 2 * np.pi]]))
    i = int(np.argmax(gaps))
    return float(_wrap(s[i] + 0.5 * gaps[i])), float(gaps[i])


def _z2_of_flow(phases: np.ndarray) -> tuple[int, float]:
    """Parity of the centres jumped by the largest gap's middle (Soluyanov–Vanderbilt) and the smallest clearance.

    The clearance is the distance of the centres at each step from the previous step's reference
    line, in units of the half-width of the gap it sits in: near 0 the count is ambiguous (a
    centre may have crossed the line or not), and the grid must be refined (Gresch et al.'s
    position tolerance, PRB 95, 075146 (2017)).
    """
    count = 0
    clearance = np.inf
    for i in range(len(phases) - 1):
        (z0, w0), (z1, _) = _gap_middle(phases[i]), _gap_middle(phases[i + 1])
        d = float(_wrap(z1 - z0))
        x = _wrap(phases[i + 1] - z0)
        if d > 0:
            inside = (x > 0) & (x <= d)
        else:
            inside = (x < 0) & (x >= d)
        count += int(np.sum(inside))
        clearance = min(clearance, float(np.min(np.abs(x))) / (0.5 * w0))
    return count % 2, clearance


@dataclass(frozen=True, eq=False, kw_only=True)
class Z2Index(Result):
    r"""The :math:`\mathbb Z_2` index on every time-reversal-symmetric 2-subtorus of a closed surface.

    Attributes
    ----------
    name : str
        The cluster or torus.
    genus : int
        g.
    subtori : ndarray of int64, shape (S, 2)
        The momenta (a, b) of each 2-subtorus.
    fixed : ndarray of int64, shape (S, 2g)
        The other momenta in units of :math:`\pi` (0 or 1; -1 marks a and b).
    z2 : ndarray of int64, shape (S,)
        The index, 0 or 1.
    clearance : ndarray, shape (S,)
        Smallest distance of a Wannier centre from the previous step's reference line, in units of
        the half-width of the largest gap: how far the count is from a tie (at least
        :data:`MIN_CLEARANCE`).
    gap : float
        Smallest direct gap at half filling over every momentum used.
    indirect_gap : float
        Lowest empty level minus highest occupied level over the same momenta; negative where the
        bands overlap (a semimetal at half filling: the index then describes the lower bands at
        each k, not an insulator, and a warning says so).
    grid : int
        Points per direction of the grids that agreed.
    time_reversal_error : float
        :func:`time_reversal_error` of the model.
    parameters : dict
        M, t2, phi, rashba.

    Examples
    --------
    >>> from hyperlattice.topology import honeycomb_torus
    >>> from hyperlattice.topology.z2 import z2_index
    >>> z2_index(honeycomb_torus(), M=0.1, t2=0.2, rashba=0.1).z2.tolist()
    [1]
    """

    COLUMNS = None
    NOT_TABULAR = "indices on a list of subtori with their fixed momenta"

    name: str
    genus: int
    subtori: np.ndarray
    fixed: np.ndarray
    z2: np.ndarray
    clearance: np.ndarray
    gap: float
    indirect_gap: float
    grid: int
    time_reversal_error: float
    parameters: dict

    def summary(self) -> dict:
        """The CLI's JSON view: ``z2`` (one per subtorus), ``z2_subtori``, ``z2_fixed``, ``z2_gap``, ``z2_grid``."""
        return {"z2": self.z2.tolist(), "z2_subtori": self.subtori.tolist(), "z2_fixed": self.fixed.tolist(),
                "z2_gap": self.gap, "z2_indirect_gap": self.indirect_gap, "z2_grid": self.grid, "z2_clearance": float(self.clearance.min()),
                "time_reversal_error": self.time_reversal_error}


def z2_index(system, *, M: float = 0.0, t2: float = 0.2, phi: float = np.pi / 2, rashba: float = 0.0,
             grid: int = 8, max_grid: int = 128) -> Z2Index:
    r"""The :math:`\mathbb Z_2` index of Kane–Mele (with Rashba) on the TR-symmetric 2-subtori of a closed surface.

    Parameters
    ----------
    system : Cluster, PlaneGraph or ModelTerms
        A {p,3} cluster with even p, the honeycomb torus, or a two-spin model's terms on a closed
        surface.
    M, t2, phi, rashba : float, optional
        Kane–Mele's sublattice mass, spin–orbit amplitude and phase, Rashba coupling
        (:func:`~hyperlattice.topology.models.model_terms`; ignored for ModelTerms).
    grid : int, optional
        Starting points per direction (default 8).
    max_grid : int, optional
        The grid doubles until it resolves the bands and the next grid gives the same indices (module
        docstring), up to this (default 128).

    Returns
    -------
    Z2Index

    Raises
    ------
    ValueError
        Time reversal broken, the gap closing on a grid, a surface too big, bad parameters.
    ConvergenceError
        No two successive grids up to ``max_grid`` agree.

    Examples
    --------
    >>> from hyperlattice.topology import honeycomb_torus
    >>> from hyperlattice.topology.z2 import z2_index
    >>> z2_index(honeycomb_torus(), M=2.0, t2=0.2).z2.tolist()
    [0]
    """
    for nm, v in (("M", M), ("t2", t2), ("phi", phi), ("rashba", rashba)):
        _validate.real(nm, v, minimum=-1e6, maximum=1e6)
    grid = _validate.integer("grid", grid, minimum=4, maximum=1024)
    max_grid = _validate.integer("max_grid", max_grid, minimum=grid, maximum=1024)
    terms, name, g2 = _terms(system, M, t2, phi, rashba)
    tr = time_reversal_error(terms)
    if tr > TR_TOL:
        raise ValueError(f"the model breaks time reversal (|s_y H(k)* s_y - H(-k)| = {tr:.1e} of |H|): "
                         "the Z2 index needs a time-reversal-symmetric model (no flux).")
    bloch = _Bloch(terms)
    occ = bloch.rows // 2
    subtori, fixed = [], []
    for a, b in itertools.combinations(range(g2), 2):
        others = [c for c in range(g2) if c not in (a, b)]
        for bits in itertools.product((0, 1), repeat=len(others)):
            f = -np.ones(g2, dtype=np.int64)
            f[others] = bits
            subtori.append((a, b))
            fixed.append(f)
    tol = 50 * bloch.rows * np.finfo(float).eps * max(bloch.scale, 1.0)

    def run(n):
        z, cl, gaps, ind, ok = [], [], [], [], []
        for (a, b), f in zip(subtori, fixed):
            base = np.where(f > 0, np.pi, 0.0)
            _, ph, gap, indirect, resolved = _wilson(bloch, a, b, base, n, occ)
            if gap <= tol:
                raise ValueError(f"the gap at half filling closes on subtorus ({a}, {b}) with the other momenta at "
                                 f"{(f[f >= 0] * np.pi).round(4).tolist()} (smallest gap {gap:.2e} <= {tol:.1e}): "
                                 "the Z2 index is undefined here.")
            zz, c = _z2_of_flow(ph)
            z.append(zz), cl.append(c), gaps.append(gap), ind.append(indirect), ok.append(resolved)
        return np.array(z, dtype=np.int64), np.array(cl), min(gaps), min(ind), all(ok) and min(cl) >= MIN_CLEARANCE

    n = grid
    prev = run(n)
    while True:
        if 2 * n > max_grid:
            raise ConvergenceError(f"the Z2 indices of two successive grids up to {n} points differ; "
                                   f"raise max_grid above {max_grid}.")
        cur = run(2 * n)
        n *= 2
        if np.array_equal(cur[0], prev[0]) and prev[4] and cur[4]:
            break
        prev = cur
    indirect = float(min(cur[3], prev[3]))
    if indirect <= 0:
        warnings.warn(f"the bands overlap at half filling (indirect gap {indirect:.3g} on the grids): a semimetal, "
                      "so the Z2 index of the lower bands does not describe an insulator.", stacklevel=2)
    params = dict(M=float(M), t2=float(t2), phi=float(phi), rashba=float(rashba))
    if isinstance(system, ModelTerms):
        params = dict(system.parameters)
    genus = g2 // 2
    return Z2Index(name=name, genus=genus, subtori=np.array(subtori, dtype=np.int64).reshape(-1, 2),
                   fixed=np.array(fixed, dtype=np.int64).reshape(-1, g2), z2=cur[0], clearance=cur[1],
                   gap=float(min(cur[2], prev[2])), indirect_gap=indirect, grid=int(n),
                   time_reversal_error=tr, parameters=params)


from .._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
