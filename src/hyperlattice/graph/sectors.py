r"""Sector-only construction of big {p,q} flakes: one site per rotation orbit, never the full lattice.

The p-fold rotation :math:`R` acts freely on the sites of :func:`~hyperlattice.graph.lattice.ring_lattice`,
and the ring-by-ring construction is exactly p-periodic: ring k is p copies of one angular
sector of :math:`n_k/p` sites. :func:`sector_lattice` therefore runs the layer step of the
builder on one sector only, with periodic wrap-around, and records each edge orbit once, as
a pair (orbit, shift) per end. That is all the angular-momentum blocks need
(:mod:`hyperlattice.graph.symmetry`): p times less arithmetic and memory than building the
lattice first.

Site labels, orbit order and the rotation are those of :func:`ring_lattice` (the same roll of
each ring to start at the smallest polar angle :math:`\ge 0`), so :func:`sector_block` of a
:class:`SectorLattice` is the same matrix as :func:`~hyperlattice.graph.symmetry.sector_hamiltonian`
of the full lattice, entry for entry (tested).

The mirror :math:`z \mapsto \bar z` (through the vertex of ring 1 on the positive real axis) is a
symmetry too. It maps sector m onto -m; combined with complex conjugation it is an antiunitary
involution of :math:`H_m`, so every block has a real form of the same size
(:func:`sector_block` with ``mirror="real"``), and for m = 0 it splits the block into a
mirror-even and a mirror-odd half (``mirror="even"`` / ``"odd"``). The ground state (positive,
Perron-Frobenius) lies in the even half of m = 0.

:func:`lowest_pair` computes :math:`E_0` and :math:`E_1` from these real blocks by shift-invert
Lanczos and proves that no other level lies below :math:`E_1` by Sylvester's law of inertia
(a symmetric :math:`LDL^T` factorisation of every block shifted to just below :math:`E_1`
counts its eigenvalues below the shift).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from .. import _validate
from .. import geometry
from ..errors import ConvergenceError
from .lattice import _check_pq, _available_memory, _layer_topology, _type_counts  # noqa: F401

__all__ = ["SectorLattice", "sector_lattice", "sector_block", "lowest_pair", "flake_memory"]

#: Peak bytes per *site of the full lattice* while building a :class:`SectorLattice` and solving
#: for E0, E1 (measured peak RSS, with margin); the full lattice needs about 400.
_BYTES_PER_SITE_SECTORS = 60


@dataclass(frozen=True, eq=False)
class SectorLattice:
    r"""A {p,q} ring lattice stored as its rotation orbits (a compact form of the flake).

    Attributes
    ----------
    p, q, rings : int
    ring_sizes : ndarray of int64, shape (rings,)
        Sites on each ring of the full lattice (p times the orbits of that ring).
    rows, cols : ndarray of int32, shape (D,)
        Directed neighbour entries between orbits: orbit ``rows[e]`` (its representative, shift 0)
        is a neighbour of the site :math:`R^{s}` (representative of ``cols[e]``), ``s = shifts[e]``.
        Each edge orbit appears twice (once from each end), as in the full lattice's sector block.
    shifts : ndarray of int8, shape (D,)
    mirror_orbit : ndarray of int32, shape (N/p,)
        The mirror :math:`\bar z` maps representative o onto :math:`R^{t_o}` (representative of
        ``mirror_orbit[o]``) with ``t_o = mirror_shift[o]``.
    mirror_shift : ndarray of int8, shape (N/p,)
    z : ndarray of complex128, shape (N/p,), or None
        Coordinates of the representatives (the full lattice's site ``i`` of ring k is
        :math:`e^{2\pi i s/p} z_o`), kept when ``coordinates=True``.
    """

    p: int
    q: int
    rings: int
    ring_sizes: np.ndarray
    rows: np.ndarray
    cols: np.ndarray
    shifts: np.ndarray
    mirror_orbit: np.ndarray
    mirror_shift: np.ndarray
    z: np.ndarray | None = None

    @property
    def sites(self) -> int:
        """Sites N of the full lattice."""
        return int(self.ring_sizes.sum())

    @property
    def size(self) -> int:
        """Number of orbits N/p (the dimension of every sector block)."""
        return self.sites // self.p

    @property
    def nbytes(self) -> int:
        """Bytes held by the arrays."""
        arrays = (self.ring_sizes, self.rows, self.cols, self.shifts, self.mirror_orbit, self.mirror_shift)
        return int(sum(a.nbytes for a in arrays) + (0 if self.z is None else self.z.nbytes))

    def __repr__(self) -> str:
        return (f"<SectorLattice {{{self.p},{self.q}}} rings={self.rings} sites={self.sites} "
                f"orbits={self.size}>")


def flake_memory(p: int, q: int, rings: int) -> int:
    """Estimated peak bytes of :func:`lowest_pair` for the ``rings``-ring {p,q} flake (before allocating)."""
    p, q = _check_pq(p, q)
    rings = _validate.positive_int("rings", rings)
    counts, _ = _type_counts(p, q, rings, stop_above=2**62)
    return int(sum(counts) * _BYTES_PER_SITE_SECTORS)


def _check_flake_size(p: int, q: int, rings: int, max_bytes) -> int:
    """Full-lattice site count, or ValueError when the sector build will not fit."""
    limit = _available_memory() if max_bytes is None else _validate.positive_int("max_bytes", max_bytes)
    per_site = _BYTES_PER_SITE_SECTORS
    counts, _ = _type_counts(p, q, rings, stop_above=max(limit // per_site, 1))
    n = sum(counts)
    # orbit ids are 32-bit: N/p < 2**31
    if len(counts) < rings or n * per_site > limit or n // p >= 2**31 - 1:
        more = "" if len(counts) == rings else "more than "
        raise ValueError(f"the sector build of the {{{p},{q}}} flake with {rings:,} rings has {more}{n:,} sites "
                         f"and needs {more}about {n * per_site / 1024**3:.1f} GB, more than the "
                         f"{limit / 1024**3:.1f} GB {'available' if max_bytes is None else 'allowed by max_bytes'}.")
    return n


def _sector_topology(spokes: np.ndarray, p: int, q: int):
    """The layer step of :func:`~hyperlattice.graph.lattice._layer_topology` on one angular sector.

    ``spokes``: outward spokes of the first ``nb`` (= n_ring / p) boundary positions in
    construction order; the boundary is p-periodic, so position ``nb + i`` is a rotated copy of
    ``i``. Returns (owner, k, m_sub, spoke_slot, mid_poly, mid_t, mid_slot, poly_count) for the
    spokes and new sites of the first sector, with the last spoke's neighbour taken from the
    next sector (``owner`` has one extra entry, ``nb + owner[0]``; slots may reach ``m_sub``
    when p = 3 merges the last spoke end into the next sector).
    """
    nb = spokes.shape[0]
    owner = np.repeat(np.arange(nb, dtype=np.int64), spokes)
    n_sp = owner.shape[0]
    if n_sp == 0:
        raise RuntimeError("boundary without outward spokes: not a hyperbolic tessellation")
    first = np.zeros(nb, dtype=np.int64)
    np.cumsum(spokes[:-1], out=first[1:])
    k = np.arange(n_sp, dtype=np.int64) - first[owner] + 1
    owner_ext = np.concatenate([owner, owner[:1] + nb])
    k_ext = np.concatenate([k, k[:1]])
    n_old = owner_ext[1:] - owner + 1
    contrib = p - n_old - 1
    if np.any(contrib < 0):
        raise RuntimeError("inconsistent layer combinatorics (polygon with too many old vertices)")
    offsets = np.zeros(n_sp + 1, dtype=np.int64)
    np.cumsum(contrib, out=offsets[1:])
    m_sub = int(offsets[-1])
    spoke_slot = offsets            # n_sp + 1 entries: the extra one is m_sub + offsets[0]
    r = np.maximum(contrib - 1, 0)
    mid_poly = np.repeat(np.arange(n_sp, dtype=np.int64), r)
    mstart = np.zeros(n_sp, dtype=np.int64)
    np.cumsum(r[:-1], out=mstart[1:])
    mid_t = np.arange(mid_poly.shape[0], dtype=np.int64) - mstart[mid_poly] + 1
    mid_slot = offsets[mid_poly] + contrib[mid_poly] - mid_t
    distinct = contrib != 0
    poly_count = np.bincount(spoke_slot[:-1] % m_sub, minlength=m_sub)
    poly_count += np.bincount(spoke_slot[1:][distinct] % m_sub, minlength=m_sub)
    poly_count += np.bincount(mid_slot, minlength=m_sub)
    return owner_ext, k_ext, m_sub, spoke_slot, mid_poly, mid_t, mid_slot, poly_count


def _ring_start(zs: np.ndarray, phases: np.ndarray, p: int) -> int:
    """Construction position of the site with the smallest polar angle >= 0 (as ring_lattice rolls).

    The full ring is ``phases[s] * zs[i]`` at position ``s * m + i``; only the copy of each
    sector site whose angle falls near [0, 2 pi / p) can be the first, so three candidate
    copies per site are enough (the angles are evaluated exactly as for the full ring).
    """
    m = zs.shape[0]
    step = 2.0 * math.pi / p
    base = np.floor(-np.angle(zs) / step).astype(np.int64)
    best_ang, best_pos = np.inf, 0
    for d in (-1, 0, 1):
        s = np.mod(base + d, p)
        ang = np.angle(phases[s] * zs)
        ang = np.where(ang < -1e-12, ang + 2 * math.pi, np.maximum(ang, 0.0))
        pos = s * m + np.arange(m)
        # argmin over the ring in position order: the smallest angle, ties to the first position
        key = np.lexsort((pos, ang))[0]
        if ang[key] < best_ang or (ang[key] == best_ang and pos[key] < best_pos):
            best_ang, best_pos = float(ang[key]), int(pos[key])
    return best_pos


def sector_lattice(p: int = 7, q: int = 3, rings: int = 3, *, coordinates: bool = False,
                   max_bytes: int | None = None) -> SectorLattice:
    r"""Build the rotation orbits of the ``rings``-ring {p,q} lattice without the lattice itself.

    Parameters
    ----------
    p, q : int
        Hyperbolic Schläfli symbol.
    rings : int
        Number of rings :math:`\ell \ge 1`.
    coordinates : bool
        Keep the coordinates of the orbit representatives (they are computed anyway, to order
        each ring as :func:`~hyperlattice.graph.lattice.ring_lattice` does).
    max_bytes : int, optional
        Refuse (``ValueError``) before allocating when the estimated peak memory of the build
        and of :func:`lowest_pair` exceeds it; default: the memory available now.

    Returns
    -------
    SectorLattice
        Orbits ordered as the representatives of ``rotation_orbits(ring_lattice(p, q, rings))``.

    Examples
    --------
    >>> s = sector_lattice(7, 3, 3)
    >>> s.sites, s.size
    (112, 16)
    """
    p, q = _check_pq(p, q)
    rings = _validate.positive_int("rings", rings)
    coordinates = _validate.flag("coordinates", coordinates)
    _check_flake_size(p, q, rings, max_bytes)
    theta = 2.0 * math.pi / q
    circumradius = math.atanh(geometry.r0(p, q))
    centre_fraction = circumradius / geometry.d0(p, q)
    phases = np.exp(2j * math.pi * np.arange(p) / p)
    r0 = geometry.r0(p, q)

    sizes = [p]
    starts = [0]
    bases = [0]
    zs_rings = [np.array([r0 * phases[0]])]      # construction-order sector coordinates per ring
    spokes = np.full(1, q - 2, dtype=np.int64)
    # edge orbits as (ring a, construction position a, ring b, position b), per ring
    edge_blocks = [(1, np.zeros(1, dtype=np.int64), 1, np.ones(1, dtype=np.int64))]
    zp = zs_rings[0]
    for level in range(2, rings + 1):
        m_prev = zp.shape[0]
        owner, k, m_sub, spoke_slot, mid_poly, mid_t, mid_slot, poly_count = _sector_topology(spokes, p, q)

        def zb(c):  # coordinates of construction positions c of the previous ring (any integer)
            return phases[(c // m_prev) % p] * zp[c % m_prev]

        ends = geometry._rotate_about(zb(owner - 1), zb(owner), k * theta)
        zs = np.empty(m_sub, dtype=np.complex128)
        n_sp = owner.shape[0] - 1
        first = spoke_slot[:n_sp] < m_sub
        zs[spoke_slot[:n_sp][first]] = ends[:n_sp][first]
        if mid_poly.shape[0]:
            second_end = ends[mid_poly + 1]
            b_pt = zb(owner[mid_poly + 1])
            toward_b = geometry._geodesic_point(second_end, b_pt, centre_fraction)
            centre = geometry._rotate_about(toward_b, second_end, 0.5 * theta)
            zs[mid_slot] = geometry._rotate_about(second_end, centre, -2.0 * math.pi * mid_t / p)
        edge_blocks.append((level - 1, owner[:n_sp], level, spoke_slot[:n_sp]))
        cyc = np.arange(m_sub, dtype=np.int64)
        edge_blocks.append((level, cyc, level, cyc + 1))
        sizes.append(p * m_sub)
        bases.append(bases[-1] + sizes[-2] // p)
        zs_rings.append(zs)
        spokes = q - 1 - poly_count
        zp = zs
    starts = [_ring_start(zs, phases, p) for zs in zs_rings]
    sizes_a = np.array(sizes, dtype=np.int64)
    n_orbits = int(sizes_a.sum()) // p

    def orbit_shift(ring_k, c):
        n = sizes[ring_k - 1]
        m = n // p
        f = np.mod(c - starts[ring_k - 1], n)
        return bases[ring_k - 1] + f % m, f // m

    rows, cols, shifts = [], [], []
    for ka, ca, kb, cb in edge_blocks:
        oa, sa = orbit_shift(ka, ca)
        ob, sb = orbit_shift(kb, cb)
        rows += [oa, ob]
        cols += [ob, oa]
        shifts += [np.mod(sb - sa, p), np.mod(sa - sb, p)]
    del edge_blocks
    rows_a = np.concatenate(rows).astype(np.int32)
    cols_a = np.concatenate(cols).astype(np.int32)
    shifts_a = np.concatenate(shifts).astype(np.int8)
    del rows, cols, shifts
    order = np.argsort(rows_a, kind="stable")
    rows_a, cols_a, shifts_a = rows_a[order], cols_a[order], shifts_a[order]

    # mirror z -> conj(z): reverses each ring; it fixes the first site when that lies on the axis
    mir_o = np.empty(n_orbits, dtype=np.int32)
    mir_s = np.empty(n_orbits, dtype=np.int8)
    z_rep = np.empty(n_orbits, dtype=np.complex128) if coordinates else None
    for idx, zs in enumerate(zs_rings):
        n = sizes[idx]
        m = n // p
        c0 = starts[idx]
        first_z = phases[(c0 // m) % p] * zs[c0 % m]
        on_axis = abs(math.atan2(first_z.imag, first_z.real)) < 1e-9
        r = np.arange(m, dtype=np.int64)
        f = np.mod(-r, n) if on_axis else n - 1 - r
        mir_o[bases[idx]:bases[idx] + m] = bases[idx] + f % m
        mir_s[bases[idx]:bases[idx] + m] = f // m
        if coordinates:
            c = np.mod(r + c0, n)
            z_rep[bases[idx]:bases[idx] + m] = phases[(c // m) % p] * zs[c % m]
    return SectorLattice(p=p, q=q, rings=rings, ring_sizes=sizes_a, rows=rows_a, cols=cols_a, shifts=shifts_a,
                         mirror_orbit=mir_o, mirror_shift=mir_s, z=z_rep)


# ----------------------------------------------------------------------------
# blocks
# ----------------------------------------------------------------------------

_MIRRORS = (None, "real", "even", "odd")


def _check_sector_lattice(slat) -> SectorLattice:
    if not isinstance(slat, SectorLattice):
        raise ValueError(f"expected a SectorLattice from sector_lattice(), got {type(slat).__name__}.")
    return slat


def mirror_basis(slat: SectorLattice, m: int, mirror: str):
    """The real basis of a block: for each orbit o its (up to two) basis indices and coefficients.

    Returns ``(idx, coef, dim)``: orbit o is ``sum_j coef[j, o] * w_{idx[j, o]}`` in terms of the
    basis vectors w of the even/odd half (m = 0) or of the real form (m != 0) after the gauge
    ``g_o = exp(-i pi m t_o / p)``; coefficient 0 marks an unused slot.
    """
    p = slat.p
    o = np.arange(slat.size, dtype=np.int64)
    mu = slat.mirror_orbit.astype(np.int64)
    fixed = mu == o
    lead = o <= mu                   # one class per {o, mu(o)}, labelled by its smaller orbit
    pair_lead = lead & ~fixed
    if mirror in ("even", "odd"):
        keep = lead if mirror == "even" else pair_lead
        pos = np.cumsum(keep) - 1
        cls = np.minimum(o, mu)
        idx = np.stack([pos[cls], pos[cls]])
        coef = np.zeros((2, slat.size))
        s = math.sqrt(0.5)
        if mirror == "even":
            coef[0] = np.where(fixed, 1.0, s)
        else:   # e_o - e_mu(o), sign + on the smaller orbit
            coef[0] = np.where(fixed, 0.0, np.where(o < mu, s, -s))
        return idx, coef.astype(np.complex128), int(keep.sum())
    # real form of m != 0: w+ = (e_o + e_mu)/sqrt2, w- = i (e_o - e_mu)/sqrt2, fixed: e_o
    width = np.where(fixed, 1, 2)
    start = np.zeros(slat.size, dtype=np.int64)
    cum = np.cumsum(np.where(lead, width, 0))
    start[1:] = cum[:-1]
    cls = np.minimum(o, mu)
    base = start[cls]
    s = math.sqrt(0.5)
    idx = np.stack([base, base + 1])
    coef = np.zeros((2, slat.size), dtype=np.complex128)
    # e_o = (w+ - i w-)/sqrt2 for the smaller orbit, (w+ + i w-)/sqrt2 for the larger
    coef[0] = np.where(fixed, 1.0, s)
    coef[1] = np.where(fixed, 0.0, np.where(o < mu, -1j * s, 1j * s))
    idx[1] = np.where(fixed, base, idx[1])
    return idx, coef, int(cum[-1])


def sector_block(slat: SectorLattice, m: int, *, mirror: str | None = None, t: float = 1.0,
                 shift: float = 0.0) -> sp.csr_matrix:
    r"""The angular-momentum block :math:`H_m - \text{shift}` of :math:`H = -tA`, from a :class:`SectorLattice`.

    Parameters
    ----------
    slat : SectorLattice
    m : int
        Sector, signed or in ``range(p)``.
    mirror : {None, "real", "even", "odd"}
        None: :math:`H_m` in the orbit basis, exactly ``sector_hamiltonian(ring_lattice(...), m)``.
        ``"real"``: an orthogonally equivalent real symmetric form of :math:`H_m` (same size,
        same spectrum). ``"even"`` / ``"odd"`` (m = 0 or p/2 only): the mirror-even / -odd
        half of the (real) block.
    t : float
        Hopping amplitude.
    shift : float
        Subtracted on the diagonal.

    Returns
    -------
    scipy.sparse.csr_matrix
        Sorted indices, duplicates summed; real unless ``mirror`` is None and the block is complex.
    """
    from .symmetry import signed_sector

    slat = _check_sector_lattice(slat)
    p = slat.p
    m = signed_sector(m, p)
    t = _validate.real("the hopping t", t)
    shift = _validate.real("shift", shift)
    mirror = _validate.choice("mirror", mirror, _MIRRORS) if mirror is not None else None
    if mirror in ("even", "odd") and (2 * m) % p:
        raise ValueError("mirror='even'/'odd' splits the blocks m = 0 and m = p/2 only; use mirror='real'.")
    n = slat.size
    s = slat.shifts.astype(np.int64)
    real_phase = (2 * m) % p == 0
    if real_phase:
        vals = -t * (np.where(s % 2 == 0, 1.0, -1.0) if m else np.ones(s.shape[0]))
    else:
        vals = -t * np.exp(2j * np.pi * ((m * s) % p) / p)
    rows = slat.rows
    cols = slat.cols
    if mirror is None:
        mat = sp.csr_matrix((vals, (rows, cols)), shape=(n, n))
        if shift:
            mat = mat - shift * sp.identity(n, format="csr", dtype=mat.dtype)
        mat.sum_duplicates()
        mat.sort_indices()
        return mat
    if m and mirror in ("even", "odd"):
        raise ValueError("mirror='even'/'odd' is implemented for m = 0; use mirror='real' for m = p/2.")
    if mirror in ("even", "odd"):
        idx, coef, dim = mirror_basis(slat, 0, mirror)
        c = coef.real
        ok = c[0] != 0
        # B = W^T H W with one basis vector per orbit (slot 0): entries c_a c_b H_ab
        sel = ok[rows] & ok[cols]
        r_i = idx[0][rows[sel]]
        c_i = idx[0][cols[sel]]
        v = vals[sel] * c[0][rows[sel]] * c[0][cols[sel]]
        mat = sp.csr_matrix((v, (r_i, c_i)), shape=(dim, dim))
    else:
        idx, coef, dim = mirror_basis(slat, m, "real")
        # gauge g_o = exp(-i pi m t_o / p): H~_ab = conj(g_a) H_ab g_b
        tt = slat.mirror_shift.astype(np.int64)
        g = np.exp(-1j * np.pi * m * tt / p)
        v = vals * np.conj(g[rows]) * g[cols]
        parts_r, parts_c, parts_v = [], [], []
        for i in range(2):
            ci = coef[i][rows]
            keep_i = ci != 0
            for j in range(2):
                cj = coef[j][cols]
                keep = keep_i & (cj != 0)
                parts_r.append(idx[i][rows[keep]])
                parts_c.append(idx[j][cols[keep]])
                parts_v.append(np.conj(ci[keep]) * v[keep] * cj[keep])
        r_i = np.concatenate(parts_r)
        c_i = np.concatenate(parts_c)
        vv = np.concatenate(parts_v)
        del parts_r, parts_c, parts_v
        # B = W^H H~ W is real (J-invariant basis), so B = sum of the real parts of the terms
        mat = sp.csr_matrix((vv.real, (r_i, c_i)), shape=(dim, dim))
    if shift:
        mat = mat - shift * sp.identity(dim, format="csr")
    mat.sum_duplicates()
    mat.sort_indices()
    return mat
