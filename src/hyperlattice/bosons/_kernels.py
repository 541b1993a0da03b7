"""numba kernels of the Bose–Hubbard exact diagonalisation (imported on first use, cached on disk).

Every kernel walks the states of a :class:`~hyperlattice.bosons.basis.BosonBasis` and, for each
hop :math:`a_i^\\dagger a_j` along an edge, finds the target state's rank from the source's rank
by :func:`moved_rank`: only the terms of the rank sum between i and j change (see the basis
module). States are processed in chunks so that the scratch array of each chunk is allocated
once, not once per state.
"""

from __future__ import annotations

import numba
import numpy as np
from numba import prange


@numba.njit(cache=True, inline="always")
def moved_rank(occ, rem, weights, s, i, j, pos, npos):  # pragma: no cover - jitted
    """Rank of the state :math:`a_i^\\dagger a_j |s\\rangle` (i != j, occ[j] > 0, occ[i] < nmax).

    Only the occupied sites strictly between i and j (``pos[:npos]``, ascending) contribute
    besides i and j themselves: :math:`W_k(r, 0) = 0` for every r, so an empty site's term is 0
    before and after the move. The cost is O(occupied sites), not O(|i - j|).
    """
    if i < j:
        d = weights[i, rem[i], occ[i] + 1] - weights[i, rem[i], occ[i]]
        for a in range(npos):
            k = pos[a]
            if k <= i:
                continue
            if k >= j:
                break
            d += weights[k, rem[k] - 1, occ[k]] - weights[k, rem[k], occ[k]]
        d += weights[j, rem[j] - 1, occ[j] - 1] - weights[j, rem[j], occ[j]]
    else:
        d = weights[j, rem[j], occ[j] - 1] - weights[j, rem[j], occ[j]]
        for a in range(npos):
            k = pos[a]
            if k <= j:
                continue
            if k >= i:
                break
            d += weights[k, rem[k] + 1, occ[k]] - weights[k, rem[k], occ[k]]
        d += weights[i, rem[i] + 1, occ[i] + 1] - weights[i, rem[i], occ[i]]
    return s + d


@numba.njit(cache=True, inline="always")
def fill_rem(occ, n, rem, pos):  # pragma: no cover - jitted
    """rem[k] = bosons on sites >= k; pos = occupied sites ascending; returns their number."""
    r = n
    npos = 0
    for k in range(occ.shape[0]):
        rem[k] = r
        v = occ[k]
        r -= v
        if v != 0:
            pos[npos] = k
            npos += 1
    return npos


def _chunks(dim):
    return max(1, min(dim, 256 * numba.get_num_threads()))


@numba.njit(cache=True, parallel=True)
def diagonal(states, U, mu, out):  # pragma: no cover - jitted
    dim, m = states.shape
    for s in prange(dim):
        e = 0.0
        for k in range(m):
            v = float(states[s, k])
            e += 0.5 * U * v * (v - 1.0) - mu * v
        out[s] = e
    return 0


@numba.njit(cache=True, parallel=True)
def matvec(states, weights, n, c, ptr, nbr, diag, t, sq, x, y, nchunks):  # pragma: no cover - jitted
    """y = H x, gathered row by row (race-free): H is real symmetric."""
    dim, m = states.shape
    step = (dim + nchunks - 1) // nchunks
    for ch in prange(nchunks):
        rem = np.empty(m + 1, dtype=np.int64)
        pos = np.empty(m, dtype=np.int64)
        for s in range(ch * step, min(dim, (ch + 1) * step)):
            occ = states[s]
            npos = fill_rem(occ, n, rem, pos)
            acc = diag[s] * x[s]
            for aj in range(npos):
                j = pos[aj]
                nj = occ[j]
                for e in range(ptr[j], ptr[j + 1]):
                    i = nbr[e]
                    ni = occ[i]
                    if ni >= c:
                        continue
                    tgt = moved_rank(occ, rem, weights, s, i, j, pos, npos)
                    acc -= t * sq[nj] * sq[ni + 1] * x[tgt]
            y[s] = acc
    return 0


@numba.njit(cache=True, parallel=True)
def row_counts(states, c, ptr, nbr, counts, nchunks):  # pragma: no cover - jitted
    dim, m = states.shape
    step = (dim + nchunks - 1) // nchunks
    for ch in prange(nchunks):
        for s in range(ch * step, min(dim, (ch + 1) * step)):
            occ = states[s]
            k = 1
            for j in range(m):
                if occ[j] == 0:
                    continue
                for e in range(ptr[j], ptr[j + 1]):
                    if occ[nbr[e]] < c:
                        k += 1
            counts[s] = k
    return 0


@numba.njit(cache=True, parallel=True)
def csr_fill(states, weights, n, c, ptr, nbr, diag, t, sq, indptr, indices, data, nchunks):  # pragma: no cover
    dim, m = states.shape
    step = (dim + nchunks - 1) // nchunks
    for ch in prange(nchunks):
        rem = np.empty(m + 1, dtype=np.int64)
        pos = np.empty(m, dtype=np.int64)
        for s in range(ch * step, min(dim, (ch + 1) * step)):
            occ = states[s]
            npos = fill_rem(occ, n, rem, pos)
            k = indptr[s]
            indices[k] = s
            data[k] = diag[s]
            k += 1
            for aj in range(npos):
                j = pos[aj]
                nj = occ[j]
                for e in range(ptr[j], ptr[j + 1]):
                    i = nbr[e]
                    ni = occ[i]
                    if ni >= c:
                        continue
                    indices[k] = moved_rank(occ, rem, weights, s, i, j, pos, npos)
                    data[k] = -t * sq[nj] * sq[ni + 1]
                    k += 1
    return 0


@numba.njit(cache=True, parallel=True)
def orbits(states, weights, n, rot, p, rep, shift, period, nchunks):  # pragma: no cover - jitted
    """Orbit of every state under the site permutation ``rot`` (order p).

    ``rep[s]``: smallest rank in the orbit; ``period[s]``: orbit length L (divides p);
    ``shift[s]``: the t in [0, L) with s = R^t rep[s], where R moves the bosons of site i to
    site rot[i].
    """
    dim, m = states.shape
    step = (dim + nchunks - 1) // nchunks
    for ch in prange(nchunks):
        cur = np.empty(m, dtype=np.int64)
        nxt = np.empty(m, dtype=np.int64)
        for s in range(ch * step, min(dim, (ch + 1) * step)):
            for k in range(m):
                cur[k] = states[s, k]
            best = s
            best_k = 0
            length = p
            for k in range(1, p + 1):
                for a in range(m):
                    nxt[rot[a]] = cur[a]
                r = 0
                left = n
                for a in range(m):
                    r += weights[a, left, nxt[a]]
                    left -= nxt[a]
                if r == s:
                    length = k
                    break
                if r < best:
                    best = r
                    best_k = k
                for a in range(m):
                    cur[a] = nxt[a]
            rep[s] = best
            period[s] = length
            # best = R^best_k s, so s = R^(L - best_k) best
            shift[s] = (length - best_k) % length
    return 0


@numba.njit(cache=True, parallel=True)
def sector_counts(states, c, ptr, nbr, reps, counts, nchunks):  # pragma: no cover - jitted
    dim, m = states.shape
    nr = reps.shape[0]
    step = (nr + nchunks - 1) // nchunks
    for ch in prange(nchunks):
        for a in range(ch * step, min(nr, (ch + 1) * step)):
            occ = states[reps[a]]
            k = 1
            for j in range(m):
                if occ[j] == 0:
                    continue
                for e in range(ptr[j], ptr[j + 1]):
                    if occ[nbr[e]] < c:
                        k += 1
            counts[a] = k
    return 0


@numba.njit(cache=True, parallel=True)
def sector_fill(states, weights, n, c, ptr, nbr, diag, t, sq, reps, rep, shift, period, index,
                phase_re, phase_im, offsets, rows, cols, re, im, nchunks):  # pragma: no cover - jitted
    r"""COO entries of the block :math:`H_m`: column = the source representative, row = the
    representative of each target, value amp * omega^(-m t) * sqrt(L_src / L_tgt); targets whose
    orbit carries no state of angular momentum m are dropped (their entry is 0)."""
    dim, m = states.shape
    nr = reps.shape[0]
    step = (nr + nchunks - 1) // nchunks
    for ch in prange(nchunks):
        rem = np.empty(m + 1, dtype=np.int64)
        pos = np.empty(m, dtype=np.int64)
        for a in range(ch * step, min(nr, (ch + 1) * step)):
            s = reps[a]
            occ = states[s]
            npos = fill_rem(occ, n, rem, pos)
            k = offsets[a]
            rows[k] = a
            cols[k] = a
            re[k] = diag[s]
            im[k] = 0.0
            k += 1
            ls = float(period[s])
            for aj in range(npos):
                j = pos[aj]
                nj = occ[j]
                for e in range(ptr[j], ptr[j + 1]):
                    i = nbr[e]
                    ni = occ[i]
                    if ni >= c:
                        continue
                    tgt = moved_rank(occ, rem, weights, s, i, j, pos, npos)
                    r = rep[tgt]
                    b = index[r]
                    if b < 0:
                        rows[k] = a
                        cols[k] = a
                        re[k] = 0.0
                        im[k] = 0.0
                    else:
                        amp = -t * sq[nj] * sq[ni + 1] * np.sqrt(ls / period[r])
                        rows[k] = b
                        cols[k] = a
                        re[k] = amp * phase_re[shift[tgt]]
                        im[k] = amp * phase_im[shift[tgt]]
                    k += 1
    return 0


@numba.njit(cache=True, parallel=True)
def one_body(states, weights, n, c, sq, psi_re, psi_im, out_re, out_im, nchunks):  # pragma: no cover
    r"""Per-chunk sums of :math:`\langle a_i^\dagger a_j\rangle` over all ordered pairs (any graph
    distance): out[ch, i, j] (diagonal: :math:`\langle n_i\rangle`)."""
    dim, m = states.shape
    step = (dim + nchunks - 1) // nchunks
    for ch in prange(nchunks):
        rem = np.empty(m + 1, dtype=np.int64)
        pos = np.empty(m, dtype=np.int64)
        for s in range(ch * step, min(dim, (ch + 1) * step)):
            xr = psi_re[s]
            xi = psi_im[s]
            if xr == 0.0 and xi == 0.0:
                continue
            occ = states[s]
            npos = fill_rem(occ, n, rem, pos)
            w = xr * xr + xi * xi
            for aj in range(npos):
                j = pos[aj]
                nj = occ[j]
                out_re[ch, j, j] += w * nj
                for i in range(m):
                    if i == j:
                        continue
                    ni = occ[i]
                    if ni >= c:
                        continue
                    tgt = moved_rank(occ, rem, weights, s, i, j, pos, npos)
                    amp = sq[nj] * sq[ni + 1]
                    # conj(psi[tgt]) * psi[s]
                    yr = psi_re[tgt]
                    yi = psi_im[tgt]
                    out_re[ch, i, j] += amp * (yr * xr + yi * xi)
                    out_im[ch, i, j] += amp * (yr * xi - yi * xr)
    return 0
