r"""Exact grand-canonical thermal averages of the Bose–Hubbard model by full diagonalisation.

The reference of the quantum Monte Carlo (:func:`hyperlattice.bosons.qmc`): every particle-number
block :math:`N = 0 \dots M\,n_{\max}` of

.. math::

    H = -\sum_{i<j} t_{ij} (a_i^\dagger a_j + \mathrm{h.c.})
        + \frac{U}{2} \sum_i n_i (n_i - 1) - \mu \sum_i n_i ,
    \qquad t_{ij} = t A_{ij},

with the occupation cutoff :math:`n_i \le n_{\max}` is diagonalised densely, and

.. math::

    \langle O \rangle = \frac{\sum_N \operatorname{Tr}_N O\, e^{-\beta H}}{\sum_N \operatorname{Tr}_N e^{-\beta H}} .

Two routes, the same numbers (to rounding):

* ``"dense"``: each N block of the whole Fock space :math:`(n_{\max}+1)^M` (at most
  :data:`MAX_STATES` states) in the occupation basis; any graph, weighted adjacencies too;
* ``"sectors"``: on a flake or a periodic cluster with a rotation R of order p (every flake; a
  cluster when its face rotation is found, :func:`~hyperlattice.bosons.ed.bose_hubbard_graph`),
  each N block is split into the p angular-momentum sectors of R
  (:func:`~hyperlattice.bosons.ed.fock_sectors`, :func:`~hyperlattice.bosons.ed.sector_block`).
  H is real, so sector :math:`-m` is the complex conjugate of sector m: same eigenvalues, and
  its contribution to :math:`\langle a_i^\dagger a_j\rangle` is the complex conjugate of that
  of m; only :math:`m = 0 \dots \lfloor p/2\rfloor` are diagonalised. The one-body density
  matrix is accumulated from each sector's thermal density matrix
  :math:`\rho_m = \Phi_m e^{-\beta E_m}\Phi_m^\dagger` through the lift
  :math:`\psi(R^s r) = \omega^{ms}\phi_r/\sqrt{L_r}`
  (:func:`~hyperlattice.bosons.ed.lift_sector_vector`):
  :math:`\langle\beta|\rho|\alpha\rangle = \omega^{m(s_\beta - s_\alpha)}\,
  \rho_m[r_\beta, r_\alpha]/\sqrt{L_\beta L_\alpha}`.

Sizes are known before any work: the sector dimensions follow from Burnside's count of the Fock
states fixed by each power of R (:func:`sector_dimensions`), and a problem is refused in one
sentence when a block exceeds :data:`BLOCK_MAX` states or the whole job :data:`WORK_MAX`
(dense-diagonalisation work, in units of :math:`d^3` flops, complex blocks counted 4 times).
"""

from __future__ import annotations

import dataclasses
import hashlib
import math
from collections import OrderedDict
from typing import ClassVar

import numpy as np
import scipy.sparse as sp

from .. import _validate
from ..results import Column, Result

__all__ = ["exact_thermal", "ThermalAverages", "sector_dimensions", "MAX_STATES", "BLOCK_MAX", "WORK_MAX",
           "AUTO_SECTORS"]

#: largest Fock space (all particle numbers) of the ``"dense"`` route
MAX_STATES = 20_000
#: largest block (states of one N, or of one sector of one N) diagonalised densely
BLOCK_MAX = 5_000
#: method="auto" takes the sector route (when there is a rotation) once an N block exceeds this size
AUTO_SECTORS = 1_000
#: largest total work: sum over the diagonalised blocks of d^3 (complex blocks counted 4 times);
#: the Bolza cluster with hard-core bosons is about 1.7e11 (a few minutes on one loaded core)
WORK_MAX = 6e11
#: eigenvalue spectra kept for reuse (see exact_thermal, Notes)
_CACHE_SIZE = 4
_CACHE: OrderedDict = OrderedDict()


@dataclasses.dataclass(frozen=True, eq=False, kw_only=True)
class ThermalAverages(Result):
    r"""Exact grand-canonical thermal averages of the Bose–Hubbard model (:func:`exact_thermal`).

    Attributes
    ----------
    system : str
        What was diagonalised (``"{7,3} flake, l = 1"``, a cluster, or ``"graph of M sites"``).
    sites : int
        Number of sites M.
    states : int
        Fock states summed over, all particle numbers: :math:`(n_{\max}+1)^M`.
    U, mu, t : float
        Interaction, chemical potential and hopping scale (energies, in the unit of the hopping).
    beta : float
        Inverse temperature (inverse energy unit).
    nmax : int
        Occupation cutoff (1: hard-core bosons).
    energy : float
        :math:`\langle H\rangle`, total, the :math:`-\mu N` term included (energy unit).
    density : float
        :math:`\langle N\rangle/M` (bosons per site).
    compressibility : float
        :math:`\kappa = \beta(\langle N^2\rangle - \langle N\rangle^2)/M` (per site, per energy unit).
    free_energy : float
        :math:`F = -\ln Z/\beta` (energy unit).
    site_density : ndarray, shape (M,), or None
        :math:`\langle n_i\rangle` (bosons); None when ``one_body=False``.
    green : ndarray, shape (M, M), or None
        :math:`G_{ij} = \langle a_i^\dagger a_j\rangle`, with :math:`G_{ii} = \langle n_i\rangle`
        (bosons); None when ``one_body=False``.
    condensate_fraction : float
        Largest eigenvalue of G over :math:`\langle N\rangle` (nan without G or without bosons).
    bonds : ndarray of int, shape (B, 2)
        The bonds (i < j).
    bond_kinetic : ndarray, shape (B,), or None
        :math:`\langle a_i^\dagger a_j + a_j^\dagger a_i\rangle` per bond (bosons).
    method : str
        ``"dense"`` or ``"sectors"`` (see the module docstring).
    sectors : int
        Order p of the rotation used (1 for ``"dense"``).
    largest_block : int
        States of the largest block diagonalised.

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.bosons import exact_thermal
    >>> ex = exact_thermal(hl.ring_lattice(7, 3, 1), U=4.0, mu=1.0, beta=2.0, nmax=2)
    >>> row = ex.table()[1]
    >>> row["observable"], round(row["value"], 6), row["unit"]
    ('density', 0.97273, 'bosons per site')
    """

    COLUMNS = (Column("site_density", "site_density", "bosons"),)
    #: the unit of each scalar observable (the rows of :meth:`table`)
    UNITS: ClassVar[dict] = {"energy": "t", "density": "bosons per site", "compressibility": "1/(t site)",
                             "free_energy": "t", "condensate_fraction": "1"}

    system: str
    sites: int
    states: int
    U: float
    mu: float
    t: float
    beta: float
    nmax: int
    energy: float
    density: float
    compressibility: float
    free_energy: float
    site_density: np.ndarray | None
    green: np.ndarray | None
    condensate_fraction: float
    bonds: np.ndarray
    bond_kinetic: np.ndarray | None
    method: str
    sectors: int
    largest_block: int

    def table(self) -> list[dict]:
        """One row per scalar observable: ``observable, value, unit`` (units in words, t = the hopping)."""
        return [{"observable": k, "value": float(getattr(self, k)), "unit": u} for k, u in self.UNITS.items()]


# ----------------------------------------------------------------------------
# the system
# ----------------------------------------------------------------------------

def _bond_list(system, t: float):
    """(sites, bi, bj, t_ij, label) of a flake, a cluster or an adjacency matrix (each bond once, i < j)."""
    from .meanfield import _adjacency, _system_label

    a = sp.csr_matrix(_adjacency(system))
    up = sp.triu(a, k=1).tocoo()
    keep = up.data != 0
    label = _system_label(system)
    if label == "graph":
        label = f"graph of {a.shape[0]} sites"
    return (a.shape[0], up.row[keep].astype(np.int64), up.col[keep].astype(np.int64),
            t * up.data[keep].astype(float), label)


def _rotation_graph(system):
    """The BoseHubbardGraph of a flake or cluster with a rotation, else None."""
    from .ed import bose_hubbard_graph

    if sp.issparse(system) or isinstance(system, np.ndarray):
        return None
    g = bose_hubbard_graph(system)
    return g if g.rotation is not None and g.p > 1 else None


def _poly_mul(a: list, b: list, top: int) -> list:
    out = [0] * (top + 1)
    for i, x in enumerate(a):
        if x:
            for j, y in enumerate(b[:top + 1 - i]):
                if y:
                    out[i + j] += x * y
    return out


def sector_dimensions(rotation, nmax: int) -> np.ndarray:
    r"""Dimensions of the angular-momentum sectors of every particle-number block, without building them.

    Burnside / character count: the number of Fock states with N bosons fixed by :math:`R^s` is the
    coefficient of :math:`x^N` in :math:`\prod_{c} \sum_{v=0}^{n_{\max}} x^{v |c|}` over the cycles
    c of :math:`R^s`, and sector m (eigenvalue :math:`\omega^m` of R, :math:`\omega = e^{2\pi i/p}`)
    has dimension :math:`\frac1p\sum_s \omega^{-ms}\,\mathrm{Fix}_N(R^s)`.

    Parameters
    ----------
    rotation : array of int, shape (M,)
        A site permutation R (site i -> rotation[i]); p is its order.
    nmax : int
        Occupation cutoff, >= 1.

    Returns
    -------
    ndarray of int64, shape (M * nmax + 1, p)
        ``dims[N, m]``: states of sector m in the N-boson block.

    Raises
    ------
    ValueError
        If ``rotation`` is not a permutation or ``nmax`` < 1.

    Examples
    --------
    >>> from hyperlattice.bosons.thermal import sector_dimensions
    >>> sector_dimensions([1, 2, 3, 0], 1).tolist()      # 4 hard-core sites on a ring
    [[1, 0, 0, 0], [1, 1, 1, 1], [2, 1, 2, 1], [1, 1, 1, 1], [1, 0, 0, 0]]
    """
    perm = np.asarray(rotation)
    if perm.ndim != 1 or perm.size == 0 or perm.dtype.kind not in "iu" or \
            not np.array_equal(np.sort(perm), np.arange(perm.size)):
        raise ValueError("rotation must be a permutation of 0..M-1.")
    nmax = _validate.integer("nmax", nmax, minimum=1, maximum=255)
    m_sites = perm.size
    if m_sites * nmax > 4096:
        raise ValueError(f"sector_dimensions counts Fock states of at most 4096 bosons (sites x nmax), "
                         f"got {m_sites} x {nmax}.")
    # cycle lengths of R, and its order p
    seen = np.zeros(m_sites, dtype=bool)
    lengths = []
    for i in range(m_sites):
        if not seen[i]:
            k, n = i, 0
            while not seen[k]:
                seen[k] = True
                k = int(perm[k])
                n += 1
            lengths.append(n)
    p = 1
    for n in lengths:
        p = p * n // math.gcd(p, n)
    top = m_sites * nmax
    fix = []
    if p > 4096:
        raise ValueError(f"the rotation has order {p}, more than the 4096 sectors sector_dimensions counts.")
    for s in range(p):
        poly = [1]
        for n in lengths:
            g = math.gcd(n, s) if s else n          # R^s splits a cycle of length n into gcd(n, s) cycles
            clen = n // g
            factor = [0] * (nmax * clen + 1)
            for v in range(nmax + 1):
                factor[v * clen] = 1
            for _ in range(g):
                poly = _poly_mul(poly, factor, top)
        fix.append(poly + [0] * (top + 1 - len(poly)))
    fix = np.array(fix, dtype=object)                  # (p, top + 1), exact integers
    dims = np.zeros((top + 1, p), dtype=np.int64)
    for m in range(p):
        # (1/p) sum_s omega^{-ms} Fix(R^s): the real part, Fix(R^s) = Fix(R^-s)
        acc = np.zeros(top + 1)
        for s in range(p):
            acc += np.cos(2 * np.pi * m * s / p) * fix[s].astype(float)
        dims[:, m] = np.rint(acc / p).astype(np.int64)
    return dims


# ----------------------------------------------------------------------------
# the blocks: (N, multiplicity, eigenvalues at mu = 0, one-body accumulator or None)
# ----------------------------------------------------------------------------

def _dense_blocks(sites, bi, bj, tij, U, nmax, vectors):
    c = nmax + 1
    dim = c ** sites
    codes = np.arange(dim, dtype=np.int64)
    occ = (codes[:, None] // c ** np.arange(sites, dtype=np.int64)[None, :]) % c      # (dim, sites)
    ntot = occ.sum(axis=1)
    radix = c ** np.arange(sites, dtype=np.int64)
    diag = 0.5 * U * (occ * (occ - 1)).sum(axis=1)
    sq = np.sqrt(np.arange(c + 1, dtype=float))
    for n in range(sites * nmax + 1):
        idx = np.flatnonzero(ntot == n)
        pos = np.full(dim, -1, dtype=np.int64)
        pos[idx] = np.arange(idx.size)
        h = np.diag(diag[idx]).astype(float)
        o = occ[idx]
        for b in range(bi.size):
            i, j = bi[b], bj[b]
            for src, dst in ((j, i), (i, j)):            # a_dst^dagger a_src
                ok = (o[:, src] > 0) & (o[:, dst] < nmax)
                rows = np.flatnonzero(ok)
                amp = tij[b] * sq[o[rows, src]] * sq[o[rows, dst] + 1]
                tgt = pos[idx[rows] - radix[src] + radix[dst]]
                np.add.at(h, (tgt, rows), -amp)
        if not vectors:
            yield n, 1, np.linalg.eigvalsh(h), None
            continue
        w, v = np.linalg.eigh(h)

        def one_body(bw, v=v, o=o, idx=idx, pos=pos):
            rho = (v * bw) @ v.T                              # unnormalised block density matrix
            dens = np.diag(rho) @ o
            green = np.zeros((sites, sites))
            for i in range(sites):
                for j in range(sites):
                    if i == j:
                        continue
                    ok = (o[:, j] > 0) & (o[:, i] < nmax)
                    rows = np.flatnonzero(ok)                 # |beta> -> a_i^dag a_j |beta> = amp |alpha>
                    amp = sq[o[rows, j]] * sq[o[rows, i] + 1]
                    tgt = pos[idx[rows] - radix[j] + radix[i]]
                    green[i, j] += float(np.sum(rho[rows, tgt] * amp))
            return dens, green

        yield n, 1, w, one_body


def _moves(basis, nmax):
    """Every hop a_i^dagger a_j (i != j) of the N-boson basis: (beta, alpha, i, j, amplitude)."""
    from .basis import rank_states

    occ = basis.states.astype(np.int64)
    sites = occ.shape[1]
    sq = np.sqrt(np.arange(nmax + 2, dtype=float))
    out = [[], [], [], [], []]
    for i in range(sites):
        for j in range(sites):
            if i == j:
                continue
            rows = np.flatnonzero((occ[:, j] > 0) & (occ[:, i] < nmax))
            if rows.size == 0:
                continue
            moved = occ[rows].copy()
            amp = sq[moved[:, j]] * sq[moved[:, i] + 1]
            moved[:, j] -= 1
            moved[:, i] += 1
            alpha = np.atleast_1d(rank_states(basis, moved))
            for lst, val in zip(out, (rows, alpha, np.full(rows.size, i), np.full(rows.size, j), amp)):
                lst.append(val)
    if not out[0]:
        return (np.zeros(0, dtype=np.int64),) * 4 + (np.zeros(0),)
    return tuple(np.concatenate(x) for x in out)


def _sector_blocks(g, U, t, nmax, vectors):
    from .basis import boson_basis
    from .ed import _sector_index, fock_sectors, sector_block

    sites, p = g.sites, g.p
    for n in range(sites * nmax + 1):
        basis = boson_basis(sites, n, nmax)
        sec = fock_sectors(basis, g)
        moves = _moves(basis, nmax) if vectors else None
        occ = basis.states.astype(float)
        for m in range(p // 2 + 1):
            if sec.dim(m) == 0:
                continue
            mult = 1 if (m == 0 or 2 * m == p) else 2
            h = sector_block(basis, g, sec, m, U=U, t=t, mu=0.0).toarray()
            if mult == 1:
                h = np.ascontiguousarray(h.real)              # m = 0, p/2: exactly real (see sector_block)
            if not vectors:
                yield n, mult, np.linalg.eigvalsh(h), None
                continue
            w, v = np.linalg.eigh(h)

            def one_body(bw, v=v, m=m, mult=mult, sec=sec, moves=moves, occ=occ):
                _, index = _sector_index(sec, m)
                rho = (v * bw) @ v.conj().T                   # rho_m, unnormalised
                r = index[sec.rep]                            # position of each state's orbit in sector m
                inside = r >= 0
                diag = np.zeros(r.size)
                diag[inside] = np.real(np.diagonal(rho))[r[inside]] / sec.period[inside]
                dens = mult * (diag @ occ)
                b, a, i, j, amp = moves
                rb, ra = r[b], r[a]
                ok = (rb >= 0) & (ra >= 0)
                b, a, i, j, amp, rb, ra = b[ok], a[ok], i[ok], j[ok], amp[ok], rb[ok], ra[ok]
                ang = 2.0 * np.pi * m * ((sec.shift[b] - sec.shift[a]) % p) / p
                el = rho[rb, ra] * np.exp(1j * ang) / np.sqrt(sec.period[b] * sec.period[a])
                val = mult * amp * np.real(el)                # m and -m: twice the real part
                green = np.bincount(i * sites + j, weights=val, minlength=sites * sites).reshape(sites, sites)
                return dens, green

            yield n, mult, w, one_body


# ----------------------------------------------------------------------------
# the public function
# ----------------------------------------------------------------------------

def _plan(sites, nmax, g, method, label):
    """(route, p, largest block, work) of a problem, refused in one sentence when it will not fit."""
    from .basis import basis_dimension

    dense_states = (nmax + 1) ** sites
    if method == "auto":
        small = dense_states <= MAX_STATES and basis_dimension(sites, sites * nmax // 2, nmax) <= AUTO_SECTORS
        method = "dense" if small or g is None else "sectors"
    if method == "sectors" and g is None:
        raise ValueError(f"the {label} has no rotation symmetry to split the blocks with; use method='dense'.")
    if method == "dense":
        if dense_states > MAX_STATES:
            have = (f"{dense_states:,}" if dense_states < 10**15
                    else f"about 10^{int(sites * math.log10(nmax + 1))}")
            raise ValueError(f"exact_thermal diagonalises at most {MAX_STATES:,} Fock states without symmetry "
                             f"sectors, and {sites} sites with nmax = {nmax} have {have}.")
        dims = [basis_dimension(sites, n, nmax) for n in range(sites * nmax + 1)]
        return "dense", 1, max(dims), float(sum(d ** 3 for d in dims))
    p = g.p
    if sites * nmax > 4096:
        # the largest block is at least the average one: (nmax + 1)^M / (M nmax + 1) states, over p sectors
        k = int(sites * math.log10(nmax + 1) - math.log10(sites * nmax + 1) - math.log10(p))
        raise ValueError(f"exact_thermal diagonalises at most {BLOCK_MAX:,} states per block densely, and the "
                         f"{label} with nmax = {nmax} has sectors of more than 10^{k} states.")

    # a sector holds at least D_N / p states: refuse a hopeless problem before counting exactly
    low = basis_dimension(sites, sites * nmax // 2, nmax) // p          # the middle block is the largest
    if low > BLOCK_MAX:
        raise ValueError(f"exact_thermal diagonalises at most {BLOCK_MAX:,} states per block densely, and the "
                         f"{label} with nmax = {nmax} has sectors of at least "
                         f"{f'{low:,}' if low < 10**15 else f'10^{len(str(low)) - 1}'} states.")
    dims = sector_dimensions(g.rotation, nmax)
    big, work, where = 0, 0.0, (0, 0)
    for n in range(dims.shape[0]):
        for m in range(p // 2 + 1):
            d = int(dims[n, m])
            work += (1.0 if (m == 0 or 2 * m == p) else 4.0) * float(d) ** 3
            if d > big:
                big, where = d, (n, m)
    if big > BLOCK_MAX:
        raise ValueError(f"exact_thermal diagonalises at most {BLOCK_MAX:,} states per block densely, and the "
                         f"{label} with nmax = {nmax} has a sector of {big:,} (N = {where[0]}, m = {where[1]}).")
    if work > WORK_MAX:
        raise ValueError(f"exact_thermal does at most {WORK_MAX:.0e} units of dense-diagonalisation work, and the "
                         f"{label} with nmax = {nmax} needs {work:.1e}.")
    return "sectors", p, big, work


def _cache_key(bi, bj, tij, sites, U, t, nmax, route) -> str:
    h = hashlib.sha256()
    unit = tij / t
    for a in (bi, bj, unit):
        h.update(np.ascontiguousarray(a).tobytes())
    # hard-core bosons: no U term, and the spectrum at t is t times the spectrum at t = 1
    h.update(repr((sites, nmax, route, 0.0 if nmax == 1 else U, 1.0 if nmax == 1 else t)).encode())
    return h.hexdigest()


def exact_thermal(system, *, U: float, mu: float, beta: float, nmax: int, t: float = 1.0,
                  method: str = "auto", one_body: bool = True) -> ThermalAverages:
    r"""Exact thermal averages of the Bose–Hubbard model over all particle numbers.

    Parameters
    ----------
    system : Lattice, Cluster or sparse matrix
        A flake (:func:`~hyperlattice.ring_lattice`), a periodic cluster, or a symmetric adjacency
        matrix with non-negative weights (bond hopping :math:`t_{ij} = t A_{ij}`).
    U, mu : float
        On-site interaction and chemical potential (in the energy unit of t).
    beta : float
        Inverse temperature, > 0.
    nmax : int
        Occupation cutoff per site, >= 1.
    t : float, optional
        Hopping scale (default 1); any sign, the spectrum is exact.
    method : {"auto", "dense", "sectors"}, optional
        ``"dense"``: every N block of the whole Fock space (at most :data:`MAX_STATES` states);
        ``"sectors"``: every N block split by the rotation of a flake or cluster (see the module
        docstring); ``"auto"`` (default): sectors when the system has a rotation and an N block
        exceeds :data:`AUTO_SECTORS` states, else dense.
    one_body : bool, optional
        Also the site densities, :math:`G_{ij}`, the bond kinetic terms and the condensate fraction
        (default True). False needs eigenvalues only: faster, and the spectrum is kept for reuse.

    Returns
    -------
    ThermalAverages
        ``energy`` (total :math:`\langle H\rangle`, the :math:`-\mu N` term included), ``density``,
        ``compressibility``, ``free_energy``, and (``one_body``) ``site_density``, ``green``
        (:math:`G_{ij} = \langle a_i^\dagger a_j\rangle`), ``bond_kinetic`` per bond of ``bonds``,
        ``condensate_fraction``; :meth:`ThermalAverages.table` lists the scalars with their units.

    Raises
    ------
    ValueError
        On bad input, or when a block exceeds :data:`BLOCK_MAX` states or the work
        :data:`WORK_MAX` (refused before any diagonalisation).
    MemoryError
        When the largest block will not fit in memory.

    Notes
    -----
    With ``one_body=False`` the eigenvalues of the last :data:`_CACHE_SIZE` problems are kept
    (bytes: 8 per Fock state), keyed by the graph, the cutoff, U and t: μ shifts each N block by
    :math:`-\mu N` and β enters only the Boltzmann weights, so a scan over (μ, β) diagonalises
    once; for hard-core bosons (no U term) the spectrum at t is t times that at t = 1, so a scan
    over t reuses it too.

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.bosons import exact_thermal
    >>> ex = exact_thermal(hl.ring_lattice(7, 3, 1), U=4.0, mu=1.0, beta=2.0, nmax=2)
    >>> round(ex.density, 6), ex.states, ex.method
    (0.97273, 2187, 'dense')
    """
    U = _validate.real("U", U)
    mu = _validate.real("mu", mu)
    t = _validate.real("t", t)
    beta = _validate.real("beta", beta)
    if not beta > 0:
        raise ValueError(f"beta must be positive, got {beta!r}.")
    nmax = _validate.integer("nmax", nmax, minimum=1, maximum=255)
    method = _validate.choice("method", method, ("auto", "dense", "sectors"))
    one_body = _validate.flag("one_body", one_body)
    sites, bi, bj, tij, label = _bond_list(system, t)
    g = _rotation_graph(system) if method != "dense" else None
    route, p, big, work = _plan(sites, nmax, g, method, label)
    c = 16.0 if route == "sectors" else 8.0
    _validate.require_memory(f"exact_thermal's largest block ({big:,} states)", (4 if one_body else 2) * c * big * big)
    hard_core_scale = nmax == 1 and t != 0
    key = _cache_key(bi, bj, tij, sites, U, t, nmax, route) if t != 0 else None
    spectra = _CACHE.get(key) if (key is not None and not one_body) else None
    blocks = []                                             # (N, mult, energies at mu, bw-sums...) per block
    if spectra is None:
        tt = 1.0 if hard_core_scale else t
        if route == "dense":
            gen = _dense_blocks(sites, bi, bj, tij / t * tt if t != 0 else tij, U, nmax, one_body)
        else:
            gen = _sector_blocks(g, U, tt, nmax, one_body)
        spectra = []
        for n, mult, w, ob in gen:
            spectra.append((n, mult, w))
            if one_body:
                e = (t if hard_core_scale else 1.0) * w - mu * n
                emin = float(e.min())
                bw = np.exp(-beta * (e - emin))
                dens, green = ob(bw)
                blocks.append((n, mult, e, emin, bw, dens, green))
        if key is not None and sum(w.size for _, _, w in spectra) * 8 < 64 * 2**20:
            _CACHE[key] = spectra
            _CACHE.move_to_end(key)
            while len(_CACHE) > _CACHE_SIZE:
                _CACHE.popitem(last=False)
    if not one_body:
        for n, mult, w in spectra:
            e = (t if hard_core_scale else 1.0) * w - mu * n
            emin = float(e.min())
            blocks.append((n, mult, e, emin, np.exp(-beta * (e - emin)), None, None))
    e0 = min(b[3] for b in blocks)
    z = e1 = n1 = n2 = 0.0
    dens = np.zeros(sites)
    green = np.zeros((sites, sites))
    for n, mult, e, emin, bw, bd, bg in blocks:
        f = mult * math.exp(-beta * (emin - e0))
        zb = f * float(bw.sum())
        z += zb
        e1 += f * float(bw @ e)
        n1 += n * zb
        n2 += n * n * zb
        if one_body:
            scale = math.exp(-beta * (emin - e0))           # mult is inside bd and bg already
            dens += scale * bd
            green += scale * bg
    nm = n1 / z
    kin = cf = None
    if one_body:
        dens /= z
        green /= z
        green = 0.5 * (green + green.T)                      # real symmetric: rounding only
        green[np.diag_indices(sites)] = dens
        kin = np.array([green[i, j] + green[j, i] for i, j in zip(bi, bj)])
        lam = float(np.linalg.eigvalsh(green)[-1])
        cf = float(lam / nm) if nm > 0 else math.nan
    return ThermalAverages(
        system=label, sites=int(sites), states=int((nmax + 1) ** sites), U=U, mu=mu, t=t, beta=beta, nmax=nmax,
        energy=float(e1 / z), density=float(nm / sites), compressibility=float(beta * (n2 / z - nm * nm) / sites),
        free_energy=float(e0 - math.log(z) / beta),
        site_density=dens if one_body else None, green=green if one_body else None,
        condensate_fraction=cf if one_body else math.nan,
        bonds=np.stack([bi, bj], axis=1), bond_kinetic=kin, method=route, sectors=int(p), largest_block=int(big))


from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
