"""Interacting bosons on the l = 12 {7,3} flake (725,760 sites): Gutzwiller mean field and discrete GP.

Each against a peer in the same process, on the same work:

* Gutzwiller: one self-consistency sweep (all local ground states) by the package's numba kernel
  (Sturm bisection + inverse iteration on each tridiagonal local Hamiltonian) against numpy's batched
  ``eigh`` on the stacked (nmax+1)x(nmax+1) matrices (LAPACK per matrix), then the whole
  self-consistent run timed alone.
* GP ground state: the package (L-BFGS, then Newton through graph.factor) against scipy's L-BFGS
  run to the same GP residual without the Newton polish.

Prints times and ratios (peer / package). Run: ``python benchmarks/bench_bosons_meanfield.py``.
"""

from __future__ import annotations

import math
import time

import numpy as np

import hyperlattice as hl
from hyperlattice.bosons import gp as G
from hyperlattice.bosons import meanfield as mf


def best(fn, repeat=2):
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t0)
    return min(times), out


def main() -> None:
    lat = hl.ring_lattice(7, 3, 12)
    a = mf._adjacency(lat)
    n = a.shape[0]
    print(f"l = 12 flake: {n} sites")
    lam = mf.largest_adjacency_eigenvalue(lat)
    t = 1.5 * mf.lobe_boundary(lam, 0.4)
    nmax = 4
    phi = t * (a @ np.full(n, 0.7))
    outs = [np.empty(n) for _ in range(3)]
    kernel = mf._local_kernel(n >= mf._PARALLEL_SITES)
    cold = np.full(n, np.nan)   # no warm start: every site from its Gershgorin bracket
    kernel(phi, cold, 1.0, 0.4, nmax, *outs)  # compile

    def ours():
        kernel(phi, cold, 1.0, 0.4, nmax, *outs)
        return outs[0].copy()

    def peer():
        k = np.arange(nmax + 1)
        base = np.diag(0.5 * k * (k - 1) - 0.4 * k)
        hop = np.diag(np.sqrt(k[1:]), 1) + np.diag(np.sqrt(k[1:]), -1)
        h = base[None, :, :] - phi[:, None, None] * hop[None, :, :]
        _, v = np.linalg.eigh(h)
        v0 = v[:, :, 0]
        return np.abs(np.sum(np.sqrt(k[1:])[None, :] * v0[:, :-1] * v0[:, 1:], axis=1))

    t_ours, psi_ours = best(ours)
    t_peer, psi_peer = best(peer, 1)
    print(f"Gutzwiller sweep: package {t_ours:.2f} s, numpy batched eigh {t_peer:.2f} s, ratio {t_peer / t_ours:.1f}x "
          f"(max |psi difference| {np.max(np.abs(psi_ours - psi_peer)):.1e})")
    t0 = time.perf_counter()
    st = mf.gutzwiller(lat, t, 0.4, 1.0)
    print(f"Gutzwiller self-consistent state: {time.perf_counter() - t0:.1f} s, {st.iterations} iterations, "
          f"residual {st.residual:.1e}, converged {st.converged}")

    N = float(n)
    t0 = time.perf_counter()
    s = G.gp_ground_state(lat, N, 0.5)
    t_gp = time.perf_counter() - t0
    print(f"GP ground state (package): {t_gp:.1f} s, residual {s.residual:.1e}, mu = {s.mu:.10f}")
    from scipy.optimize import minimize

    h = -a

    def eg(x):
        nx = np.linalg.norm(x)
        psi = math.sqrt(N) * x / nx
        hp = h @ psi
        e = float(psi @ hp + 0.25 * np.sum(psi**4))
        g = 2.0 * (hp + 0.5 * psi**3)
        return e, (math.sqrt(N) / nx) * (g - psi * (psi @ g) / N)

    t0 = time.perf_counter()
    res = minimize(eg, np.ones(n), jac=True, method="L-BFGS-B", options={"maxiter": 20000, "gtol": 1e-12, "ftol": 0.0})
    t_peer = time.perf_counter() - t0
    psi = math.sqrt(N) * res.x / np.linalg.norm(res.x)
    mu = (psi @ (h @ psi) + 0.5 * np.sum(psi**4)) / N
    r = np.linalg.norm(h @ psi + 0.5 * psi**3 - mu * psi) / (abs(mu) * math.sqrt(N))
    print(f"GP by plain L-BFGS (peer): {t_peer:.1f} s, {res.nit} iterations, residual {r:.1e}; "
          f"ratio {t_peer / t_gp:.1f}x at {'a worse' if r > s.residual else 'the same'} residual")


if __name__ == "__main__":
    main()
