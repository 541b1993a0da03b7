r"""numba kernels of the classical spin Monte Carlo (Ising, XY, Heisenberg) on any graph.

Imported on first use by :mod:`hyperlattice.spins.classical` (never at package import), compiled
with ``cache=True``. The front end owns validation, the gauge, memory checks and statistics; these
kernels only move the Markov chain and accumulate raw sums.

Configuration
-------------
``spins`` is an (N, n) array of unit vectors (n = 1: Ising, entries ±1; n = 2: XY; n = 3:
Heisenberg) in the *gauged* frame: a site sign :math:`g_i = \pm 1` turns the couplings into
:math:`g_i g_j J_{ij}` (all non-negative when a cluster update runs) and the field into
``hsite[i]`` :math:`= g_i h` along component 0; the physical spin is :math:`g_i s_i`. The graph is
given in CSR form (``indptr``, ``indices``, gauged coupling ``J`` per stored entry).

Random numbers come from the bosons' xoshiro256** generator (:mod:`hyperlattice.bosons._sse_kernels`),
whose whole state is an array: a checkpoint continues a chain bit-identically.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from ..bosons._sse_kernels import _below, _uniform

#: per-sweep scalars: E, E^2, m2, m4, |m|, m_0 (the field component), ms2, ms4, |ms|, m2 from the
#: Wolff clusters (improved estimator; 0 for local updates), clusters per sweep
NSCALARS = 11


@numba.njit(cache=True, inline="always")
def _random_unit(rng, ncomp, out):  # pragma: no cover - jitted
    if ncomp == 1:
        out[0] = 1.0
    elif ncomp == 2:
        phi = 2.0 * math.pi * _uniform(rng)
        out[0] = math.cos(phi)
        out[1] = math.sin(phi)
    else:
        z = 2.0 * _uniform(rng) - 1.0
        phi = 2.0 * math.pi * _uniform(rng)
        r = math.sqrt(max(0.0, 1.0 - z * z))
        out[0] = z
        out[1] = r * math.cos(phi)
        out[2] = r * math.sin(phi)


@numba.njit(cache=True)
def _wolff(spins, ncomp, indptr, indices, J, padd, beta, rng, queue, inside, r):  # pragma: no cover - jitted
    r"""One Wolff cluster (Wolff, PRL 62, 361 (1989)): reflection of the embedded Ising spins
    :math:`\sigma_i = s_i\cdot r` along a random direction r; a bond joins when
    :math:`u < 1 - e^{-2\beta J_{ij}\sigma_i\sigma_j}` (before the flip; for Ising spins the
    precomputed ``padd`` of each bond). Returns (size, sum |sigma|)."""
    n = spins.shape[0]
    _random_unit(rng, ncomp, r)
    seed = _below(rng, n)
    sr = 0.0
    for a in range(ncomp):
        sr += spins[seed, a] * r[a]
    proj = abs(sr)
    for a in range(ncomp):
        spins[seed, a] -= 2.0 * sr * r[a]
    inside[seed] = True
    queue[0] = seed
    head = 0
    size = 1
    while head < size:
        i = queue[head]
        head += 1
        si = 0.0                       # the flipped sigma_i; before the flip it was -si
        for a in range(ncomp):
            si += spins[i, a] * r[a]
        for k in range(indptr[i], indptr[i + 1]):
            j = indices[k]
            if inside[j]:
                continue
            if ncomp == 1:
                sj = spins[j, 0]
                if sj != si and _uniform(rng) < padd[k]:    # aligned before i flipped
                    spins[j, 0] = -sj
                    inside[j] = True
                    queue[size] = j
                    size += 1
                    proj += 1.0
                continue
            sj = 0.0
            for a in range(ncomp):
                sj += spins[j, a] * r[a]
            x = -si * sj * J[k]
            if x > 0.0 and _uniform(rng) < -math.expm1(-2.0 * beta * x):
                for a in range(ncomp):
                    spins[j, a] -= 2.0 * sj * r[a]
                inside[j] = True
                queue[size] = j
                size += 1
                proj += abs(sj)
    for k in range(size):
        inside[queue[k]] = False
    return size, proj


@numba.njit(cache=True, inline="always")
def _find(parent, i):  # pragma: no cover - jitted
    root = i
    while parent[root] != root:
        root = parent[root]
    while parent[i] != root:            # path compression
        nxt = parent[i]
        parent[i] = root
        i = nxt
    return root


@numba.njit(cache=True)
def _swendsen_wang(spins, ncomp, indptr, indices, J, padd, beta, rng, parent, size, state, psum, r):  # pragma: no cover
    r"""One Swendsen–Wang update (Swendsen & Wang, PRL 58, 86 (1987); O(n) by the embedded Ising
    spins along a random direction r, as in :func:`_wolff`): every bond joins with
    :math:`1 - e^{-2\beta J_{ij}\sigma_i\sigma_j}` when :math:`\sigma_i\sigma_j > 0`, every cluster
    (union-find) is reflected with probability 1/2. Returns (clusters, sum over clusters of
    (sum |sigma|)^2) for the improved estimator."""
    n = spins.shape[0]
    _random_unit(rng, ncomp, r)
    for i in range(n):
        parent[i] = i
        size[i] = 1
        state[i] = 0
        psum[i] = 0.0
    for i in range(n):
        si = 0.0
        for a in range(ncomp):
            si += spins[i, a] * r[a]
        for k in range(indptr[i], indptr[i + 1]):
            j = indices[k]
            if j <= i:
                continue
            if ncomp == 1:
                if spins[j, 0] != spins[i, 0] or _uniform(rng) >= padd[k]:
                    continue
            else:
                sj = 0.0
                for a in range(ncomp):
                    sj += spins[j, a] * r[a]
                x = si * sj * J[k]
                if x <= 0.0 or _uniform(rng) >= -math.expm1(-2.0 * beta * x):
                    continue
            a_ = _find(parent, i)
            b_ = _find(parent, j)
            if a_ != b_:
                if size[a_] < size[b_]:
                    a_, b_ = b_, a_
                parent[b_] = a_
                size[a_] += size[b_]
    clusters = 0
    for i in range(n):
        root = _find(parent, i)
        if state[root] == 0:
            state[root] = 1 if _uniform(rng) < 0.5 else 2
            clusters += 1
        sr = 0.0
        for a in range(ncomp):
            sr += spins[i, a] * r[a]
        psum[root] += abs(sr)
        if state[root] == 1:
            for a in range(ncomp):
                spins[i, a] -= 2.0 * sr * r[a]
    imp = 0.0
    for i in range(n):
        if parent[i] == i:
            imp += psum[i] * psum[i]
    return clusters, imp


@numba.njit(cache=True)
def _local_field(spins, ncomp, indptr, indices, J, hsite, i, hv):  # pragma: no cover - jitted
    for a in range(ncomp):
        hv[a] = 0.0
    for k in range(indptr[i], indptr[i + 1]):
        j = indices[k]
        for a in range(ncomp):
            hv[a] += J[k] * spins[j, a]
    hv[0] += hsite[i]


@numba.njit(cache=True)
def _heatbath(spins, ncomp, indptr, indices, J, hsite, beta, rng, hv, e1, e2):  # pragma: no cover - jitted
    r"""One heat-bath pass over the sites in order: each spin drawn from
    :math:`\exp(\beta\, h_i\cdot s_i)`, :math:`h_i = \sum_j J_{ij} s_j + h_i^{\mathrm{ext}}`
    (Ising: :math:`P(+1) = 1/(1+e^{-2\beta h})`; XY: von Mises by Best & Fisher, Appl. Statist.
    28, 152 (1979); Heisenberg: :math:`\cos\theta` by inversion of its exponential law)."""
    n = spins.shape[0]
    for i in range(n):
        _local_field(spins, ncomp, indptr, indices, J, hsite, i, hv)
        if ncomp == 1:
            x = 2.0 * beta * hv[0]
            if x > 0:
                p = 1.0 / (1.0 + math.exp(-x))
            else:
                ex = math.exp(x)
                p = ex / (1.0 + ex)
            spins[i, 0] = 1.0 if _uniform(rng) < p else -1.0
            continue
        hn = 0.0
        for a in range(ncomp):
            hn += hv[a] * hv[a]
        hn = math.sqrt(hn)
        kappa = beta * hn
        if ncomp == 2:
            if kappa < 1e-8:
                th = 2.0 * math.pi * _uniform(rng)
            else:
                tau = 1.0 + math.sqrt(1.0 + 4.0 * kappa * kappa)
                rho = (tau - math.sqrt(2.0 * tau)) / (2.0 * kappa)
                rr = (1.0 + rho * rho) / (2.0 * rho)
                while True:
                    u1 = _uniform(rng)
                    u2 = 1.0 - _uniform(rng)
                    z = math.cos(math.pi * u1)
                    f = (1.0 + rr * z) / (rr + z)
                    c = kappa * (rr - f)
                    if c * (2.0 - c) - u2 > 0.0 or math.log(c / u2) + 1.0 - c >= 0.0:
                        break
                f = min(1.0, max(-1.0, f))
                th = math.acos(f)
                if _uniform(rng) < 0.5:
                    th = -th
                th += math.atan2(hv[1], hv[0])
            spins[i, 0] = math.cos(th)
            spins[i, 1] = math.sin(th)
            continue
        # Heisenberg
        if kappa < 1e-8:
            _random_unit(rng, 3, e1)
            for a in range(3):
                spins[i, a] = e1[a]
            continue
        u = _uniform(rng)
        ct = 1.0 + math.log(u + (1.0 - u) * math.exp(-2.0 * kappa)) / kappa
        ct = min(1.0, max(-1.0, ct))
        st = math.sqrt(max(0.0, 1.0 - ct * ct))
        phi = 2.0 * math.pi * _uniform(rng)
        # an orthonormal frame (e1, e2) perpendicular to the unit field h
        for a in range(3):
            hv[a] /= hn
        if abs(hv[0]) < 0.9:
            e1[0], e1[1], e1[2] = 0.0, -hv[2], hv[1]
        else:
            e1[0], e1[1], e1[2] = hv[2], 0.0, -hv[0]
        nrm = math.sqrt(e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2])
        for a in range(3):
            e1[a] /= nrm
        e2[0] = hv[1] * e1[2] - hv[2] * e1[1]
        e2[1] = hv[2] * e1[0] - hv[0] * e1[2]
        e2[2] = hv[0] * e1[1] - hv[1] * e1[0]
        cp = math.cos(phi)
        sp = math.sin(phi)
        for a in range(3):
            spins[i, a] = ct * hv[a] + st * (cp * e1[a] + sp * e2[a])


@numba.njit(cache=True)
def _overrelax(spins, ncomp, indptr, indices, J, hsite, hv):  # pragma: no cover - jitted
    r"""One over-relaxation pass: :math:`s_i \to 2(s_i\cdot\hat h_i)\hat h_i - s_i`, the reflection
    about the local field, which keeps the energy (microcanonical; Creutz, PRD 36, 515 (1987))."""
    n = spins.shape[0]
    for i in range(n):
        _local_field(spins, ncomp, indptr, indices, J, hsite, i, hv)
        h2 = 0.0
        sh = 0.0
        for a in range(ncomp):
            h2 += hv[a] * hv[a]
            sh += hv[a] * spins[i, a]
        if h2 <= 0.0:
            continue
        f = 2.0 * sh / h2
        nrm = 0.0
        for a in range(ncomp):
            spins[i, a] = f * hv[a] - spins[i, a]
            nrm += spins[i, a] * spins[i, a]
        nrm = math.sqrt(nrm)
        for a in range(ncomp):             # keep |s| = 1 against rounding drift
            spins[i, a] /= nrm


@numba.njit(cache=True)
def _close(bins, cur, info):  # pragma: no cover - jitted
    """Count one measurement into the running bin; close it when full, merge pairwise when the bins are."""
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
def run(nsweeps, thermalize, mode, overrelax, spins, indptr, indices, J, padd, hsite, beta, gauge, stag, rng,
        sbins, scur, sinfo, vbins, vcur, vinfo, group, cclass, crows, cevery, cbins, ccur, cinfo, counters, cstat):  # pragma: no cover
    r"""Run ``nsweeps`` sweeps; measure after each one unless ``thermalize``.

    ``mode`` 0: Wolff clusters; in thermalisation until as many spins were flipped as there are
    sites (one sweep), with the decayed mean cluster size kept in ``cstat``; measured sweeps run
    the fixed number ``counters[3]`` of clusters (N over that mean, set at the first measured sweep);
    ``mode`` 1: one heat-bath pass and ``overrelax`` over-relaxation passes (XY, Heisenberg);
    ``mode`` 2: one Swendsen–Wang update.

    Measurement (physical spins :math:`g_i s_i`; ``stag[i]`` :math:`= \epsilon_i g_i`, zero off
    bipartite graphs): the scalars of :data:`NSCALARS` to ``scur``; per site the local energy
    :math:`-\tfrac12\sum_j J_{ij}s_i\cdot s_j - h s_i^0`, the alignment :math:`s_i\cdot\hat M`,
    the staggered alignment :math:`\epsilon_i s_i\cdot\hat M_s` and :math:`s_i^0` to ``vcur``
    (4G entries: summed over the sites of each group ``group[i]``, the site itself or its ring); every ``cevery`` sweeps (``cevery`` > 0) the sums of
    :math:`s_i\cdot s_j` over the pairs i < j of each class ``cclass[i, j]`` (-1: not measured; rows from ``crows`` on have none) to ``ccur``. Bins
    are closed as in the bosons' SSE (sums of ``info[1]`` measurements; merged pairwise when full).
    ``counters``: [thermalisation sweeps, measured sweeps, correlation measurements, clusters per
    measured sweep].
    """
    n = spins.shape[0]
    ncomp = spins.shape[1]
    queue = np.empty(n, dtype=np.int64)
    inside = np.zeros(n, dtype=np.bool_)
    r = np.empty(ncomp)
    hv = np.empty(ncomp)
    e1 = np.empty(3)
    e2 = np.empty(3)
    parent = np.empty(n if mode == 2 else 1, dtype=np.int64)
    csize = np.empty(n if mode == 2 else 1, dtype=np.int64)
    cstate = np.empty(n if mode == 2 else 1, dtype=np.int8)
    psum = np.empty(n if mode == 2 else 1)
    M = np.empty(ncomp)
    Ms = np.empty(ncomp)
    ncls = ccur.shape[0]
    fn = float(n)
    ng = vcur.shape[0] // 4
    for sweep in range(nsweeps):
        imp = 0.0
        nclusters = 0
        if mode == 0:
            if thermalize:
                # clusters until N spins flipped; the decayed mean cluster size sets the count
                flipped = 0
                while flipped < n:
                    size, proj = _wolff(spins, ncomp, indptr, indices, J, padd, beta, rng, queue, inside, r)
                    flipped += size
                    cstat[0] = 0.99 * cstat[0] + size
                    cstat[1] = 0.99 * cstat[1] + 1.0
            else:
                # a fixed number of clusters per measured sweep: a count that depended on the sizes
                # drawn (a stopping time) would bias the measured configurations
                if counters[3] == 0:
                    mean = cstat[0] / cstat[1] if cstat[1] > 0 else 1.0
                    counters[3] = max(1, int(round(n / mean)))
                for c in range(counters[3]):
                    size, proj = _wolff(spins, ncomp, indptr, indices, J, padd, beta, rng, queue, inside, r)
                    nclusters += 1
                    imp += proj * proj / size
        elif mode == 2:
            nclusters, imp = _swendsen_wang(spins, ncomp, indptr, indices, J, padd, beta, rng, parent, csize, cstate,
                                            psum, r)
            # <|M|^2> = n <sum_C (sum_C |sigma|)^2>: the improved estimator times the clusters
            # (undone below, where Wolff's per-cluster mean is divided by the cluster count)
            imp *= nclusters / fn
        else:
            _heatbath(spins, ncomp, indptr, indices, J, hsite, beta, rng, hv, e1, e2)
            if ncomp > 1:
                for k in range(overrelax):
                    _overrelax(spins, ncomp, indptr, indices, J, hsite, hv)
        if thermalize:
            counters[0] += 1
            continue
        counters[1] += 1
        # energy and the moments
        E = 0.0
        for a in range(ncomp):
            M[a] = 0.0
            Ms[a] = 0.0
        for i in range(n):
            loc = 0.0
            for k in range(indptr[i], indptr[i + 1]):
                j = indices[k]
                d = 0.0
                for a in range(ncomp):
                    d += spins[i, a] * spins[j, a]
                loc += J[k] * d
            ei = -0.5 * loc - hsite[i] * spins[i, 0]
            vcur[group[i]] += ei
            E += ei
            for a in range(ncomp):
                M[a] += gauge[i] * spins[i, a]
                Ms[a] += stag[i] * spins[i, a]
        m2 = 0.0
        ms2 = 0.0
        for a in range(ncomp):
            m2 += M[a] * M[a]
            ms2 += Ms[a] * Ms[a]
        mabs = math.sqrt(m2)
        msabs = math.sqrt(ms2)
        for i in range(n):
            da = 0.0
            ds = 0.0
            for a in range(ncomp):
                da += gauge[i] * spins[i, a] * M[a]
                ds += stag[i] * spins[i, a] * Ms[a]
            g = group[i]
            vcur[ng + g] += da / mabs if mabs > 0 else 0.0
            vcur[2 * ng + g] += ds / msabs if msabs > 0 else 0.0
            vcur[3 * ng + g] += gauge[i] * spins[i, 0]
        m2 /= fn * fn
        ms2 /= fn * fn
        scur[0] += E
        scur[1] += E * E
        scur[2] += m2
        scur[3] += m2 * m2
        scur[4] += mabs / fn
        scur[5] += M[0] / fn
        scur[6] += ms2
        scur[7] += ms2 * ms2
        scur[8] += msabs / fn
        if nclusters > 0:
            # <|M|^2> = n N <(sum_C |sigma|)^2 / |C|> over Wolff clusters (per site: / N^2)
            scur[9] += ncomp * imp / nclusters / fn
        scur[10] += nclusters
        _close(sbins, scur, sinfo)
        _close(vbins, vcur, vinfo)
        if cevery > 0 and counters[1] % cevery == 0:
            for i in range(crows):
                for j in range(i + 1, n):
                    cl = cclass[i, j]
                    if cl < 0:          # a pair outside the measured set
                        continue
                    d = 0.0
                    for a in range(ncomp):
                        d += spins[i, a] * spins[j, a]
                    ccur[cl] += gauge[i] * gauge[j] * d
            counters[2] += 1
            _close(cbins, ccur, cinfo)
    return ncls


@numba.njit(cache=True)
def two_colour(indptr, indices, signs):  # pragma: no cover - jitted
    r"""Site signs :math:`g_i = \pm 1` with :math:`g_i g_j\,\mathrm{signs}_{ij} > 0` on every stored entry
    (breadth-first search, component by component); ok = False when no such signs exist."""
    n = indptr.shape[0] - 1
    g = np.zeros(n, dtype=np.int64)
    queue = np.empty(n, dtype=np.int64)
    for root in range(n):
        if g[root] != 0:
            continue
        g[root] = 1
        queue[0] = root
        head = 0
        tail = 1
        while head < tail:
            u = queue[head]
            head += 1
            for k in range(indptr[u], indptr[u + 1]):
                w = indices[k]
                want = g[u] * signs[k]
                if g[w] == 0:
                    g[w] = want
                    queue[tail] = w
                    tail += 1
                elif g[w] != want:
                    return g, False
    return g, True


@numba.njit(cache=True)
def energy(spins, indptr, indices, J, hsite):  # pragma: no cover - jitted
    r"""The energy :math:`-\tfrac12\sum_{ij} J_{ij}s_i\cdot s_j - \sum_i h_i s_i^0` of a configuration
    (gauged frame, as in :func:`run`): what a tempering exchange compares."""
    n = spins.shape[0]
    ncomp = spins.shape[1]
    E = 0.0
    for i in range(n):
        loc = 0.0
        for k in range(indptr[i], indptr[i + 1]):
            j = indices[k]
            d = 0.0
            for a in range(ncomp):
                d += spins[i, a] * spins[j, a]
            loc += J[k] * d
        E += -0.5 * loc - hsite[i] * spins[i, 0]
    return E
