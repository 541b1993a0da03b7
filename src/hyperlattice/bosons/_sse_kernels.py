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
  the link of a leg joins it to the next/previous leg on the same site (periodic in imaginary
  time). One int32 record of 8 entries per vertex holds the four leg states and then the four
  links (``rec[8v + le]``, ``rec[8v + 4 + le]``; :func:`_st` and :func:`_lk` give the positions
  from a leg), and ``vb[v]`` is the vertex's bond: a step of a loop reads one 32-byte record and
  one bond, where separate state, link, position and operator arrays cost four cache misses on a
  string larger than the cache.

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
def _diagonal_update(ops, state, nops, beta, bi, bj, cb, esite, rng, occ_sum, last, offd, measure,
                     hist):  # pragma: no cover
    r"""Insert/remove diagonal operators (Sandvik's acceptance with a uniformly chosen bond).

    When ``measure`` is set, ``occ_sum[i]`` gains :math:`\sum_p n_i(p)` over the M time slices
    of the configuration (integers), ``hist[k]`` the number of (site, slice) pairs with occupation
    k (the slice-weighted occupation histogram, for the diagonal energy) and ``offd[b]`` the
    number of off-diagonal operators on b. Returns the new number of operators.
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
                    hist[state[i]] += p + 1 - last[i]
                    hist[state[j]] += p + 1 - last[j]
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
            hist[state[i]] += m - last[i]
    return nops


@numba.njit(cache=True)
def winding_moments(ops, wind, w, scur, col):  # pragma: no cover - jitted
    r"""Winding numbers of the configuration: add their second moments to ``scur[col:]``.

    ``wind[b]`` (int64, shape (B, D)) is the winding :math:`w_b \in \mathbb Z^D` of the directed
    bond ``bi[b] -> bj[b]`` (the reverse direction has :math:`-w_b`); :math:`\sum_b w_b` over the
    bonds of a closed walk is the walk's homology class (D = 2 on a torus, 2g on a genus-g
    surface). Every off-diagonal operator moves one boson along its bond, so

    .. math:: W = \sum_{p:\ \text{off-diagonal}} \pm w_{b(p)}

    (+ for a hop i -> j, k = 2, :math:`a_j^\dagger a_i`; - for j -> i, k = 1) is the total
    winding of the world lines over the imaginary-time period: an integer vector, because the
    world lines close (the state at the end of the string is the state at its start). The
    diagonal update never changes the off-diagonal operators, so one pass over ``ops`` at any
    point of the sweep gives W. Adds :math:`W_a W_b` (a <= b, row-major upper triangle) to
    ``scur[col:col + D(D+1)/2]`` and :math:`(W \cdot W)^2` to the next entry (the variance of
    the stiffness estimator, for its autocorrelation time). ``w`` (int64, D) is scratch.

    A separate O(M) pass, called by :func:`run` only when D > 0 (periodic graphs with windings),
    so the other kernels are unchanged and a run without windings does no extra work.
    """
    d = wind.shape[1]
    for a in range(d):
        w[a] = 0
    for p in range(ops.shape[0]):
        op = ops[p]
        if op < 0 or (op & 3) == 0:
            continue
        b = op >> 2
        if (op & 3) == 2:               # a_j^dagger a_i: a boson hops i -> j along the bond
            for a in range(d):
                w[a] += wind[b, a]
        else:                           # a_i^dagger a_j: j -> i
            for a in range(d):
                w[a] -= wind[b, a]
    k = col
    ww = 0.0
    for a in range(d):
        ww += float(w[a] * w[a])
        for c in range(a, d):
            scur[k] += float(w[a] * w[c])
            k += 1
    scur[k] += ww * ww


@numba.njit(cache=True, inline="always")
def _exit_weights(w, b, le, d, s0, s1, s2, s3, bi, bj, tb, cb, esite, sq, nmax):  # pragma: no cover - jitted
    r"""Weights of the four exits of a vertex entered at leg ``le`` with change ``d`` (already applied)."""
    for x in range(4):
        dx = -d if (x >> 1) == (le >> 1) else d
        a0 = s0 + dx if x == 0 else s0
        a1 = s1 + dx if x == 1 else s1
        a2 = s2 + dx if x == 2 else s2
        a3 = s3 + dx if x == 3 else s3
        w[x] = _vertex_weight(b, a0, a1, a2, a3, bi, bj, tb, cb, esite, sq, nmax)


@numba.njit(cache=True, inline="always")
def _cumulative(w, le):  # pragma: no cover - jitted
    r"""Turn exit weights into cumulative exit probabilities (in place): least bounce.

    The four configurations a loop can leave at a vertex form a closed set with weights
    :math:`w_x` (x the exit leg, ``w[le]`` the configuration of the bounce). Detailed balance of
    the directed loops asks for a symmetric matrix :math:`a_{xy} \ge 0` with row sums
    :math:`\sum_y a_{xy} = w_x`, and :math:`P(x \to y) = a_{xy}/w_x` (Syljuåsen and Sandvik, PRE
    66, 046701 (2002)). With the weights sorted, :math:`W_1 \ge W_2 \ge W_3 \ge W_4`, the
    least total bounce is :math:`\max(0, W_1 - W_2 - W_3 - W_4)`, on the largest weight only:

    * :math:`W_1 \ge W_2 + W_3 + W_4`: :math:`a_{1k} = W_k`, :math:`a_{11} = W_1 - W_2 - W_3 - W_4`,
      all other entries 0;
    * otherwise no bounce: the zero-diagonal solutions are
      :math:`a_{12} = \lambda + (W_1 + W_2 - W_3 - W_4)/2`,
      :math:`a_{13} = \mu + (W_1 + W_3 - W_2 - W_4)/2`,
      :math:`a_{14} = \nu + (W_1 + W_4 - W_2 - W_3)/2`, :math:`a_{34} = \lambda`,
      :math:`a_{24} = \mu`, :math:`a_{23} = \nu` with :math:`\lambda + \mu + \nu =
      (W_2 + W_3 + W_4 - W_1)/2` and :math:`\nu \ge \nu_0 = \max(0, (W_2 + W_3 - W_1 - W_4)/2)`;
      the free part beyond :math:`\nu_0` is shared in proportion to the heat-bath products
      :math:`W_3W_4 : W_2W_4 : W_2W_3`.

    The matrix depends on the weight vector only (ties sorted by leg), never on the entrance, so
    the same matrix serves every configuration of the set and the balance is exact. Against the
    Metropolized Gibbs rule this removes the bounces at diagonal vertices whose weight is below
    the sum of the others (most of them in the superfluid). Entries x != le become the running
    sums of :math:`a_{le,x}/w_{le}` over the other exits in leg order; a uniform beyond all of
    them means the bounce (``w[le]`` is set to -1).
    """
    # legs by weight, largest first (stable: ties by leg)
    o0, o1, o2, o3 = 0, 1, 2, 3
    if w[o1] > w[o0]:
        o0, o1 = o1, o0
    if w[o3] > w[o2]:
        o2, o3 = o3, o2
    if w[o2] > w[o0] or (w[o2] == w[o0] and o2 < o0):
        o0, o2 = o2, o0
    if w[o3] > w[o1] or (w[o3] == w[o1] and o3 < o1):
        o1, o3 = o3, o1
    if w[o2] > w[o1] or (w[o2] == w[o1] and o2 < o1):
        o1, o2 = o2, o1
    W1 = w[o0]
    W2 = w[o1]
    W3 = w[o2]
    W4 = w[o3]
    if W1 >= W2 + W3 + W4:
        a12 = W2
        a13 = W3
        a14 = W4
        a23 = 0.0
        a24 = 0.0
        a34 = 0.0
    else:
        s = 0.5 * (W2 + W3 + W4 - W1)
        nu0 = max(0.0, 0.5 * (W2 + W3 - W1 - W4))
        rest = s - nu0
        p23 = W2 * W3
        p24 = W2 * W4
        p34 = W3 * W4
        den = p23 + p24 + p34
        lam = rest * p34 / den
        mu = rest * p24 / den
        nu = nu0 + rest * p23 / den
        a12 = max(0.0, lam + 0.5 * (W1 + W2 - W3 - W4))
        a13 = max(0.0, mu + 0.5 * (W1 + W3 - W2 - W4))
        # exactly 0 towards a configuration of weight 0 (lam = mu = 0 there already)
        a14 = max(0.0, nu + 0.5 * (W1 + W4 - W2 - W3)) if W4 > 0.0 else 0.0
        a23 = nu
        a24 = mu
        a34 = lam
    # the row of the entrance, as a_{le, x} for x = 0..3
    r0 = 0.0
    r1 = 0.0
    r2 = 0.0
    r3 = 0.0
    if le == o0:
        r0, r1, r2, r3 = 0.0, a12, a13, a14
    elif le == o1:
        r0, r1, r2, r3 = a12, 0.0, a23, a24
    elif le == o2:
        r0, r1, r2, r3 = a13, a23, 0.0, a34
    else:
        r0, r1, r2, r3 = a14, a24, a34, 0.0
    # r_k is a_{le, o_k}; scatter back to legs
    wl = w[le]
    if not wl > 0.0:            # an entrance of weight 0 is never reached: a row that bounces
        for x in range(4):
            w[x] = -1.0
        return
    acc = 0.0
    for x in range(4):
        if x == le:
            w[x] = -1.0
            continue
        if x == o0:
            v = r0
        elif x == o1:
            v = r1
        elif x == o2:
            v = r2
        else:
            v = r3
        acc += v / wl
        w[x] = acc


@numba.njit(cache=True)
def exit_table(bclass_rep, bi, bj, tb, cb, esite, sq, nmax):  # pragma: no cover - jitted
    r"""Cumulative exit probabilities per bond class, vertex code, entrance leg and sign of the change."""
    kk = nmax + 1
    ncode = kk ** 4
    out = np.zeros((bclass_rep.shape[0], ncode, 4, 2, 4))
    w = np.empty(4)
    for c in range(bclass_rep.shape[0]):
        b = bclass_rep[c]
        for code in range(ncode):
            s0 = code % kk
            s1 = (code // kk) % kk
            s2 = (code // (kk * kk)) % kk
            s3 = code // (kk * kk * kk)
            for le in range(4):
                for di in range(2):
                    d = 1 if di == 0 else -1
                    _exit_weights(w, b, le, d, s0, s1, s2, s3, bi, bj, tb, cb, esite, sq, nmax)
                    _cumulative(w, le)
                    for x in range(4):
                        out[c, code, le, di, x] = w[x]
    return out


@numba.njit(cache=True, inline="always")
def _st(leg):  # pragma: no cover - jitted
    r"""Position of leg ``leg`` = 4v + le's state in the vertex records: 8v + le."""
    return leg + (leg & ~3)


@numba.njit(cache=True, inline="always")
def _lk(leg):  # pragma: no cover - jitted
    r"""Position of leg ``leg`` = 4v + le's link in the vertex records: 8v + 4 + le."""
    return leg + (leg & ~3) + 4


@numba.njit(cache=True, inline="always")
def _gaps(leg, rec, n):  # pragma: no cover - jitted
    r"""(first gap, number of gaps) of the segment that ends at ``leg``; gap g lies just below vertex g.

    A segment runs from the upper leg of vertex a to the lower leg of the next vertex c on the
    same site and covers the gaps a+1 .. c (cyclically): c - a of them, all n when a == c.
    """
    v = leg >> 2
    w = rec[_lk(leg)] >> 2
    if (leg & 3) >= 2:
        a = v
        c = w
    else:
        a = w
        c = v
    ln = (c - a) % n
    if ln == 0:
        ln = n
    return (a + 1) % n, ln


@numba.njit(cache=True, inline="always")
def _overlap(a, la, b, lb, n):  # pragma: no cover - jitted
    r"""Length of the intersection of the cyclic gap ranges [a, a+la) and [b, b+lb) (mod n)."""
    tot = 0
    for shift in (-n, 0, n):
        lo = max(a, b + shift)
        hi = min(a + la, b + lb + shift)
        if hi > lo:
            tot += hi - lo
    return tot


@numba.njit(cache=True, inline="always")
def _pair_class(k, l, gmode, gclass, zr, zi, omz, hbin, ncls):  # pragma: no cover - jitted
    r"""Distance class of the site pair (k, l): from the table, or from the hyperbolic distance."""
    if gmode == 1:
        return gclass[k, l]
    dx = zr[k] - zr[l]
    dy = zi[k] - zi[l]
    # the package's distance (curvature -4): arcsinh(|z - z'| / sqrt((1 - |z|^2)(1 - |z'|^2)))
    c = int(np.arcsinh(np.sqrt((dx * dx + dy * dy) / (omz[k] * omz[l]))) / hbin + 0.5)
    return c if c < ncls else ncls - 1


@numba.njit(cache=True)
def _loop_update(ops, state, nops, nloops, bi, bj, tb, cb, esite, sq, nmax, rng,
                 vb, rec, first, lastleg, gmode, gfull, gcur, gclass, zr, zi, omz, hbin, vcur, voff,
                 ncls, gsign, ptab, bclass, ntab, legcap, started):  # pragma: no cover
    r"""Directed-loop update (Syljuåsen & Sandvik 2002; bosons: Syljuåsen 2003) with the
    least-bounce exit probabilities (:func:`_cumulative`). Returns the number of vertex passages.

    ``vb`` (int32, at least n) and ``rec`` (int32, at least 8n) are work arrays: the vertices'
    bonds and records (module docstring), built here from ``ops`` and ``state``.

    ``legcap`` > 0 (thermalisation only) stops starting loops once that many vertex passages are
    done: far from equilibrium the loops are long and the loop count set from the previous
    sweep's short loops would run for minutes. ``started[0]`` receives the loops started
    (starts refused at the cutoff included). Measurement sweeps pass 0 and run ``nloops`` loops.

    With ``gmode`` > 0 every position of the head on a segment (after each exit) adds the worm
    estimator of the equal-time one-body density matrix, :math:`N_{\mathrm{gap}}\sqrt{n_h n_t}`
    (the gaps shared by head and tail segment times the boson matrix elements of the two
    discontinuities), to :math:`G_{kl}` (k the site whose segment jumps up by one: :math:`a_k^\dagger`),
    in the full matrix ``gcur`` (``gfull``) and in ``vcur[voff + class(k, l)]``.
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
        vb[v] = b
        l0 = 4 * v
        r0 = 8 * v
        rec[r0] = state[i]
        rec[r0 + 1] = state[j]
        if k == 1:
            state[i] += 1
            state[j] -= 1
        elif k == 2:
            state[i] -= 1
            state[j] += 1
        rec[r0 + 2] = state[i]
        rec[r0 + 3] = state[j]
        if lastleg[i] >= 0:
            rec[r0 + 4] = lastleg[i]
            rec[_lk(lastleg[i])] = l0
        else:
            first[i] = l0
        lastleg[i] = l0 + 2
        if lastleg[j] >= 0:
            rec[r0 + 5] = lastleg[j]
            rec[_lk(lastleg[j])] = l0 + 1
        else:
            first[j] = l0 + 1
        lastleg[j] = l0 + 3
        v += 1
    for i in range(nsites):
        if first[i] >= 0:
            rec[_lk(first[i])] = lastleg[i]
            rec[_lk(lastleg[i])] = first[i]
    nlegs = 4 * nops
    visited = 0
    w = np.empty(4)
    kk = nmax + 1
    # a directed loop closes with probability one, but a configuration far from equilibrium (a
    # string still filling up) can hold a nearly deterministic cycle that misses the tail for
    # millions of steps: a loop longer than maxlen steps undoes this sweep's loop update (the legs
    # are restored) and is counted, so that the result can say so
    maxlen = 200 * nlegs + 100000
    aborted = False
    saved = rec[:2 * nlegs].copy() if nops > 0 else rec[:0].copy()
    started[0] = 0
    if nops > 0:
        for _ in range(nloops):
            if aborted or (legcap > 0 and visited >= legcap):
                break
            started[0] += 1
            j0 = _below(rng, nlegs)
            steps = 0
            d0 = 1 if _uniform(rng) < 0.5 else -1
            new = rec[_st(j0)] + d0
            if new < 0 or new > nmax:
                continue
            rec[_st(j0)] = new
            t0 = rec[_lk(j0)]
            jl = j0
            d = d0
            if gmode > 0:
                tv = j0 >> 2
                tsite = bj[vb[tv]] if (j0 & 1) else bi[vb[tv]]
                tg, tl = _gaps(j0, rec, nops)
                # the tail segment jumps up (a^dagger at tsite) when its upper end holds more bosons
                tup = (rec[_st(t0)] > rec[_st(j0)]) if (j0 & 3) >= 2 else (rec[_st(j0)] > rec[_st(t0)])
            while True:
                vv = jl >> 2
                le = jl & 3
                b = vb[vv]
                base = 8 * vv
                s0 = rec[base]
                s1 = rec[base + 1]
                s2 = rec[base + 2]
                s3 = rec[base + 3]
                r = _uniform(rng)
                ex = le
                if ntab > 0:
                    # tabulated exit probabilities of this bond class (cumulative over x)
                    di = 0 if d > 0 else 1
                    row = ptab[bclass[b], s0 + kk * (s1 + kk * (s2 + kk * s3)), le, di]
                    for x in range(4):
                        if r < row[x]:
                            ex = x
                            break
                else:
                    _exit_weights(w, b, le, d, s0, s1, s2, s3, bi, bj, tb, cb, esite, sq, nmax)
                    _cumulative(w, le)
                    for x in range(4):
                        if r < w[x]:
                            ex = x
                            break
                dx = -d if (ex >> 1) == (le >> 1) else d
                xl = 4 * vv + ex
                xs = base + ex
                visited += 1
                steps += 1
                if steps > maxlen:
                    rec[:2 * nlegs] = saved
                    aborted = True
                    break
                if gmode > 0:
                    hsite = bj[b] if (ex & 1) else bi[b]
                    if hsite != tsite:
                        hg, hl = _gaps(xl, rec, nops)
                        ov = _overlap(hg, hl, tg, tl, nops)
                        if ov > 0:
                            hx = rec[xs] + dx
                            hy = rec[_st(rec[xs + 4])]
                            # the tail's states shift when the head passed through its segment
                            val = 2.0 * ov * sq[max(rec[_st(j0)], rec[_st(t0)])] * sq[max(hx, hy)]
                            if tup:
                                k = tsite
                                l = hsite
                            else:
                                k = hsite
                                l = tsite
                            if gfull:
                                gcur[k, l] += val
                            c = _pair_class(k, l, gmode, gclass, zr, zi, omz, hbin, ncls)
                            vcur[voff + c] += val * gsign[k] * gsign[l]
                if xl == j0 or xl == t0:
                    rec[xs] += dx
                    if rec[_st(j0)] == rec[_st(t0)]:
                        break
                    rec[xs] -= dx
                nxt = rec[xs + 4]
                rec[xs] += dx
                rec[_st(nxt)] += dx
                jl = nxt
                d = dx
    # operator types and the time-0 state from the legs
    vv = 0
    for p in range(m):
        if ops[p] < 0:
            continue
        base = 8 * vv
        b = vb[vv]
        if rec[base] == rec[base + 2]:
            ops[p] = 4 * b
        elif rec[base + 2] > rec[base]:
            ops[p] = 4 * b + 1
        else:
            ops[p] = 4 * b + 2
        vv += 1
    for i in range(nsites):
        if first[i] >= 0:
            state[i] = rec[_st(first[i])]
        else:
            # no operator acts on site i: the weight does not depend on n_i (the on-site energy is
            # inside the bond vertices), so n_i is uniform over 0..nmax
            state[i] = _below(rng, nmax + 1)
    return -1 - visited if aborted else visited


@numba.njit(cache=True)
def run(nsweeps, thermalize, target_legs, ops, state, nops, nloops, beta, bi, bj, tb, cb, esite, sq, nmax,
        rng, sbins, scur, sinfo, vbins, vcur, vinfo, loopstat, gmode, gclass, zr, zi, omz, hbin, ncls,
        gbins, gcur, ginfo, gsign, ptab, bclass, eps, green_legs, wind):  # pragma: no cover - jitted
    r"""Run ``nsweeps`` sweeps. Returns (ops, nops, nloops) (``ops`` is reallocated when it grows).

    Thermalisation (``thermalize``): after each sweep the string grows to M = 4n/3 + 4 sqrt(n)
    when n > 3M/4 (Sandvik's 4n/3, with room for a short string's fluctuations), to M = 2n when
    it was full (n >= 0.95 M: the equilibrium length is then unknown, and doubling reaches it in
    a few sweeps), and the loops per sweep are set so that about ``target_legs`` x n vertex legs
    are visited per sweep (from the running mean loop length in ``loopstat``); a thermalisation
    sweep starts no loop once 2 x ``target_legs`` x n legs are visited (the loops of a
    configuration far from equilibrium are long).

    Measurement: per sweep the scalars (n, n^2, N, N^2, N^4, E, E^2) are added to ``scur`` and the
    site occupation sums / M and per-bond off-diagonal counts to ``vcur``. E is the energy estimator
    :math:`E = \frac1M\sum_p\sum_i \epsilon(n_i(p)) - n_{\mathrm{offd}}/\beta` (``eps[k]`` the
    on-site energy of occupation k, averaged over the M time slices; :math:`n_{\mathrm{offd}}` the
    off-diagonal operators); a bin of ``sinfo[1]``
    (``vinfo[1]``) sweeps is closed into ``sbins`` (``vbins``); when the bin array is full its
    bins are merged pairwise and the bin size doubles. The whole accumulation is a deterministic
    function of the sweep sequence (checkpoint-independent).

    Green function (``gmode`` > 0, measurement only): the worm sums per distance class go to the
    last ``ncls`` entries of ``vcur``; with ``gbins`` of more than one site, the full matrix
    (diagonal: the site occupations) to ``gcur`` and blocks of it to ``gbins`` (``ginfo`` as above).
    A measured sweep with the Green function runs ``max(nloops, loopstat[3])`` loops: the estimator's
    own budget, set in thermalisation like ``nloops`` but for ``green_legs`` x n legs (the update
    alone needs fewer); every other sweep runs ``nloops``.

    Winding numbers (``wind`` of shape (B, D), D > 0, measurement only): the moments of
    :func:`winding_moments` go to the scalar sums after the first seven (``scur[7:]``); with
    D = 0 nothing is done.
    """
    nsites = state.shape[0]
    nbonds = bi.shape[0]
    m = ops.shape[0]
    occ = np.zeros(nsites, dtype=np.int64)
    last = np.zeros(nsites, dtype=np.int64)
    offd = np.zeros(nbonds, dtype=np.int64)
    hist = np.zeros(eps.shape[0], dtype=np.int64)
    first = np.empty(nsites, dtype=np.int64)
    lastleg = np.empty(nsites, dtype=np.int64)
    cap = max(m, 16)
    # int32 vertex bonds and records (leg states and links side by side: one cache line per step)
    vb = np.empty(cap, dtype=np.int32)
    rec = np.empty(8 * cap, dtype=np.int32)
    nv = vcur.shape[0]
    ntab = ptab.shape[0]
    gfull = gbins.shape[1] == nsites and nsites > 1
    voff = nsites + nbonds
    wvec = np.zeros(wind.shape[1], dtype=np.int64)
    started = np.zeros(1, dtype=np.int64)
    for sweep in range(nsweeps):
        measure = not thermalize
        if measure:
            for i in range(nsites):
                occ[i] = 0
            for b in range(nbonds):
                offd[b] = 0
            for k in range(hist.shape[0]):
                hist[k] = 0
        nops = _diagonal_update(ops, state, nops, beta, bi, bj, cb, esite, rng, occ, last, offd, measure, hist)
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
            # energy: slice-averaged diagonal (site) energy minus off-diagonal operators / beta
            ediag = 0.0
            for k in range(hist.shape[0]):
                ediag += hist[k] * eps[k]
            nod = 0
            for b in range(nbonds):
                nod += offd[b]
            fE = ediag / m - nod / beta
            scur[5] += fE
            scur[6] += fE * fE
            if wind.shape[1] > 0:       # winding numbers (superfluid stiffness): periodic graphs only
                winding_moments(ops, wind, wvec, scur, 7)
            for i in range(nsites):
                vcur[i] += occ[i] / m
            if gfull:
                for i in range(nsites):
                    gcur[i, i] += occ[i] / m
            for b in range(nbonds):
                vcur[nsites + b] += offd[b]
        if ops.shape[0] > cap:
            cap = ops.shape[0]
            vb = np.empty(cap, dtype=np.int32)
            rec = np.empty(8 * cap, dtype=np.int32)
        gm = 0 if thermalize else gmode
        nl = max(nloops, int(loopstat[3])) if gm > 0 else nloops
        # thermalisation: at most twice the sweep's leg budget (see _loop_update)
        legcap = int(2.0 * target_legs * nops) + 64 if thermalize else 0
        visited = _loop_update(ops, state, nops, nl, bi, bj, tb, cb, esite, sq, nmax, rng,
                               vb, rec, first, lastleg, gm, gfull, gcur, gclass,
                               zr, zi, omz, hbin, vcur, voff, ncls, gsign, ptab, bclass, ntab, legcap, started)
        if visited < 0:     # a runaway loop: this sweep's loop update was undone (counted)
            visited = -1 - visited
            loopstat[2] += 1
        if thermalize:
            # loops per sweep from the recent mean loop length (aborted starts included); the sums
            # decay so that the short loops of the first sweeps, on a short string, are forgotten
            loopstat[0] = 0.9 * loopstat[0] + visited
            loopstat[1] = 0.9 * loopstat[1] + started[0]
            mean_len = loopstat[0] / max(loopstat[1], 1.0)
            want = target_legs * nops / max(mean_len, 1e-3)
            # at most a few loops per operator: a loop visits at least its first vertex
            nloops = int(min(max(want, 1.0), 4.0 * (nops + 16)))
            # the Green-function estimator's loops per measured sweep (its own leg budget)
            loopstat[3] = float(int(min(max(want * green_legs / target_legs, 1.0), 4.0 * (nops + 16))))
            if nops > 0.75 * m:
                # 4n/3 (Sandvik) and 4 sqrt(n) more: a short string's n fluctuates by several
                # sqrt(n), and a measurement that comes near M is flagged as truncated
                newm = (4 * nops) // 3 + 8 + int(4.0 * np.sqrt(nops))
                if nops >= 0.95 * m:
                    # a full string says nothing of the equilibrium length: double it
                    newm = 2 * nops + 8
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
            if gfull:
                ginfo[2] += 1
                if ginfo[2] == ginfo[1]:
                    nb = ginfo[0]
                    gbins[nb] = gcur
                    gcur[:, :] = 0.0
                    ginfo[0] = nb + 1
                    ginfo[2] = 0
                    if ginfo[0] == gbins.shape[0]:
                        half = gbins.shape[0] // 2
                        for a in range(half):
                            gbins[a] = gbins[2 * a] + gbins[2 * a + 1]
                        ginfo[0] = half
                        ginfo[1] *= 2
    return ops, nops, nloops


@numba.njit(cache=True)
def pair_counts(zr, zi, omz, hbin, ncls):  # pragma: no cover - jitted
    r"""Ordered site pairs (k != l) and their summed hyperbolic distance per distance class."""
    cnt = np.zeros(ncls, dtype=np.int64)
    dsum = np.zeros(ncls)
    n = zr.shape[0]
    for k in range(n):
        for l in range(n):
            if k == l:
                continue
            dx = zr[k] - zr[l]
            dy = zi[k] - zi[l]
            d = np.arcsinh(np.sqrt((dx * dx + dy * dy) / (omz[k] * omz[l])))
            c = int(d / hbin + 0.5)
            if c >= ncls:
                c = ncls - 1
            cnt[c] += 1
            dsum[c] += d
    return cnt, dsum
