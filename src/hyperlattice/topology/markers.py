r"""Real-space Chern invariants of flakes: local markers, Kitaev's sum and the Bott index.

Sign convention (Bianco and Resta, PRB 84, 241106(R) (2011)): the local marker is
:math:`c(r) = \frac{4\pi}{A}\,\mathrm{Im}\sum_{a}\langle r a|P\,x\,Q\,y\,P|r a\rangle`,
P the projector on the states below the Fermi level, Q = 1 - P, A the area per site; with it
the square-lattice QWZ model :math:`H(k) = (M + \cos k_x + \cos k_y)\sigma_z - \sin k_x\sigma_x
- \sin k_y\sigma_y` at M = +1 has C = -1 (checked in the tests, with the Fukui–Hatsugai–Suzuki
number of its Bloch bands). Every invariant here is given in this convention.

Four invariants, all from the same P:

* **the flat Bianco–Resta marker** :math:`c(r)` with x, y the Poincaré-disk coordinates and A
  the hyperbolic area per site, optionally in the chart recentred at r by the Möbius map
  :math:`w = (z - z_r)/(1 - \bar z_r z)` (so that the chart is isometric at r to first order).
  It does *not* quantise on a hyperbolic flake: the chart is conformal but not isometric over a
  correlation length, so the "position operators" x, y are not the coordinates the marker's
  derivation assumes (a Euclidean plane where :math:`[x, y] = 0` and translations act by
  shifts). On {8,3} QWZ at M = 1 its centre value is -0.84 instead of -1 (:mod:`tests`).
* **the hyperbolic local marker** (:func:`local_markers`): Kitaev's triple-sector sum centred
  at site r, :math:`\nu(r) = 12\pi i \sum_{j\in A,k\in B,l\in C}(P_{jk}P_{kl}P_{lj} -
  P_{jl}P_{lk}P_{kj})` (Kitaev, Ann. Phys. 321, 2 (2006), Eq. 131) with A, B, C the three
  sectors between the geodesic rays from r at angles :math:`\alpha_0, \alpha_0 + 2\pi/3,
  \alpha_0 + 4\pi/3` (straight rays in the recentred chart), and j, k, l restricted to the
  geodesic disk of radius R around r. It needs no position operator and no area: the sum is a
  topological invariant of the partition (it does not change when a sector boundary moves,
  as long as P is local), so it cannot depend on the chart. It converges exponentially in
  R / xi because only triples within a correlation length of the junction contribute; in
  hyperbolic space the sector boundaries separate exponentially, so fewer triples contribute
  than in the plane. Resolved by ring, it is -1 in the bulk of a Chern flake and drifts at the
  edge, where the disk leaves the flake.
* **Kitaev's real-space sum** (``kitaev``): the same sum centred at the flake's centre with the
  largest radius that stays two bond lengths inside the outer ring.
* **the Bott index** (Loring and Hastings, EPL 92, 67004 (2010)):
  :math:`B = \frac{1}{2\pi}\mathrm{Im\,Tr}\log(\tilde V\tilde U\tilde V^\dagger\tilde U^\dagger)`,
  :math:`\tilde U = P e^{2\pi i x/L_x} P`, :math:`\tilde V = P e^{2\pi i y/L_y} P` restricted to the
  occupied states (chart coordinates). It is global: edge states at the Fermi level make
  :math:`\tilde U, \tilde V` far from commuting, the spectrum of the product reaches -1 and the
  integer stops meaning anything. Two checks: ``bott_margin``, the distance of that spectrum
  from -1 (2 when they commute; below 0.05 the index flips under a small perturbation), and
  stability: the index recomputed with one occupied state less and one more (in a Chern flake
  these are edge states in the gap) must not change. The result warns when either fails.

The bulk gap at the flake's centre is the gap of the local density of states at ring 1: the
distance between the highest state below the Fermi level and the lowest above it whose weight on
ring 1 is at least a tenth of the average weight of a state there (edge states carry
exponentially small weight at the centre, so they do not close it).
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np

from .. import _validate
from ..results import Column, INDEX, Result
from .models import MODELS, PlaneGraph, model_hamiltonian, model_terms, spin_operator

__all__ = ["FlakeTopology", "flake_topology", "local_markers", "occupied_states", "OccupiedStates",
           "MAX_DENSE_ROWS", "EdgeChirality", "edge_chirality"]

#: dense diagonalisation is refused above this many rows (eigenvectors: 16 bytes x rows^2 each)
MAX_DENSE_ROWS = 9_000
#: states with at least this fraction of the mean ring-1 weight count as bulk states at the centre
CENTRE_WEIGHT = 0.1
#: the Bott index warns when its unitary product has an eigenvalue closer than this to -1
BOTT_MARGIN = 0.05
#: Kane–Mele: warn when the spectrum of P s_z P has a smaller gap than this where it is split in halves
SPIN_GAP_MIN = 0.1


# ----------------------------------------------------------------------------
# geometry of a flake
# ----------------------------------------------------------------------------

@dataclass(frozen=True)
class _Geometry:
    z: np.ndarray
    ring: np.ndarray
    hyperbolic: bool
    area: float          # area per site (hyperbolic area for a {p,q} flake)
    bond: float          # bond length in the metric
    boundary: np.ndarray  # sites of degree below the bulk degree

    def distance(self, c: complex, z: np.ndarray) -> np.ndarray:
        if self.hyperbolic:
            w = np.abs((z - c) / (1.0 - np.conj(c) * z))
            return np.arctanh(np.minimum(w, 1 - 1e-16))
        return np.abs(z - c)

    def recentre(self, c: complex, z: np.ndarray) -> np.ndarray:
        if self.hyperbolic:
            return (z - c) / (1.0 - np.conj(c) * z)
        return z - c


def _boundary(graph) -> np.ndarray:
    deg = np.bincount(np.asarray(graph.edges).ravel(), minlength=len(graph.z))
    return np.flatnonzero(deg < deg.max())


def _geometry(graph) -> _Geometry:
    if isinstance(graph, PlaneGraph):
        if graph.periodic:
            raise ValueError("the real-space markers need an open flake, not a torus (use cluster_chern).")
        area = 1.0 if graph.name == "square" else 3 * np.sqrt(3) / 4
        return _Geometry(z=np.asarray(graph.z), ring=np.asarray(graph.ring, dtype=np.int64), hyperbolic=False,
                         area=area, bond=1.0, boundary=_boundary(graph))
    if getattr(type(graph), "__hyperlattice_lattice__", False):
        _validate.lattice(graph)
        from .. import geometry
        from ..graph.flux import pgon_area

        if graph.kind != "sites":
            raise ValueError("the markers are defined on the sites of a {p,q} flake, not on a line graph.")
        return _Geometry(z=np.asarray(graph.z), ring=np.asarray(graph.ring, dtype=np.int64), hyperbolic=True,
                         area=pgon_area(graph.p, graph.q) * graph.q / graph.p, bond=geometry.d0(graph.p, graph.q),
                         boundary=_boundary(graph))
    raise ValueError(f"expected an open flake (ring_lattice or a PlaneGraph flake), got {type(graph).__name__}.")


# ----------------------------------------------------------------------------
# occupied states
# ----------------------------------------------------------------------------

@dataclass(frozen=True, eq=False, kw_only=True)
class OccupiedStates(Result):
    """Eigenpairs of a flake Hamiltonian and the states below the Fermi level.

    Attributes
    ----------
    energies : ndarray, shape (n,)
        All eigenvalues, ascending (units of the hopping).
    vectors : ndarray of complex128, shape (n, occupied)
        The occupied eigenvectors (columns).
    fermi : float
        The Fermi level (between the last occupied and the first empty level).
    orbitals : int
        Orbitals per site (rows ``i * orbitals + a``).
    centre_weight : ndarray, shape (n,)
        Weight of each eigenstate on the sites of ring 1.
    first_empty : ndarray of complex128, shape (n, 1)
        The lowest eigenvector above the Fermi level (for the Bott index's stability check).

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.topology import occupied_states
    >>> occ = occupied_states(hl.ring_lattice(8, 3, 2), "qwz", M=1.0)
    >>> occ.vectors.shape
    (96, 48)
    """

    NOT_TABULAR = "eigenvectors: a matrix, not a table"

    energies: np.ndarray
    vectors: np.ndarray
    fermi: float
    orbitals: int
    centre_weight: np.ndarray
    first_empty: np.ndarray


def _fermi_index(energies: np.ndarray, fermi, scale: float) -> tuple[int, float]:
    n = len(energies)
    if fermi is None:
        occ = n // 2
        return occ, float(0.5 * (energies[occ - 1] + energies[occ])) if 0 < occ < n else float(energies[0])
    ef = _validate.real("fermi", fermi)
    if not energies[0] <= ef <= energies[-1]:
        raise ValueError(f"the Fermi level {ef:g} lies outside the spectrum [{energies[0]:.6g}, {energies[-1]:.6g}].")
    # a level within the eigensolver's error of the Fermi level would be occupied or not by rounding
    tol = 50 * n * np.finfo(float).eps * scale
    if np.any(np.abs(energies - ef) <= tol):
        raise ValueError(f"the Fermi level {ef:g} coincides with a level (within {tol:.1e}); move it into a gap.")
    return int(np.searchsorted(energies, ef)), ef


def occupied_states(graph, model: str = "qwz", *, M: float = 1.0, t2: float = 0.2, phi: float = np.pi / 2,
                    rashba: float = 0.0, flux: float = 0.0, disorder: float = 0.0, seed: int = 0,
                    fermi: float | None = None, frame: str = "chord") -> OccupiedStates:
    """Dense diagonalisation of a model on a flake (see :func:`flake_topology` for the parameters).

    Parameters
    ----------
    graph : Lattice or PlaneGraph
        An open flake.
    model : str
        ``"qwz"``, ``"haldane"`` or ``"kane-mele"``.
    M, t2, phi, rashba, flux, disorder, seed, frame : optional
        Model parameters (:func:`~hyperlattice.topology.models.model_terms`).
    fermi : float, optional
        Fermi level; default half filling (the lower half of the levels occupied).

    Returns
    -------
    OccupiedStates

    Raises
    ------
    ValueError
        Bad model parameters, a Fermi level outside the spectrum or on a level, more than
        :data:`MAX_DENSE_ROWS` rows (use :func:`~hyperlattice.topology.kpm_marker.centre_marker`).
    """
    geo = _geometry(graph)
    terms = model_terms(graph, model, M=M, t2=t2, phi=phi, rashba=rashba, flux=flux, disorder=disorder, seed=seed,
                        frame=frame)
    rows = terms.sites * terms.orbitals
    if rows > MAX_DENSE_ROWS:
        raise ValueError(f"dense diagonalisation of {rows:,} rows is refused (at most {MAX_DENSE_ROWS:,}); "
                         "use centre_marker (Chebyshev expansion) for bigger flakes.")
    _validate.require_memory("dense diagonalisation", 3 * 16.0 * rows * rows)
    from ..graph.solvers import single_threaded_blas

    H = model_hamiltonian(terms).toarray()
    with single_threaded_blas():   # one thread: measured 6x faster on the shared 2-core machine
        e, v = np.linalg.eigh(H)
    del H
    scale = max(abs(e[0]), abs(e[-1]), 1.0)
    occ, ef = _fermi_index(e, fermi, scale)
    d = terms.orbitals
    ring1 = np.flatnonzero(geo.ring == geo.ring.min())
    rows1 = (ring1[:, None] * d + np.arange(d)[None]).ravel()
    w1 = np.sum(np.abs(v[rows1]) ** 2, axis=0)
    return OccupiedStates(energies=e, vectors=np.ascontiguousarray(v[:, :occ]), fermi=ef, orbitals=d,
                          centre_weight=w1, first_empty=np.ascontiguousarray(v[:, occ:occ + 1]))


def _centre_gap(occ: OccupiedStates) -> tuple[float, int, float]:
    """Gap of the ring-1 local DOS around the Fermi level, the number of states inside it, its lower edge."""
    e, w = occ.energies, occ.centre_weight
    mean = w.sum() / len(w)
    bulk = w >= CENTRE_WEIGHT * mean
    below = np.flatnonzero(bulk & (e < occ.fermi))
    above = np.flatnonzero(bulk & (e > occ.fermi))
    if len(below) == 0 or len(above) == 0:
        return 0.0, 0, float(occ.fermi)
    lo, hi = e[below[-1]], e[above[0]]
    inside = int(np.sum((e > lo) & (e < hi)))
    return float(hi - lo), inside, float(lo)


def _edge_weight(geo: _Geometry, occ: OccupiedStates, lo: float, rings: np.ndarray) -> np.ndarray:
    """Mean weight per ring of the occupied states inside the centre's gap (zeros when there are none)."""
    e = occ.energies[: occ.vectors.shape[1]]
    sel = np.flatnonzero(e > lo)
    if len(sel) == 0:
        return np.zeros(len(rings))
    w = np.abs(occ.vectors[:, sel]) ** 2
    per_site = w.reshape(len(geo.z), occ.orbitals, len(sel)).sum(axis=1)
    return np.array([per_site[geo.ring == r].sum(axis=0).mean() for r in rings])


# ----------------------------------------------------------------------------
# markers
# ----------------------------------------------------------------------------

def _rows(sites: np.ndarray, d: int) -> np.ndarray:
    return (sites[:, None] * d + np.arange(d)[None]).ravel()


def _sectors(w: np.ndarray, alpha0: float) -> np.ndarray:
    """Sector 0, 1, 2 of each recentred point by its angle; the point at the centre goes to sector 0."""
    ang = np.mod(np.angle(w) - alpha0, 2 * np.pi)
    sec = np.floor(ang / (2 * np.pi / 3)).astype(np.int64) % 3
    sec[np.abs(w) < 1e-12] = 0
    return sec


def _kitaev(P_block: np.ndarray, sec_rows: np.ndarray) -> float:
    """12 pi i sum (P_jk P_kl P_lj - P_jl P_lk P_kj) = -24 pi Im Tr(P_AB P_BC P_CA), Bianco–Resta sign."""
    a, b, c = (np.flatnonzero(sec_rows == s) for s in range(3))
    t = np.einsum("ij,ji->", P_block[np.ix_(a, b)] @ P_block[np.ix_(b, c)], P_block[np.ix_(c, a)])
    # Kitaev's sum is +1 where Bianco–Resta's marker is -1 (square QWZ at M = 1, checked in the tests)
    return float(24 * np.pi * t.imag)


def _alpha0(geo: _Geometry, centre: complex, idx: np.ndarray) -> float:
    """A sector offset with no site within 1e-6 rad of a boundary (ties would depend on rounding)."""
    w = geo.recentre(centre, geo.z[idx])
    ang = np.angle(w[np.abs(w) > 1e-12])
    for alpha in 0.1234 + 0.0517 * np.arange(40):
        rel = np.mod(ang - alpha, 2 * np.pi / 3)
        if np.all((rel > 1e-6) & (rel < 2 * np.pi / 3 - 1e-6)):
            return float(alpha)
    return 0.1234  # pragma: no cover - 40 offsets all hit a site


def _local_kitaev(geo: _Geometry, V: np.ndarray, d: int, centre: complex, radius: float) -> float:
    idx = np.flatnonzero(geo.distance(centre, geo.z) <= radius)
    rows = _rows(idx, d)
    Vd = V[rows]
    P = Vd @ Vd.conj().T
    sec = np.repeat(_sectors(geo.recentre(centre, geo.z[idx]), _alpha0(geo, centre, idx)), d)
    return _kitaev(P, sec)


def _flat_marker(geo: _Geometry, V: np.ndarray, d: int, sites: np.ndarray, *, recentred: bool) -> np.ndarray:
    """Bianco–Resta marker -(4 pi / A) Im <r|P x Q y P|r> at the given sites, chart or recentred chart."""
    out = np.empty(len(sites))
    if not recentred:
        x = np.repeat(geo.z.real, d)
        y = np.repeat(geo.z.imag, d)
        Xo = V.conj().T @ (x[:, None] * V)
        Yo = V.conj().T @ (y[:, None] * V)
        rows = _rows(sites, d)
        Vr = V[rows]
        # Im <r|P x Q y P|r> = -Im <r|P x P y P|r> (<r|P x y P|r> is real)
        val = -np.einsum("ij,ij->i", Vr @ (Xo @ Yo), Vr.conj()).imag
        return -4 * np.pi / geo.area * val.reshape(len(sites), d).sum(axis=1)
    for n, s in enumerate(sites):
        w = np.repeat(geo.recentre(geo.z[s], geo.z), d)
        rows = _rows(np.array([s]), d)
        u = V @ V[rows].conj().T                              # P|r>
        xu, yu = w.real[:, None] * u, w.imag[:, None] * u
        pyu = V @ (V.conj().T @ yu)                           # P y P |r>
        val = np.einsum("ij,ij->", xu.conj(), yu - pyu)       # <r|P x Q y P|r>
        out[n] = -4 * np.pi / geo.area * val.imag
    return out


def _bott(geo: _Geometry, V: np.ndarray, d: int) -> tuple[float, float]:
    x, y = geo.z.real, geo.z.imag
    lx = x.max() - x.min() + _chord(geo)
    ly = y.max() - y.min() + _chord(geo)
    ux = np.repeat(np.exp(2j * np.pi * (x - x.min()) / lx), d)
    uy = np.repeat(np.exp(2j * np.pi * (y - y.min()) / ly), d)
    U = V.conj().T @ (ux[:, None] * V)
    W = V.conj().T @ (uy[:, None] * V)
    prod = W @ U @ W.conj().T @ U.conj().T
    lam = np.linalg.eigvals(prod)
    bott = float(np.sum(np.angle(lam)) / (2 * np.pi))
    # det(W U W^+ U^+) = |det U|^2 |det W|^2 > 0, so the sum of the phases is 2 pi times an integer up
    # to rounding (n phases, each good to about n eps): report that integer, not its rounding noise
    if abs(bott - round(bott)) <= 1e-9 * max(len(lam), 1):
        bott = float(round(bott))
    margin = float(np.min(np.abs(lam / np.abs(lam) + 1))) if len(lam) else 2.0
    return bott, margin


def _chord(geo: _Geometry) -> float:
    """Typical chord length between neighbours near the centre (the Bott coordinates' period padding)."""
    c = geo.z[geo.ring == geo.ring.min()]
    if len(c) < 2:
        return 1.0
    dist = np.abs(c[:, None] - c[None, :])
    return float(np.min(dist[dist > 0]))


def local_markers(graph, occupied: OccupiedStates, sites=None, *, radius: float | None = None) -> np.ndarray:
    """The hyperbolic local marker (Kitaev's sum centred at each site, see the module docstring).

    Parameters
    ----------
    graph : Lattice or PlaneGraph
        The flake ``occupied`` was computed on.
    occupied : OccupiedStates
        From :func:`occupied_states`.
    sites : array_like of int, optional
        Sites to evaluate (default all).
    radius : float, optional
        Radius of the disk of the sum, in the metric (default 4 bond lengths).

    Returns
    -------
    numpy.ndarray of float64
        The marker at each site (Bianco–Resta sign: -1 for square QWZ at M = 1).

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.topology import occupied_states, local_markers
    >>> lat = hl.ring_lattice(8, 3, 3)
    >>> occ = occupied_states(lat, "qwz", M=1.0)
    >>> round(float(local_markers(lat, occ, [0])[0]), 1)
    -1.0
    """
    geo = _geometry(graph)
    if not isinstance(occupied, OccupiedStates) or occupied.vectors.shape[0] != len(geo.z) * occupied.orbitals:
        raise ValueError("occupied must be the OccupiedStates of this flake (from occupied_states).")
    n = len(geo.z)
    s = np.arange(n) if sites is None else _validate.site_indices("sites", sites, n)
    r = 4 * geo.bond if radius is None else _validate.real("radius", radius, minimum=0.0, maximum=1e3)
    return np.array([_local_kitaev(geo, occupied.vectors, occupied.orbitals, geo.z[i], r) for i in s])


# ----------------------------------------------------------------------------
# the flake result
# ----------------------------------------------------------------------------

@dataclass(frozen=True, eq=False, kw_only=True)
class FlakeTopology(Result):
    r"""Chern invariants of a flake, all in the Bianco–Resta sign convention.

    Attributes
    ----------
    model : str
        The model.
    parameters : dict
        Its parameters (M, t2, phi, rashba, flux, disorder, seed, fermi, radius).
    sites : int
        Sites of the flake.
    marker : float
        The hyperbolic local marker averaged over ring 1 (the centre). For Kane–Mele, the spin
        Chern number :math:`(C_\uparrow - C_\downarrow)/2` of the :math:`P s_z P` halves
        (Prodan, PRB 80, 125327 (2009)); likewise ``kitaev`` and ``bott``.
    rings : ndarray of int, shape (R,)
        Ring index.
    marker_by_ring : ndarray, shape (R,)
        The local marker averaged over the sites evaluated on each ring.
    sites_by_ring : ndarray of int, shape (R,)
        How many sites of each ring were evaluated (all of ring 1, then up to ``per_ring``).
    flat_by_ring : ndarray, shape (R,)
        The flat Bianco–Resta marker (disk coordinates) averaged over the same sites.
    recentred_by_ring : ndarray, shape (R,)
        The Bianco–Resta marker in the chart recentred at each evaluated site.
    kitaev : float
        Kitaev's sum centred at the flake's centre (radius ``kitaev_radius``).
    kitaev_radius : float
        Its radius in the metric.
    bott : float
        The Bott index (an integer up to rounding).
    bott_margin : float
        Distance of the spectrum of :math:`\tilde V\tilde U\tilde V^\dagger\tilde U^\dagger` from -1.
    bott_reliable : bool
        ``bott_margin >= 0.05`` and the index is the same with one occupied state less and one
        more (an edge state in the gap must not move a bulk index).
    gap : float
        Bulk gap of the local DOS at ring 1 around the Fermi level.
    in_gap_states : int
        Eigenstates inside that gap (edge states).
    in_gap_weight_by_ring : ndarray, shape (R,)
        Mean weight on each ring of the occupied eigenstates inside that gap (sums to 1 over the
        rings): where the edge states live.
    fermi : float
        The Fermi level.
    method : str
        ``"dense"``.
    spin_gap : float or None
        Kane–Mele only: the gap of the spectrum of :math:`P s_z P` on the occupied states where
        it is split into its upper and lower halves (2 without Rashba). The spin Chern number
        and the spin Bott index (``marker``, ``kitaev``, ``bott``: Huang and Liu, PRL 121, 126401
        (2018)) are quantised while it is open; below :data:`SPIN_GAP_MIN` a warning says so.
    z2 : int or None
        Kane–Mele only: the spin Chern marker at the centre rounded, mod 2.

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.topology import flake_topology
    >>> top = flake_topology(hl.ring_lattice(8, 3, 3), "qwz", M=1.0)
    >>> top.sites, round(top.marker, 2)
    (200, -0.98)
    """

    COLUMNS = (Column("ring", "rings", "1"), Column("marker", "marker_by_ring", "1"),
               Column("sites_evaluated", "sites_by_ring", "1"), Column("flat_marker", "flat_by_ring", "1"),
               Column("recentred_marker", "recentred_by_ring", "1"),
               Column("in_gap_weight", "in_gap_weight_by_ring", "1"))

    model: str
    parameters: dict
    sites: int
    marker: float
    rings: np.ndarray
    marker_by_ring: np.ndarray
    sites_by_ring: np.ndarray
    flat_by_ring: np.ndarray
    recentred_by_ring: np.ndarray
    kitaev: float
    kitaev_radius: float
    bott: float
    bott_margin: float
    bott_reliable: bool
    gap: float
    in_gap_states: int
    in_gap_weight_by_ring: np.ndarray
    fermi: float
    method: str
    spin_gap: float | None = None
    z2: int | None = None

    def summary(self) -> dict:
        """The CLI's JSON: sites, marker, marker_by_ring, kitaev, bott, gap and the diagnostics (Kane–Mele: z2, spin_bott, spin_gap)."""
        out = {"model": self.model, "sites": self.sites, "marker": self.marker,
               "marker_by_ring": [float(x) for x in self.marker_by_ring], "kitaev": self.kitaev,
               "bott": self.bott, "bott_reliable": self.bott_reliable, "bott_margin": self.bott_margin,
               "gap": self.gap, "in_gap_states": self.in_gap_states, "fermi": self.fermi,
               "flat_marker_centre": float(self.flat_by_ring[0]), "method": self.method,
               "parameters": self.parameters}
        if self.spin_gap is not None:
            out.update(z2=self.z2, spin_bott=self.bott, spin_gap=self.spin_gap)
        return out


def _sample(ring: np.ndarray, per_ring: int) -> np.ndarray:
    out = []
    for r in np.unique(ring):
        idx = np.flatnonzero(ring == r)
        if r == ring.min() or len(idx) <= per_ring:
            out.append(idx)
        else:
            out.append(idx[np.linspace(0, len(idx) - 1, per_ring).round().astype(np.int64)])
    return np.concatenate(out)


def _invariants(geo: _Geometry, V: np.ndarray, d: int, radius: float, per_ring: int, extra=None):
    sites = _sample(geo.ring, per_ring)
    loc = np.array([_local_kitaev(geo, V, d, geo.z[i], radius) for i in sites])
    flat = _flat_marker(geo, V, d, sites, recentred=False)
    rec = _flat_marker(geo, V, d, sites, recentred=True)
    rings = np.unique(geo.ring)
    by = lambda vals: np.array([vals[geo.ring[sites] == r].mean() for r in rings])  # noqa: E731
    count = np.array([np.sum(geo.ring[sites] == r) for r in rings], dtype=np.int64)
    # Kitaev's sum at the centre: the largest disk two bonds inside the nearest boundary site
    centre = complex(geo.z.mean()) if not geo.hyperbolic else 0j
    rmax = geo.distance(centre, geo.z[geo.boundary]).min() if len(geo.boundary) else radius
    kr = max(rmax - 2 * geo.bond, radius)
    kit = _local_kitaev(geo, V, d, centre, kr)
    bott, margin = _bott(geo, V, d)
    stable = True
    if extra is not None and V.shape[1] > 1:
        # one state less and one more (an edge state in the gap, typically): a bulk index must not move
        b_less, _ = _bott(geo, V[:, :-1], d)
        b_more, _ = _bott(geo, np.hstack([V, extra]), d)
        stable = round(b_less) == round(bott) == round(b_more)
    return dict(bott_stable=stable, rings=rings, marker_by_ring=by(loc), sites_by_ring=count, flat_by_ring=by(flat),
                recentred_by_ring=by(rec), kitaev=kit, kitaev_radius=float(kr), bott=bott, bott_margin=margin)


def flake_topology(graph, model: str = "qwz", *, M: float = 1.0, t2: float = 0.2, phi: float = np.pi / 2,
                   rashba: float = 0.0, flux: float = 0.0, disorder: float = 0.0, seed: int = 0,
                   fermi: float | None = None, radius: float | None = None, per_ring: int = 8,
                   frame: str = "chord") -> FlakeTopology:
    r"""Local marker by ring, Kitaev's sum, Bott index and the centre's gap of a model on a flake.

    Parameters
    ----------
    graph : Lattice or PlaneGraph
        An open flake: :func:`~hyperlattice.graph.lattice.ring_lattice` or a Euclidean flake of
        :mod:`hyperlattice.topology.models`.
    model : {"qwz", "haldane", "kane-mele"}
        The model (:func:`~hyperlattice.topology.models.model_terms`).
    M : float, optional
        Mass (QWZ) or sublattice mass (Haldane, Kane–Mele), default 1.
    t2, phi : float, optional
        Haldane / Kane–Mele second-neighbour amplitude and phase (default 0.2, pi/2).
    rashba : float, optional
        Kane–Mele Rashba coupling, default 0.
    flux : float, optional
        Flux quanta per p-gon (ring lattices), default 0.
    disorder : float, optional
        Box disorder width W, default 0.
    seed : int, optional
        Disorder seed.
    fermi : float, optional
        Fermi level; default half filling.
    radius : float, optional
        Radius of the local marker's disk in the metric; default 4 bond lengths.
    per_ring : int, optional
        Sites evaluated per ring beyond ring 1 (evenly spread; all of ring 1), default 8.
    frame : {"chord", "tangent", "transport"}, optional
        QWZ / Rashba bond angles (:func:`~hyperlattice.topology.models.model_terms`).

    Returns
    -------
    FlakeTopology

    Raises
    ------
    ValueError
        Unknown model, non-finite parameters, a Fermi level outside the spectrum, a flake too
        big for dense diagonalisation.

    Warns
    -----
    UserWarning
        When the Bott index is unreliable (its unitary product reaches within 0.5 of -1).

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.topology.models import square_flake
    >>> from hyperlattice.topology import flake_topology
    >>> top = flake_topology(square_flake(12), "qwz", M=1.0)
    >>> round(top.marker, 2), round(top.kitaev, 2), round(top.bott)
    (-1.0, -1.0, -1)
    """
    from ..graph.solvers import single_threaded_blas

    with single_threaded_blas():   # one thread: measured 6x faster dense eigh on the shared 2-core machine
        return _flake_topology(graph, model, M=M, t2=t2, phi=phi, rashba=rashba, flux=flux, disorder=disorder,
                               seed=seed, fermi=fermi, radius=radius, per_ring=per_ring, frame=frame)


def _flake_topology(graph, model, *, M, t2, phi, rashba, flux, disorder, seed, fermi, radius, per_ring, frame):
    model = _validate.choice("model", model, MODELS)
    per_ring = _validate.integer("per_ring", per_ring, minimum=1, maximum=100_000)
    geo = _geometry(graph)
    r = 4 * geo.bond if radius is None else _validate.real("radius", radius, minimum=1e-3, maximum=1e3)
    occ = occupied_states(graph, model, M=M, t2=t2, phi=phi, rashba=rashba, flux=flux, disorder=disorder,
                          seed=seed, fermi=fermi, frame=frame)
    d = occ.orbitals
    V = occ.vectors
    if model == "kane-mele":
        # split the occupied space by the sign of P s_z P (Prodan's spin Chern number)
        sz = spin_operator(model, len(geo.z))
        S = V.conj().T @ (sz @ V)
        ev, U = np.linalg.eigh(0.5 * (S + S.conj().T))
        half = len(ev) // 2
        spin_gap = float(ev[half] - ev[half - 1]) if 0 < half < len(ev) else 0.0
        if spin_gap < SPIN_GAP_MIN:
            warnings.warn(f"the spectrum of P s_z P has a gap of only {spin_gap:.2g} where it is split: the spin "
                          "Chern marker and the spin Bott index are not protected (Rashba mixes the spins too "
                          "much); the Z2 index of a closed surface (z2_index) does not need s_z.", stacklevel=3)
        up, dn = V @ U[:, half:], V @ U[:, :half]
        a, b = _invariants(geo, up, d, r, per_ring), _invariants(geo, dn, d, r, per_ring)
        keep = ("rings", "sites_by_ring", "kitaev_radius")
        inv = {k: a[k] if k in keep else 0.5 * (a[k] - b[k]) for k in a}
        inv["bott_margin"] = min(a["bott_margin"], b["bott_margin"])
        inv["bott_stable"] = a["bott_stable"] and b["bott_stable"]
    else:
        spin_gap = None
        inv = _invariants(geo, V, d, r, per_ring, occ.first_empty)
    gap, inside, lo = _centre_gap(occ)
    edge_weight = _edge_weight(geo, occ, lo, inv["rings"])
    reliable = bool(inv["bott_margin"] >= BOTT_MARGIN and inv["bott_stable"])
    if not reliable:
        why = ("it changes when one state is added to or removed from the occupied ones"
               if not inv["bott_stable"] else
               f"its unitary product has an eigenvalue within {inv['bott_margin']:.2g} of -1")
        warnings.warn(f"the Bott index is unreliable: {why} ({inside} states inside the centre's gap: edge "
                      "states at the Fermi level make the projector non-local); trust the local marker.",
                      stacklevel=3)
    params = dict(M=M, t2=t2, phi=phi, rashba=rashba, flux=flux, disorder=disorder, seed=seed,
                  radius=float(r), per_ring=per_ring, frame=frame)
    return FlakeTopology(model=model, parameters=params, sites=len(geo.z),
                         marker=float(inv["marker_by_ring"][0]), rings=inv["rings"],
                         marker_by_ring=inv["marker_by_ring"], sites_by_ring=inv["sites_by_ring"],
                         flat_by_ring=inv["flat_by_ring"], recentred_by_ring=inv["recentred_by_ring"],
                         kitaev=float(inv["kitaev"]), kitaev_radius=float(inv["kitaev_radius"]),
                         bott=float(inv["bott"]), bott_margin=float(inv["bott_margin"]), bott_reliable=reliable,
                         gap=gap, in_gap_states=inside, in_gap_weight_by_ring=edge_weight, fermi=occ.fermi,
                         method="dense", spin_gap=spin_gap,
                         z2=None if spin_gap is None else int(round(float(inv["marker_by_ring"][0]))) % 2)




# ----------------------------------------------------------------------------
# edge states: where they are and which way they run
# ----------------------------------------------------------------------------

@dataclass(frozen=True, eq=False, kw_only=True)
class EdgeChirality(Result):
    r"""The direction of an edge wave packet built from the states inside the centre's gap.

    A packet is put on the boundary sites around the one nearest the positive real axis (a
    Gaussian of width ``width`` bond lengths, plain or staggered by the sublattice sign, with the
    orbital spinor among six fixed ones: the combination the in-gap states keep best), projected on the eigenstates inside the bulk gap at the centre, and
    evolved exactly in that basis. ``angle`` is the circular mean of the polar angle of :math:`|\psi_i(t)|^2` (unwrapped);
    ``chirality`` is +1 when it grows (counterclockwise), -1 when it decreases, 0 when there is
    no in-gap state.

    Attributes
    ----------
    model : str
        The model.
    parameters : dict
        Its parameters.
    times : ndarray, shape (T,)
        Times (units of 1/t).
    angle : ndarray, shape (T,)
        Mean polar angle of the packet (radians, unwrapped, 0 at t = 0).
    chirality : int
        Sign of the final angle (+1 counterclockwise, -1 clockwise, 0 without in-gap states).
    in_gap_states : int
        Eigenstates in the bulk gap at the centre that the packet is made of.
    packet_weight : float
        Weight of the initial packet kept by the projection.

    Examples
    --------
    >>> from hyperlattice.topology import edge_chirality, square_flake
    >>> edge_chirality(square_flake(10), "qwz", M=1.0).chirality
    1
    """

    COLUMNS = (Column("time", "times", "1/t"), Column("angle", "angle", "rad"))

    model: str
    parameters: dict
    times: np.ndarray
    angle: np.ndarray
    chirality: int
    in_gap_states: int
    packet_weight: float


def edge_chirality(graph, model: str = "qwz", *, M: float = 1.0, t2: float = 0.2, phi: float = np.pi / 2,
                   duration: float = 4.0, steps: int = 41, width: float = 2.0) -> EdgeChirality:
    """Which way the edge states of a flake run (see :class:`EdgeChirality`).

    Parameters
    ----------
    graph : Lattice or PlaneGraph
        An open flake (dense diagonalisation, at most 9,000 rows).
    model : {"qwz", "haldane"}
        The model.
    M, t2, phi : float, optional
        Model parameters.
    duration : float, optional
        Final time (units of 1/t), default 4.
    steps : int, optional
        Number of times sampled, default 41.
    width : float, optional
        Width of the packet along the edge in bond lengths, default 2.

    Returns
    -------
    EdgeChirality
    """
    from ..graph.solvers import single_threaded_blas

    model = _validate.choice("model", model, ("qwz", "haldane"))
    duration = _validate.real("duration", duration, minimum=1e-6, maximum=1e6)
    steps = _validate.integer("steps", steps, minimum=2, maximum=100_000)
    width = _validate.real("width", width, minimum=1e-3, maximum=1e3)
    geo = _geometry(graph)
    terms = model_terms(graph, model, M=M, t2=t2, phi=phi)
    rows = terms.sites * terms.orbitals
    if rows > MAX_DENSE_ROWS:
        raise ValueError(f"dense diagonalisation of {rows:,} rows is refused (at most {MAX_DENSE_ROWS:,}).")
    d = terms.orbitals
    with single_threaded_blas():
        e, v = np.linalg.eigh(model_hamiltonian(terms).toarray())
    occ_n = len(e) // 2
    fermi = 0.5 * (e[occ_n - 1] + e[occ_n])
    ring1 = np.flatnonzero(geo.ring == geo.ring.min())
    w1 = np.sum(np.abs(v[_rows(ring1, d)]) ** 2, axis=0)
    bulk = w1 >= CENTRE_WEIGHT * w1.mean()
    below, above = np.flatnonzero(bulk & (e < fermi)), np.flatnonzero(bulk & (e > fermi))
    times = np.linspace(0.0, duration, steps)
    params = dict(M=M, t2=t2, phi=phi, duration=duration, width=width)
    gap_idx = (np.flatnonzero((e > e[below[-1]]) & (e < e[above[0]]))
               if len(below) and len(above) else np.zeros(0, dtype=np.int64))
    if len(gap_idx) == 0:
        return EdgeChirality(model=model, parameters=params, times=times, angle=np.zeros(steps), chirality=0,
                             in_gap_states=0, packet_weight=0.0)
    centre = 0j if geo.hyperbolic else complex(geo.z.mean())
    w = geo.recentre(centre, geo.z)
    theta = np.angle(w)
    edge = geo.boundary
    start = edge[np.argmin(np.abs(theta[edge]))]
    dist = geo.distance(geo.z[start], geo.z)
    amp = np.exp(-0.5 * (dist / (width * geo.bond)) ** 2)
    amp[np.setdiff1d(np.arange(len(amp)), edge)] = 0.0
    V = v[:, gap_idx]
    # the orbital content of the packet: the spinor (of a few) that the in-gap states keep best
    spinors = [np.ones(1)] if d == 1 else [np.array(s_, dtype=np.complex128) / np.linalg.norm(s_) for s_ in
                                           ([1, 0], [0, 1], [1, 1], [1, -1], [1, 1j], [1, -1j])]
    from .models import _darts

    envelopes = [amp]
    sub = _darts(graph).bipartite_sign
    if sub is not None:      # the staggered envelope: edge states near momentum pi (square QWZ at M > 0)
        envelopes.append(amp * sub)
    best = None
    for sp_, env in ((a_, b_) for a_ in spinors for b_ in envelopes):
        psi0 = (env[:, None] * sp_[None, :]).ravel()
        psi0 = psi0 / np.linalg.norm(psi0)
        c_try = V.conj().T @ psi0
        kept_try = float(np.vdot(c_try, c_try).real)
        if best is None or kept_try > best[1] * (1 + 1e-9):
            best = (c_try, kept_try)
    c, kept = best
    psi_t = V @ (np.exp(-1j * np.outer(e[gap_idx], times)) * c[:, None])     # (rows, T)
    dens = (np.abs(psi_t) ** 2).reshape(len(geo.z), d, steps).sum(axis=1)
    mean = np.unwrap(np.angle((np.exp(1j * theta)[:, None] * dens).sum(axis=0)))
    angle = mean - mean[0]
    # a drift below the rounding of the angle is no drift (ties reported as 0)
    tol = 1e3 * np.finfo(float).eps * len(geo.z)
    chir = int(np.sign(angle[-1])) if abs(angle[-1]) > tol else 0
    return EdgeChirality(model=model, parameters=params, times=times, angle=angle, chirality=chir,
                         in_gap_states=len(gap_idx), packet_weight=kept)


from .._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
