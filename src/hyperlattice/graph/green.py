r"""Graph Green functions (``eq20``): :math:`G_{ij}(\omega) = [(H-\omega)^{-1}]_{ij}`.

:math:`H = -tA` (plus optional on-site terms), for real or complex :math:`\omega`. Small
lattices use one dense eigendecomposition for many frequencies; large ones a sparse LU per
frequency. The comparison with the continuum through the dictionary ``eq21`` lives in
:mod:`hyperlattice.compare.green`.

Two accelerations of the sparse route, both checked by the true residual of
every column they return:

* **Rotation sectors.** A lattice whose H commutes with the p-fold rotation (no on-site term, or
  an invariant one) is factorised block by block: :math:`H - \omega` splits into the Bloch blocks
  :math:`H_m - \omega` (:mod:`hyperlattice.graph.symmetry`), p times smaller, of which
  m = 0..p/2 are factorised (:math:`H_{-m} = \overline{H_m}`); one symbolic analysis serves
  all complex blocks and every ω. A column is assembled by a length-p FFT over the orbits.
* **Many frequencies below the band.** For a scan over many real ω below the spectrum, one
  factorisation at an anchor :math:`\omega_0` gives :math:`K = (H-\omega_0)^{-1}`, and
  :math:`(H-\omega)^{-1} b = (1 - \delta K)^{-1} K b`, :math:`\delta = \omega - \omega_0`:
  all shifted systems share one Krylov space of K (Lanczos; the Galerkin solution of each
  shift is the conjugate-gradient one, since :math:`1 - \delta K` is positive definite for
  ω below the spectrum). Each shift is accepted only when its true residual
  :math:`r = b - (H-\omega)x` meets the backward-error bound :data:`_SCAN_BACKWARD` and the
  proved forward bound :math:`\|x - x^*\| \le \|r\|/\delta` is at most :data:`_FORWARD_TOL`
  times :math:`\|x^*\|`; the others are factorised one by one as before.

**Proved error bounds.** Below the band :math:`H - \omega` is positive definite with smallest
eigenvalue :math:`E_0 - \omega`, so any :math:`\delta \le E_0 - \omega` turns a residual into
an error bound. Lower bounds of :math:`E_0`: the Gershgorin bound, every ω whose
positive-definite factorisation succeeded, and a Collatz–Wielandt bound
:math:`E_0 \ge \min_i (Zv)_i/v_i` (:func:`_e0_lower_bound`, Z = diagonal minus the moduli of
the off-diagonal entries) from a positive approximate ground state v (the scan's top Ritz
vector, or three steps of inverse iteration from the constant vector); for complex ω,
:math:`\delta = |\mathrm{Im}\,\omega|`. :attr:`GraphResolvent.report` gives, per ω of the last
call, the route, the backward error and the proved relative error bound (NaN where no δ is
known: inside the band, or a ground state that changes sign).

Conjugate gradients on :math:`H - \omega` for one column were measured and not adopted: at
ℓ = 12 (725,760 sites, source 10) they need 43, 190 and 267 iterations for a relative residual
of 1e-12 at ω = −3.5, −2.95 and −2.935, one sparse product each (6 ms), against 0.4 s for
CHOLMOD's whole analyse + factor + solve.
"""

from __future__ import annotations

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp

from .. import _validate
from .lattice import Lattice
from .operators import hamiltonian
from .symmetry import rotation_invariant, rotation_orbits

__all__ = ["graph_green", "GraphResolvent"]

_DENSE_MAX = 4000          # full matrices / eigendecompositions only up to this many sites
_ON_SPECTRUM = 1e3         # |omega - E_n| below this many ulps of ||H|| counts as "on the spectrum"
#: the rotation-sector factorisation from this many sites up (below it one factorisation of H is
#: as fast and there is less to assemble)
_SECTOR_MIN = 20_000
#: a column from the sector route or the many-omega scan is accepted when its residual obeys
#: ||b - (H - omega) x|| <= _SCAN_BACKWARD (||H - omega||_1 ||x|| + ||b||): a normwise backward
#: error of ~60 ulps (the direct factorisation reaches 1e-16 to 1e-15 on these lattices)
_SCAN_BACKWARD = 1e-14
#: a column from the many-omega scan is accepted only when, besides the backward error, its
#: proved forward error ||x - x*|| <= (||b - (H - omega) x|| + rounding) / delta (delta a proved
#: lower bound of the distance from omega to the spectrum) is at most this fraction of ||x*||, or
#: its residual is below the rounding bound itself (near the band edge, where the rounding term
#: alone approaches 1e-12 for a direct solve as well); the direct factorisation delivers 1e-14 to
#: 1e-13 there in fact (condition number times rounding), without a proof
_FORWARD_TOL = 1e-12
#: the many-omega scan (one anchor factorisation, shared Krylov space) is used when
#: S (_SCAN_FACTOR + k) >= _SCAN_TYPICAL k for S real omegas and k sources, and S >= _SCAN_MIN:
#: a factorisation costs ~4 solves, an anchor ~45 Lanczos steps (one solve each) per source plus
#: ~1 solve per shift; measured at l = 12 (benchmarks/bench_green_scan.py, same process) the scan
#: and one factorisation per omega break even near 20 omegas for one source
_SCAN_MIN = 8
_SCAN_FACTOR = 4.0
_SCAN_TYPICAL = 100.0
#: Lanczos steps per anchor at most (and never more vectors than 1/8 of the free memory)
_SCAN_STEPS = 160
#: anchors per scan at most; the shifts still unconverged are factorised one by one
_SCAN_ANCHORS = 3


def _is_scalar(x) -> bool:
    """One site index (as opposed to a list of them); decided without np.asarray on odd input."""
    return bool(np.isscalar(x) or (isinstance(x, np.ndarray) and x.ndim == 0))


def _as_omegas(omega) -> tuple[np.ndarray, bool]:
    """One frequency or a 1-d array of them, as complex128 (and whether it was a scalar)."""
    arr = _validate.complex_array("omega", omega, ndim=(0, 1))
    return np.atleast_1d(arr), arr.ndim == 0


class _SectorFactor:
    r"""The factorisation of :math:`H - \omega` through the p-fold rotation sectors (real ω, real H).

    ``H`` commutes with the rotation R of ``lattice``. With the orbit table
    ``idx[s, o]`` = site :math:`R^s r_o`, a vector v splits into sector parts
    :math:`\phi^{(m)}_o = \sum_s e^{-2\pi i m s/p} v(R^s r_o)` (an FFT along s), and
    :math:`(H-\omega)^{-1}v` is the inverse FFT of :math:`(H_m - \omega)^{-1}\phi^{(m)}` with
    :math:`(H_m)_{o o'} = \sum_{j = R^{s} r_{o'}} H_{r_o j}\, e^{2\pi i m s/p}` (the Bloch block of
    :mod:`hyperlattice.graph.symmetry`, built here from the rows of H at the representatives).
    For real v and ω the parts m and p - m are complex conjugate, so m = 0..p/2 are solved
    (numpy's ``rfft``). Blocks m = 0 and p/2 are real, the others complex Hermitian; all share one
    pattern (every diagonal entry stored), so one complex analysis serves the complex blocks and
    one real one the real blocks, at every ω.
    """

    def __init__(self, lattice: Lattice, H: sp.csc_matrix, what: str, diag: np.ndarray | None = None) -> None:
        from .factor import analyze

        orbits = rotation_orbits(lattice)
        p, k, n = orbits.p, orbits.size, H.shape[0]
        self.p, self.k, self.n = p, k, n
        idx = np.empty((p, k), dtype=np.int64)
        idx[orbits.shift, orbits.orbit] = np.arange(n, dtype=np.int64)
        self.idx = idx
        # orbit order (position s k + o) to sites: on ring lattices a few long runs of
        # consecutive sites (one per ring and rotation), copied as slices
        flat = idx.reshape(-1)
        cut = np.flatnonzero(np.diff(flat) != 1) + 1
        starts = np.concatenate([[0], cut]).astype(np.int64)
        ends = np.concatenate([cut, [n]]).astype(np.int64)
        self._runs = [(int(a), int(flat[a]), int(b - a)) for a, b in zip(starts, ends)]
        reps = orbits.representatives
        start = H.indptr[reps].astype(np.int64)
        count = (H.indptr[reps + 1] - H.indptr[reps]).astype(np.int64)
        total = int(count.sum())
        first = np.repeat(np.cumsum(count) - count, count)
        pos = np.arange(total, dtype=np.int64) - first + np.repeat(start, count)
        j = H.indices[pos]
        # H is symmetric: column r_o of the CSC matrix is row r_o
        row_of = np.repeat(np.arange(k, dtype=np.int64), count)
        hvals = H.data[pos]
        rows = np.concatenate([row_of, np.arange(k, dtype=np.int64)])
        cols = np.concatenate([orbits.orbit[j], np.arange(k, dtype=np.int64)])
        shift = np.concatenate([orbits.shift[j], np.zeros(k, dtype=np.int64)])
        vals = np.concatenate([hvals, np.zeros(k)])            # every diagonal entry stored
        key = cols * k + rows                                  # CSC order: column, then row
        order = np.argsort(key, kind="stable")
        key = key[order]
        first = np.ones(key.shape[0], dtype=bool)
        first[1:] = key[1:] != key[:-1]
        ukey = key[first]
        slot = np.cumsum(first) - 1                            # entry order[i] adds to slot[i]
        indptr = np.zeros(k + 1, dtype=np.int64)
        np.cumsum(np.bincount(ukey // k, minlength=k), out=indptr[1:])
        self._indices = (ukey % k).astype(np.int32)
        self._indptr = indptr.astype(np.int32)
        self._diag = np.flatnonzero(self._indices == np.repeat(np.arange(k), np.diff(indptr)))
        # most slots hold one entry; the few repeated ones (two neighbours in one orbit) are added
        self._vals = vals[order[first]]
        # the rotation powers as small integers (m s < p^2 / 2 fits int16 for every p the package builds)
        self._shift = shift[order[first]].astype(np.int16 if p * p < 2 ** 15 else np.int64)
        self._extra_slot, self._extra = slot[~first], order[~first]
        self._all_vals, self._all_shift = vals, shift
        # m*s mod p indexes one table of unit roots, so that conjugate entries are exact conjugates
        self._roots = np.exp(2j * np.pi * np.arange(p) / p)
        self._real = [m for m in range(p // 2 + 1) if (2 * m) % p == 0]
        blocks = {m: self._block(m) for m in range(p // 2 + 1)}
        # one analysis of the complex pattern for the complex blocks, one of the same pattern in
        # real arithmetic for m = 0 (and p/2): their solves are the cheaper ones in every step
        label = f"the rotation-sector blocks of {what}"
        analysis = analyze(sp.csc_matrix((blocks[1], self._indices, self._indptr), shape=(k, k)), what=label)
        real = analyze(sp.csc_matrix((blocks[0], self._indices, self._indptr), shape=(k, k)), what=label)
        for an in (analysis, real):
            # the analyses keep the block's own pattern (every diagonal entry is stored already),
            # so the blocks' values are handed over in that order, unchecked against it again
            if not (np.array_equal(an.matrix.indptr, self._indptr) and np.array_equal(an.matrix.indices, self._indices)):
                raise RuntimeError("internal: the analysis reordered the sector blocks' pattern.")  # pragma: no cover
        self.views = {m: (real if m in self._real else analysis).with_values(blocks[m]) for m in blocks}
        # ||H||_1 from the representatives' columns (every column of an orbit has the same
        # moduli): an upper bound of every block's 1-norm, ||H_m||_1 <= ||H||_1
        sums = np.bincount(row_of, weights=np.abs(hvals), minlength=k)
        h_norm = float(sums.max()) if k else 0.0
        for view in self.views.values():
            # Hermitian by construction (the Bloch blocks of a symmetric H, real diagonal): the
            # factorisation layer's symmetry check (a full |A - A^H| per block) is not repeated;
            # every column of this route is residual-checked against H itself
            view._hermitian_of = view.matrix
            view.norm = h_norm
        # the Collatz-Wielandt data of sector 0 (e0_lower_bound): the diagonal of H at the
        # representatives, W the m = 0 block of the off-diagonal moduli |O| (its entries are the
        # moduli summed over each orbit; an entry of H's own diagonal is left out), the number of
        # entries of H per representative's row, and how far H's diagonal strays from its
        # representative's along an orbit (an on-site term invariant to rounding only)
        own = j == reps[row_of]
        absvals = np.concatenate([np.where(own, 0.0, np.abs(hvals)), np.zeros(k)])
        self._w0 = sp.csc_matrix((np.bincount(slot, weights=absvals[order], minlength=ukey.shape[0]),
                                  self._indices, self._indptr), shape=(k, k))
        self._d0 = np.zeros(k)
        self._d0[row_of[own]] = hvals[own]
        self._rows0 = count
        # diag: H's diagonal, None when it is zero (then so is every _d0)
        self._spread = (float(np.max(np.abs(diag - self._d0[orbits.orbit]))) * (1.0 + np.finfo(float).eps)
                        if diag is not None else 0.0)
        # the real orthogonal p x p matrix C of the sector coordinates u = C v[idx]: row 0 the
        # m = 0 part, then the real and imaginary parts of the m-th Fourier component
        # sum_s e^{-2 pi i m s / p} v[idx[s]] (times sqrt(2/p)), and the m = p/2 part for even p;
        # in these coordinates H - omega is block diagonal: one block H_m - omega per m
        ss = np.arange(p)
        rows, self._slots = [np.full(p, 1 / np.sqrt(p))], {0: (0, None)}
        for m in range(1, (p + 1) // 2):
            ang = 2 * np.pi * m * ss / p
            self._slots[m] = (len(rows), len(rows) + 1)
            rows += [np.sqrt(2 / p) * np.cos(ang), -np.sqrt(2 / p) * np.sin(ang)]
        if p % 2 == 0:
            self._slots[p // 2] = (len(rows), None)
            rows.append(np.where(ss % 2 == 0, 1.0, -1.0) / np.sqrt(p))
        self.C = np.array(rows)
        self.backend = analysis.backend
        # all blocks' factors are held at once: their total must fit (each analysis checked one)
        self.bytes_needed = sum(v.bytes_needed for v in self.views.values())

    def _block(self, m: int) -> np.ndarray:
        """The values of the Bloch block H_m on the blocks' pattern (``_indices``, ``_indptr``)."""
        p = self.p
        phase = (m * self._shift) % p                      # small integers: one table of roots
        if (2 * m) % p == 0:                               # a real block: m = 0 or p/2
            data = self._roots.real.take(phase)
            data *= self._vals
            extra = self._all_vals[self._extra] * self._roots[(m * self._all_shift[self._extra]) % p].real
            np.add.at(data, self._extra_slot, extra)
            return data
        data = self._roots.take(phase)
        data *= self._vals
        extra = self._all_vals[self._extra] * self._roots[(m * self._all_shift[self._extra]) % p]
        np.add.at(data, self._extra_slot, extra)
        data[self._diag] = data[self._diag].real          # a Hermitian diagonal is real
        return data

    def to_sites(self, V: np.ndarray, out: np.ndarray) -> np.ndarray:
        """Rows of V in orbit order (position s k + o) written into ``out`` in site order."""
        if len(self._runs) > self.n // 64:
            out[..., self.idx.reshape(-1)] = V
        else:
            for a, d, m in self._runs:
                out[..., d:d + m] = V[..., a:a + m]
        return out

    def gather(self, b: np.ndarray) -> np.ndarray:
        """Site vector(s) b of shape (N, ...) in orbit order: shape (p, k, ...), ``b[idx]``."""
        if len(self._runs) > self.n // 64:
            return b[self.idx]
        out = np.empty((self.p * self.k,) + b.shape[1:], dtype=b.dtype)
        for a, d, m in self._runs:
            out[a:a + m] = b[d:d + m]
        return out.reshape((self.p, self.k) + b.shape[1:])

    def scatter(self, u: np.ndarray, out: np.ndarray) -> np.ndarray:
        """The inverse of :meth:`gather`: u of shape (p, k, ...) into ``out`` (N, ...), ``out[idx] = u``."""
        if len(self._runs) > self.n // 64:
            out[self.idx] = u
            return out
        flat = u.reshape((self.p * self.k,) + u.shape[2:])
        for a, d, m in self._runs:
            out[d:d + m] = flat[a:a + m]
        return out

    def permuted(self, H: sp.csc_matrix) -> sp.csr_matrix:
        """H with rows and columns in orbit order (position s k + o: site idx[s, o]), built once."""
        if getattr(self, "_Hp", None) is None:
            perm = self.idx.reshape(-1)
            self._Hp = H.tocsr()[perm][:, perm].tocsr()
        return self._Hp

    def e0_upper(self, omega: float, steps: int = 12) -> float | None:
        r"""An upper bound of the lowest level from a short Lanczos run on the m = 0 block's inverse at ``omega``.

        None when :math:`H_0 - \omega` is not positive definite (ω above the lowest level).
        The largest Ritz value θ of :math:`(H_0-\omega)^{-1}` is at most its largest
        eigenvalue, so ω + 1/θ is at least the lowest level of :math:`H_0`, hence of H.
        """
        from scipy.linalg import eigvalsh_tridiagonal

        f = self.views[0].factor(omega, positive=True)
        if not f.positive_definite:
            return None
        q = np.full(self.k, 1 / np.sqrt(self.k))
        q_prev, b_prev, alpha, beta = np.zeros(self.k), 0.0, [], []
        for _ in range(min(steps, self.k)):
            w = f.solve(q).real
            a = float(q @ w)
            w -= a * q + b_prev * q_prev
            b = float(np.linalg.norm(w))
            alpha.append(a)
            if b <= np.finfo(float).eps * abs(a):
                break
            beta.append(b)
            q_prev, b_prev, q = q, b, w / b
        theta = eigvalsh_tridiagonal(np.array(alpha), np.array(beta[:len(alpha) - 1]))[-1]
        return omega + 1.0 / theta

    def ground_state(self, factor, steps: int = 3) -> np.ndarray:
        """A rotation-invariant approximation of the ground state: inverse iteration on the m = 0 block.

        Returns its orbit values φ (shape (k,)): the vector on the sites is ``φ[orbit]``.
        """
        v = np.ones(self.k)
        for _ in range(steps):
            v = factor.solve(v).real
            v /= np.abs(v).max()
        return v

    def e0_lower_bound(self, phi: np.ndarray) -> float:
        r"""A proved lower bound of the lowest eigenvalue of the whole H from positive orbit values φ.

        The bound of :func:`_e0_lower_bound` for the rotation-invariant vector
        :math:`v_i = \phi_{o(i)}` (o(i) the orbit of site i), computed in sector 0 alone (N/p
        values, no product with the whole H). Proof: let :math:`Z = D - |O|` (D the diagonal of
        H, O its off-diagonal part). The off-diagonal part is invariant under the rotation R
        exactly (every hop of a lattice Hamiltonian is -t, and R maps the lattice's edges onto
        edges), so the neighbours of :math:`i = R^s r_o` are the images under :math:`R^s` of the
        neighbours of the representative :math:`r_o`, with the same moduli and in the same
        orbits. Hence

        .. math:: \frac{(Zv)_i}{v_i} = D_{ii} - \frac{\sum_{j \ne i} |H_{ij}|\,\phi_{o(j)}}{\phi_o}
                  = D_{ii} - \frac{(W\phi)_o}{\phi_o},\qquad
                  W_{o o'} = \sum_{j \in o',\, j \ne r_o} |H_{r_o j}|,

        W the m = 0 Bloch block of :math:`|O|` (non-negative, N/p x N/p). With
        :math:`D_{ii} \ge D_{r_o r_o} - \sigma`, σ the largest deviation of H's diagonal from its
        representative's along an orbit (0 without an on-site term; at most 1e-12 of the term,
        the tolerance of :func:`~hyperlattice.graph.symmetry.rotation_invariant`, for an
        invariant one), Collatz–Wielandt for the Z-matrix Z (:func:`_e0_lower_bound`) gives

        .. math:: E_0(H) \ge \lambda_{min}(Z) \ge \min_i \frac{(Zv)_i}{v_i}
                  \ge \min_o \Big(D_{r_o r_o} - \frac{(W\phi)_o}{\phi_o}\Big) - \sigma .

        The rounding of :math:`(W\phi)_o` is bounded as in :func:`_e0_lower_bound`, with the number
        of entries of H in row :math:`r_o` (the same for every site of the orbit); it covers
        the sums forming W (at most that many non-negative terms). For :math:`H = -tA`, t > 0,
        Z = H and the Perron vector of H is rotation-invariant (it is unique), so φ from inverse
        iteration on the m = 0 block makes the bound as tight as the full one. ``-inf`` when φ
        is not positive everywhere.
        """
        phi = np.asarray(phi, dtype=float)
        if phi.shape != (self.k,) or not np.all(np.isfinite(phi)) or not np.all(phi > 0):
            return -np.inf
        z = self._w0 @ phi                               # (W phi)_o >= 0
        d = self._d0
        ratio = d - z / phi
        err = 8.0 * (self._rows0 + 1) * np.finfo(float).eps * (np.abs(d) + z / phi)
        return float(np.min(ratio - err)) - self._spread

    def factor(self, omega: float) -> "_SectorSolve | None":
        """The block factors at a real ω, or None when some block is not positive definite."""
        factors = {}
        for m, view in self.views.items():
            f = view.factor(omega, positive=True)
            if not f.positive_definite:
                return None
            factors[m] = f
        return _SectorSolve(self, omega, factors)


class _SectorSolve:
    r"""Solves with :math:`H - \omega` from the sector factors (real right-hand sides)."""

    def __init__(self, sectors: _SectorFactor, omega: float, factors: dict) -> None:
        self.sectors, self.sigma, self.factors = sectors, omega, factors
        self.backend = f"{sectors.backend} (rotation sectors)"
        self.kind = next(iter(factors.values())).kind
        self.positive_definite = True

    def to_sectors(self, b: np.ndarray) -> np.ndarray:
        """Site vector(s) (N,) or (N, c) to sector coordinates, shape (p, k[, c]) (orthogonal)."""
        sec = self.sectors
        v = sec.gather(b)
        return (sec.C @ v.reshape(sec.p, -1)).reshape(v.shape)

    def from_sectors(self, u: np.ndarray) -> np.ndarray:
        """The inverse of :meth:`to_sectors` (C is orthogonal)."""
        sec = self.sectors
        out = np.empty((sec.n,) + u.shape[2:])
        return sec.scatter((sec.C.T @ u.reshape(sec.p, -1)).reshape(u.shape), out)

    def apply(self, u: np.ndarray, out: np.ndarray | None = None) -> np.ndarray:
        r""":math:`(H - \omega)^{-1}` in sector coordinates (block by block), into ``out`` if given (not ``u``)."""
        sec = self.sectors
        out = np.empty_like(u) if out is None else out
        for m, f in self.factors.items():
            re, im = sec._slots[m]
            if im is None:
                out[re] = f.solve(u[re]).real
            else:
                x = f.solve(u[re] + 1j * u[im])
                out[re], out[im] = x.real, x.imag
        return out

    def solve(self, b: np.ndarray) -> np.ndarray:
        # to_sectors, apply and from_sectors with two work arrays of the size of b (every fresh
        # array of that size costs its page faults)
        sec = self.sectors
        v = sec.gather(np.asarray(b, dtype=float))
        shape = v.shape
        u = sec.C @ v.reshape(sec.p, -1)
        self.apply(u.reshape(shape), out=v)
        np.matmul(sec.C.T, v.reshape(sec.p, -1), out=u)
        return sec.scatter(u.reshape(shape), _prefaulted((sec.n,) + shape[2:]))


def _csr_matvec(A: sp.csr_matrix, x: np.ndarray, out: np.ndarray) -> np.ndarray:
    """out += A @ x for a CSR matrix (SciPy's kernel, into a buffer that is reused).

    SciPy's compiled kernel when its private module is there (no temporary of length n), else the
    public product.
    """
    try:
        from scipy.sparse import _sparsetools
        kernel = _sparsetools.csr_matvec
    except (ImportError, AttributeError):                 # pragma: no cover - other SciPy layouts
        out += A @ x
        return out
    kernel(A.shape[0], A.shape[1], A.indptr, A.indices, A.data, x, out)
    return out


def _prefaulted(shape, dtype=float) -> np.ndarray:
    """A zero array whose pages are mapped in one go (``MAP_POPULATE``), else ``np.zeros``.

    Large outputs and Krylov bases are written once: faulting their pages in one by one costs
    about 2 ms per MB on the shared benchmark machine, mapping them up front about 0.5 ms.
    """
    import mmap

    size = int(np.prod(shape)) * np.dtype(dtype).itemsize
    flags = getattr(mmap, "MAP_POPULATE", 0)
    if size < 1 << 22 or not flags:
        return np.zeros(shape, dtype=dtype)
    try:
        buf = mmap.mmap(-1, size, flags=mmap.MAP_PRIVATE | mmap.MAP_ANONYMOUS | flags)
    except (OSError, ValueError, OverflowError):
        return np.zeros(shape, dtype=dtype)
    return np.frombuffer(buf, dtype=dtype).reshape(shape)


class _Rows:
    """Vectors of length n appended one by one, stored in prefaulted blocks of ``block`` rows."""

    def __init__(self, n: int, block: int = 8) -> None:
        self.n, self.block, self.blocks, self.count = n, block, [], 0

    def new(self) -> np.ndarray:
        if self.count == len(self.blocks) * self.block:
            self.blocks.append(_prefaulted((self.block, self.n)))
        row = self.blocks[-1][self.count % self.block]
        self.count += 1
        return row

    def __len__(self) -> int:
        return self.count

    def parts(self):
        """(first row, block rows) pairs covering the stored rows in order."""
        for b, blk in enumerate(self.blocks):
            lo = b * self.block
            yield lo, blk[:min(self.block, self.count - lo)]


def _shifted_lanczos(apply_k, c: np.ndarray, deltas: np.ndarray, scale: tuple, a0_norm: float,
                     steps: int, forward: float = 0.0):
    r"""Galerkin solutions of :math:`(1 - \delta_i K)\,x_i = c` for many δ in one Krylov space of K.

    Hand-written: SciPy's ``cg`` solves one system at a time and no installed library runs the
    shifted family. Lanczos on the symmetric positive definite K (the three-term recurrence, no
    reorthogonalisation: the Galerkin solutions stay the conjugate-gradient iterates of each
    shift in finite precision), :math:`K Q_j = Q_j T_j + \beta_j q_{j+1} e_j^T`; for each δ,
    :math:`y = \|c\|(1 - \delta T_j)^{-1} e_1` through the eigenvectors of :math:`T_j`, and
    :math:`x = Q_j y` has the residual :math:`\delta \beta_j y_j q_{j+1}`, i.e. at most
    :math:`|\delta \beta_j y_j|\,\|H - \omega_0\|` for the system :math:`H - \omega`. A shift is
    done when that estimate is below a tenth of its acceptance bounds: the backward error
    :data:`_SCAN_BACKWARD` ``* (scale[0] * |x| + scale[1])`` (``scale``: the norms
    :math:`\|H-\omega_i\|_1` per shift and :math:`\|b\|`) and, when ``forward`` > 0, the forward
    error ``forward * d_i * |x|`` with :math:`d_i` the current estimate of the distance from
    :math:`\omega_i` to the spectrum; the caller checks the true residuals and certifies.

    Returns ``(Q, Y, done, e0_shift, top)``: Q (:class:`_Rows`, j rows) the Lanczos vectors, Y (j, S) the
    coefficients, ``done`` the shifts whose estimate converged, :math:`1/\theta_{max}` (the largest
    Ritz value of K is at most that of K itself, so :math:`\omega_0 + 1/\theta_{max}` bounds the
    lowest level from above) and ``top`` (j,), the coefficients of the Ritz vector of
    :math:`\theta_{max}` (an approximate ground state, positive for a Perron–Frobenius H).
    """
    from scipy.linalg import eigh_tridiagonal

    gamma = float(np.linalg.norm(c))
    Q = _Rows(c.shape[0])
    q = Q.new()
    np.multiply(c, 1.0 / gamma, out=q)
    alpha, beta = [], []
    q_prev, b_prev = np.zeros_like(c), 0.0
    tmp = np.empty_like(c)
    S = deltas.shape[0]
    done = np.zeros(S, dtype=bool)
    Y = np.zeros((1, S))
    inv_theta = np.inf
    top = np.ones(1)
    for j in range(steps):
        w = apply_k(q)
        # einsum, not BLAS, for the inner products: threaded level-1 BLAS runs 5-8x slower on a
        # loaded machine (and its last bits depend on the thread count)
        a = float(np.einsum("i,i->", q, w))
        w -= np.multiply(q, a, out=tmp)
        if b_prev:
            w -= np.multiply(q_prev, b_prev, out=tmp)
        b = float(np.sqrt(np.einsum("i,i->", w, w)))
        alpha.append(a)
        beta.append(b)
        theta, U = eigh_tridiagonal(np.array(alpha), np.array(beta[:-1]))
        denom = 1.0 - theta[:, None] * deltas[None, :]
        ok = np.all(denom > 0, axis=0)                       # 1 - delta K positive definite so far
        Z = U[0][:, None] / np.where(denom > 0, denom, 1.0)
        Y = gamma * (U @ Z)
        last = np.abs(Y[-1])
        xnorm = gamma * np.linalg.norm(Z, axis=0)
        est = np.abs(deltas) * b * last * a0_norm
        target = _SCAN_BACKWARD * (scale[0] * xnorm + scale[1])
        inv_theta = 1.0 / float(theta[-1]) if theta[-1] > 0 else np.inf
        top = U[:, -1]
        if forward > 0 and np.isfinite(inv_theta):
            # distance to the lowest level as the Ritz value sees it (an overestimate early on)
            dist = np.maximum(inv_theta - deltas, 0.0)
            target = np.minimum(target, forward * dist * xnorm)
        done = ok & (est <= 0.1 * target)
        if np.all(done) or b <= np.finfo(float).eps * abs(a):
            done |= ok & (b <= np.finfo(float).eps * abs(a))   # an invariant subspace: exact
            break
        q_prev, b_prev = q, b
        q = Q.new()
        np.multiply(w, 1.0 / b, out=q)
    while len(Q) > Y.shape[0]:            # the last vector was made but not used
        Q.count -= 1
    return Q, Y, done, inv_theta, top


def _e0_lower_bound(H: sp.csc_matrix, v: np.ndarray) -> float:
    r"""A proved lower bound of the lowest eigenvalue of the Hermitian H from a positive vector v.

    With :math:`Z = D - |O|` (D the diagonal of H, :math:`|O|` its off-diagonal part taken
    entrywise in modulus), :math:`x^\dagger H x \ge |x|^T Z |x|`, so :math:`E_0(H) \ge
    \lambda_{min}(Z)`; Z is a symmetric Z-matrix, and for every v > 0 the Collatz–Wielandt
    inequality for the nonnegative :math:`cI - Z` gives :math:`\lambda_{min}(Z) \ge
    \min_i (Zv)_i / v_i`. The bound is tight when v is the ground state of Z (for
    :math:`H = -tA`, t > 0, Z = H). The rounding of :math:`(Zv)_i` (three ulps of
    :math:`(|H| v)_i` per row for these graphs, taken as 8 n_row ulps) is subtracted.
    ``-inf`` when v is not positive everywhere.
    """
    v = np.asarray(v, dtype=float)
    if v.size == 0 or not np.all(np.isfinite(v)) or not np.all(v > 0):
        return -np.inf
    d = H.diagonal().real
    absH = abs(H)
    z = absH @ v - np.abs(d) * v                     # (|O| v)_i >= 0
    rows = np.diff(H.tocsr().indptr) if H.format != "csc" else np.diff(H.indptr)   # H Hermitian: column = row counts
    ratio = d - z / v
    err = 8.0 * (rows + 1) * np.finfo(float).eps * (np.abs(d) + z / v)
    return float(np.min(ratio - err))


class GraphResolvent:
    r"""The resolvent :math:`(H-\omega)^{-1}` of one lattice Hamiltonian for many :math:`\omega`.

    ``method="dense"`` diagonalises :math:`H = V\,\mathrm{diag}(E)\,V^T` once
    (:math:`O(N^3)`); afterwards a column costs :math:`O(N^2)` per :math:`\omega` via
    ``eq20`` and the distance of :math:`\omega` to the spectrum is known exactly. That pays
    for :math:`N \lesssim 4000` and more than a few :math:`\omega`. ``method="sparse"``
    factorises :math:`H-\omega` through :mod:`hyperlattice.graph.factor` once per :math:`\omega`
    (below the spectrum an :math:`LDL^T`/Cholesky without pivoting, CHOLMOD when installed, whose
    pivots prove :math:`\omega < E_0`; elsewhere SuperLU's pivoted LU; the fill-in is tiny on these
    graphs) and keeps the factorization of the last :math:`\omega`, so several sources at one
    :math:`\omega` reuse it; ``backend`` records what ran. ``"auto"`` picks sparse.

    A complex Hermitian :math:`H` (Peierls phases of a flux, :mod:`hyperlattice.graph.flux`) is
    kept complex: ``dense`` then uses :math:`V^\dagger` in ``eq20`` and ``sparse`` factorises the
    complex :math:`H - \omega` (Cholesky-type below the band, where it is Hermitian positive definite).

    Parameters
    ----------
    system : Lattice or sparse/dense matrix
        A lattice (then :math:`H` = :func:`hyperlattice.graph.operators.hamiltonian`) or :math:`H`,
        real symmetric or complex Hermitian.
    t : float
        Hopping amplitude (lattice input only).
    onsite : callable, array or None
        On-site term (lattice input only), as in :func:`~hyperlattice.graph.operators.hamiltonian`.
    method : {"auto", "dense", "sparse"}
        See above; default ``"auto"`` (sparse).

    Raises
    ------
    ValueError
        On a non-square or non-Hermitian matrix, an unknown method, ``dense`` above
        ``_DENSE_MAX`` sites, and (in the evaluation methods) for :math:`\omega` on the real
        spectrum to within rounding.

    Notes
    -----
    :math:`\omega` is in the unit of H (units of t for a lattice with t = 1); rows and columns
    are sites, 0-based ring by ring. With this sign convention :math:`G(\omega) > 0` on the
    diagonal below the band.

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.graph.green import GraphResolvent
    >>> res = GraphResolvent(hl.ring_lattice(7, 3, 2))
    >>> g = res.column(-3.5, 0)
    >>> res.method, g.shape, round(float(g[0].real), 6), round(float(g[1].real), 6)
    ('sparse', (35,), 0.412092, 0.14892)
    """

    def __init__(self, system, *, t: float = 1.0, onsite=None, method: str = "auto") -> None:
        method = _validate.choice("method", method, ("auto", "dense", "sparse"))
        t = _validate.real("the hopping t", t)
        if isinstance(system, Lattice) and onsite is None:
            # H = -tA straight from the neighbour lists: hamiltonian(system, t), without its
            # intermediate copies (the adjacency's ones, then their product with -t)
            _validate.lattice(system)
            indptr, indices = system.neighbours()
            H = sp.csr_matrix((np.full(indices.shape[0], -t), indices, indptr), shape=(system.sites,) * 2)
            H.has_sorted_indices = True
        elif isinstance(system, Lattice):
            H = hamiltonian(system, t=t, onsite=onsite)
        else:
            if t != 1.0 or onsite is not None:
                raise ValueError("t and onsite apply to a lattice; a matrix H is used as given.")
            # the one door for matrices: Hermitian up to rounding, then symmetrised; float64, or
            # complex128 when an entry has a nonzero imaginary part
            H = _validate.hermitian_matrix("the Hamiltonian", system)
        if isinstance(system, Lattice) and np.iscomplexobj(H.data):
            if np.any(H.data.imag != 0):
                raise ValueError("the on-site term must be real so that H is Hermitian.")
            H = H.real
        H = H.astype(complex if np.iscomplexobj(H.data) else float, copy=False)
        if H.format == "csr":
            # H is Hermitian: its CSR arrays read as CSC hold H^T = conj(H), no conversion needed
            data = H.data.conj() if np.iscomplexobj(H.data) else H.data
            H = sp.csc_matrix((data, H.indices, H.indptr), shape=H.shape)
        self.H = H.tocsc()
        self.n = H.shape[0]
        # the rotation-sector route: a large lattice whose H commutes with its rotation (real H)
        self._sectors = None
        self._sector_ok = bool(isinstance(system, Lattice) and self.n >= _SECTOR_MIN
                               and not np.iscomplexobj(self.H.data)
                               and getattr(system, "rotation", None) is not None
                               and (onsite is None or rotation_invariant(system, onsite)))
        self._lattice = system if self._sector_ok else None
        if method == "auto":
            method = "sparse"
        if method == "dense" and self.n > _DENSE_MAX:
            raise ValueError(f"the dense method is limited to {_DENSE_MAX} sites (this lattice has {self.n}).")
        self.method = method
        # column sums of |H| (= row sums, H Hermitian): ||H||_1 >= ||H||_2 and the Gershgorin discs,
        # in one pass over H without temporaries (_csc_stats)
        norm, lower, d_row, diag_nonzero = _csc_stats(self.H)
        self.norm = norm
        # the rounding of a computed residual b - (H - omega) x is at most gamma (|b| + (|H| +
        # |omega|)|x|) entrywise, gamma = (d + 2) eps / (1 - (d + 2) eps) for d entries per row:
        # added to every residual norm a proved error bound is built from
        self._gamma = (d_row + 2) * np.finfo(float).eps / (1.0 - (d_row + 2) * np.finfo(float).eps)
        self._eig = None
        self._lu = None
        self._lu_omega = None
        self._analysis = None      # graph/factor analysis for omega below the band (Cholesky-type)
        self._general = None       # graph/factor analysis for the pivoted LU elsewhere
        self.backend = ""          # the factorisation backend of the last sparse omega
        # a lower bound of the spectrum (Gershgorin): below it H - omega is positive definite
        self._lower = lower
        self._diagonal = self.H.diagonal() if diag_nonzero else None      # None: all zero
        # an upper bound of E0 (the Rayleigh quotient of the constant vector): a real omega below
        # it may lie below the spectrum, so the positive-definite factorisation is tried first;
        # _band: the lowest real omega where it was found indefinite (omega above it: pivoted LU)
        self._upper = float(np.real(self.H.data.sum())) / self.n if self.n else 0.0
        self._band = np.inf
        # proved lower bounds of E0: the highest omega whose positive-definite factorisation
        # succeeded, and the Collatz-Wielandt bound of a scan's Ritz vector (_e0_lower_bound)
        self._proved_below = -np.inf
        self._e0_lower = -np.inf
        self._routes: dict = {}
        self._last = None
        self._many_direct = False
        #: what the last :func:`graph_green` call did, per omega: ``route`` (``"dense"``,
        #: ``"factorisation"``, ``"rotation sectors"``, ``"pivoted LU"``, ``"krylov scan"``),
        #: ``backward_error`` (the largest normwise backward error
        #: ||b - (H - omega) x|| / (||H - omega||_1 ||x|| + ||b||) over the sources) and
        #: ``error_bound`` (a proved bound of the relative 2-norm error ||x - x*|| / ||x*||, from
        #: the residual and a proved distance to the spectrum; NaN where no such distance is known)
        self.report: dict = {}

    # -- spectrum checks -------------------------------------------------------
    def _tol(self, omega: complex) -> float:
        return _ON_SPECTRUM * np.finfo(float).eps * max(1.0, self.norm + abs(omega))

    def _on_spectrum_error(self, omega: complex, detail: str) -> ValueError:
        return ValueError(
            f"omega = {omega:g} lies on (or within rounding of) the real spectrum of H ({detail}); "
            "the graph Green function does not exist there. Give omega a small imaginary part.")

    def _eigh(self) -> tuple[np.ndarray, np.ndarray]:
        if self._eig is None:
            self._eig = sla.eigh(self.H.toarray())
        return self._eig

    def _factor(self, omega: complex):
        """The factorisation of H - omega (graph/factor), cached for the last omega.

        Below the spectrum a Cholesky-type factorisation without pivoting (CHOLMOD when installed)
        is tried first: its success proves omega < E0 and it is the fastest. Elsewhere (inside the
        band, complex omega) a pivoted LU, stable for an indefinite or non-Hermitian H - omega.
        """
        from .factor import FactorizationError, analyze

        if self._lu is not None and self._lu_omega == omega:
            return self._lu
        shift = omega.real if omega.imag == 0 else omega      # real arithmetic for real omega
        what = f"H - omega of the {self.n:,}-site lattice"
        try:
            lu = None
            if omega.imag == 0 and omega.real < max(self._lower, min(self._upper, self._band)):
                lu = self._positive_factor(omega.real, what)
            if lu is None:
                if self._general is None:
                    self._general = analyze(self.H, backend="superlu", what=what)
                lu = self._general.factor(shift, pivoting=True)
        except FactorizationError as exc:     # exactly singular: omega is an eigenvalue
            raise self._on_spectrum_error(omega, "singular factorization") from exc
        if lu.kind == "LU":
            piv = np.abs(lu._lu.U.diagonal())
            if piv.size and piv.min() <= self._tol(omega):
                raise self._on_spectrum_error(omega, f"LU pivot {piv.min():.1e}")
        self._lu, self._lu_omega = lu, omega
        self.backend = lu.backend
        return lu

    def _sector_factor(self, what: str):
        """The rotation-sector factorisation (built once), or None where it does not apply or fit."""
        from .factor import available_memory

        if self._sectors is None and self._sector_ok:
            try:
                sectors = _SectorFactor(self._lattice, self.H, what, self._diagonal)
            except ValueError:                  # the rotation does not act freely: no sectors
                sectors = None
            if sectors is not None and sectors.bytes_needed > available_memory():
                sectors = None                  # the full factorisation refuses in one sentence
            self._sectors = sectors if sectors is not None else False
            self._sector_ok = sectors is not None
        return self._sectors or None

    def _positive_factor(self, omega: float, what: str):
        """A factorisation of H - omega that proves it positive definite, or None (then omega is in the band)."""
        from .factor import analyze

        # several omegas in a row: one full analysis and one real factorisation per omega are
        # cheaper than p/2 + 1 sector blocks (three of them complex) per omega; the sectors win
        # for one omega, where the full matrix's analysis is most of the cost
        full = self._many_direct and self._sectors is None
        sectors = self._sector_factor(what) if self._sector_ok and not full else None
        if sectors is not None:
            lu = sectors.factor(omega)
        else:
            if self._analysis is None:
                self._analysis = analyze(self.H, what=what)
            lu = self._analysis.factor(omega, positive=True)
            if not lu.positive_definite:
                lu = None
        if lu is None:
            self._band = min(self._band, omega)
        else:
            self._proved_below = max(self._proved_below, omega)
        return lu

    def _proved_residual(self, rn, xn, omega, bn):
        """A computed residual norm plus the bound of its rounding (see ``_gamma``)."""
        return rn + self._gamma * (bn + (self.norm + np.abs(omega)) * xn)

    def _delta_lower(self, omega):
        """A proved lower bound of the distance from real omega to the spectrum (<= 0: none known)."""
        e0 = max(self._lower, self._e0_lower, self._proved_below)
        return e0 - np.asarray(omega, dtype=float)

    def _errors(self, omega: complex, rhs: np.ndarray, x: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Per column: the normwise backward error, the proved relative forward error bound (NaN: none) and ||x||.

        Forward: ||x - x*|| <= ||r|| / delta with delta the distance from omega to the spectrum of
        the Hermitian H (at least |Im omega|, or the proved :meth:`_delta_lower` for real omega);
        relative to ||x*|| >= ||x|| - ||r|| / delta.
        """
        # real arithmetic for a real omega and real x (a complex scalar would double the work)
        w = omega.real if omega.imag == 0 else omega
        if (x.ndim == 2 and x.shape[1] == 1 and x.dtype == float and rhs.dtype == float
                and self.H.dtype == float and omega.imag == 0):
            # one real column: r = rhs - (H x - w x) in one work array, H^T = H read as CSR (no
            # copy); the rounding bound (_gamma) holds for any order of the d + 2 terms
            x1, b1 = x[:, 0], rhs[:, 0]
            r = np.multiply(x1, -w)
            _csr_matvec(sp.csr_matrix((self.H.data, self.H.indices, self.H.indptr), shape=self.H.shape), x1, r)
            np.subtract(b1, r, out=r)
            # einsum, not BLAS: the last bits do not depend on the thread count
            rn = np.array([np.sqrt(np.einsum("i,i->", r, r))])
            xn = np.array([np.sqrt(np.einsum("i,i->", x1, x1))])
            bn = np.array([np.sqrt(np.einsum("i,i->", b1, b1))])
        else:
            r = self.H @ x
            if np.iscomplexobj(w) or np.iscomplexobj(r) or np.iscomplexobj(rhs):
                r = rhs - (r - w * x)
            else:
                r -= w * x
                np.subtract(rhs, r, out=r)
            rn = np.linalg.norm(r, axis=0)
            xn = np.linalg.norm(x, axis=0)
            bn = np.linalg.norm(rhs, axis=0)
        back = rn / ((self.norm + abs(omega)) * xn + bn)
        delta = abs(omega.imag) if omega.imag != 0 else float(self._delta_lower(omega.real))
        if delta > 0:
            err = self._proved_residual(rn, xn, omega, bn) / delta
            fwd = np.where(err < xn, err / np.maximum(xn - err, np.finfo(float).tiny), np.inf)
        else:
            fwd = np.full(rn.shape, np.nan)
        back = np.where(np.isfinite(rn), back, np.inf)
        return back, fwd, xn

    # -- evaluation ------------------------------------------------------------
    def columns(self, omega, sources) -> np.ndarray:
        r"""Columns :math:`G_{\cdot j}(\omega)` for the given sources: array ``(N, len(sources))``.

        Parameters
        ----------
        omega : complex
            One frequency, off the real spectrum of H.
        sources : sequence of int
            Source sites j (0-based).

        Returns
        -------
        numpy.ndarray of complex128, shape (N, len(sources))
            Column k is :math:`G_{\cdot j_k}(\omega)`.
        """
        om, _ = _as_omegas(omega)
        if om.size != 1:
            raise ValueError("columns() takes one omega; use graph_green for several.")
        omega = complex(om[0])
        src = _validate.site_indices("sources", sources, self.n)
        if self.method == "dense":
            E, V = self._eigh()
            dist = np.min(np.abs(E - omega))
            if dist <= self._tol(omega):
                raise self._on_spectrum_error(omega, f"distance {dist:.1e} to an eigenvalue")
            out = (V / (E - omega)) @ V[src].conj().T
            # eq20 with the exact distance to the spectrum: rounding only (not bounded here)
            self._last = ("dense", np.nan, np.nan)
        else:
            lu = self._factor(omega)
            rhs = np.zeros((self.n, src.size), dtype=float if omega.imag == 0 and self.H.dtype == float else complex)
            rhs[src, np.arange(src.size)] = 1.0
            out = lu.solve(rhs)
            e0_before = self._e0_lower
            if omega.imag == 0 and lu.kind != "LU" and not self._delta_lower(omega.real) > 0:
                # a proved distance to the spectrum for the error bound: Collatz-Wielandt with
                # three steps of inverse iteration from the constant vector (positive for a
                # Perron-Frobenius H; otherwise no bound is claimed); on the sector route in
                # sector 0 alone (_SectorFactor.e0_lower_bound)
                if isinstance(lu, _SectorSolve):
                    sec = lu.sectors
                    bound = sec.e0_lower_bound(sec.ground_state(lu.factors[0]))
                else:
                    v = np.ones(self.n)
                    for _ in range(3):
                        v = lu.solve(v).real
                        v /= np.abs(v).max()
                    bound = _e0_lower_bound(self.H, v)
                self._e0_lower = max(self._e0_lower, bound)
            back, fwd, xn = self._errors(omega, rhs, out)
            if isinstance(lu, _SectorSolve) and not np.all(back <= _SCAN_BACKWARD):
                # the sector blocks do not reproduce H (an on-site term invariant only to
                # rounding): the full factorisation from now on, and no bound from sector 0
                self._sector_ok, self._sectors, self._lu, self._lu_omega = False, False, None, None
                self._e0_lower = e0_before
                lu = self._factor(omega)
                out = lu.solve(rhs)
                back, fwd, xn = self._errors(omega, rhs, out)
            route = ("rotation sectors" if isinstance(lu, _SectorSolve)
                     else "pivoted LU" if lu.kind == "LU" else "factorisation")
            self._last = (route, float(np.max(back, initial=0.0)), float(np.max(fwd, initial=0.0)))
            # ||(H - omega)^{-1}||_2 = 1/dist(omega, spectrum) for Hermitian H: a column this
            # large means the factorization was done within rounding of an eigenvalue
            big = float(np.max(xn)) if src.size else 0.0
            if not (np.isfinite(big) and np.all(np.isfinite(xn))) or big * self._tol(omega) >= 1.0:
                raise self._on_spectrum_error(omega, f"column norm {big:.1e}")
            if not np.iscomplexobj(out):
                # the complex result in pages mapped in one go (_prefaulted), the real part copied in
                res = _prefaulted(out.shape, complex)
                res.real[...] = out
                return res
        return out.astype(complex)

    def _scan(self, oms: np.ndarray, src: np.ndarray) -> tuple[set, np.ndarray | None]:
        """Columns for many real omegas below the band through shared Krylov spaces (module docstring).

        Returns ``(taken, out)``: ``out`` (complex, shape ``(len(oms), N, len(src))``, or None
        when the scan does not apply) holds the columns of the omegas ``taken``, whose every
        column met both acceptance bounds (backward error :data:`_SCAN_BACKWARD`, proved forward
        error :data:`_FORWARD_TOL`), recorded in :attr:`_routes`; the caller factorises the
        others one by one (into ``out``).
        """
        from .factor import available_memory

        k = src.size
        if self.method != "sparse" or np.iscomplexobj(self.H.data) or k == 0:
            return set(), None
        bound = max(self._lower, min(self._upper, self._band))
        cand = np.flatnonzero((oms.imag == 0) & (oms.real < bound))
        values = np.unique(oms.real[cand])
        S = values.size
        if S < _SCAN_MIN or S * (_SCAN_FACTOR + k) < _SCAN_TYPICAL * k:
            return set(), None
        # the Lanczos vectors, their site-order copy and H times them take 3 x 8 N bytes each:
        # at most 3/8 of the free memory; the output was sized by the caller
        free = available_memory()
        steps = int(min(_SCAN_STEPS, free // (64 * self.n) - 1))
        if steps < 8 or 16 * self.n * k * oms.size > free // 2:
            return set(), None
        out = _prefaulted((oms.size, self.n, k), complex)
        what = f"H - omega of the {self.n:,}-site lattice"
        found: dict[float, tuple] = {}
        e0_upper = np.inf
        pending = values
        # H^T = H: the CSC arrays read as CSR (no copy)
        Ht = sp.csr_matrix((self.H.data, self.H.indices, self.H.indptr), shape=self.H.shape)
        where: dict[float, list] = {}
        for i in cand:
            where.setdefault(float(oms[i].real), []).append(int(i))
        for _ in range(_SCAN_ANCHORS):
            if np.isfinite(e0_upper):
                pending = pending[pending < e0_upper]
            if pending.size < _SCAN_MIN:
                break
            if not np.isfinite(e0_upper):
                w0 = float(np.median(pending))
                sectors = self._sector_factor(what) if self._sector_ok else None
                if sectors is not None:
                    # the lowest level from the m = 0 block alone (p times smaller): the anchor
                    # can then balance the condition of the shifts on both sides of it
                    est = sectors.e0_upper(w0)
                    if est is None:
                        pending, e0_upper = pending[pending < w0], w0
                        continue
                    e0_upper = est
                    pending = pending[pending < e0_upper]
                    if pending.size < _SCAN_MIN:
                        break
            if np.isfinite(e0_upper):
                # balance the condition (E0 - w_min)/(E0 - w0) = (E0 - w0)/(E0 - w_max) of the shifts
                d = e0_upper - pending
                w0 = float(e0_upper - np.sqrt(d.max() * d.min()))
            lu = self._positive_factor(w0, what)
            if lu is not None:
                self.backend = lu.backend
            if lu is None:                    # w0 is in the band, and so is every omega above it
                pending = pending[pending < w0]
                e0_upper = min(e0_upper, w0)
                continue
            self._proved_below = max(self._proved_below, w0)   # the factorisation proved w0 < E0
            deltas = pending - w0
            hn = self.norm + np.abs(pending)
            accepted = np.ones(pending.size, dtype=bool)
            info = np.zeros((pending.size, 3))                # backward error, forward bound, max |x|
            xbuf = _prefaulted((min(32, pending.size), self.n))
            tbuf, rbuf = np.empty((1, self.n)), np.empty(self.n)
            if isinstance(lu, _SectorSolve):
                # the Krylov space in sector coordinates (an orthogonal change of basis), where
                # K is block diagonal: no transform per step; the Lanczos vectors are taken to
                # site order once, all together
                sec = lu.sectors
                apply = lambda q: lu.apply(q.reshape(sec.p, sec.k)).reshape(-1)        # noqa: E731
                start = lambda b: lu.apply(lu.to_sectors(b)).reshape(-1)                # noqa: E731

                buf = np.empty((sec.p, sec.k))

                def to_sites(Q):
                    # one contiguous array, row by row: orbit order (C^T per orbit), then sites
                    Qs = _prefaulted((len(Q), self.n))
                    for lo, blk in Q.parts():
                        for r, q in enumerate(blk):
                            np.matmul(sec.C.T, q.reshape(sec.p, sec.k), out=buf)
                            sec.to_sites(buf.reshape(-1), Qs[lo + r])
                    return Qs
            else:
                def to_sites(Q):
                    Qs = _prefaulted((len(Q), self.n))
                    for lo, blk in Q.parts():
                        Qs[lo:lo + blk.shape[0]] = blk
                    return Qs

                apply, start = lu.solve, lu.solve
            for c_i, j in enumerate(src):
                b = np.zeros(self.n)
                b[j] = 1.0
                Q, Y, done, inv_theta, top = _shifted_lanczos(apply, start(b), deltas, (hn, 1.0),
                                                              self.norm + abs(w0), steps, _FORWARD_TOL)
                e0_upper = min(e0_upper, w0 + inv_theta)
                Qs = to_sites(Q)
                del Q
                # a proved lower bound of E0 from the Ritz vector of the lowest level (positive
                # for a Perron-Frobenius H), by Collatz-Wielandt (_e0_lower_bound)
                v = top @ Qs
                v = v if v.sum() >= 0 else -v
                self._e0_lower = max(self._e0_lower, _e0_lower_bound(self.H, v))
                delta = self._delta_lower(pending)
                some = np.flatnonzero(done & accepted)
                if some.size:
                    # x = Q^T y for every shift, 32 at a time (one matrix product each), and
                    # the true residuals (H - omega) x - b, one sparse product per column
                    first = np.array([where[float(pending[i])][0] for i in some])
                    rn, xn = np.empty(some.size), np.empty(some.size)
                    outr, r = out.real, rbuf
                    for lo in range(0, some.size, 32):
                        part = some[lo:lo + 32]
                        X = np.matmul(np.ascontiguousarray(Y[:, part].T), Qs, out=xbuf[:part.size])
                        for r_i, x in enumerate(X):
                            i, t = part[r_i], first[lo + r_i]
                            outr[t, :, c_i] = x
                            r[:] = 0.0
                            _csr_matvec(Ht, x, r)
                            r -= np.multiply(x, pending[i], out=tbuf[0])
                            r[j] -= 1.0
                            rn[lo + r_i] = np.sqrt(np.einsum("i,i->", r, r))
                            xn[lo + r_i] = np.sqrt(np.einsum("i,i->", x, x))
                    back = rn / (hn[some] * xn + 1.0)
                    fwd = np.where(delta[some] > 0,
                                   self._proved_residual(rn, xn, pending[some], 1.0)
                                   / np.where(delta[some] > 0, delta[some], 1.0), np.inf)
                    # the proved error within _FORWARD_TOL, or the residual below its own
                    # rounding bound (then nothing evaluated in floating point proves more: the
                    # bound is what a direct solve proves there too, within a factor 2)
                    floor = self._proved_residual(0.0, xn, pending[some], 1.0)
                    ok = (np.isfinite(rn) & (back <= _SCAN_BACKWARD)
                          & ((fwd <= _FORWARD_TOL * (xn - fwd)) | ((rn <= floor) & (fwd < xn))))
                    done[some] = ok
                    for r_i, (i, t) in enumerate(zip(some, first)):
                        if ok[r_i]:
                            for t2 in where[float(pending[i])][1:]:
                                out[t2, :, c_i] = out[t, :, c_i]
                            info[i] = np.maximum(info[i], (back[r_i], fwd[r_i] / (xn[r_i] - fwd[r_i]), xn[r_i]))
                accepted &= done
                del Qs
            for i in np.flatnonzero(accepted):
                found[float(pending[i])] = info[i]
            pending = pending[~accepted]
            if pending.size == 0:
                break
        taken = set()
        for i in cand:
            got = found.get(float(oms[i].real))
            if got is None:
                continue
            back, fwd, big = got
            if big * self._tol(complex(oms[i])) >= 1.0:        # as in columns(): omega on the spectrum
                raise self._on_spectrum_error(complex(oms[i]), f"column norm {big:.1e}")
            taken.add(int(i))
            self._routes[int(i)] = ("krylov scan", back, fwd)
        return taken, out

    def column(self, omega, source) -> np.ndarray:
        r"""One column :math:`G_{\cdot j}(\omega)` (all targets i for source j), shape ``(N,)``.

        Parameters
        ----------
        omega : complex
            One frequency, off the real spectrum of H.
        source : int
            The source site j (0-based).

        Returns
        -------
        numpy.ndarray of complex128, shape (N,)
            :math:`G_{ij}(\omega)` for every target i.
        """
        source = _validate.site_index("source", source, self.n)
        return self.columns(omega, [source])[:, 0]

    def entries(self, omega, rows, cols) -> np.ndarray:
        r"""Entries :math:`G_{r_k c_k}(\omega)` for paired index arrays (one solve per distinct column).

        Parameters
        ----------
        omega : complex
            One frequency, off the real spectrum of H.
        rows, cols : sequence of int
            Paired site indices (0-based); a length-1 array pairs with every entry of the other.

        Returns
        -------
        numpy.ndarray of complex128
            :math:`G_{r_k c_k}(\omega)`, one per pair.
        """
        rows = _validate.site_indices("rows", rows, self.n)
        cols = _validate.site_indices("cols", cols, self.n)
        if rows.size != cols.size and 1 not in (rows.size, cols.size):
            raise ValueError(f"rows and cols must pair up: got {rows.size} rows and {cols.size} cols.")
        rows, cols = np.broadcast_arrays(rows, cols)
        ucols, inv = np.unique(cols, return_inverse=True)
        block = self.columns(omega, ucols)
        return block[rows, inv]


_KERNELS: dict = {}


def _csc_stats(H: sp.csc_matrix) -> tuple[float, float, int, bool]:
    r"""One pass over the Hermitian H: ``(||H||_1, Gershgorin lower bound, most entries in a column,
    whether some diagonal entry is nonzero)``.

    The column sums of |H| are added in storage order (as ``np.add.reduceat`` does for short
    columns); the Gershgorin bound is :math:`\min_i (\mathrm{Re}\,H_{ii} - (c_i - |H_{ii}|))`, c_i the
    column sum. Numba, so that no array of the size of H is made.
    """
    if H.shape[0] == 0:
        return 0.0, 0.0, 0, False
    if "stats" not in _KERNELS:
        import numba

        @numba.njit(cache=True)
        def stats(indptr, indices, data):          # pragma: no cover - compiled
            n = indptr.shape[0] - 1
            norm = 0.0
            lower = np.inf
            most = 0
            nonzero = False
            for c in range(n):
                s = 0.0
                dr = 0.0
                da = 0.0
                for q in range(indptr[c], indptr[c + 1]):
                    a = abs(data[q])
                    s += a
                    if indices[q] == c:
                        dr = data[q].real
                        da = a
                norm = max(norm, s)
                lower = min(lower, dr - (s - da))
                most = max(most, indptr[c + 1] - indptr[c])
                nonzero = nonzero or dr != 0.0
            return norm, lower, most, nonzero

        _KERNELS["stats"] = stats
    norm, lower, most, nonzero = _KERNELS["stats"](H.indptr, H.indices, H.data)
    return float(norm), float(lower), int(most), bool(nonzero)


def _free_memory() -> int:
    from .factor import available_memory

    return available_memory()


def graph_green(lattice, omega, source=None, targets=None, *, t: float = 1.0, onsite=None,
                method: str = "auto") -> np.ndarray:
    r"""Graph Green function :math:`G_{ij}(\omega) = [(H-\omega)^{-1}]_{ij}` of :math:`H = -tA + V`.

    This is the paper's Eq. (18) (``eq20``),

    .. math:: G_{ij}(\omega) = \sum_{n=1}^N \frac{\psi_n(i)\psi_n^*(j)}{E_n-\omega},

    evaluated by a sparse factorisation of :math:`H - \omega` or, for many :math:`\omega`
    on small lattices, from one dense eigendecomposition (:class:`GraphResolvent`). Below the
    band, :math:`\omega < E_0`, it is compared with the continuum Green function through the
    dictionary :math:`\lambda = 4(\omega + q)/(q h^2)` (Eq. (19)).

    Parameters
    ----------
    lattice : Lattice or matrix
        The lattice (then :math:`H` = :func:`~hyperlattice.graph.operators.hamiltonian`) or
        :math:`H` itself (sparse or dense), real symmetric or complex Hermitian (a flux
        Hamiltonian, ``hamiltonian(lattice, flux=f)``).
    omega : complex or 1-d array_like
        Frequency :math:`\omega`, in units of t; real values must not lie on the spectrum.
        Several values reuse one eigendecomposition when ``method="dense"`` (worth it for many
        :math:`\omega` and :math:`N \lesssim 4000`).
    source : int, sequence of int, or None, optional
        Source site(s) j (0-based, ring 1 first, each ring counterclockwise). ``None``
        (default): the full matrix (small lattices only, N <= 4000).
    targets : int or sequence of int, optional
        Restrict the result to these target sites i (0-based); default: all sites.
    t : float, optional
        Hopping amplitude (lattice input only); default 1.
    onsite : scalar, array or callable, optional
        On-site term V in units of t (lattice input only); default None.
    method : {"auto", "dense", "sparse"}, optional
        See :class:`GraphResolvent`; ``"auto"`` (default) picks sparse.

    Returns
    -------
    numpy.ndarray of complex128
        Shape ``(N,)`` for one source, ``(N, k)`` for k sources, ``(N, N)`` for ``source=None``
        (first axis restricted to ``targets`` if given); a leading axis of length
        ``len(omega)`` if ``omega`` is an array. Units of 1/t.

    Raises
    ------
    ValueError
        Bad site index, NaN omega, omega on the spectrum (to within rounding), a non-Hermitian
        matrix, ``t``/``onsite`` given with a matrix, or a lattice too large for a
        full matrix or the dense method (more than 4000 sites).

    See Also
    --------
    GraphResolvent, hyperlattice.continuum.green.continuum_green,
    hyperlattice.compare.green.compare_green

    References
    ----------
    .. [1] I. Boettcher et al., Phys. Rev. A 102, 032208 (2020), Eqs. (18) and (19).

    Examples
    --------
    >>> import hyperlattice as hl
    >>> lat = hl.ring_lattice(7, 3, 2)
    >>> g = hl.graph_green(lat, -3.5, source=0)
    >>> g.shape, round(float(g[0].real), 6), round(float(g[1].real), 6)
    ((35,), 0.412092, 0.14892)
    >>> G = hl.graph_green(lat, [-3.5, -4.0], source=0, targets=[0, 1])
    >>> G.shape
    (2, 2)
    """
    res = lattice if isinstance(lattice, GraphResolvent) else GraphResolvent(
        lattice, t=t, onsite=onsite, method=method)
    oms, scalar = _as_omegas(omega)
    if source is None:
        if res.n > _DENSE_MAX:
            raise ValueError(f"the full Green matrix is limited to {_DENSE_MAX} sites (this lattice has {res.n}).")
        src = np.arange(res.n)
        one = False
    elif _is_scalar(source):
        src = np.array([_validate.site_index("source", source, res.n)])
        one = True
    else:
        src = _validate.site_indices("source", source, res.n)
        one = False
    tg = None
    if targets is not None:
        one_target = _is_scalar(targets)
        tg = (np.array([_validate.site_index("targets", targets, res.n)]) if one_target
              else _validate.site_indices("targets", targets, res.n))
    # many real omegas below the band: one anchor factorisation and a shared Krylov space
    res._routes = {}
    pre, full = res._scan(oms, src) if oms.size > 1 else (set(), None)
    # the scan's output array is the result when all targets are wanted (no copy)
    in_place = full is not None and tg is None
    direct = [i for i, w in enumerate(oms) if i not in pre and w.imag == 0 and w.real < res._upper]
    res._many_direct = len(direct) >= 3
    out = None
    routes, back, fwd = [], np.full(oms.size, np.nan), np.full(oms.size, np.nan)
    for i, w in enumerate(oms):
        if i in pre:
            block = full[i]
            route, back[i], fwd[i] = res._routes[i]
        else:
            block = res.columns(complex(w), src)
            route, back[i], fwd[i] = res._last
            if in_place:
                full[i] = block
        routes.append(route)
        res.report = {"omega": oms[:i + 1].copy(), "route": list(routes), "backward_error": back[:i + 1].copy(),
                      "error_bound": fwd[:i + 1].copy()}
        if in_place:
            continue
        if tg is not None:
            block = block[tg]
        if one:
            block = block[:, 0]
        if tg is not None and one_target:
            block = block[0]
        if scalar:
            return block
        if out is None:
            out = np.empty((oms.size,) + np.shape(block), dtype=complex)
        out[i] = block
    res._many_direct = False
    if in_place:
        return full[:, :, 0] if one else full
    return out


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
