r"""The p-fold rotation as a site permutation, and the angular-momentum sectors of H.

The rotation :math:`R: z \mapsto e^{2\pi i/p} z` maps the lattice onto itself and acts freely
on its sites (no site is fixed by any power :math:`R^s`, :math:`0 < s < p`), so the sites fall
into :math:`N/p` orbits of exactly p sites each. A state of angular momentum m obeys

.. math:: \psi(R^s i) = \omega^{m s}\, \psi(i), \qquad \omega = e^{2\pi i/p},

the lattice counterpart of :math:`e^{i m \phi}` in the continuum (paper, Eqs. ``spec1`` and
``spec2``). Writing :math:`\psi(R^s r_o) = \omega^{m s} \phi_o / \sqrt{p}` for the orbit
representatives :math:`r_o`, the rotation-invariant Hamiltonian :math:`H = -tA + V` becomes
the :math:`N/p \times N/p` Bloch block

.. math:: (H_m)_{o o'} = V_{r_o}\delta_{o o'} - t \sum_{j \sim r_o,\; j = R^{s_j} r_{o'}} \omega^{m s_j},

built here directly from the edge list (never from a dense projector). :math:`H_m` is real
symmetric for m = 0 and m = p/2 and complex Hermitian otherwise, with
:math:`H_{-m} = \overline{H_m}` because H is real: sectors m and p - m (= -m) are degenerate.
Sector labels are signed, :math:`m \in (-p/2, p/2]`.

With a uniform magnetic field (``flux=f``, :mod:`hyperlattice.graph.flux`) the Peierls phases
are in a rotation-invariant gauge, :math:`\theta_{R i, R j} = \theta_{ij}`, so the same blocks
exist with every hop weighted by :math:`e^{i\theta_{ij}}` on top of its Bloch phase. H is then
complex: every block is complex Hermitian, :math:`H_{-m} \ne \overline{H_m}`, and all p
sectors are distinct (no +-m degeneracy).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from .. import _validate
from .flux import _flux, edge_phases
from .lattice import Lattice
from .operators import OnSite, SectorTable, _fixed_width, _real_onsite

__all__ = [
    "RotationOrbits",
    "rotation_orbits",
    "signed_sector",
    "rotation_invariant",
    "sector_table",
    "sector_hamiltonian",
    "lift",
]


@dataclass(frozen=True, eq=False)
class RotationOrbits:
    """Orbits of the p-fold rotation on the sites of a lattice.

    Attributes
    ----------
    p : int
        Order of the rotation.
    representatives : ndarray of int64, shape (N/p,)
        One site per orbit (the smallest site index of the orbit, i.e. its sector-0 site).
    orbit : ndarray of int64, shape (N,)
        Orbit index of every site.
    shift : ndarray of int64, shape (N,)
        The power s with ``site == R^s(representatives[orbit[site]])``.

    Notes
    -----
    Site indices are the lattice's (0-based, ring by ring); R is the rotation
    :math:`z \\mapsto e^{2\\pi i/p} z` (``lattice.rotation``).

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.graph.symmetry import rotation_orbits
    >>> orb = rotation_orbits(hl.ring_lattice(7, 3, 2))
    >>> orb.size, orb.representatives.tolist()
    (5, [0, 7, 8, 9, 10])
    >>> orb.orbit[:8].tolist(), orb.shift[:8].tolist()    # ring 1 is one orbit
    ([0, 0, 0, 0, 0, 0, 0, 1], [0, 1, 2, 3, 4, 5, 6, 0])
    """

    p: int
    representatives: np.ndarray
    orbit: np.ndarray
    shift: np.ndarray

    @property
    def size(self) -> int:
        """Number of orbits N/p (the dimension of every sector block)."""
        return int(self.representatives.shape[0])


def rotation_orbits(lattice: Lattice) -> RotationOrbits:
    """Split the sites into orbits of the p-fold rotation ``lattice.rotation``.

    Works from the permutation itself (not from an assumed site layout), so it serves the
    line graph as well. Cost O(pN) in vectorised numpy.

    Parameters
    ----------
    lattice : Lattice
        Site lattice or line graph; its rotation must act freely.

    Returns
    -------
    RotationOrbits
        ``p``, ``representatives`` (N/p,) the smallest site of each orbit, ``orbit`` (N,) the
        orbit index of every site, ``shift`` (N,) the power s with
        ``site == R^s(representatives[orbit[site]])``, and ``size`` = N/p.

    Raises
    ------
    ValueError
        If the permutation is not of order p or fixes a site under some power
        :math:`R^s`, 0 < s < p (then the sector blocks would not all have size N/p).

    See Also
    --------
    sector_hamiltonian, lift

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.graph.symmetry import rotation_orbits
    >>> orbits = rotation_orbits(hl.ring_lattice(7, 3, 2))
    >>> orbits.size, orbits.representatives.tolist()
    (5, [0, 7, 8, 9, 10])
    >>> orbits.shift[:9].tolist()
    [0, 1, 2, 3, 4, 5, 6, 0, 0]
    """
    _validate.lattice(lattice)
    p = int(lattice.p)
    n = lattice.sites
    rot = np.asarray(lattice.rotation, dtype=np.int64)
    if rot.shape != (n,) or n % p:
        raise ValueError(f"the lattice rotation is not a permutation of its {n} sites into orbits of size {p}.")
    status, reps, orbit, shift = _orbit_kernel()(rot, p)
    if 0 < status < p:
        raise ValueError(f"the rotation fixes a site after {status} of {p} steps: it does not act freely.")
    if status:
        raise ValueError(f"the lattice rotation is not of order p = {p}.")
    return RotationOrbits(p=p, representatives=reps, orbit=orbit, shift=shift)


_KERNELS: dict = {}


def _orbit_kernel():
    """Numba pass over the cycles of the rotation: orbits, shifts and representatives in one sweep.

    Returns ``(status, reps, orbit, shift)``: status 0 when every cycle has exactly p sites,
    else the smallest cycle length below p (a power R^s, s < p, fixes a site), or p when a cycle
    is longer than p or the map is not a permutation. Site i opens an orbit when no smaller site
    reached it, so representatives are the smallest sites of their orbits, in increasing order.
    """
    if "orbits" in _KERNELS:
        return _KERNELS["orbits"]
    import numba

    @numba.njit(cache=True)
    def walk(rot, p):                          # pragma: no cover - compiled
        n = rot.shape[0]
        k = n // p
        orbit = np.full(n, -1, np.int64)
        shift = np.zeros(n, np.int64)
        reps = np.empty(k, np.int64)
        count = 0
        short = p
        broken = False
        for i in range(n):
            if orbit[i] >= 0:
                continue
            label = count if count < k else 0      # beyond k orbits only the cycle lengths matter
            j = i
            for s in range(p + 1):
                if s > 0 and j == i:
                    short = min(short, s)          # a cycle of s sites (s = p: as it should be)
                    break
                if s == p or j < 0 or j >= n or orbit[j] >= 0:
                    broken = True                  # longer than p, or not a permutation
                    break
                orbit[j] = label
                shift[j] = s
                j = rot[j]
            if count < k:
                reps[count] = i
            count += 1
        if short < p:
            return short, reps, orbit, shift
        if broken or count != k:
            return p, reps, orbit, shift
        return 0, reps, orbit, shift

    _KERNELS["orbits"] = walk
    return walk


def _check_orbits(orbits, lattice: Lattice | None = None) -> None:
    if not isinstance(orbits, RotationOrbits):
        raise ValueError(f"orbits must come from rotation_orbits(lattice), got {type(orbits).__name__}.")
    if lattice is not None and (orbits.p != lattice.p or orbits.orbit.shape[0] != lattice.sites):
        raise ValueError("orbits belong to a different lattice (call rotation_orbits on this one).")


def signed_sector(m, p: int) -> int:
    r"""Normalise a sector label to the signed form ``m in (-p/2, p/2]``.

    Accepts ``0 <= m < p`` (Bloch phase :math:`e^{2\pi i m/p}`) or an already signed value
    ``-p/2 < m <= p/2``; sector p - m is reported as -m.

    Parameters
    ----------
    m : int
        The sector (angular momentum) label.
    p : int
        Order of the rotation, p >= 3.

    Returns
    -------
    int
        The signed sector in :math:`(-p/2, p/2]`.

    Raises
    ------
    ValueError
        If m is neither in ``range(p)`` nor a signed value in :math:`(-p/2, p/2]`.

    Examples
    --------
    >>> from hyperlattice.graph.symmetry import signed_sector
    >>> signed_sector(6, 7), signed_sector(-3, 7), signed_sector(3, 6)
    (-1, -3, 3)
    """
    p = _validate.integer("p", p, minimum=3, maximum=_validate.PQ_MAX)
    m = _validate.integer("sector m", m)
    if not (-p / 2 < m < p):
        raise ValueError(
            f"sector m must be in range(p) = 0..{p - 1} or a signed value in ({-p / 2:g}, {p / 2:g}], got {m}.")
    m %= p
    return m - p if m > p / 2 else m


def rotation_invariant(lattice: Lattice, onsite: OnSite = None) -> bool:
    r"""True if the on-site term is invariant under the p-fold rotation (to 1e-12 relative).

    Parameters
    ----------
    lattice : Lattice
        Site lattice or line graph.
    onsite : scalar, array or callable ``(z, ring) -> array``, optional
        The on-site term V (see :func:`~hyperlattice.graph.operators.onsite_values`); None
        (default) is invariant.

    Returns
    -------
    bool
        Whether :math:`V_{R(i)} = V_i` for every site to within
        :math:`10^{-12}\max(1, \max|V|)`.

    Raises
    ------
    ValueError
        For an invalid lattice or on-site term.

    See Also
    --------
    sector_hamiltonian

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.graph.symmetry import rotation_invariant
    >>> lat = hl.ring_lattice(7, 3, 2)
    >>> rotation_invariant(lat, lambda z, ring: 1.0 * ring), rotation_invariant(lat, lambda z, ring: z.real)
    (True, False)
    """
    _validate.lattice(lattice)
    v = _real_onsite(lattice, onsite)
    if v is None:
        return True
    scale = max(1.0, float(np.max(np.abs(v))))
    return bool(np.max(np.abs(v[lattice.rotation] - v)) <= 1e-12 * scale)


def sector_table(lattice: Lattice, m: int, t: float = 1.0, onsite: OnSite = None, *,
                 orbits: RotationOrbits | None = None, flux: float = 0.0) -> SectorTable:
    """The Bloch block :math:`H_m` as a fixed-width table over the orbit representatives.

    Parameters
    ----------
    lattice : Lattice
        Site lattice or line graph; its rotation must act freely.
    m : int
        Sector, signed or in ``range(p)`` (see :func:`signed_sector`).
    t : float, optional
        Hopping amplitude, the energy unit; default 1.
    onsite : scalar, array or callable, optional
        Rotation-invariant on-site term in units of t (checked); default None.
    orbits : RotationOrbits, optional
        Precomputed orbits (saves O(pN) when several sectors are built).
    flux : float, optional
        Flux quanta per p-gon of a uniform field (:mod:`hyperlattice.graph.flux`); the block
        is complex for any nonzero flux. Default 0.

    Returns
    -------
    SectorTable
        ``m`` (signed), ``cols`` and ``weights`` (N/p, width) and ``diag`` (N/p,);
        ``to_csr()`` gives the block as a sparse matrix.

    Raises
    ------
    ValueError
        For an invalid sector, t or flux, orbits of another lattice, or an on-site term that
        is not rotation invariant.

    See Also
    --------
    sector_hamiltonian

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.graph.symmetry import sector_table
    >>> table = sector_table(hl.ring_lattice(7, 3, 2), 1)
    >>> table.m, table.cols.shape, table.is_complex
    (1, (5, 3), True)
    """
    _validate.lattice(lattice)
    p = int(lattice.p)
    m = signed_sector(m, p)
    t = _validate.real("the hopping t", t)
    flux = _flux(flux)
    if orbits is None:
        orbits = rotation_orbits(lattice)
    else:
        _check_orbits(orbits, lattice)
    v = _real_onsite(lattice, onsite)
    if v is not None and not rotation_invariant(lattice, v):
        raise ValueError("the on-site term is not invariant under the p-fold rotation, so H has no "
                         "angular-momentum sectors; use method='dense' or 'sparse'.")
    return _table(lattice, m, t, v, orbits, edge_phases(lattice, flux) if flux != 0.0 else None)


def _table(lattice: Lattice, m: int, t: float, v: np.ndarray | None, orbits: RotationOrbits,
           theta: np.ndarray | None) -> SectorTable:
    """The block H_m (m signed) from checked input: on-site values v (or None), Peierls phases theta (or None)."""
    p = int(lattice.p)
    orbit, shift = orbits.orbit, orbits.shift
    e = lattice.edges.astype(np.int64)
    i, j = e[:, 0], e[:, 1]
    # only edges touching a representative are needed: the other p-1 copies of each edge orbit
    # carry the same relative phase and are accounted for by the Bloch ansatz itself.
    a = shift[i] == 0
    b = shift[j] == 0
    rows = np.concatenate([orbit[i[a]], orbit[j[b]]])
    cols = np.concatenate([orbit[j[a]], orbit[i[b]]])
    s = np.concatenate([shift[j[a]], shift[i[b]]])
    if theta is not None:
        # row i (a representative) hops from j with theta_ij; the rows of the reversed edges
        # (j a representative) get theta_ji = -theta_ij. The gauge is rotation invariant, so
        # the phase of the representative's copy of the edge is that of every copy.
        phase = np.concatenate([theta[a], -theta[b]])
        vals = -t * np.exp(1j * (2 * np.pi * ((m * s) % p) / p + phase))
    elif 2 * m % p == 0:
        # m = 0 or p/2: the phases are +-1, keep the block real (half the work of complex)
        vals = -t * np.where(s % 2 == 0, 1.0, -1.0) if m else np.full(s.shape[0], -t)
    else:
        vals = -t * np.exp(2j * np.pi * ((m * s) % p) / p)
    tc, tv = _fixed_width(orbits.size, rows, cols, vals)
    diag = np.zeros(orbits.size) if v is None else v[orbits.representatives].copy()
    return SectorTable(m=m, cols=tc, weights=tv, diag=diag)


@dataclass(frozen=True, eq=False)
class _SectorBlocks:
    """The Bloch blocks of a built lattice that one request needs, built together by :func:`_sector_blocks`.

    Attributes
    ----------
    orbits : RotationOrbits
        The orbits of the rotation (for lifting sector vectors).
    size : int
        N/p, the dimension of every block.
    tables : dict
        Signed sector m -> :class:`~hyperlattice.graph.operators.SectorTable` of :math:`H_m`.
    """

    orbits: RotationOrbits
    size: int
    tables: dict


def _sector_blocks(lattice: Lattice, ms, t: float, onsite: OnSite = None, *, flux: float = 0.0) -> _SectorBlocks:
    """Every block H_m, m in ``ms``, of a built lattice in one call: the orbits, the on-site values and the
    Peierls phases are computed once for all of them (the block builder of the routes in graph/spectrum).

    The caller has validated t and flux and checked that V is rotation invariant (:func:`rotation_invariant`).
    """
    orbits = rotation_orbits(lattice)
    v = _real_onsite(lattice, onsite)
    theta = edge_phases(lattice, flux) if flux != 0.0 else None
    p = int(lattice.p)
    tables = {}
    for m in ms:
        m = signed_sector(m, p)
        tables[m] = _table(lattice, m, t, v, orbits, theta)
    return _SectorBlocks(orbits=orbits, size=orbits.size, tables=tables)


def sector_hamiltonian(lattice: Lattice, m: int, t: float = 1.0, onsite: OnSite = None,
                       flux: float = 0.0) -> sp.csr_matrix:
    r"""The angular-momentum block :math:`H_m` of :math:`H = -tA + V` as CSR.

    With the Bloch ansatz :math:`\psi(R^s r_o) = e^{2\pi i m s/p}\phi_o/\sqrt p` over the
    orbits of the p-fold rotation R, H splits into p blocks of size N/p.

    Parameters
    ----------
    lattice : Lattice
        Site lattice or line graph; its rotation must act freely.
    m : int
        Sector: ``0 <= m < p`` or signed ``-p/2 < m <= p/2`` (Bloch phase :math:`e^{2\pi i m/p}`).
    t : float, optional
        Hopping amplitude (t = 1 in the paper, the default).
    onsite : scalar, array or callable, optional
        On-site term in units of t; must be invariant under the rotation. Default None.
    flux : float, optional
        Flux quanta per p-gon of a uniform field (complex block for any nonzero flux);
        default 0.

    Returns
    -------
    scipy.sparse.csr_matrix, shape (N/p, N/p)
        Without flux real symmetric for m = 0 and m = p/2, complex Hermitian otherwise
        (always complex Hermitian with flux). Row and column o
        belong to the orbit of ``rotation_orbits(lattice).representatives[o]``; the union of
        the spectra over the p sectors is the spectrum of H.

    Raises
    ------
    ValueError
        For an invalid sector, t or flux, a rotation that does not act freely, or an on-site
        term that is not rotation invariant.

    See Also
    --------
    rotation_orbits, lift, hyperlattice.graph.spectrum.lowest_levels

    Examples
    --------
    >>> import numpy as np
    >>> from hyperlattice import ring_lattice
    >>> from hyperlattice.graph.symmetry import sector_hamiltonian
    >>> sector_hamiltonian(ring_lattice(7, 3, 1), 0).toarray().tolist()
    [[-2.0]]
    >>> h1 = sector_hamiltonian(ring_lattice(7, 3, 2), 1)
    >>> h1.shape, h1.dtype, round(float(np.linalg.eigvalsh(h1.toarray())[0]), 6)
    ((5, 5), dtype('complex128'), -2.283335)
    """
    return sector_table(lattice, m, t, onsite, flux=flux).to_csr()


def lift(orbits: RotationOrbits, m: int, phi: np.ndarray) -> np.ndarray:
    r"""Lift sector vectors :math:`\phi` (shape (N/p,) or (N/p, k)) to full-lattice vectors.

    :math:`\psi(R^s r_o) = \omega^{m s}\phi_o/\sqrt{p}` with :math:`\omega = e^{2\pi i/p}`, so a
    normalised :math:`\phi` gives a normalised :math:`\psi`; it is an eigenvector of H when
    :math:`\phi` is one of :math:`H_m`.

    Parameters
    ----------
    orbits : RotationOrbits
        From :func:`rotation_orbits` of the lattice.
    m : int
        The sector of :math:`\phi`, signed or in ``range(p)``.
    phi : array_like, shape (N/p,) or (N/p, k)
        Sector vector(s), one row per orbit.

    Returns
    -------
    numpy.ndarray, shape (N,) or (N, k)
        The lattice vectors (0-based site order); real for real :math:`\phi` in sectors 0 and
        p/2, complex otherwise.

    Raises
    ------
    ValueError
        If ``orbits`` is not a RotationOrbits, m is not a sector, or ``phi`` has not one row
        per orbit.

    See Also
    --------
    rotation_orbits, sector_hamiltonian

    Examples
    --------
    >>> import numpy as np
    >>> import hyperlattice as hl
    >>> from hyperlattice.graph.symmetry import lift, rotation_orbits
    >>> lat = hl.ring_lattice(7, 3, 2)
    >>> e, v = np.linalg.eigh(hl.sector_hamiltonian(lat, 1).toarray())
    >>> psi = lift(rotation_orbits(lat), 1, v[:, 0])
    >>> psi.shape, round(float(np.linalg.norm(psi)), 6)
    ((35,), 1.0)
    >>> bool(np.linalg.norm(hl.hamiltonian(lat) @ psi - e[0] * psi) < 1e-12)
    True
    """
    _check_orbits(orbits)
    p = orbits.p
    m = signed_sector(m, p)
    try:
        kind = np.asarray(phi).dtype.kind
    except (TypeError, ValueError):
        kind = "c"  # ragged or odd input: let the validator word the error
    # real vectors stay real (sectors 0 and p/2 have real phases)
    phi = (_validate.real_array if kind in "biuf" else _validate.complex_array)("phi", phi, ndim=(1, 2))
    if phi.shape[0] != orbits.size:
        raise ValueError(f"phi must have one row per orbit ({orbits.size}), got shape {phi.shape}.")
    phase = np.exp(2j * np.pi * ((m * orbits.shift) % p) / p) / np.sqrt(p)
    if 2 * m % p == 0:
        phase = phase.real
    out = phi[orbits.orbit]
    return out * (phase[:, None] if out.ndim == 2 else phase)


def _lift_columns(orbits: RotationOrbits, ms, phis) -> np.ndarray:
    """The lattice states of sector vectors ``phis[k]`` of sectors ``ms[k]``, as the columns of one array
    (complex when any is)."""
    cols = [lift(orbits, m, phi) for m, phi in zip(ms, phis)]
    if any(np.iscomplexobj(c) for c in cols):
        cols = [c.astype(np.complex128) for c in cols]
    return np.column_stack(cols)


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
