r"""Chern numbers of Abelian Bloch bands on closed surfaces (clusters and tori).

On a periodic cluster of genus g the Abelian Bloch Hamiltonian :math:`H(k)` of a model
(:func:`~hyperlattice.topology.models.bloch_model_hamiltonian`, windings of
:mod:`hyperlattice.graph.bands`) lives on the 2g-torus :math:`k \in [0, 2\pi)^{2g}`. The bands
below the Fermi level define a vector bundle over it, and its first Chern class is the
antisymmetric integer matrix

.. math:: C_{ab} = \frac{1}{2\pi}\int dk_a\, dk_b\, F_{ab}, \qquad a < b,

one number per 2-subtorus :math:`(k_a, k_b)` (the other momenta at 0). Each is computed by the
lattice method of Fukui, Hatsugai and Suzuki (J. Phys. Soc. Jpn. 74, 1674 (2005)) on an
n x n grid: the Berry phase of every plaquette, from the determinants of the overlap matrices
of the occupied eigenvectors at its corners, is taken in :math:`(-\pi, \pi]`, and their sum is
:math:`2\pi C` exactly (an integer for any grid) once the gap is open at every grid point;
the result equals the continuum Chern number when no plaquette's phase is near :math:`\pm\pi`.
Both are checked: the smallest direct gap on the grid is reported and refused when it is below
the eigensolver's error, and the grid is doubled (up to ``max_grid``) until the largest
plaquette phase is below :math:`\pi/2`. Sign: :math:`F = \partial_a A_b - \partial_b A_a`,
:math:`A = i\langle u|\nabla u\rangle`, which gives C = -1 for square-lattice QWZ at M = 1, the
Bianco–Resta sign of :mod:`hyperlattice.topology.markers`.

Invariants that do not depend on the basis of :math:`H_1(\Sigma;\mathbb Z)`: under a change of
basis :math:`C \to A^T C A`, :math:`A \in GL(2g, \mathbb Z)`, the gcd of the entries is
invariant and the Pfaffian changes by :math:`\det A = \pm 1`, so :math:`|\mathrm{Pf}\, C|` is
invariant (the product of the invariant factors of the Smith normal form of C).
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass

import numpy as np

from .. import _validate
from ..errors import ConvergenceError
from ..results import Result
from .models import MODELS, PlaneGraph, bloch_model_hamiltonian, model_terms

__all__ = ["ClusterChern", "cluster_chern", "pfaffian"]


def pfaffian(matrix) -> float:
    """Pfaffian of an antisymmetric matrix (expansion along the first row; 2g <= 12).

    Parameters
    ----------
    matrix : array_like, shape (2m, 2m)
        Antisymmetric.

    Returns
    -------
    float

    Examples
    --------
    >>> from hyperlattice.topology.surfaces import pfaffian
    >>> pfaffian([[0, 1, 0, 0], [-1, 0, 0, 0], [0, 0, 0, 2], [0, 0, -2, 0]])
    2.0
    """
    a = _validate.real_array("matrix", matrix, ndim=2)
    n = a.shape[0]
    if a.shape != (n, n) or n % 2 or n > 12:
        raise ValueError(f"matrix must be square of even size at most 12, got shape {a.shape}.")
    if not np.allclose(a, -a.T):
        raise ValueError("matrix must be antisymmetric.")
    return float(_pf(a))


def _pf(a: np.ndarray) -> float:
    n = a.shape[0]
    if n == 0:
        return 1.0
    total = 0.0
    for j in range(1, n):
        if a[0, j] == 0:
            continue
        keep = [k for k in range(n) if k not in (0, j)]
        total += (-1) ** (j - 1) * a[0, j] * _pf(a[np.ix_(keep, keep)])
    return total


@dataclass(frozen=True, eq=False, kw_only=True)
class ClusterChern(Result):
    """First Chern numbers of the occupied Abelian bands on all 2-subtori of the 2g-torus.

    Attributes
    ----------
    model : str
        The model.
    parameters : dict
        Its parameters.
    name : str
        The cluster (or torus).
    genus : int
        Genus g (1 for a torus).
    chern : ndarray of int64, shape (2g, 2g)
        Antisymmetric :math:`C_{ab}` (Bianco–Resta sign).
    chern_raw : ndarray of float, shape (2g, 2g)
        The plaquette sums before rounding (integers up to rounding by construction).
    gcd : int
        gcd of the entries of C.
    pfaffian : int
        Pf C.
    gap : float
        Smallest direct gap at the Fermi level over all grid points.
    grid : int
        Points per direction of the n x n grid of every subtorus.
    max_plaquette : float
        Largest plaquette Berry phase over all subtori (radians, below pi/2).
    occupied : int
        Bands below the Fermi level (half filling unless ``occupied`` or ``fermi_level`` was given).
    fermi_window : tuple of float
        (top of the occupied bands, bottom of the empty bands) over every grid point used: any
        Fermi level strictly inside gives the same Chern numbers.
    fermi_level : float or None
        The Fermi level asked for, if one was.

    Examples
    --------
    >>> from hyperlattice.topology import square_torus
    >>> from hyperlattice.topology.surfaces import cluster_chern
    >>> cluster_chern(square_torus(), "qwz", M=1.0).chern.tolist()
    [[0, -1], [1, 0]]
    """

    NOT_TABULAR = "a matrix of Chern numbers and its invariants"

    model: str
    parameters: dict
    name: str
    genus: int
    chern: np.ndarray
    chern_raw: np.ndarray
    gcd: int
    pfaffian: int
    gap: float
    grid: int
    max_plaquette: float
    occupied: int
    fermi_window: tuple = (float("nan"), float("nan"))
    fermi_level: float | None = None

    def summary(self) -> dict:
        """The CLI's JSON: chern, gcd, pfaffian, gap, and the grid and checks."""
        return {"model": self.model, "cluster": self.name, "genus": self.genus,
                "chern": self.chern.tolist(), "gcd": self.gcd, "pfaffian": self.pfaffian, "gap": self.gap,
                "grid": self.grid, "max_plaquette": self.max_plaquette, "occupied": self.occupied,
                "fermi_window": list(self.fermi_window), "fermi_level": self.fermi_level,
                "parameters": self.parameters}


def _subtorus(terms, a: int, b: int, n: int, occ: int, g2: int, edges: list | None = None):
    """FHS plaquette sum of one subtorus on an n x n grid; returns (C, min gap, max |plaquette|, gaps ok)."""
    ks = 2 * np.pi * np.arange(n) / n
    kk = np.zeros((n * n, g2))
    ka, kb = np.meshgrid(ks, ks, indexing="ij")
    kk[:, a], kk[:, b] = ka.ravel(), kb.ravel()
    H = bloch_model_hamiltonian(terms, kk)
    e, v = np.linalg.eigh(H)
    gap = float(np.min(e[:, occ] - e[:, occ - 1]))
    if edges is not None:
        edges.append((float(e[:, occ - 1].max()), float(e[:, occ].min())))
    tol = 50 * H.shape[-1] * np.finfo(float).eps * max(1.0, float(np.max(np.abs(e))))
    u = v[:, :, :occ].reshape(n, n, -1, occ)

    def link(x, y):
        det = np.linalg.det(np.einsum("...ia,...ib->...ab", x.conj(), y))
        return det

    u1 = np.roll(u, -1, axis=0)
    u2 = np.roll(u, -1, axis=1)
    u12 = np.roll(u1, -1, axis=1)
    loop = link(u, u1) * link(u1, u12) * link(u12, u2) * link(u2, u)
    f = np.angle(loop)
    # the loop product is exp(-i * flux of F), F = curl A with A = i<u|grad u>: hence the minus sign
    return float(-f.sum() / (2 * np.pi)), gap, float(np.max(np.abs(f))), gap > tol, tol


def _all_subtori(terms, g2, occ, n, max_grid, raw, gaps, plaq, edges=None, fermi=None):
    """Fill raw, gaps, plaq (and the band edges at the Fermi level) for every subtorus; returns the largest grid."""
    for a, b in itertools.combinations(range(g2), 2):
        while True:
            c, gap, fmax, ok, tol = _subtorus(terms, a, b, n, occ, g2, edges)
            if fermi is not None and not edges[-1][0] < fermi < edges[-1][1]:
                raise ValueError(f"the Fermi level {fermi:g} lies in a band on the {n} x {n} grid of subtorus "
                                 f"({a}, {b}): band {occ} reaches {edges[-1][0]:.4g} and band {occ + 1} comes "
                                 f"down to {edges[-1][1]:.4g}.")
            if not ok:
                raise ValueError(f"the gap above band {occ} closes on the {n} x {n} grid of subtorus ({a}, {b}) "
                                 f"(smallest gap {gap:.2e} <= {tol:.1e}): the Chern numbers are undefined here.")
            if fmax < np.pi / 2:
                break
            if 2 * n > max_grid:
                raise ConvergenceError(f"a plaquette Berry phase is {fmax:.2f} rad on the {n} x {n} grid of "
                                       f"subtorus ({a}, {b}); raise max_grid above {max_grid}.")
            n *= 2
        raw[a, b], raw[b, a] = c, -c
        gaps.append(gap)
        plaq.append(fmax)
    return n


def cluster_chern(cluster, model: str = "qwz", *, M: float = 1.0, t2: float = 0.2, phi: float = np.pi / 2,
                  rashba: float = 0.0, grid: int = 12, max_grid: int = 96, occupied=None,
                  fermi_level=None) -> ClusterChern:
    r"""First Chern numbers :math:`C_{ab}` of a model's occupied Abelian bands on every 2-subtorus.

    Parameters
    ----------
    cluster : Cluster or PlaneGraph
        A periodic {p,q} cluster with its rotation system
        (:func:`~hyperlattice.graph.clusters.pbc_cluster`), or a Euclidean torus of
        :mod:`hyperlattice.topology.models`.
    model : {"qwz", "haldane", "kane-mele"}
        The model.
    M, t2, phi, rashba : float, optional
        Model parameters (:func:`~hyperlattice.topology.models.model_terms`).
    grid : int, optional
        Starting points per direction of each subtorus grid (default 12).
    max_grid : int, optional
        The grid is doubled until every plaquette phase is below pi/2, up to this (default 96).
    occupied : int, optional
        Bands below the Fermi level (default half of them).
    fermi_level : float, optional
        The Fermi level instead of ``occupied``: the bands below it at k = 0 are occupied, and it
        must lie in the gap above them at every grid point used (checked: the band edges over the
        grids are ``fermi_window``).

    Returns
    -------
    ClusterChern

    Raises
    ------
    ValueError
        For a cluster without a closed rotation system, an unknown model, bad parameters, a
        gap that closes on the grid (the Chern numbers are then undefined), a Fermi level outside
        the spectrum or inside a band on the grid, or both ``occupied`` and ``fermi_level``.
    ConvergenceError
        If the plaquette phases stay above pi/2 at ``max_grid``.

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.topology.surfaces import cluster_chern
    >>> res = cluster_chern(hl.pbc_cluster(8, 3, "bolza"), "qwz", M=1.0)
    >>> res.chern.shape, res.grid
    ((4, 4), 12)
    """
    from ..graph.clusters import Cluster
    from ..graph.solvers import single_threaded_blas

    if isinstance(cluster, PlaneGraph):
        if not cluster.periodic:
            raise ValueError("cluster_chern needs a closed surface (a cluster or a torus), not an open flake.")
        name, genus = f"{cluster.name} torus", 1
    elif isinstance(cluster, Cluster):
        name, genus = cluster.name, cluster.genus
    else:
        raise ValueError(f"expected a Cluster (pbc_cluster) or a torus PlaneGraph, got {type(cluster).__name__}.")
    model = _validate.choice("model", model, MODELS)
    grid = _validate.integer("grid", grid, minimum=4, maximum=512)
    max_grid = _validate.integer("max_grid", max_grid, minimum=grid, maximum=512)
    terms = model_terms(cluster, model, M=M, t2=t2, phi=phi, rashba=rashba)
    rows = terms.sites * terms.orbitals
    g2 = terms.windings.shape[1]
    _validate.require_memory("the Bloch Hamiltonians of one grid", 3 * 16.0 * rows * rows * max_grid ** 2)
    if occupied is not None and fermi_level is not None:
        raise ValueError("give occupied or fermi_level, not both.")
    if fermi_level is not None:
        fermi_level = _validate.real("fermi_level", fermi_level)
        e0 = np.linalg.eigvalsh(bloch_model_hamiltonian(terms, np.zeros((1, g2)))[0])
        occ = int(np.count_nonzero(e0 < fermi_level))
        if occ in (0, rows):
            raise ValueError(f"the Fermi level {fermi_level:g} is outside the spectrum at k = 0 "
                             f"[{e0[0]:.4g}, {e0[-1]:.4g}].")
    elif occupied is not None:
        occ = _validate.integer("occupied", occupied, minimum=1, maximum=rows - 1)
    else:
        occ = rows // 2
    raw = np.zeros((g2, g2))
    gaps, plaq, edges = [], [], []
    n = grid
    with single_threaded_blas():   # one thread: the grid's many small eigh calls
        n = _all_subtori(terms, g2, occ, n, max_grid, raw, gaps, plaq, edges, fermi_level)
    window = (max(x for x, _ in edges), min(y for _, y in edges))
    if fermi_level is not None and not window[0] < fermi_level < window[1]:
        raise ValueError(f"the Fermi level {fermi_level:g} lies in a band on the grids: band {occ} reaches "
                         f"{window[0]:.4g} and band {occ + 1} comes down to {window[1]:.4g}.")
    chern = np.rint(raw).astype(np.int64)
    vals = [abs(int(x)) for x in chern[np.triu_indices(g2, 1)]]
    gcd = math.gcd(*vals) if vals else 0
    pf = int(round(_pf(chern.astype(float)))) if g2 <= 12 else 0
    params = dict(M=M, t2=t2, phi=phi, rashba=rashba)
    return ClusterChern(model=model, parameters=params, name=name, genus=genus, chern=chern, chern_raw=raw,
                        gcd=gcd, pfaffian=pf, gap=float(min(gaps)), grid=n, max_plaquette=float(max(plaq)),
                        occupied=occ, fermi_window=window, fermi_level=fermi_level)


from .._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
