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

:func:`lowest_sector_levels` runs in four parts, each in one place: the plan (``_plan_solve``, a
pure function: which real blocks, how the search starts, which blocks are small enough for dense
eigh), the block builder (``_Blocks``: every real block of the flake, built on demand from the
shared pattern of its kind), the proved search (``_solve``; each block is solved by
:mod:`hyperlattice.graph.factor` or :mod:`hyperlattice.graph.solvers`, and counted by Sylvester
inertia through the factor) and the assembly of the labelled :class:`~hyperlattice.graph.levels.Spectrum`
(``_assemble``). :func:`~hyperlattice.graph.spectrum.lowest_levels` reaches all of it through one call.
"""

from __future__ import annotations

import dataclasses
import math
import time
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from .. import _validate
from .. import geometry
from .._ties import eigenvalue_tolerance, stable_order
from ..errors import ConvergenceError
from . import factor as fct
from .factor import available_memory
from .lattice import _check_pq, _type_counts
from .levels import Spectrum
from .solvers import _check_residuals, _dense_block_lowest, _lanczos_ritz, _single_threaded_blas
from .symmetry import signed_sector

__all__ = ["SectorLattice", "sector_lattice", "sector_block", "lowest_pair", "lowest_sector_levels", "flake_memory"]

#: Peak bytes per *site of the full lattice* while building a :class:`SectorLattice` and solving
#: for E0, E1: measured 107 B at 15 rings (1.39 GB peak RSS for 13.0 M sites, interpreter
#: included), with margin; the full lattice alone needs about 400.
_BYTES_PER_SITE_SECTORS = 130


@dataclass(frozen=True, eq=False)
class SectorLattice:
    r"""A {p,q} ring lattice stored as its rotation orbits (a compact form of the flake).

    Attributes
    ----------
    p, q, rings : int
        Schläfli symbol and number of rings of the flake.
    ring_sizes : ndarray of int64, shape (rings,)
        Sites on each ring of the full lattice (p times the orbits of that ring).
    rows, cols : ndarray of int32, shape (D,)
        Directed neighbour entries between orbits: orbit ``rows[e]`` (its representative, shift 0)
        is a neighbour of the site :math:`R^{s}` (representative of ``cols[e]``), ``s = shifts[e]``.
        Each edge orbit appears twice (once from each end), as in the full lattice's sector block;
        the entries are grouped by ring, not sorted.
    shifts : ndarray of int8, shape (D,)
        The rotation power s of each entry.
    mirror_orbit : ndarray of int32, shape (N/p,)
        The mirror :math:`\bar z` maps representative o onto :math:`R^{t_o}` (representative of
        ``mirror_orbit[o]``) with ``t_o = mirror_shift[o]``.
    mirror_shift : ndarray of int8, shape (N/p,)
        The rotation power :math:`t_o` of the mirror image.
    z : ndarray of complex128, shape (N/p,), or None
        Poincaré-disk coordinates of the representatives (the full lattice's site ``i`` of ring k is
        :math:`e^{2\pi i s/p} z_o`), kept when ``coordinates=True``.

    Examples
    --------
    >>> from hyperlattice.graph.sectors import sector_lattice
    >>> slat = sector_lattice(7, 3, 2)
    >>> slat
    <SectorLattice {7,3} rings=2 sites=35 orbits=5>
    >>> slat.ring_sizes.tolist(), slat.size, slat.z is None
    ([7, 28], 5, True)
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
    r"""Estimated peak bytes of :func:`lowest_pair` for the ``rings``-ring {p,q} flake.

    Counted before anything is allocated, from the exact site count and a fixed number of
    bytes per site of the sector build and solve.

    Parameters
    ----------
    p, q : int
        Hyperbolic Schläfli symbol.
    rings : int
        Number of rings :math:`\ell \ge 1`.

    Returns
    -------
    int
        Estimated peak memory in bytes.

    Raises
    ------
    ValueError
        For an invalid {p,q} or ``rings``.

    See Also
    --------
    lowest_pair, sector_lattice

    Examples
    --------
    >>> from hyperlattice.graph.sectors import flake_memory
    >>> flake_memory(7, 3, 3)
    14560
    """
    p, q = _check_pq(p, q)
    rings = _validate.positive_int("rings", rings)
    counts, _ = _type_counts(p, q, rings, stop_above=2**62)
    return int(sum(counts) * _BYTES_PER_SITE_SECTORS)


def _check_flake_size(p: int, q: int, rings: int, max_bytes) -> int:
    """Full-lattice site count, or ValueError when the sector build will not fit."""
    # the address-space limit and the cgroup count too, not only free RAM
    limit = available_memory() if max_bytes is None else _validate.positive_int("max_bytes", max_bytes)
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
    ang0 = np.angle(zs)
    # angle of the copy inside [0, step): the first site is among the smallest of these, up to
    # rounding; only those near the minimum (or near the sector edge) are evaluated exactly
    red = np.mod(ang0, step)
    red = np.where(red > step - 1e-9, red - step, red)
    cand = np.flatnonzero(red <= red.min() + 1e-9)
    base = np.floor(-ang0[cand] / step).astype(np.int64)
    best_ang, best_pos = np.inf, 0
    for d in (-1, 0, 1):
        s = np.mod(base + d, p)
        ang = np.angle(phases[s] * zs[cand])
        ang = np.where(ang < -1e-12, ang + 2 * math.pi, np.maximum(ang, 0.0))
        pos = s * m + cand
        # argmin over the ring in position order: the smallest angle, ties to the first position
        key = np.lexsort((pos, ang))[0]
        if ang[key] < best_ang or (ang[key] == best_ang and pos[key] < best_pos):
            best_ang, best_pos = float(ang[key]), int(pos[key])
    return best_pos


def sector_lattice(p: int = 7, q: int = 3, rings: int = 3, *, coordinates: bool = False,
                   max_bytes: int | None = None) -> SectorLattice:
    r"""Build the rotation orbits of the ``rings``-ring {p,q} lattice without the lattice itself.

    The p-fold rotation about the centre maps the flake onto itself; one representative per
    orbit (N/p of them) and the orbit-to-orbit hops with their rotation shifts are all the
    sector blocks :func:`sector_block` need, so flakes far too big to build as a
    :class:`~hyperlattice.graph.lattice.Lattice` can be solved.

    Parameters
    ----------
    p, q : int, optional
        Hyperbolic Schläfli symbol, :math:`(p-2)(q-2) > 4`; default {7,3}.
    rings : int, optional
        Number of rings :math:`\ell \ge 1`; default 3.
    coordinates : bool, optional
        Keep the coordinates of the orbit representatives (they are computed anyway, to order
        each ring as :func:`~hyperlattice.graph.lattice.ring_lattice` does); default False.
    max_bytes : int, optional
        Refuse (``ValueError``) before allocating when the estimated peak memory of the build
        and of :func:`lowest_pair` exceeds it; default: the memory available now.

    Returns
    -------
    SectorLattice
        Orbits ordered as the representatives of ``rotation_orbits(ring_lattice(p, q, rings))``;
        ``sites`` is N, ``size`` the number N/p of orbits, ``rows``/``cols``/``shifts`` the
        orbit hops.

    Raises
    ------
    ValueError
        For an invalid {p,q} or ``rings``, or a build that would exceed ``max_bytes`` (or the
        available memory), or more than 2**31 - 1 orbits.

    See Also
    --------
    sector_block, lowest_pair, hyperlattice.graph.symmetry.rotation_orbits

    Examples
    --------
    >>> from hyperlattice.graph.sectors import sector_lattice
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


def mirror_basis(slat: SectorLattice, mirror: str) -> tuple[np.ndarray, np.ndarray, np.ndarray, int]:
    r"""The real basis of a mirror-reduced block, orbit by orbit.

    Orbit o is :math:`e_o = \sum_j c_{jo} w_{\mathrm{idx}[j, o]}` with :math:`c = \mathrm{mag}\, e^{i\gamma}`
    in terms of the basis vectors w: of the even or odd half (``"even"``/``"odd"``, m = 0), or
    of the real form (``"real"``, after the gauge :math:`g_o = e^{-i\pi m t_o/p}`):
    :math:`w_\pm` from :math:`e_o \pm e_{\mu(o)}` (the minus one times i) for each mirror pair,
    :math:`e_o` for an orbit the mirror fixes. Returns ``(idx, mag, gamma, dim)`` with arrays of
    shape (2, N/p); ``mag == 0`` marks an unused slot (or an orbit absent from the odd half).
    """
    o = np.arange(slat.size, dtype=np.int64)
    mu = slat.mirror_orbit.astype(np.int64)
    fixed = mu == o
    lead = o <= mu                   # one class per {o, mu(o)}, labelled by its smaller orbit
    cls = np.minimum(o, mu)
    s = math.sqrt(0.5)
    mag = np.zeros((2, slat.size))
    gamma = np.zeros((2, slat.size))
    if mirror in ("even", "odd"):
        keep = lead if mirror == "even" else lead & ~fixed
        pos = np.cumsum(keep) - 1
        idx = np.stack([pos[cls], pos[cls]])
        if mirror == "even":
            mag[0] = np.where(fixed, 1.0, s)
        else:   # e_o - e_mu(o), + on the smaller orbit
            mag[0] = np.where(fixed, 0.0, np.where(o < mu, s, -s))
        return idx, mag, gamma, int(keep.sum())
    width = np.where(fixed, 1, 2)
    cum = np.cumsum(np.where(lead, width, 0))
    start = np.concatenate([[0], cum[:-1]])
    base = start[cls]
    idx = np.stack([base, np.where(fixed, base, base + 1)])
    # e_o = (w+ - i w-)/sqrt2 for the smaller orbit of a pair, (w+ + i w-)/sqrt2 for the larger
    mag[0] = np.where(fixed, 1.0, s)
    mag[1] = np.where(fixed, 0.0, s)
    gamma[1] = np.where(o < mu, -0.5 * np.pi, 0.5 * np.pi)
    return idx, mag, gamma, int(cum[-1])


_KERNELS = {}


def _kernels():
    r"""numba kernels of the mirror-reduced blocks (compiled on first use, cached on disk).

    ``pattern`` emits the (row, col) of every term of :math:`W^H G^H H_m G W` (the same for all
    m); ``values`` accumulates the real part of each term into its CSR slot. The phase of a
    term is :math:`\pi\kappa/p + d\pi/2` with the integer :math:`\kappa = m(2s + t_a - t_b)` and
    :math:`d \in \{0, \pm1, \pm2\}` from the basis phases, so two small tables replace cos().
    """
    if not _KERNELS:
        import numba

        @numba.njit(cache=True)
        def pattern(rows, cols, idx, mag, out_r, out_c):  # pragma: no cover - jitted
            k = 0
            for e in range(rows.shape[0]):
                a = rows[e]
                b = cols[e]
                for i in range(2):
                    if mag[i, a] == 0.0:
                        continue
                    for j in range(2):
                        if mag[j, b] == 0.0:
                            continue
                        out_r[k] = idx[i, a]
                        out_c[k] = idx[j, b]
                        k += 1
            return k

        @numba.njit(cache=True)
        def slots(out_r, out_c, indptr, indices, slot):  # pragma: no cover - jitted
            for k in range(out_r.shape[0]):
                r = out_r[k]
                c = out_c[k]
                for x in range(indptr[r], indptr[r + 1]):
                    if indices[x] == c:
                        slot[k] = x
                        break

        @numba.njit(cache=True)
        def values(rows, cols, shifts, tmir, mag, quarter, m, p, t, costab, sintab, slot, data):  # pragma: no cover
            k = 0
            two_p = 2 * p
            for e in range(rows.shape[0]):
                a = rows[e]
                b = cols[e]
                kappa = (m * (2 * shifts[e] + tmir[a] - tmir[b])) % two_p
                if kappa < 0:
                    kappa += two_p
                cb = costab[kappa]
                sb = sintab[kappa]
                for i in range(2):
                    if mag[i, a] == 0.0:
                        continue
                    for j in range(2):
                        if mag[j, b] == 0.0:
                            continue
                        d = quarter[j, b] - quarter[i, a]
                        if d == 0:
                            v = cb
                        elif d == 1:
                            v = -sb
                        elif d == -1:
                            v = sb
                        else:
                            v = -cb
                        data[slot[k]] += -t * mag[i, a] * mag[j, b] * v
                        k += 1

        _KERNELS.update(pattern=pattern, slots=slots, values=values)
    return _KERNELS


class _BlockFactory:
    """Mirror-reduced blocks of one SectorLattice: the pattern of each kind is built once."""

    def __init__(self, slat: SectorLattice, *, diagonal: bool = False):
        self.slat = slat
        # diagonal: every diagonal entry stored (zero where no term lands), the pattern the
        # factorisation layer analyses, so that no block is copied to insert them at every shift
        self.diagonal = diagonal
        self._patterns = {}
        self._bases = {}
        self._labels = {}
        self._wide = None

    def order_halves(self, real_permutation: np.ndarray) -> bool:
        """Number the rows of the m = 0 halves (even, odd) in the order of a fill-reducing ordering
        of the real blocks: the row of a class of mirror orbits {o, mu(o)} goes where the first of
        the class's real rows is eliminated. The halves' graphs are the real blocks' with each
        class's rows merged, so the order fits them as well as their own minimum-degree ordering
        ({7,3}, l = 14: nnz(L) 1,699,465 and 1,698,480 against AMD's 1,699,467 and 1,696,325) and
        spares computing it. The blocks are the same up to this renumbering (same spectrum).
        Returns False (nothing changed) once a half's pattern has been built."""
        if "even" in self._patterns or "odd" in self._patterns:
            return False
        rank = np.empty(real_permutation.shape[0], dtype=np.int64)
        rank[real_permutation] = np.arange(real_permutation.shape[0], dtype=np.int64)
        idx_r, mag_r, _, _ = self._basis("real")
        used_r = mag_r != 0.0
        # the real rows of orbit o (its class's rows); a fixed orbit has one (both slots name it)
        first = np.minimum(rank[idx_r[0]], np.where(used_r[1], rank[idx_r[1]], rank[idx_r[0]]))
        for mirror in ("even", "odd"):
            idx, mag, _, dim = self._basis(mirror)
            used = mag[0] != 0.0
            key = np.full(dim, np.iinfo(np.int64).max, dtype=np.int64)
            np.minimum.at(key, idx[0][used], first[used])
            order = np.argsort(key, kind="stable")
            label = np.empty(dim, dtype=np.int64)
            label[order] = np.arange(dim, dtype=np.int64)
            self._labels[mirror] = label
        return True

    def _basis(self, mirror: str):
        if mirror not in self._bases:
            self._bases[mirror] = mirror_basis(self.slat, mirror)
        return self._bases[mirror]

    def _pattern(self, mirror: str):
        if mirror not in self._patterns:
            slat = self.slat
            k = _kernels()
            idx, mag, gamma, dim = self._basis(mirror)
            if mirror in self._labels:
                idx = self._labels[mirror][idx]         # the renumbering of order_halves
            nz = np.count_nonzero(mag, axis=0)
            count = int(np.dot(nz[slat.rows].astype(np.int64), nz[slat.cols]))
            extra = dim if self.diagonal else 0
            out_r = np.empty(count + extra, dtype=np.int32)
            out_c = np.empty(count + extra, dtype=np.int32)
            k["pattern"](slat.rows, slat.cols, idx.astype(np.int32), mag, out_r, out_c)
            if extra:
                out_r[count:] = out_c[count:] = np.arange(dim, dtype=np.int32)
            pat = sp.csr_matrix((np.ones(count + extra, dtype=np.int8), (out_r, out_c)), shape=(dim, dim))
            pat.sum_duplicates()
            pat.sort_indices()
            slot = np.empty(count, dtype=np.int32 if count < 2**31 else np.int64)
            k["slots"](out_r[:count], out_c[:count], pat.indptr, pat.indices, slot)
            del out_r, out_c
            quarter = np.rint(gamma / (0.5 * np.pi)).astype(np.int64)
            self._patterns[mirror] = (pat.indptr, pat.indices, slot, mag, quarter, dim)
        return self._patterns[mirror]

    def dim(self, mirror: str) -> int:
        """Dimension of the blocks of this kind."""
        return self._basis(mirror)[3] if mirror not in self._patterns else self._patterns[mirror][5]

    def block(self, m: int, mirror: str, t: float, *, csc: bool = False):
        """The real block (m, mirror) as CSR, or with ``csc`` as CSC on the same arrays: the block is
        symmetric (each value is the same sum of the same terms at both ends of an edge), so its CSR
        arrays are its CSC arrays too (up to the rounding of the order in which three or more terms
        are summed into one entry), and the factorisation layer needs no conversion."""
        indptr, indices, slot, mag, quarter, dim = self._pattern(mirror)
        slat = self.slat
        p = slat.p
        if self._wide is None:
            # the kernel's integer arguments, widened once per flake (not at every block)
            self._wide = (slat.shifts.astype(np.int64), slat.mirror_shift.astype(np.int64))
        shifts, mirror_shift = self._wide
        kappa = np.arange(2 * p)
        data = np.zeros(indices.shape[0])
        _kernels()["values"](slat.rows, slat.cols, shifts, mirror_shift,
                             mag, quarter, int(m), int(p), float(t), np.cos(np.pi * kappa / p),
                             np.sin(np.pi * kappa / p), slot, data)
        # the imaginary parts cancel between mirror images (B is real), so the real parts are B
        mat = (sp.csc_matrix if csc else sp.csr_matrix)((data, indices, indptr), shape=(dim, dim))
        mat.has_sorted_indices = True
        return mat


def sector_block(slat: SectorLattice, m: int, *, mirror: str | None = None, t: float = 1.0,
                 shift: float = 0.0) -> sp.csr_matrix:
    r"""The angular-momentum block :math:`H_m - \text{shift}` of :math:`H = -tA`, from a :class:`SectorLattice`.

    Parameters
    ----------
    slat : SectorLattice
        From :func:`sector_lattice`.
    m : int
        Sector (angular momentum), signed or in ``range(p)``.
    mirror : {None, "real", "even", "odd"}, optional
        None (default): :math:`H_m` in the orbit basis, exactly
        ``sector_hamiltonian(ring_lattice(...), m)``. ``"real"``: an orthogonally equivalent
        real symmetric form of :math:`H_m` (same size, same spectrum; its sparsity pattern is
        the same for every m). ``"even"`` / ``"odd"`` (m = 0 only): the mirror-even / -odd
        half of the block.
    t : float, optional
        Hopping amplitude, the energy unit; default 1.
    shift : float, optional
        Subtracted on the diagonal (units of t); default 0.

    Returns
    -------
    scipy.sparse.csr_matrix
        Sorted indices, duplicates summed (zeros from cancelling terms are kept, so that the
        pattern does not depend on m); real unless ``mirror`` is None and the block is complex.
        N/p square, or smaller for ``"even"``/``"odd"``.

    Raises
    ------
    ValueError
        If ``slat`` is not a SectorLattice, ``m`` is not a sector of p, ``mirror`` is unknown,
        or ``"even"``/``"odd"`` is asked for m != 0.

    See Also
    --------
    sector_lattice, hyperlattice.graph.symmetry.sector_hamiltonian

    Examples
    --------
    >>> import numpy as np
    >>> from hyperlattice.graph.sectors import sector_block, sector_lattice
    >>> slat = sector_lattice(7, 3, 3)
    >>> b = sector_block(slat, 1)
    >>> b.shape, b.dtype
    ((16, 16), dtype('complex128'))
    >>> sector_block(slat, 1, mirror="real").dtype
    dtype('float64')
    >>> round(float(np.linalg.eigvalsh(sector_block(slat, 0).toarray())[0]), 6)   # E0
    -2.786702
    """
    slat = _check_sector_lattice(slat)
    p = slat.p
    m = signed_sector(m, p)
    t = _validate.hopping("the hopping t", t)
    shift = _validate.real("shift", shift)
    mirror = _validate.choice("mirror", mirror, _MIRRORS) if mirror is not None else None
    if mirror in ("even", "odd") and m != 0:
        raise ValueError("mirror='even'/'odd' splits the block m = 0 only; use mirror='real'.")
    n = slat.size
    if mirror is None:
        s = slat.shifts.astype(np.int64)
        if (2 * m) % p == 0:
            vals = -t * (np.where(s % 2 == 0, 1.0, -1.0) if m else np.ones(s.shape[0]))
        else:
            vals = -t * np.exp(2j * np.pi * ((m * s) % p) / p)
        mat = sp.csr_matrix((vals, (slat.rows, slat.cols)), shape=(n, n))
        dim = n
    else:
        mat = _BlockFactory(slat).block(m, mirror, t)
        dim = mat.shape[0]
    if shift:
        mat = mat - shift * sp.identity(dim, format="csr", dtype=mat.dtype)
    mat.sum_duplicates()
    mat.sort_indices()
    return mat


# ----------------------------------------------------------------------------
# E0 and E1 of a big flake
# ----------------------------------------------------------------------------

#: order of the mirror halves of a block when levels tie (m = 0 even first)
_HALF_ORDER = {"even": 0, "odd": 1, "real": 2}


def _block_specs(p: int) -> list[tuple[int, str]]:
    """The real blocks whose union is the spectrum of H (each m != 0, p/2 stands for the pair +-m)."""
    specs = [(0, "even"), (0, "odd")]
    specs += [(m, "real") for m in range(1, p // 2 + 1)]
    return specs


def lowest_pair(p: int = 7, q: int = 3, rings: int = 3, *, t: float = 1.0, tol: float = 1e-10,
                backend: str = "auto", sectors: SectorLattice | None = None, max_bytes: int | None = None,
                progress=None):
    r"""E0 and E1 of :math:`H = -tA` on the ``rings``-ring {p,q} flake, from sector blocks only.

    :func:`lowest_sector_levels` with ``levels=2`` (see there for the method and the proof
    that no level was missed). The lattice is never built, so flakes of millions of sites fit.

    Parameters
    ----------
    p, q : int, optional
        Hyperbolic Schläfli symbol; default {7,3}.
    rings : int, optional
        Number of rings :math:`\ell \ge 1`; default 3.
    t : float, optional
        Hopping amplitude, positive (energy unit); default 1.
    tol : float, optional
        Largest accepted residual, in units of t; default 1e-10.
    backend : {"auto", "cholmod", "superlu"}, optional
        Sparse factorisation (:func:`hyperlattice.graph.factor.resolve_backend`); default
        ``"auto"``.
    sectors : SectorLattice, optional
        A prebuilt :func:`sector_lattice` of the same flake (saves the build).
    max_bytes : int, optional
        Memory budget in bytes; default: the memory available.
    progress : bool, None or callable, optional
        A progress bar on stderr (None: when stderr is a terminal), or a function receiving
        short status strings.

    Returns
    -------
    Spectrum
        Two levels :math:`E_0 < E_1`, ascending, in units of t, with (n, m) labels and
        residuals; ``method`` is ``"sector-shift-invert"``; ``timings`` has ``"build"``,
        ``"solve"``, ``"total"`` and one entry per block; ``description`` names the
        factorisation backend; no eigenvectors.

    Raises
    ------
    ValueError
        Bad input, or a flake that will not fit.
    FactorMemoryError
        The factorisation of a block will not fit (refused before work).
    ConvergenceError
        A residual above 100 tol, or levels the inertia counts contradict.

    See Also
    --------
    lowest_sector_levels, hyperlattice.graph.spectrum.lowest_levels, flake_memory

    Examples
    --------
    >>> import hyperlattice as hl
    >>> spec = hl.lowest_pair(7, 3, 3)
    >>> [round(float(e), 6) for e in spec.energies], spec.m.tolist(), spec.method
    ([-2.786702, -2.626896], [0, 1], 'sector-shift-invert')
    """
    return lowest_sector_levels(p, q, rings, 2, t=t, tol=tol, backend=backend, sectors=sectors,
                                max_bytes=max_bytes, progress=progress)


def _states(spec, p: int) -> int:
    """States per level of a real block: 2 for m and -m (0 < m < p/2), else 1."""
    m, kind = spec
    return 1 if kind in ("even", "odd") or (2 * m) % p == 0 else 2


def lowest_sector_levels(p: int = 7, q: int = 3, rings: int = 3, levels: int = 2, *, t: float = 1.0,
                         tol: float = 1e-10, backend: str = "auto", sectors: SectorLattice | None = None,
                         max_bytes: int | None = None, progress=None):
    r"""The ``levels`` lowest states of :math:`H = -tA` on the {p,q} flake, from sector blocks only.

    The lattice is never built (:func:`sector_lattice`). The spectrum of H is the union of the
    real mirror-reduced blocks (:func:`sector_block`): m = 0 even and odd, and m = 1..p/2 (each
    level of 0 < m < p/2 is a ±m pair, two states). In each block the wanted levels are found by
    shift-invert Lanczos (ARPACK on :math:`(B - \sigma)^{-1}`, σ below them, proved below by the
    factorisation itself: :mod:`hyperlattice.graph.factor`). How many levels each block holds is
    first guessed from short Lanczos runs (their Ritz values are upper bounds of the levels), then
    **proved**: every block is factorised at :math:`x = E_{K} - \delta` (the K-th state, δ = twice
    its residual plus ``1e-10 |E|``) and Sylvester's law of inertia counts its eigenvalues below x;
    a block holding more than were computed is solved again for all of them, until the counts
    agree. So no level below :math:`E_K - \delta` is missed. All blocks of one kind share one
    symbolic analysis (the real forms of m = 1..p/2 have one sparsity pattern).

    Parameters
    ----------
    p, q, rings : int, optional
        The flake: hyperbolic Schläfli symbol and number of rings; default {7,3} with 3 rings.
        Ignored when ``sectors`` is given.
    levels : int, optional
        Number K of lowest states (a ±m pair counts twice); default 2.
    t : float, optional
        Hopping amplitude, positive; default 1. The blocks are solved at t = 1 and the levels
        scaled by t.
    tol : float, optional
        Largest accepted residual :math:`\|H\psi - E\psi\|`, in units of t (a ConvergenceError
        above 100 tol, a ConvergenceWarning between tol and 100 tol); default 1e-10.
    backend : {"auto", "cholmod", "superlu"}, optional
        Sparse factorisation (:func:`hyperlattice.graph.factor.resolve_backend`; "splu" is accepted
        for "superlu"); default ``"auto"``.
    sectors : SectorLattice, optional
        A prebuilt :func:`sector_lattice` of the same flake (saves the build).
    max_bytes : int, optional
        Memory budget in bytes; refused before allocating when the estimate (the build, and the
        factorisation fill from the symbolic analysis) exceeds it (default: the memory available).
    progress : bool, None or callable, optional
        A bar over the block solves on stderr (:mod:`hyperlattice._progress`; None: when stderr is a
        terminal), or a function receiving short status strings.

    Returns
    -------
    Spectrum
        K levels ascending (units of t), labels (n, m) (+m before -m), residuals; ``method`` is
        ``"sector-shift-invert"``; ``timings`` per stage and block; no eigenvectors.

    Raises
    ------
    ValueError
        Bad input (including ``levels`` above N, or a t that makes the energies overflow), or a
        flake that will not fit.
    FactorMemoryError
        The factorisation of a block will not fit (one sentence; refused before work).
    ConvergenceError
        A residual above 100 tol, or levels the inertia counts contradict.

    See Also
    --------
    lowest_pair, sector_block, hyperlattice.graph.spectrum.lowest_levels

    Examples
    --------
    >>> from hyperlattice.graph.sectors import lowest_sector_levels
    >>> spec = lowest_sector_levels(7, 3, 3, 4)
    >>> [round(float(e), 6) for e in spec.energies]
    [-2.786702, -2.626896, -2.626896, -2.48208]
    >>> spec.n.tolist(), spec.m.tolist()
    ([1, 1, 1, 1], [0, 1, -1, 2])
    """

    t_start = time.perf_counter()
    t = _validate.hopping("the hopping t", t, positive=True)
    tol = _validate.solver_tolerance("tol", tol)
    levels = _validate.positive_int("levels", levels)
    backend = fct.resolve_backend(backend)
    if max_bytes is not None:
        max_bytes = _validate.positive_int("max_bytes", max_bytes)
    if t != 1.0:
        # the spectrum of -tA is t times that of -A (t > 0), residuals too: solve at t = 1 and scale,
        # exactly (one correctly rounded product), whatever the magnitude of t (at t = 1e20 the
        # shift-invert margins and ARPACK's tolerance would otherwise sit at the wrong scale)
        base = lowest_sector_levels(p, q, rings, levels, t=1.0, tol=tol, backend=backend, sectors=sectors,
                                    max_bytes=max_bytes, progress=progress)
        with np.errstate(over="ignore"):
            energies, errors = base.energies * t, base.errors * t
        if not (np.all(np.isfinite(energies)) and np.all(np.isfinite(errors))):
            raise ValueError(f"t = {t:g} makes the energies exceed the float64 range.")
        return dataclasses.replace(base, energies=energies, errors=errors,
                                   description=base.description + f" Solved at t = 1 and scaled by t = {t:g}.")
    tol_h = tol * t  # residuals relative to the energy scale t of H = -tA (an absolute tolerance fails at t = 1e20)
    progress = _validate.progress("progress", progress)
    from .._progress import progress_bar

    # the blocks are solved as the search needs them (their number is not known in advance)
    with progress_bar(None, "sector blocks", unit="solve", progress=progress) as bar:
        if sectors is None:
            p, q = _check_pq(p, q)
            rings = _validate.positive_int("rings", rings)
            bar.note(f"building the sector lattice of {{{p},{q}}}, {rings} rings")
            sectors = sector_lattice(p, q, rings, max_bytes=max_bytes)
        else:
            sectors = _check_sector_lattice(sectors)
        timings = {"build": time.perf_counter() - t_start}
        if sectors.sites < 2:  # pragma: no cover - every flake has p >= 3 sites
            raise ValueError("a flake with one site has no E1.")
        if levels > sectors.sites:
            raise ValueError(f"levels = {levels:,} exceeds the {sectors.sites:,} states of this flake.")
        with _single_threaded_blas():
            # the block builder (every real block, built in one place), the plan (which blocks and how: a
            # pure function), the proved search (each block solved through graph/factor and graph/solvers)
            blocks = _Blocks(sectors, t, timings)
            plan = _plan_solve(sectors.p, sectors.q, sectors.size, levels, blocks.dims())
            solved = _solve(plan, blocks, _Solves(plan, blocks, t, tol_h, backend, max_bytes, bar, timings))
        # checked here, so that a warning names the caller's line (stacklevel 4 of _check_residuals)
        _check_residuals(np.array([lv[3] for lv in solved.states[:levels]]), tol_h,
                         f"{{{sectors.p},{sectors.q}}} flake with {sectors.rings} rings")
        return _assemble(plan, solved, sectors, t_start, timings)      # the labelled levels


#: real blocks of at most this many rows (or at most 2k + 2 for k levels) are diagonalised densely
_DENSE_BLOCK = 400


@dataclass(frozen=True)
class _Plan:
    """How the sector-only route solves one request (chosen by :func:`_plan_solve`, a pure function).

    ``specs`` are the real blocks (m, half) whose union is the spectrum, in tie order; ``start``
    is how the search begins: ``"pair"`` (E0 from m = 0 even, E1 from the +-1 pair with the shift
    just below E0), ``"estimate"`` (each block's share of the K lowest guessed from Ritz values)
    or ``"ground"`` (E0 alone); ``floor_tol`` is the rounding floor of every computed level.
    """

    p: int
    q: int
    levels: int
    specs: tuple
    start: str
    floor_tol: float

    def states(self, spec) -> int:
        """States per level of the block ``spec`` (2 for a +-m pair)."""
        return _states(spec, self.p)

    @staticmethod
    def dense(dim: int, k: int) -> bool:
        """The k lowest of a block of ``dim`` rows by dense eigh (else shift-invert)."""
        return dim <= 2 * k + 2 or dim <= _DENSE_BLOCK

    @staticmethod
    def analysis_key(spec):
        """The real forms of m = 1..p/2 share one sparsity pattern, hence one symbolic analysis."""
        return "real" if spec[1] == "real" else spec

    @staticmethod
    def held(spec) -> bool:
        """Blocks kept in memory from the start (the ground state's and E1's): the others are rebuilt."""
        return spec in ((0, "even"), (1, "real"))


def _plan_solve(p: int, q: int, size: int, levels: int, dims: dict) -> _Plan:
    """The route of a sector-only request: which real blocks, and how the search starts (no work).

    ``floor_tol`` is the rounding floor of every computed level, c n eps ||H|| with ||H|| <= q (t = 1)
    and n the largest block.
    """
    specs = tuple(spec for spec in _block_specs(p) if dims[spec[1]] > 0)
    if levels <= 2 and (1, "real") in specs:
        start = "pair"
    elif levels > 2:
        start = "estimate"
    else:  # pragma: no cover - every flake has the block m = 1
        start = "ground"
    return _Plan(p=p, q=q, levels=levels, specs=specs, start=start, floor_tol=eigenvalue_tolerance(1.0 * q, size))


class _Blocks:
    """Every real sector block of one flake, built in this one place on demand.

    Only the blocks holding a computed level stay in memory (``keep``); the others are rebuilt
    from the shared pattern of their kind when needed again (a few ms against the solves).
    """

    def __init__(self, slat: SectorLattice, t: float, timings: dict):
        self.slat = slat
        self.t = t
        self.timings = timings
        # CSC with every diagonal entry stored: the layout graph/factor analyses and factorises, so a
        # block goes to CHOLMOD at every shift without a conversion or a copy to insert its diagonal
        self._factory = _BlockFactory(slat, diagonal=True)
        self._held = {}

    def dims(self) -> dict:
        """Rows of the blocks of each kind ("even", "odd", "real")."""
        return {kind: self._factory.dim(kind) for kind in ("even", "odd", "real")}

    def order_halves(self, real_permutation: np.ndarray) -> bool:
        """The m = 0 halves numbered after the real blocks' ordering (:meth:`_BlockFactory.order_halves`)."""
        return self._factory.order_halves(real_permutation)

    def get(self, spec, keep: bool) -> sp.csc_matrix:
        if spec in self._held:
            return self._held[spec]
        t0 = time.perf_counter()
        mat = self._factory.block(spec[0], spec[1], self.t, csc=True)
        self.timings[f"block {spec[0]} {spec[1]}"] = time.perf_counter() - t0
        if keep:
            self._held[spec] = mat
        return mat


class _Solves:
    """The numerical work of one request, delegated to graph/factor and graph/solvers.

    Holds what the blocks share: one symbolic analysis per kind of block (every kind analysed
    before any numeric work, so a factorisation that will not fit is refused at once) and the
    Ritz values of each block.
    """

    def __init__(self, plan: _Plan, blocks: _Blocks, t: float, tol: float, backend: str, max_bytes, bar,
                 timings: dict):
        self.plan, self.blocks, self.t, self.tol = plan, blocks, t, tol
        self.backend, self.max_bytes, self.bar, self.timings = backend, max_bytes, bar, timings
        self.analyses = {}
        self._ritz = {}
        self.info = {}

    def analyse_all(self) -> None:
        # every kind of block analysed before any numeric work: a factorisation that will not fit is
        # refused now, with one sentence, not after minutes of solving the blocks that do fit.
        # The real blocks first: the m = 0 halves are numbered after their fill-reducing ordering
        # (_BlockFactory.order_halves), which CHOLMOD then keeps instead of ordering them anew
        for spec in sorted(self.plan.specs, key=lambda s: s[1] != "real"):
            key = self.plan.analysis_key(spec)
            if key in self.analyses:
                continue
            ordered = False
            if spec[1] != "real" and "real" in self.analyses and self.analyses["real"].permutation is not None:
                ordered = self.blocks.order_halves(self.analyses["real"].permutation)
            mat = self.blocks.get(spec, self.plan.held(spec))
            self.analyses[key] = fct.analyze(
                mat, backend=self.backend, max_bytes=self.max_bytes, ordered=ordered,
                what=f"the sector block m = {spec[0]} ({spec[1]}, {mat.shape[0]:,} rows)")
            del mat

    @property
    def backend_ran(self) -> str:
        return next(iter(self.analyses.values())).backend if self.analyses else self.backend

    def ritz(self, spec) -> np.ndarray:
        if spec not in self._ritz:
            self._ritz[spec] = _lanczos_ritz(self.blocks.get(spec, False), 40)
        return self._ritz[spec]

    def lowest(self, spec, k: int, below: float | None = None):
        """k lowest levels of a block: dense when small, else sigma below them (proved by the factor)
        and shift-invert."""
        mat = self.blocks.get(spec, True)
        t0 = time.perf_counter()
        k = min(k, mat.shape[0])
        if self.plan.dense(mat.shape[0], k):
            e, res = _dense_block_lowest(mat, k)
            self.timings[f"solve {spec[0]} {spec[1]}"] = time.perf_counter() - t0
            return e, res
        e, res, sigma, solves = fct._proved_shift_lowest(
            mat, k, self.analyses[self.plan.analysis_key(spec)], self.tol, f"block m={spec[0]}",
            what=f"block m={spec[0]} ({spec[1]})", below=below, ritz=None if below is not None else self.ritz(spec),
            scale=self.t, symmetric=True)
        self.info[spec] = {"sigma": sigma, "solves": solves}
        self.timings[f"solve {spec[0]} {spec[1]}"] = time.perf_counter() - t0
        self.bar.note(f"block m={spec[0]} {spec[1]}: {e.tolist()} after {solves} solves")
        self.bar.update()
        return e, res

    def count_below(self, spec, x: float, positive: bool) -> int | None:
        """Eigenvalues of the block below x (Sylvester's law of inertia), or None when not proved."""
        mat = self.blocks.get(spec, False)
        t0 = time.perf_counter()
        factor = self.analyses[self.plan.analysis_key(spec)].factor(x, positive=positive, matrix=mat,
                                                                    symmetric=True)
        count = factor.negatives
        del factor, mat
        self.timings["inertia"] = self.timings.get("inertia", 0.0) + time.perf_counter() - t0
        return count


@dataclass(frozen=True)
class _Solved:
    """What the search found: every computed state (ascending, tie-ordered), the inertia counts at x."""

    states: list
    counts: dict
    x: float
    backend: str


def _state_list(plan: _Plan, found: dict) -> list:
    """All states found so far, ascending; states of different blocks whose energies agree within
    their error bounds are ordered by (m, mirror half, index), never by the last bits of the
    energies, so the cut at ``levels`` and the labels are the same everywhere."""
    out = []
    for spec, (e, r) in found.items():
        for j in range(e.shape[0]):
            out += [(float(e[j]), spec, j, float(r[j]))] * plan.states(spec)
    if not out:
        return out
    order = stable_order(np.array([lv[0] for lv in out]), np.array([lv[3] for lv in out]) + plan.floor_tol,
                         np.array([lv[1][0] for lv in out]),
                         np.array([_HALF_ORDER[lv[1][1]] for lv in out]), np.array([lv[2] for lv in out]))
    return [out[i] for i in order]


def _solve(plan: _Plan, blocks: _Blocks, solves: _Solves) -> _Solved:
    """The K lowest states of the blocks, proved: guess each block's share, solve, count by inertia.

    How many levels each block holds among the K lowest is first guessed (Ritz values are upper
    bounds of the levels), then every block is factorised at x just below the K-th state and
    Sylvester's law of inertia counts its levels below x; a block holding more than were computed
    is solved again, until the counts agree.
    """
    levels, specs = plan.levels, plan.specs
    solves.analyse_all()
    e0, r0 = solves.lowest((0, "even"), 1)
    found = {(0, "even"): (e0, r0)}
    if plan.start == "pair":
        # E1: the (+-1) pair for every {p,q} measured so far; the inertia counts below check it.
        # Every level lies above E0 (minus its error): the shift just below E0 needs no search
        found[(1, "real")] = solves.lowest((1, "real"), 1, below=float(e0[0]) - 2.0 * float(r0[0]))
    elif plan.start == "estimate":
        # how many levels each block holds among the K lowest, guessed from Ritz values (upper
        # bounds of the levels, so every block holds at least its share); the counts below prove it
        est = sorted((float(th), spec) for spec in specs for th in solves.ritz(spec)[:levels]
                     for _ in range(plan.states(spec)))
        cut = est[min(levels, len(est)) - 1][0]
        for spec in specs:
            k_b = sum(1 for th, sp_ in est if sp_ == spec and th <= cut) // plan.states(spec)
            if k_b > found.get(spec, (np.zeros(0),))[0].shape[0]:
                found[spec] = solves.lowest(spec, k_b)
    counts = {}
    for _ in range(4 * len(specs) + 4):
        states = _state_list(plan, found)
        if len(states) < levels:
            # fewer states than wanted: one more level from the block whose next Ritz value is lowest
            nxt = min(specs, key=lambda sp_: float(solves.ritz(sp_)[min(found.get(sp_, (np.zeros(0),))[0].shape[0],
                                                                        39)]))
            known = found.get(nxt, (np.zeros(0), np.zeros(0)))
            low = float(known[0][0]) - 2.0 * float(known[1][0]) if known[0].shape[0] else None
            found[nxt] = solves.lowest(nxt, known[0].shape[0] + 1, below=low)
            continue
        ek, _, _, resk = states[levels - 1]
        # margin: the backward error of LDL^T without pivoting on these sparse blocks is about
        # (column count) * eps * ||B|| ~ 1e-14; 1e-10 leaves ample room for rounding
        x = ek - 2.0 * resk - 1e-10 * max(1.0, abs(ek))
        missing = None
        counts = {}
        for spec in specs:
            have = sum(1 for lv in states if lv[1] == spec and lv[0] < x) // plan.states(spec)
            counts[spec] = solves.count_below(spec, x, positive=have == 0)
            if counts[spec] is not None and counts[spec] > have:
                missing = (spec, counts[spec])
                break
        if missing is None:
            break
        spec, count = missing
        # the levels below x that were missed, and the next; the block's lowest level is known,
        # so sigma goes just below it (a far sigma crowds the inverse's eigenvalues: measured
        # 150 solves for 3 levels at l = 14 against 40 with sigma at the known level)
        known = found.get(spec)
        low = None if known is None or known[0].shape[0] == 0 else float(known[0][0]) - 2.0 * float(known[1][0])
        found[spec] = solves.lowest(spec, count + 1, below=low)
    else:  # pragma: no cover
        raise ConvergenceError("the inertia counts and the computed levels do not agree.")
    return _Solved(states=states, counts=counts, x=x, backend=solves.backend_ran)


def _assemble(plan: _Plan, solved: _Solved, slat: SectorLattice, t_start: float, timings: dict) -> Spectrum:
    """The labelled Spectrum of the K lowest states: signed sector m (+m before -m) and radial index n."""
    p, q, levels, states = plan.p, plan.q, plan.levels, solved.states
    chosen = states[:levels]
    energies = np.array([lv[0] for lv in chosen])
    res = np.array([lv[3] for lv in chosen])
    ms, ns = [], []
    seen = set()
    for lv in chosen:
        m = lv[1][0]
        # the second state of a +-m pair is -m
        signed = -m if (lv[1], lv[2]) in seen else m
        seen.add((lv[1], lv[2]))
        # radial index: levels of the same |m| below it, across both mirror halves of m = 0
        # (below it beyond both error bounds: a degenerate partner is not "below")
        below = len({(o[1], o[2]) for o in states
                     if o[1][0] == m and o[0] < lv[0] - (o[3] + lv[3] + 2.0 * plan.floor_tol)})
        ms.append(signed)
        ns.append(below + 1)
    timings["solve"] = time.perf_counter() - t_start - timings["build"]
    timings["total"] = time.perf_counter() - t_start
    proved = all(c is not None for c in solved.counts.values())
    delta = states[levels - 1][0] - solved.x
    how = ("CHOLMOD (LL^T below the band, simplicial LDL^T for the counts)" if solved.backend == "cholmod"
           else "SuperLU (symmetric ordering, no pivoting)")
    proof = (f"Sylvester inertia of every block at E{levels - 1} - {delta:.1e} shows no other level below it"
             if proved else "the SuperLU ordering was not symmetric, so no inertia count proves the order")
    description = (f"Shift-invert Lanczos on the real mirror-reduced {slat.size:,}-orbit sector blocks "
                   f"(m = 0 even/odd, 1..{p // 2}) of the {{{p},{q}}} flake built sector by sector, "
                   f"factorised by {how}; {proof}.")
    return Spectrum(energies=energies, n=np.array(ns), m=np.array(ms), errors=res, method="sector-shift-invert",
                    description=description, p=p, q=q, rings=slat.rings, sites=slat.sites, kind="sites",
                    timings=timings, backend=solved.backend)


def _flake_levels(lattice, levels: int, t: float, tol: float, progress) -> Spectrum | None:
    """:func:`lowest_sector_levels` of a built lattice, or None when it is not the plain {p,q} ring flake
    that the sector-only build reproduces (then the caller's route runs). One call from the route."""
    try:
        slat = sector_lattice(lattice.p, lattice.q, lattice.rings)
    except ValueError:
        return None
    # the same flake: same sites, same edges, same degree histogram (a rewired or loaded-and-edited
    # lattice takes the route that reads its own edges)
    degrees = np.bincount(np.asarray(lattice.edges).ravel(), minlength=lattice.sites)
    orbit_deg = np.bincount(slat.rows, minlength=slat.size)
    if (slat.sites != lattice.sites or slat.rows.shape[0] * lattice.p != 2 * lattice.edges.shape[0]
            or not np.array_equal(np.bincount(degrees), lattice.p * np.bincount(orbit_deg))):
        return None
    return lowest_sector_levels(sectors=slat, levels=levels, t=t, tol=tol, progress=progress)


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
