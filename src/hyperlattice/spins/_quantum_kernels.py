r"""numba kernels of the spin-1/2 XXZ SSE: the diagonal update with the bond interaction and the
spin observables, around the bosons' directed-loop update.

Imported on first use by :mod:`hyperlattice.spins.quantum` (never at package import), compiled
with ``cache=True``. The configuration, the operator string, the vertex list, the directed-loop
update (:func:`hyperlattice.bosons._sse_kernels._loop_update`, least-bounce exits), the random
numbers (xoshiro256**) and the winding numbers are the bosons' (hard-core bosons, n = S^z + 1/2);
what is here is only what the Bose–Hubbard engine does not have:

* the bond-diagonal weight :math:`W_b(n_i, n_j) = C_b - h_b(n_i, n_j)` with an arbitrary 2 x 2
  table per bond (the :math:`J\Delta S^z_iS^z_j` term couples both occupations; the boson
  engine's diagonal weight is a sum of one-site terms), in the diagonal update and in the
  exit-probability table the loop update reads;
* the measurements along imaginary time: the staggered magnetisation
  :math:`M_s = \sum_i \epsilon_i S^z_i` and its square and fourth power, the site magnetisation,
  the site-resolved staggered correlation :math:`\epsilon_i S^z_i M_s` and the bond correlation
  :math:`S^z_iS^z_j`, each averaged over the M time slices of the configuration; the diagonal
  energy follows from the last two, :math:`\sum_b J_b\Delta\,\overline{S^z_iS^z_j} - h\sum_i\overline{S^z_i}`.
"""

from __future__ import annotations

import numba
import numpy as np

from ..bosons import _sse_kernels as K

#: per-sweep scalars: n, n^2, E, E^2, Sz, Sz^2, Sz^4, Ms^2, (Ms^2)^2, Ms^4, E_diag, E_diag^2, E E_diag
#: (then the winding moments)
NSCALARS = 13


@numba.njit(cache=True, inline="always")
def _vertex_weight(b, s0, s1, s2, s3, wdiag, tb):  # pragma: no cover - jitted
    r"""<s2 s3| -H_b + C_b |s0 s1> for hard-core bosons (0 when not allowed)."""
    if s0 < 0 or s1 < 0 or s2 < 0 or s3 < 0 or s0 > 1 or s1 > 1 or s2 > 1 or s3 > 1:
        return 0.0
    if s0 == s2:
        if s1 != s3:
            return 0.0
        return wdiag[b, s0, s1]
    if s0 + s1 != s2 + s3:
        return 0.0
    return tb[b]


@numba.njit(cache=True)
def exit_table(rep, wdiag, tb):  # pragma: no cover - jitted
    r"""Cumulative exit probabilities (least bounce) per bond class, vertex code, entrance leg and
    sign of the change, in the layout of the bosons' table (nmax = 1: 16 vertex codes)."""
    out = np.zeros((rep.shape[0], 16, 4, 2, 4))
    w = np.empty(4)
    for c in range(rep.shape[0]):
        b = rep[c]
        for code in range(16):
            s0 = code & 1
            s1 = (code >> 1) & 1
            s2 = (code >> 2) & 1
            s3 = (code >> 3) & 1
            for le in range(4):
                for di in range(2):
                    d = 1 if di == 0 else -1
                    for x in range(4):
                        dx = -d if (x >> 1) == (le >> 1) else d
                        a0 = s0 + dx if x == 0 else s0
                        a1 = s1 + dx if x == 1 else s1
                        a2 = s2 + dx if x == 2 else s2
                        a3 = s3 + dx if x == 3 else s3
                        w[x] = _vertex_weight(b, a0, a1, a2, a3, wdiag, tb)
                    K._cumulative(w, le)
                    for x in range(4):
                        out[c, code, le, di, x] = w[x]
    return out


@numba.njit(cache=True, inline="always")
def _close_bonds(x, skip, state, bi, bj, nptr, nbond, p1, zz, lastb):  # pragma: no cover - jitted
    r"""Close the time intervals of the bonds of site x (but ``skip``) in the :math:`S^z_iS^z_j` sums."""
    for k in range(nptr[x], nptr[x + 1]):
        bb = nbond[k]
        if bb == skip:
            continue
        zz[bb] += (state[bi[bb]] - 0.5) * (state[bj[bb]] - 0.5) * (p1 - lastb[bb])
        lastb[bb] = p1


@numba.njit(cache=True)
def _diagonal_update(ops, state, nops, beta, bi, bj, wdiag, stag, nptr, nbond, rng, measure, acc,
                     sz, st, lastp, lasti, zz, lastb, offd):  # pragma: no cover - jitted
    r"""Insert/remove diagonal operators; with ``measure`` the time-slice averages of the sweep.

    ``acc`` gets (:math:`M_s^2`, :math:`M_s^4`), each summed over the M slices;
    ``sz[i]`` :math:`\sum_p S^z_i(p)`, ``st[i]`` :math:`\sum_p S^z_i(p) M_s(p)`, ``zz[b]``
    :math:`\sum_p S^z_i(p)S^z_j(p)` and ``offd[b]`` the off-diagonal operators of bond b.
    """
    m = ops.shape[0]
    nb = bi.shape[0]
    n = state.shape[0]
    bnb = beta * nb
    ms = 0.0
    integ = 0.0
    last = 0
    if measure:
        for b in range(nb):
            lastb[b] = 0
        for i in range(n):
            ms += stag[i] * (state[i] - 0.5)
            lastp[i] = 0
            lasti[i] = 0.0
        acc[0] = 0.0
        acc[1] = 0.0
    for p in range(m):
        op = ops[p]
        if op < 0:
            b = K._below(rng, nb)
            w = wdiag[b, state[bi[b]], state[bj[b]]]
            if K._uniform(rng) * (m - nops) < bnb * w:
                ops[p] = 4 * b
                nops += 1
        elif (op & 3) == 0:
            b = op >> 2
            w = wdiag[b, state[bi[b]], state[bj[b]]]
            if K._uniform(rng) * bnb * w < m - nops + 1:
                ops[p] = -1
                nops -= 1
        else:
            b = op >> 2
            i = bi[b]
            j = bj[b]
            if measure:
                ln = p + 1 - last
                m2 = ms * ms
                acc[0] += m2 * ln
                acc[1] += m2 * m2 * ln
                integ += ms * ln
                last = p + 1
                offd[b] += 1
                for x in (i, j):
                    s = state[x] - 0.5
                    sz[x] += s * (p + 1 - lastp[x])
                    st[x] += s * (integ - lasti[x])
                    lastp[x] = p + 1
                    lasti[x] = integ
                _close_bonds(i, -1, state, bi, bj, nptr, nbond, p + 1, zz, lastb)
                _close_bonds(j, b, state, bi, bj, nptr, nbond, p + 1, zz, lastb)
                ms -= stag[i] * (state[i] - 0.5) + stag[j] * (state[j] - 0.5)
            if (op & 3) == 1:
                state[i] += 1
                state[j] -= 1
            else:
                state[i] -= 1
                state[j] += 1
            if measure:
                ms += stag[i] * (state[i] - 0.5) + stag[j] * (state[j] - 0.5)
    if measure:
        ln = m - last
        m2 = ms * ms
        acc[0] += m2 * ln
        acc[1] += m2 * m2 * ln
        integ += ms * ln
        for x in range(n):
            s = state[x] - 0.5
            sz[x] += s * (m - lastp[x])
            st[x] += s * (integ - lasti[x])
        for b in range(nb):
            zz[b] += (state[bi[b]] - 0.5) * (state[bj[b]] - 0.5) * (m - lastb[b])
    return nops


@numba.njit(cache=True, inline="always")
def _close_bin(bins, cur, info):  # pragma: no cover - jitted
    r"""One more sweep in the current bin; a full bin is stored, and a full bin array merged pairwise."""
    info[2] += 1
    if info[2] == info[1]:
        nb = info[0]
        for k in range(cur.shape[0]):
            bins[nb, k] = cur[k]
            cur[k] = 0.0
        info[0] = nb + 1
        info[2] = 0
        if info[0] == bins.shape[0]:
            half = bins.shape[0] // 2
            for a in range(half):
                for k in range(cur.shape[0]):
                    bins[a, k] = bins[2 * a, k] + bins[2 * a + 1, k]
            info[0] = half
            info[1] *= 2


@numba.njit(cache=True)
def run(nsweeps, thermalize, target_legs, ops, state, nops, nloops, beta, bi, bj, tb, cb, wdiag, jz, hfield, stag,
        nptr, nbond, rng, sbins, scur, sinfo, vbins, vcur, vinfo, loopstat, ptab, bclass, wind):  # pragma: no cover
    r"""Run ``nsweeps`` sweeps (diagonal update, then the bosons' directed loops with ``ptab``).

    Returns (ops, nops, nloops). Thermalisation adapts the string length (M = 4n/3 when
    n > 3M/4) and the loops per sweep (about ``target_legs`` x n vertex legs) as the bosons'
    engine does. Measurement: per sweep the scalars of :data:`NSCALARS` (then the winding moments
    when ``wind`` has columns) to ``scur``, and to ``vcur`` the slice averages of
    :math:`S^z_i` (sites), :math:`\epsilon_i S^z_i M_s` (sites), :math:`S^z_iS^z_j` (bonds) and
    the off-diagonal operator counts (bonds); bins are closed as in the bosons' engine.
    """
    n = state.shape[0]
    nb = bi.shape[0]
    m = ops.shape[0]
    acc = np.zeros(2)
    sz = np.zeros(n)
    st = np.zeros(n)
    lastp = np.zeros(n, dtype=np.int64)
    lasti = np.zeros(n)
    zz = np.zeros(nb)
    lastb = np.zeros(nb, dtype=np.int64)
    offd = np.zeros(nb, dtype=np.int64)
    first = np.empty(n, dtype=np.int64)
    lastleg = np.empty(n, dtype=np.int64)
    cap = max(m, 16)
    vb = np.empty(cap, dtype=np.int32)
    rec = np.empty(8 * cap, dtype=np.int32)
    esite = np.zeros((n, 2))
    sq = np.sqrt(np.arange(3.0))
    gcur = np.zeros((1, 1))
    gclass = np.zeros((1, 1), dtype=np.int64)
    one = np.ones(1)
    started = np.zeros(1, dtype=np.int64)     # loops started (the bosons' thermalisation cap is not used)
    gsign = np.ones(n)
    ntab = ptab.shape[0]
    wvec = np.zeros(wind.shape[1], dtype=np.int64)
    for sweep in range(nsweeps):
        measure = not thermalize
        if measure:
            for i in range(n):
                sz[i] = 0.0
                st[i] = 0.0
            for b in range(nb):
                zz[b] = 0.0
                offd[b] = 0
        nops = _diagonal_update(ops, state, nops, beta, bi, bj, wdiag, stag, nptr, nbond, rng, measure, acc,
                                sz, st, lastp, lasti, zz, lastb, offd)
        if measure:
            fm = float(m)
            stot = 0.0
            for i in range(n):
                stot += state[i] - 0.5
            nod = 0
            for b in range(nb):
                nod += offd[b]
            fn = float(nops)
            # the diagonal energy summed over the slices from the bond and site sums (jz = J_b Delta)
            ediag = 0.0
            for b in range(nb):
                ediag += jz[b] * zz[b]
            for i in range(n):
                ediag -= hfield * sz[i]
            e = ediag / fm - nod / beta
            m2 = acc[0] / fm
            scur[0] += fn
            scur[1] += fn * fn
            scur[2] += e
            scur[3] += e * e
            scur[4] += stot
            scur[5] += stot * stot
            scur[6] += stot * stot * stot * stot
            scur[7] += m2
            scur[8] += m2 * m2
            scur[9] += acc[1] / fm
            scur[10] += ediag / fm
            scur[11] += (ediag / fm) ** 2
            scur[12] += e * ediag / fm
            if wind.shape[1] > 0:
                K.winding_moments(ops, wind, wvec, scur, NSCALARS)
            for i in range(n):
                vcur[i] += sz[i] / fm
                vcur[n + i] += stag[i] * st[i] / fm
            for b in range(nb):
                vcur[2 * n + b] += zz[b] / fm
                vcur[2 * n + nb + b] += offd[b]
        if ops.shape[0] > cap:
            cap = ops.shape[0]
            vb = np.empty(cap, dtype=np.int32)
            rec = np.empty(8 * cap, dtype=np.int32)
        visited = K._loop_update(ops, state, nops, nloops, bi, bj, tb, cb, esite, sq, 1, rng,
                                 vb, rec, first, lastleg, 0, False, gcur, gclass,
                                 one, one, one, 1.0, vcur, 0, 1, gsign, ptab, bclass, ntab, 0, started)
        if visited < 0:
            visited = -1 - visited
            loopstat[2] += 1
        if thermalize:
            loopstat[0] = 0.9 * loopstat[0] + visited
            loopstat[1] = 0.9 * loopstat[1] + nloops
            mean_len = loopstat[0] / max(loopstat[1], 1.0)
            want = target_legs * nops / max(mean_len, 1e-3)
            nloops = int(min(max(want, 1.0), 4.0 * (nops + 16)))
            if nops > 0.75 * m:
                newm = (4 * nops) // 3 + 8
                new = np.full(newm, -1, dtype=np.int64)
                k = 0
                for p in range(m):
                    if ops[p] >= 0:
                        new[(k * newm) // nops] = ops[p]
                        k += 1
                ops = new
                m = newm
        else:
            _close_bin(sbins, scur, sinfo)
            _close_bin(vbins, vcur, vinfo)
    return ops, nops, nloops
