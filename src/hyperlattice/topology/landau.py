r"""Landau levels on closed hyperbolic surfaces: Hofstadter bands of clusters and their Chern numbers.

Graph side. On a cluster of genus g with F faces a uniform field puts :math:`f = N_\phi/F` flux
quanta through every p-gon (the total :math:`N_\phi` is an integer on a closed surface, Dirac's
quantisation). The edge phases :math:`a_e` (line integrals of A along i -> j) solve
:math:`\sum_{e\in\partial F} \pm a_e = 2\pi f` on every counterclockwise face
(:func:`cluster_flux_phases`; minimum-norm solution, the residual is checked), and the Abelian
Bloch Hamiltonian of :math:`H = -tA` becomes

.. math:: H(k)_{ij} = -t \sum_{e: i\to j} e^{\,i k\cdot w_e - i a_e},

k on the 2g-torus of flat connections added to the field (the windings of
:mod:`hyperlattice.graph.bands`). Its lowest bands group into Landau bands; the first Chern
numbers :math:`C_{ab}` of each group (cumulative projector, Fukui–Hatsugai–Suzuki on every
2-subtorus, :mod:`~hyperlattice.topology.surfaces`) are the Hall conductances of the filled
levels.

Continuum side (curvature -4, :math:`\hbar = e = 1`). Comtet's levels of :math:`-\Delta_B` on the
disk, :math:`\kappa_N = (2N+1)B - 4N(N+1)` for :math:`N < B/4 - 1/2`
(:func:`hyperlattice.continuum.magnetic.landau_levels`), with the field of the flux
(:func:`hyperlattice.dictionary.field_from_flux`); on a closed surface of genus g (area
:math:`\pi(g-1)`, :math:`N_\phi = B(g-1)/2`) level N has degeneracy
:math:`D_N = N_\phi - (2N+1)(g-1)` (Riemann–Roch for N = 0; Iengo and Li, Nucl. Phys. B 413,
735 (1994), for all N), and the bundle of each level over the torus of flat connections has
first Chern class the intersection form of the surface, one unit of Hall conductance per level
whatever its degeneracy (Avron, Klein, Pnueli and Sadun, PRL 69, 128 (1992)): in the windings'
basis :math:`C^{(N)}_{ab} = \pm Q_{ab}`, with :math:`Q_{ab} = \int_\Sigma \alpha_a\cup\alpha_b`
of the winding cocycles (:func:`intersection_form`), :math:`|\mathrm{Pf}\,Q| = 1`. The lattice energies
follow from the paper's map :math:`E = -q + \frac q4 h^2\kappa`
(:func:`hyperlattice.dictionary.energy_from_lambda`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .. import _validate
from ..results import Column, Result
from .models import ModelTerms

__all__ = ["cluster_flux_phases", "intersection_form", "hofstadter_terms", "LandauBands", "landau_bands"]


def _cluster(value):
    from ..graph.clusters import Cluster

    if not isinstance(value, Cluster):
        raise ValueError(f"expected a Cluster (from pbc_cluster), got {type(value).__name__}.")
    return value


def _face_incidence(c):
    """(F, p) edge index and sign (+1 when the ccw face runs along i -> j, i < j) of every face."""
    edges = np.asarray(c.edges, dtype=np.int64)
    n = c.sites
    keys = edges[:, 0] * n + edges[:, 1]
    faces = np.asarray(c.faces, dtype=np.int64)
    a, b = faces, np.roll(faces, -1, axis=1)
    e = np.searchsorted(keys, np.minimum(a, b) * n + np.maximum(a, b))
    return faces, e, np.where(a < b, 1, -1)


def cluster_flux_phases(cluster, n_phi: int) -> np.ndarray:
    r"""Edge phases :math:`a_e` of a uniform field with :math:`N_\phi` flux quanta through a closed cluster.

    Parameters
    ----------
    cluster : Cluster
        A periodic cluster with its rotation system.
    n_phi : int
        Total flux quanta (an integer on a closed surface); each face gets :math:`N_\phi/F`,
        positive counterclockwise.

    Returns
    -------
    numpy.ndarray of float, shape (E,)
        :math:`a_e` for each edge (i, j), i < j, of ``cluster.edges`` (the line integral from i to
        j); every counterclockwise face sums to :math:`2\pi N_\phi/F` modulo :math:`2\pi`.

    Raises
    ------
    ValueError
        For a bad cluster or flux.

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.topology.landau import cluster_flux_phases
    >>> a = cluster_flux_phases(hl.pbc_cluster(8, 3, "bolza"), 3)
    >>> a.shape
    (24,)
    """
    c = _cluster(cluster)
    n_phi = _validate.integer("n_phi", n_phi, minimum=-10**6, maximum=10**6)
    faces, e, s = _face_incidence(c)
    nf, ne = len(faces), c.n_edges
    D = np.zeros((nf, ne))
    np.add.at(D, (np.repeat(np.arange(nf), c.p), e.ravel()), s.ravel())
    rhs = np.full(nf, 2 * np.pi * n_phi / nf)
    rhs[-1] -= 2 * np.pi * n_phi          # the same phases mod 2 pi, summing to zero over the closed surface
    a, *_ = np.linalg.lstsq(D, rhs, rcond=None)
    res = float(np.max(np.abs(D @ a - rhs))) if nf else 0.0
    if res > 1e-9 * max(1.0, abs(n_phi)):  # pragma: no cover - the system is consistent on a closed surface
        raise ValueError(f"the face fluxes cannot be solved (residual {res:.1e}).")
    return a


def intersection_form(cluster) -> np.ndarray:
    r"""The intersection form :math:`Q_{ab} = \int_\Sigma \alpha_a \cup \alpha_b` of the winding cocycles.

    :math:`\alpha_a` is the a-th component of the windings of
    :func:`~hyperlattice.graph.bands.edge_windings` (a 1-cocycle: it sums to zero around every
    face). The cup product is taken on the subdivision of every face into triangles
    :math:`(v_k, v_{k+1}, c_f)` about a face centre, with one global vertex order (sites by index,
    then centres) so that the simplicial formula :math:`(\alpha\cup\beta)[x, y, z] =
    \alpha(x\to y)\,\beta(y\to z)` holds; the cocycles are extended to the centre edges by the
    face's potential.

    Parameters
    ----------
    cluster : Cluster
        A periodic cluster.

    Returns
    -------
    numpy.ndarray of int64, shape (2g, 2g)
        Antisymmetric and unimodular (:math:`|\mathrm{Pf}\,Q| = 1`, checked).

    Examples
    --------
    >>> import numpy as np
    >>> import hyperlattice as hl
    >>> from hyperlattice.topology.landau import intersection_form
    >>> Q = intersection_form(hl.pbc_cluster(8, 3, "bolza"))
    >>> Q.shape, round(float(abs(np.linalg.det(Q))))
    ((4, 4), 1)
    """
    from ..graph.bands import edge_windings
    from .surfaces import _pf

    c = _cluster(cluster)
    w = edge_windings(c).windings.astype(float)               # (E, 2g) along i -> j, i < j
    faces, e, s = _face_incidence(c)
    nf, p = faces.shape
    step = w[e] * s[:, :, None]                                # (F, p, 2g) along the ccw boundary
    phi = np.concatenate([np.zeros((nf, 1, w.shape[1])), np.cumsum(step, axis=1)[:, :-1]], axis=1)
    if np.any(np.abs(step.sum(axis=1)) > 1e-9):  # pragma: no cover - edge_windings checks it
        raise ValueError("the windings are not a cocycle.")
    # one triangle (v_k, v_{k+1}, c_f) per boundary step, ccw; cochain on its three edges
    alpha = {  # value on the directed edge between two of the three corners (0: v_k, 1: v_{k+1}, 2: c_f)
        (0, 1): step, (1, 2): -np.roll(phi, -1, axis=1), (0, 2): -phi,
    }
    ids = np.stack([faces, np.roll(faces, -1, axis=1), c.sites + np.repeat(np.arange(nf)[:, None], p, axis=1)],
                   axis=-1)                                    # (F, p, 3) global vertex numbers
    order = np.argsort(ids, axis=-1)                           # sorted corners x < y < z
    # parity of the sorting permutation of (0, 1, 2)
    perm = order
    # even permutations of the ccw corners (0, 1, 2) are the cyclic ones
    parity = np.where(((perm[..., 0] == 0) & (perm[..., 1] == 1)) | ((perm[..., 0] == 1) & (perm[..., 1] == 2))
                      | ((perm[..., 0] == 2) & (perm[..., 1] == 0)), 1, -1)

    def edge_value(i, j):
        """Cochain on the directed edge corner i -> corner j (arrays of corner labels)."""
        out = np.zeros(step.shape)
        for (u, v), val in alpha.items():
            out += np.where(((i == u) & (j == v))[..., None], val, 0.0)
            out -= np.where(((i == v) & (j == u))[..., None], val, 0.0)
        return out

    x, y, z = order[..., 0], order[..., 1], order[..., 2]
    first = edge_value(x, y)                                   # (F, p, 2g)
    second = edge_value(y, z)
    Q = np.einsum("fp,fpa,fpb->ab", parity.astype(float), first, second)
    Qi = np.rint(Q).astype(np.int64)
    # |Pf Q| = 1 <=> |det Q| = 1 (det = Pf^2); the determinant (LU) stays cheap at large genus, the Pfaffian's
    # expansion does not
    unimodular = (abs(round(_pf(Qi.astype(float)))) == 1 if len(Qi) <= 12
                  else abs(abs(np.linalg.det(Qi.astype(float))) - 1.0) < 1e-6)
    if np.max(np.abs(Q - Qi)) > 1e-9 or not np.array_equal(Qi, -Qi.T) or not unimodular:
        raise ValueError("the intersection form of the windings is not unimodular: the cluster's map is broken.")
    return Qi


def hofstadter_terms(cluster, n_phi: int, *, t: float = 1.0) -> ModelTerms:
    r"""The hop list of :math:`H = -tA` with :math:`N_\phi` flux quanta on a cluster, for the Abelian bands.

    Parameters
    ----------
    cluster : Cluster
        A periodic cluster.
    n_phi : int
        Total flux quanta (see :func:`cluster_flux_phases`).
    t : float, optional
        Hopping (default 1).

    Returns
    -------
    ModelTerms
        One orbital; blocks :math:`-t e^{-ia}` with the windings of the darts.

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.topology.landau import hofstadter_terms
    >>> hofstadter_terms(hl.pbc_cluster(8, 3, "bolza"), 2).windings.shape
    (48, 4)
    """
    from ..graph.bands import edge_windings

    c = _cluster(cluster)
    t = _validate.real("t", t, minimum=-1e6, maximum=1e6)
    a = cluster_flux_phases(c, n_phi)
    W = edge_windings(c)
    edges = np.asarray(c.edges, dtype=np.int64)
    tail = np.concatenate([edges[:, 0], edges[:, 1]])
    head = np.concatenate([edges[:, 1], edges[:, 0]])
    # H[i, j] for the step i -> j carries e^{-i a(i -> j)} (the line integral from j back to i)
    ph = np.concatenate([-a, a])
    wind = np.concatenate([W.windings, -W.windings])
    blocks = (-t * np.exp(1j * ph))[:, None, None].astype(np.complex128)
    return ModelTerms(model="hofstadter", orbitals=1, onsite=np.zeros((c.sites, 1, 1), dtype=np.complex128),
                      tail=tail, head=head, blocks=blocks, windings=wind.astype(np.int64),
                      parameters={"n_phi": int(n_phi), "t": t})


@dataclass(frozen=True, eq=False, kw_only=True)
class LandauBands(Result):
    r"""The lowest Landau bands of a cluster in a field, lattice and continuum side by side.

    Attributes
    ----------
    name : str
        The cluster.
    p, q, genus, faces : int
        Its {p,q}, genus and number of faces.
    n_phi : int
        Total flux quanta; ``flux`` = n_phi / faces per p-gon.
    flux, field : float
        Flux per p-gon and the continuum field B (curvature -4).
    level : ndarray of int64
        Level index N.
    bands : ndarray of int64
        Bands in the lattice group (counted from the bottom, separated by a gap on the grid).
    degeneracy : ndarray of int64
        Continuum :math:`D_N = N_\phi - (2N+1)(g-1)` (0 past the last discrete level).
    energy_min, energy_max : ndarray of float
        The lattice group's energy range on the grid.
    energy_continuum : ndarray of float
        :math:`E_N = -q + \frac q4 h^2 \kappa_N` (NaN past the last discrete level).
    gap_above : ndarray of float
        Smallest gap above the group on the grid.
    chern : ndarray of int64, shape (levels, 2g, 2g)
        First Chern matrix of the group alone (difference of cumulative projectors).
    gcd, pfaffian : ndarray of int64
        Basis-independent invariants of each group's matrix.
    intersection : ndarray of int64, shape (2g, 2g)
        The continuum prediction up to the sign of B: :math:`\pm Q` (:func:`intersection_form`).
    matches : ndarray of bool
        Whether the group's matrix is :math:`\pm Q`.
    grid : int
        Points per direction of the 2-subtorus grids.

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.topology.landau import landau_bands
    >>> res = landau_bands(hl.pbc_cluster(8, 3, "bolza"), 3, levels=1)
    >>> res.bands.tolist(), res.degeneracy.tolist()
    ([2], [2])
    """

    COLUMNS = (Column("level", "level", "1"), Column("bands", "bands", "1"),
               Column("degeneracy", "degeneracy", "1"), Column("energy_min", "energy_min", "t"),
               Column("energy_max", "energy_max", "t"), Column("energy_continuum", "energy_continuum", "t"),
               Column("gap_above", "gap_above", "t"), Column("gcd", "gcd", "1"), Column("pfaffian", "pfaffian", "1"),
               Column("matches", "matches", "1"))

    name: str
    p: int
    q: int
    genus: int
    faces: int
    n_phi: int
    flux: float
    field: float
    level: np.ndarray
    bands: np.ndarray
    degeneracy: np.ndarray
    energy_min: np.ndarray
    energy_max: np.ndarray
    energy_continuum: np.ndarray
    gap_above: np.ndarray
    chern: np.ndarray
    gcd: np.ndarray
    pfaffian: np.ndarray
    intersection: np.ndarray
    matches: np.ndarray
    grid: int

    def summary(self) -> dict:
        """The CLI's JSON view."""
        return {"cluster": self.name, "genus": self.genus, "faces": self.faces, "n_phi": self.n_phi,
                "flux": self.flux, "field": self.field, "level": self.level.tolist(), "bands": self.bands.tolist(),
                "degeneracy": self.degeneracy.tolist(), "energy_min": self.energy_min.tolist(),
                "energy_max": self.energy_max.tolist(), "energy_continuum": self.energy_continuum.tolist(),
                "gap_above": self.gap_above.tolist(), "chern": self.chern.tolist(), "gcd": self.gcd.tolist(),
                "pfaffian": self.pfaffian.tolist(), "intersection": self.intersection.tolist(),
                "matches": self.matches.tolist(), "grid": self.grid}


def _groups(e: np.ndarray, levels: int, min_gap: float) -> list[int]:
    """Cumulative band counts at the first ``levels`` gaps of the band structure (bands x k)."""
    lo, hi = e.min(axis=0), e.max(axis=0)
    cuts = [j for j in range(1, e.shape[1]) if lo[j] - hi[j - 1] > min_gap]
    return cuts[:levels]


def landau_bands(cluster, n_phi: int, *, levels: int = 2, grid: int = 12, max_grid: int = 48,
                 min_gap: float = 1e-3) -> LandauBands:
    r"""The lowest Landau bands of :math:`H = -tA` on a cluster with :math:`N_\phi` flux quanta and their Chern numbers.

    The band groups are cut at the gaps of the band structure sampled on every grid of the
    2-subtori (a gap must exceed ``min_gap`` everywhere); each group's Chern matrix is the
    difference of the cumulative ones (:func:`~hyperlattice.topology.surfaces.cluster_chern`'s
    method with the Fermi level in that gap).

    Parameters
    ----------
    cluster : Cluster
        A periodic cluster (a few hundred sites at most: dense Bloch Hamiltonians).
    n_phi : int
        Total flux quanta, 1 to the number of faces.
    levels : int, optional
        Lowest band groups to report (default 2).
    grid, max_grid : int, optional
        The 2-subtorus grids (doubled until every plaquette phase is below pi/2).
    min_gap : float, optional
        Smallest gap (units of t) that separates two groups (default 1e-3).

    Returns
    -------
    LandauBands

    Raises
    ------
    ValueError
        For bad input, or when fewer than ``levels`` gaps are open.

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.topology.landau import landau_bands
    >>> res = landau_bands(hl.pbc_cluster(7, 3, "klein"), 4, levels=1, grid=8)
    >>> int(res.bands[0]), int(res.degeneracy[0]), bool(res.matches[0]), int(res.gcd[0])
    (2, 2, True, 1)
    """
    from .. import dictionary
    from ..continuum.magnetic import landau_levels
    from ..graph.solvers import single_threaded_blas
    from .models import bloch_model_hamiltonian
    from .surfaces import _all_subtori, _pf

    c = _cluster(cluster)
    nf = c.n_faces
    n_phi = _validate.integer("n_phi", n_phi, minimum=1, maximum=nf)
    levels = _validate.integer("levels", levels, minimum=1, maximum=20)
    grid = _validate.integer("grid", grid, minimum=4, maximum=256)
    max_grid = _validate.integer("max_grid", max_grid, minimum=grid, maximum=256)
    min_gap = _validate.real("min_gap", min_gap, minimum=0.0, maximum=10.0)
    if c.sites > 400:
        raise ValueError(f"landau_bands diagonalises dense Bloch Hamiltonians: at most 400 sites, got {c.sites}.")
    terms = hofstadter_terms(c, n_phi)
    g2 = 2 * c.genus
    # band structure on the coarse grids of all 2-subtori (the same points the Chern numbers use)
    ks = 2 * np.pi * np.arange(grid) / grid
    pts = []
    for a in range(g2):
        for b in range(a + 1, g2):
            kk = np.zeros((grid * grid, g2))
            A, B = np.meshgrid(ks, ks, indexing="ij")
            kk[:, a], kk[:, b] = A.ravel(), B.ravel()
            pts.append(kk)
    kk = np.concatenate(pts)
    with single_threaded_blas():
        e = np.linalg.eigvalsh(bloch_model_hamiltonian(terms, kk))
    cuts = _groups(e, levels, min_gap)
    if len(cuts) < levels:
        raise ValueError(f"only {len(cuts)} gap(s) above {min_gap:g} open among the lowest bands at N_phi = {n_phi}; "
                         f"ask for fewer levels.")
    Q = intersection_form(c)
    cum = []
    n = grid
    with single_threaded_blas():
        for occ in cuts:
            raw = np.zeros((g2, g2))
            n = max(n, _all_subtori(terms, g2, occ, grid, max_grid, raw, [], []))
            cum.append(np.rint(raw).astype(np.int64))
    chern = np.array([cum[0]] + [cum[i] - cum[i - 1] for i in range(1, len(cum))])
    bounds = [0] + cuts
    sizes = np.diff(bounds)
    B = float(dictionary.field_from_flux(n_phi / nf, c.p, c.q))
    kappa = landau_levels(B)["kappa"] if abs(B) <= 1e6 else np.array([])
    N = np.arange(levels)
    deg = np.maximum(0, n_phi - (2 * N + 1) * (c.genus - 1))
    deg = np.where(N < len(kappa), deg, 0)
    e_cont = np.array([float(dictionary.energy_from_lambda(kappa[i], c.p, c.q)) if i < len(kappa) else math.nan
                       for i in N])
    gcds = np.array([math.gcd(*[abs(int(x)) for x in m[np.triu_indices(g2, 1)]]) for m in chern], dtype=np.int64)
    pfs = np.array([int(round(_pf(m.astype(float)))) for m in chern], dtype=np.int64)
    matches = np.array([np.array_equal(m, Q) or np.array_equal(m, -Q) for m in chern])
    emin = np.array([e[:, lo].min() for lo in bounds[:-1]])
    emax = np.array([e[:, hi - 1].max() for hi in bounds[1:]])
    gap_above = np.array([e[:, hi].min() - e[:, hi - 1].max() for hi in bounds[1:]])
    return LandauBands(name=c.name, p=c.p, q=c.q, genus=c.genus, faces=nf, n_phi=n_phi, flux=n_phi / nf, field=B,
                       level=N.astype(np.int64), bands=sizes.astype(np.int64), degeneracy=deg.astype(np.int64),
                       energy_min=emin, energy_max=emax, energy_continuum=e_cont, gap_above=gap_above,
                       chern=chern, gcd=gcds, pfaffian=pfs, intersection=Q, matches=matches, grid=n)


from .._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
