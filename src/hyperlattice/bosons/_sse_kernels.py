r"""numba kernels of the stochastic series expansion (SSE) of the Bose–Hubbard model.

Imported on first use by :mod:`hyperlattice.bosons.sse` (never at package import), compiled with
``cache=True``. The front end owns validation, memory checks and statistics; these kernels only
move the Markov chain and accumulate raw sums.

Configuration
-------------
* ``state[i]``: occupation of site i in the imaginary-time slice 0;
* ``ops[p]``, p = 0..M-1: -1 for the identity, else ``4*b + k`` for bond b with k = 0 (the
  diagonal vertex), 1 (:math:`a_i^\dagger a_j`, site i = ``bi[b]`` gains a boson) or 2
  (:math:`a_j^\dagger a_i`);
* the vertex list of the loop update: vertex v (the v-th non-identity operator) has legs
  4v + 0 (site i, below), 4v + 1 (site j, below), 4v + 2 (site i, above), 4v + 3 (site j, above);
  ``link`` joins each leg to the next/previous leg on the same site (periodic in imaginary time).

Random numbers
--------------
The kernels draw from their own xoshiro256** generator (Blackman & Vigna 2018) whose whole state
is four uint64 words passed in and out as an array. numba's built-in ``np.random`` inside njit
keeps a hidden per-thread state that cannot be read or restored exactly, so a checkpoint could
not continue a chain bit-identically; with an explicit state array it can (and two chains with
different seeds are independent streams seeded through splitmix64).
"""

from __future__ import annotations

import numba
import numpy as np

# ----------------------------------------------------------------------------
# xoshiro256** (public-domain algorithm of Blackman & Vigna), state = uint64[4]
# ----------------------------------------------------------------------------

_M64 = 0xFFFFFFFFFFFFFFFF


def seed_state(seed: int) -> np.ndarray:
    r"""The four xoshiro256** state words from an integer seed, through splitmix64 (pure Python)."""
    x = int(seed) & _M64
    out = np.empty(4, dtype=np.uint64)
    for k in range(4):
        x = (x + 0x9E3779B97F4A7C15) & _M64
        z = x
        z = ((z ^ (z >> 30)) * 0xBF58476D1CE4E5B9) & _M64
        z = ((z ^ (z >> 27)) * 0x94D049BB133111EB) & _M64
        out[k] = z ^ (z >> 31)
    if not np.any(out):
        out[0] = 1
    return out


@numba.njit(cache=True, inline="always")
def _rotl(x, k):  # pragma: no cover - jitted
    return (x << np.uint64(k)) | (x >> np.uint64(64 - k))


@numba.njit(cache=True, inline="always")
def _next(s):  # pragma: no cover - jitted
    result = _rotl(s[1] * np.uint64(5), 7) * np.uint64(9)
    t = s[1] << np.uint64(17)
    s[2] ^= s[0]
    s[3] ^= s[1]
    s[1] ^= s[2]
    s[0] ^= s[3]
    s[2] ^= t
    s[3] = _rotl(s[3], 45)
    return result


@numba.njit(cache=True, inline="always")
def _uniform(s):  # pragma: no cover - jitted
    r"""A double in [0, 1) from the top 53 bits."""
    return np.float64(_next(s) >> np.uint64(11)) * 1.1102230246251565e-16


@numba.njit(cache=True, inline="always")
def _below(s, m):  # pragma: no cover - jitted
    r"""An integer in [0, m) by scaling a 53-bit uniform (bias below m / 2**53: negligible)."""
    k = np.int64(_uniform(s) * m)
    return k if k < m else m - 1


# ----------------------------------------------------------------------------
# vertex weights
# ----------------------------------------------------------------------------

@numba.njit(cache=True, inline="always")
def _vertex_weight(b, s0, s1, s2, s3, bi, bj, tb, cb, esite, sq, nmax):  # pragma: no cover - jitted
    r"""Matrix element <s2 s3| H_b |s0 s1> of the bond operator (0 when not allowed)."""
    if s0 < 0 or s1 < 0 or s2 < 0 or s3 < 0 or s0 > nmax or s1 > nmax or s2 > nmax or s3 > nmax:
        return 0.0
    if s0 == s2:
        if s1 != s3:
            return 0.0
        return cb[b] - esite[bi[b], s0] - esite[bj[b], s1]
    if s0 + s1 != s2 + s3:
        return 0.0
    d = s2 - s0
    if d == 1 or d == -1:
        return tb[b] * sq[max(s0, s2)] * sq[max(s1, s3)]
    return 0.0


# ----------------------------------------------------------------------------
# one Monte Carlo sweep: diagonal update, then directed loops
# ----------------------------------------------------------------------------

@numba.njit(cache=True)
def _diagonal_update(ops, state, nops, beta, bi, bj, cb, esite, rng, occ_sum, last, offd, measure):  # pragma: no cover
    r"""Insert/remove diagonal operators (Sandvik's acceptance with a uniformly chosen bond).

    When ``measure`` is set, ``occ_sum[i]`` gains :math:`\sum_p n_i(p)` over the M time slices
    of the configuration (integers) and ``offd[b]`` the number of off-diagonal operators on b.
    Returns the new number of operators.
    """
    m = ops.shape[0]
    nb = bi.shape[0]
    bnb = beta * nb
    if measure:
        for i in range(state.shape[0]):
            last[i] = 0
    for p in range(m):
        op = ops[p]
        if op < 0:
            b = _below(rng, nb)
            w = cb[b] - esite[bi[b], state[bi[b]]] - esite[bj[b], state[bj[b]]]
            if _uniform(rng) * (m - nops) < bnb * w:
                ops[p] = 4 * b
                nops += 1
        else:
            b = op >> 2
            k = op & 3
            if k == 0:
                w = cb[b] - esite[bi[b], state[bi[b]]] - esite[bj[b], state[bj[b]]]
                if _uniform(rng) * bnb * w < m - nops + 1:
                    ops[p] = -1
                    nops -= 1
            else:
                i = bi[b]
                j = bj[b]
                if measure:
                    occ_sum[i] += state[i] * (p + 1 - last[i])
                    occ_sum[j] += state[j] * (p + 1 - last[j])
                    last[i] = p + 1
                    last[j] = p + 1
                    offd[b] += 1
                if k == 1:
                    state[i] += 1
                    state[j] -= 1
                else:
                    state[i] -= 1
                    state[j] += 1
    if measure:
        for i in range(state.shape[0]):
            occ_sum[i] += state[i] * (m - last[i])
    return nops


@numba.njit(cache=True)
def _loop_update(ops, state, nops, nloops, bi, bj, tb, cb, esite, sq, nmax, rng,
                 vpos, link, legs, first, lastleg, wind, crossing, gacc, gdist, measure_green):  # pragma: no cover
    r"""Directed-loop update (Syljuåsen & Sandvik 2002; bosons: Syljuåsen 2003) with the
    Metropolized-Gibbs exit probabilities. Returns (legs visited, loops done).

    ``gacc[c]`` accumulates the worm estimator of :math:`\langle a_k^\dagger a_l\rangle` for the
    site pairs of class ``gdist[k, l]`` (see :func:`hyperlattice.bosons.sse.qmc`, Notes).
    """
    nsites = state.shape[0]
    for i in range(nsites):
        first[i] = -1
        lastleg[i] = -1
    m = ops.shape[0]
    # vertex list and links in O(M + sites)
    v = 0
    for p in range(m):
        op = ops[p]
        if op < 0:
            continue
        b = op >> 2
        k = op & 3
        i = bi[b]
        j = bj[b]
        vpos[v] = p
        l0 = 4 * v
        legs[l0] = state[i]
        legs[l0 + 1] = state[j]
        if k == 1:
            state[i] += 1
            state[j] -= 1
        elif k == 2:
            state[i] -= 1
            state[j] += 1
        legs[l0 + 2] = state[i]
        legs[l0 + 3] = state[j]
        if lastleg[i] >= 0:
            link[l0] = lastleg[i]
            link[lastleg[i]] = l0
        else:
            first[i] = l0
        lastleg[i] = l0 + 2
        if lastleg[j] >= 0:
            link[l0 + 1] = lastleg[j]
            link[lastleg[j]] = l0 + 1
        else:
            first[j] = l0 + 1
        lastleg[j] = l0 + 3
        v += 1
    for i in range(nsites):
        if first[i] >= 0:
            link[first[i]] = lastleg[i]
            link[lastleg[i]] = first[i]
    nlegs = 4 * nops
    visited = 0
    w = np.empty(4)
    if nops > 0:
        for _ in range(nloops):
            j0 = _below(rng, nlegs)
            d0 = 1 if _uniform(rng) < 0.5 else -1
            new = legs[j0] + d0
            if new < 0 or new > nmax:
                continue
            legs[j0] = new
            t0 = link[j0]
            jl = j0
            d = d0
            while True:
                vv = jl >> 2
                le = jl & 3
                b = ops[vpos[vv]] >> 2
                base = 4 * vv
                s0 = legs[base]
                s1 = legs[base + 1]
                s2 = legs[base + 2]
                s3 = legs[base + 3]
                z = 0.0
                for x in range(4):
                    dx = -d if (x >> 1) == (le >> 1) else d
                    a0 = s0 + dx if x == 0 else s0
                    a1 = s1 + dx if x == 1 else s1
                    a2 = s2 + dx if x == 2 else s2
                    a3 = s3 + dx if x == 3 else s3
                    w[x] = _vertex_weight(b, a0, a1, a2, a3, bi, bj, tb, cb, esite, sq, nmax)
                    z += w[x]
                # Metropolized Gibbs: P(le -> x) = min(w_x / (Z - w_le), w_x / (Z - w_x)), x != le
                wl = w[le]
                r = _uniform(rng)
                ex = le
                acc = 0.0
                for x in range(4):
                    if x == le or w[x] <= 0.0:
                        continue
                    pr = w[x] / (z - wl)
                    alt = w[x] / (z - w[x])
                    if alt < pr:
                        pr = alt
                    acc += pr
                    if r < acc:
                        ex = x
                        break
                dx = -d if (ex >> 1) == (le >> 1) else d
                xl = base + ex
                visited += 1
                if xl == j0 or xl == t0:
                    legs[xl] += dx
                    if legs[j0] == legs[t0]:
                        break
                    legs[xl] -= dx
                nxt = link[xl]
                legs[xl] += dx
                legs[nxt] += dx
                jl = nxt
                d = dx
    # operator types and the time-0 state from the legs
    for vv in range(nops):
        base = 4 * vv
        b = ops[vpos[vv]] >> 2
        if legs[base] == legs[base + 2]:
            ops[vpos[vv]] = 4 * b
        elif legs[base + 2] > legs[base]:
            ops[vpos[vv]] = 4 * b + 1
        else:
            ops[vpos[vv]] = 4 * b + 2
    for i in range(nsites):
        if first[i] >= 0:
            state[i] = legs[first[i]]
        else:
            # no operator acts on site i: the weight does not depend on n_i (the on-site energy is
            # inside the bond vertices), so n_i is uniform over 0..nmax
            state[i] = _below(rng, nmax + 1)
    return visited


@numba.njit(cache=True)
def run(nsweeps, thermalize, target_legs, ops, state, nops, nloops, beta, bi, bj, tb, cb, esite, sq, nmax,
        rng, sbins, scur, sinfo, vbins, vcur, vinfo, loopstat):  # pragma: no cover - jitted
    r"""Run ``nsweeps`` sweeps. Returns (ops, nops, nloops) (``ops`` is reallocated when it grows).

    Thermalisation (``thermalize``): after each sweep the string grows to M = 4n/3 when
    n > 3M/4 (Sandvik), and the loops per sweep are set so that about ``target_legs`` x n
    vertex legs are visited per sweep (from the running mean loop length in ``loopstat``).

    Measurement: per sweep the scalars (n, n^2, N, N^2, N^4) are added to ``scur`` and the site
    occupation sums / M and per-bond off-diagonal counts to ``vcur``; a bin of ``sinfo[1]``
    (``vinfo[1]``) sweeps is closed into ``sbins`` (``vbins``); when the bin array is full its
    bins are merged pairwise and the bin size doubles. The whole accumulation is a deterministic
    function of the sweep sequence (checkpoint-independent).
    """
    nsites = state.shape[0]
    nbonds = bi.shape[0]
    m = ops.shape[0]
    occ = np.zeros(nsites, dtype=np.int64)
    last = np.zeros(nsites, dtype=np.int64)
    offd = np.zeros(nbonds, dtype=np.int64)
    first = np.empty(nsites, dtype=np.int64)
    lastleg = np.empty(nsites, dtype=np.int64)
    cap = max(m, 16)
    vpos = np.empty(cap, dtype=np.int64)
    link = np.empty(4 * cap, dtype=np.int64)
    legs = np.empty(4 * cap, dtype=np.int64)
    dummy_i = np.zeros((1, 1), dtype=np.int64)
    dummy_f = np.zeros(1)
    nv = vcur.shape[0]
    for sweep in range(nsweeps):
        measure = not thermalize
        if measure:
            for i in range(nsites):
                occ[i] = 0
            for b in range(nbonds):
                offd[b] = 0
        nops = _diagonal_update(ops, state, nops, beta, bi, bj, cb, esite, rng, occ, last, offd, measure)
        if measure:
            ntot = 0
            for i in range(nsites):
                ntot += state[i]
            fn = float(nops)
            fN = float(ntot)
            scur[0] += fn
            scur[1] += fn * fn
            scur[2] += fN
            scur[3] += fN * fN
            scur[4] += fN * fN * fN * fN
            for i in range(nsites):
                vcur[i] += occ[i] / m
            for b in range(nbonds):
                vcur[nsites + b] += offd[b]
        if ops.shape[0] > cap:
            cap = ops.shape[0]
            vpos = np.empty(cap, dtype=np.int64)
            link = np.empty(4 * cap, dtype=np.int64)
            legs = np.empty(4 * cap, dtype=np.int64)
        visited = _loop_update(ops, state, nops, nloops, bi, bj, tb, cb, esite, sq, nmax, rng,
                               vpos, link, legs, first, lastleg, dummy_i, dummy_i, dummy_f, dummy_i, False)
        if thermalize:
            loopstat[0] += visited
            loopstat[1] += nloops
            # loops per sweep from the mean loop length so far (aborted starts included)
            mean_len = loopstat[0] / max(loopstat[1], 1.0)
            want = target_legs * nops / max(mean_len, 1e-3)
            nloops = int(min(max(want, 1.0), 1e9))
            if nops > 0.75 * m:
                newm = (4 * nops) // 3 + 8
                new = np.full(newm, -1, dtype=np.int64)
                # spread the operators evenly (their order is what matters)
                k = 0
                for p in range(m):
                    if ops[p] >= 0:
                        new[(k * newm) // nops] = ops[p]
                        k += 1
                ops = new
                m = newm
        else:
            # close bins
            sinfo[2] += 1
            if sinfo[2] == sinfo[1]:
                nb = sinfo[0]
                for k in range(scur.shape[0]):
                    sbins[nb, k] = scur[k]
                    scur[k] = 0.0
                sinfo[0] = nb + 1
                sinfo[2] = 0
                if sinfo[0] == sbins.shape[0]:
                    half = sbins.shape[0] // 2
                    for a in range(half):
                        for k in range(scur.shape[0]):
                            sbins[a, k] = sbins[2 * a, k] + sbins[2 * a + 1, k]
                    sinfo[0] = half
                    sinfo[1] *= 2
            vinfo[2] += 1
            if vinfo[2] == vinfo[1]:
                nb = vinfo[0]
                for k in range(nv):
                    vbins[nb, k] = vcur[k]
                    vcur[k] = 0.0
                vinfo[0] = nb + 1
                vinfo[2] = 0
                if vinfo[0] == vbins.shape[0]:
                    half = vbins.shape[0] // 2
                    for a in range(half):
                        for k in range(nv):
                            vbins[a, k] = vbins[2 * a, k] + vbins[2 * a + 1, k]
                    vinfo[0] = half
                    vinfo[1] *= 2
    return ops, nops, nloops
