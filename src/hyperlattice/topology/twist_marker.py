r"""A local Chern marker on closed surfaces, from the cluster's projector and its twist derivatives.

A closed surface has no position operator, so the Bianco–Resta marker of a flake has no meaning
on a cluster. What it has are the U(1) twists of its boundary conditions: the Abelian momenta
:math:`k_a` of the windings' cocycles (:mod:`hyperlattice.graph.bands`), i.e. fluxes threaded
through the surface's 2g handles. The occupied projector :math:`P(k)` of the twisted
Hamiltonian has the Berry curvature :math:`F_{ab}`, and on a cluster much larger than the
correlation length it does not depend on the twist (Niu, Thouless and Wu, PRB 31, 3372 (1985)),
so one point gives the Chern number, :math:`C_{ab} \simeq 2\pi\,\mathrm{tr}\,F_{ab}(0)` (the
single-point formula of Ceresoli and Resta, PRB 76, 012405 (2007)). Its trace resolves into sites,

.. math:: c_{ab}(x) = 2\pi i \sum_{\alpha\in x}\big[P\,(\partial_a P\,\partial_b P - \partial_b P\,\partial_a P)\,P\big]_{\alpha\alpha},
   \qquad \sum_x c_{ab}(x) = 2\pi\,\mathrm{tr}F_{ab}(0),

the local Chern marker of a periodic cell (Baù and Marrazzo, PRB 109, 014206 (2024), there with
the twists of a Euclidean supercell), at the single twist :math:`k = 0`, with
:math:`\partial_a P` from the exact :math:`\partial_a H = i\sum w_a B` and first-order
perturbation theory (the curvature engine of :mod:`hyperlattice.topology.closed`; the same sign:
square-lattice QWZ at M = 1 has C = -1).

What it measures on a hyperbolic cluster. :math:`\partial_a H` acts only on the bonds that cross
the cut of cocycle a (a closed curve on the surface), so :math:`\partial_a P` lives within a
correlation length of that cut, and :math:`c_{ab}(x)` within a correlation length of the places
where the cuts of a and b cross. Each crossing carries the local Hall conductance :math:`\sigma`
with the crossing's sign, :math:`\sum_x c_{ab}(x) = \sigma\, Q_{ab}` (:math:`Q` the intersection
form, :func:`~hyperlattice.topology.landau.intersection_form`): this is the charge-deficiency
(Kitaev) form of the Hall conductance, :math:`2\pi i\,\mathrm{tr}\,P[[P,\Theta_a],[P,\Theta_b]]`
with :math:`\Theta` the step functions across two crossing cuts (Avron, Seiler and Simon, Commun.
Math. Phys. 159, 399 (1994); Kitaev, Ann. Phys. 321, 2 (2006), appendix C), summed around the
surface. The result reports the sum rule (the whole matrix :math:`\sum_x c_{ab}(x)` for every pair
from one diagonalisation) and the locality: for each site the distance (in bonds) to the farther of
the two cuts, and the share of the marker within each distance.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass

import numpy as np

from .. import _validate
from ..results import Result
from .models import MODELS, ModelTerms, model_terms

__all__ = ["TwistMarker", "twist_marker"]

#: largest Hamiltonian diagonalised densely here (rows = sites x orbitals)
MAX_ROWS = 6000
#: bytes of twist derivatives X_a held at once by the sum rule (directions go in chunks of this size)
_GRAM_BYTES = 2e8


@dataclass(frozen=True, eq=False, kw_only=True)
class TwistMarker(Result):
    r"""The twist-derivative Chern marker of a cluster (module docstring).

    Attributes
    ----------
    model, name : str
        Model and cluster.
    sites : int
        Sites of the cluster.
    genus : int
        g.
    total : ndarray of float, shape (2g, 2g)
        :math:`2\pi\,\mathrm{tr}F_{ab}(0) = \sum_x c_{ab}(x)` for every pair (antisymmetric; NaN
        when not asked for).
    pairs : ndarray of int64, shape (S, 2)
        The pairs (a, b) resolved by site.
    marker : ndarray of float, shape (S, sites)
        :math:`c_{ab}(x)`.
    distance : ndarray of int64, shape (S, sites)
        Bonds from x to the farther of the two cuts (the sites on the bonds where the cocycle is
        nonzero).
    gap : float
        The gap above the occupied levels at zero twist.
    occupied : int
        Levels below the Fermi level.

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.topology.frames import qwz_frame_terms
    >>> from hyperlattice.topology.twist_marker import twist_marker
    >>> res = twist_marker(qwz_frame_terms(hl.pbc_cluster(8, 3, "bolza"), M=1.0), pairs=[(0, 1)])
    >>> res.marker.shape, bool(abs(res.marker[0].sum() - res.total[0, 1]) < 1e-9)
    ((1, 16), True)
    """

    model: str
    name: str
    sites: int
    genus: int
    total: np.ndarray
    pairs: np.ndarray
    marker: np.ndarray
    distance: np.ndarray
    gap: float
    occupied: int

    def within(self, radius: int) -> np.ndarray:
        """Share of each pair's marker on the sites within ``radius`` bonds of both cuts (sum there / total).

        Parameters
        ----------
        radius : int
            Bonds.

        Returns
        -------
        numpy.ndarray of float, shape (S,)
        """
        r = _validate.integer("radius", radius, minimum=0, maximum=10**6)
        inside = np.where(self.distance <= r, self.marker, 0.0).sum(axis=1)
        return inside / self.marker.sum(axis=1)

    def table(self):
        """One row per (pair, distance): the marker summed over the sites at that distance and cumulatively."""
        import pandas as pd

        rows = []
        for s, (a, b) in enumerate(self.pairs.tolist()):
            for d in range(int(self.distance[s].max()) + 1):
                at = self.distance[s] == d
                rows.append({"a": a, "b": b, "distance": d, "sites": int(at.sum()),
                             "marker": float(self.marker[s][at].sum()),
                             "cumulative": float(self.marker[s][self.distance[s] <= d].sum())})
        return pd.DataFrame(rows)

    def summary(self) -> dict:
        """JSON view."""
        return {"model": self.model, "cluster": self.name, "sites": self.sites, "genus": self.genus,
                "total": self.total.tolist(), "pairs": self.pairs.tolist(),
                "pair_totals": self.marker.sum(axis=1).tolist(), "gap": self.gap, "occupied": self.occupied}


def _cut_distance(terms: ModelTerms, a: int, b: int) -> np.ndarray:
    """Bonds from each site to the farther of the cuts of cocycles a and b."""
    import scipy.sparse as sp
    from scipy.sparse.csgraph import shortest_path

    n = terms.sites
    adj = sp.csr_matrix((np.ones(len(terms.tail)), (terms.tail, terms.head)), shape=(n, n))
    out = []
    for c in (a, b):
        on = terms.windings[:, c] != 0
        src = np.unique(np.concatenate([terms.tail[on], terms.head[on]]))
        d = shortest_path(adj, unweighted=True, indices=src, directed=False).min(axis=0)
        out.append(d)
    return np.maximum(out[0], out[1]).astype(np.int64)


def twist_marker(system, model: str = "qwz", *, pairs=None, occupied=None, fermi_level=None, twist=None,
                 sum_rule: bool = True, **params) -> TwistMarker:
    r"""The local Chern marker :math:`c_{ab}(x)` of a cluster from its projector at zero twist.

    Parameters
    ----------
    system : Cluster or ModelTerms
        A periodic cluster and a model, or model terms with windings (e.g.
        :func:`~hyperlattice.topology.frames.qwz_frame_terms`).
    model : str, optional
        The model when ``system`` is a cluster (default qwz, the lift frame).
    pairs : sequence of (a, b), optional
        Pairs resolved by site (default the pairs (0, b) and the pair (1, 2)... up to six pairs
        with a nonzero total). The sum rule ``total`` covers every pair.
    occupied : int, optional
        Levels below the Fermi level (default half).
    fermi_level : float, optional
        The Fermi level instead (it must fall in a gap at zero twist).
    twist : array_like, shape (2g,), optional
        Evaluate at this twist k instead of k = 0 (the marker of the twisted Hamiltonian).
    sum_rule : bool, optional
        Compute ``total`` for every pair (default True; :math:`O(g^2)` products of the size of
        the occupied-empty block, the costly part at large genus). False leaves it NaN.
    **params
        Model parameters when ``system`` is a cluster.

    Returns
    -------
    TwistMarker

    Raises
    ------
    ValueError
        For an open graph, more rows than :data:`MAX_ROWS`, a Fermi level outside the spectrum, a
        gap that closes at zero twist, or a bad pair.

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.topology.twist_marker import twist_marker
    >>> res = twist_marker(hl.pbc_cluster(8, 3, "bolza"), "haldane", M=0.0, t2=0.2, fermi_level=-1.3)
    >>> res.occupied, res.total.shape
    (5, (4, 4))
    """
    from ..graph.clusters import Cluster
    from ..graph.solvers import single_threaded_blas  # noqa: F401 - same BLAS policy as the rest
    from .models import bloch_model_hamiltonian

    if isinstance(system, ModelTerms):
        terms, name = system, system.model
        if terms.windings.shape[1] == 0:
            raise ValueError("these model terms are on an open graph: no twists.")
        cname, genus = "terms", terms.windings.shape[1] // 2
    elif isinstance(system, Cluster):
        model = _validate.choice("model", model, MODELS)
        terms, cname, genus = model_terms(system, model, **params), system.name, system.genus
    else:
        raise ValueError(f"expected a Cluster or ModelTerms, got {type(system).__name__}.")
    name = terms.model
    rows = terms.sites * terms.orbitals
    if rows > MAX_ROWS:
        raise ValueError(f"twist_marker diagonalises densely: {rows} rows is above {MAX_ROWS}.")
    _validate.require_memory("the projector and twist derivatives", 16.0 * rows * rows * 8)
    g2 = terms.windings.shape[1]
    k0 = np.zeros(g2) if twist is None else _validate.real_array("twist", twist, ndim=1)
    if k0.shape != (g2,):
        raise ValueError(f"twist must have {g2} components, got {k0.shape}.")
    H = bloch_model_hamiltonian(terms, k0[None])[0]
    phased = terms.blocks * np.exp(1j * (terms.windings @ k0))[:, None, None]
    e, v = np.linalg.eigh(H)
    if occupied is not None and fermi_level is not None:
        raise ValueError("give occupied or fermi_level, not both.")
    if fermi_level is not None:
        fermi_level = _validate.real("fermi_level", fermi_level)
        occ = int(np.count_nonzero(e < fermi_level))
        if occ in (0, rows):
            raise ValueError(f"the Fermi level {fermi_level:g} is outside the spectrum [{e[0]:.4g}, {e[-1]:.4g}].")
    elif occupied is not None:
        occ = _validate.integer("occupied", occupied, minimum=1, maximum=rows - 1)
    else:
        occ = rows // 2
    gap = float(e[occ] - e[occ - 1])
    tol = 50 * rows * np.finfo(float).eps * max(1.0, float(np.abs(e).max()))
    if gap <= tol:
        raise ValueError(f"the levels {occ} and {occ + 1} are degenerate at zero twist (gap {gap:.1e}): "
                         "no marker at this filling.")
    vo, ve = v[:, :occ], v[:, occ:]
    den = e[None, :occ] - e[occ:, None]                      # (empty, occ): E_n - E_m
    d = terms.orbitals
    # rows touched by hops that carry winding a, and the hop blocks there: dH_a = sum i w_a B
    r_idx = (terms.tail[:, None, None] * d + np.arange(d)[None, :, None]).repeat(d, axis=2)
    c_idx = (terms.head[:, None, None] * d + np.arange(d)[None, None, :]).repeat(d, axis=1)

    def X(a):
        on = terms.windings[:, a] != 0
        touched = np.unique(np.concatenate([r_idx[on].ravel(), c_idx[on].ravel()]))
        pos = np.searchsorted(touched, np.arange(rows))
        small = np.zeros((len(touched), len(touched)), dtype=np.complex128)
        vals = (1j * terms.windings[on, a][:, None, None] * phased[on])
        np.add.at(small, (pos[r_idx[on]], pos[c_idx[on]]), vals)
        return (ve[touched].conj().T @ small @ vo[touched]) / den

    if pairs is None:
        pairs = [(0, b) for b in range(1, g2)][:6]
    if not isinstance(pairs, (list, tuple, np.ndarray)):
        raise ValueError(f"pairs must be a sequence of (a, b) pairs, got {type(pairs).__name__}.")
    pairs = [tuple(_validate.int_list("pair", pr, minimum=0, maximum=g2 - 1)) for pr in pairs]
    for pr in pairs:
        if len(pr) != 2 or pr[0] == pr[1]:
            raise ValueError(f"a pair is two different momentum indices, got {pr}.")
    # the sum rule for every pair: -4 pi Im tr(X_a^dagger X_b), directions in chunks to bound memory
    total = np.zeros((g2, g2)) if sum_rule else np.full((g2, g2), np.nan)
    chunk = max(1, int(_GRAM_BYTES // (16 * vo.shape[1] * ve.shape[1] + 1)))
    blocks = [list(range(s, min(g2, s + chunk))) for s in range(0, g2, chunk)]
    for i, bi in enumerate(blocks if sum_rule else []):
        xi = np.array([X(a) for a in bi]).reshape(len(bi), -1)
        for bj in blocks[i:]:
            xj = xi if bj == bi else np.array([X(a) for a in bj]).reshape(len(bj), -1)
            gram = xi.conj() @ xj.T
            total[np.ix_(bi, bj)] = -4 * np.pi * gram.imag
            total[np.ix_(bj, bi)] = 4 * np.pi * gram.imag.T
    if sum_rule:
        total = 0.5 * (total - total.T)
    marker, dist = [], []
    cache = {}
    for a, b in pairs:
        for c in (a, b):
            if c not in cache:
                cache[c] = X(c)
        m = cache[a].conj().T @ cache[b]
        m = m - m.conj().T                                    # X_a^dag X_b - X_b^dag X_a (occ x occ)
        diag = np.einsum("in,nk,ik->i", vo, m, vo.conj(), optimize=True)
        marker.append((2 * np.pi * 1j * diag).real.reshape(terms.sites, d).sum(axis=1))
        dist.append(_cut_distance(terms, a, b))
    return TwistMarker(model=name, name=cname, sites=terms.sites, genus=genus, total=total,
                       pairs=np.array(pairs, dtype=np.int64).reshape(-1, 2), marker=np.array(marker),
                       distance=np.array(dist, dtype=np.int64).reshape(len(pairs), terms.sites), gap=gap,
                       occupied=occ)


from .._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
