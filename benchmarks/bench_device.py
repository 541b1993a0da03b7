"""Transmission sweeps of resonator devices: hyperlattice.device.transmission against one sparse LU per
frequency, as a user would write it (scipy.sparse.linalg.splu of ω − H + iΓ/2, two solves, S assembled).

Cases (the issue's): the Kollár device (line graph of the {7,3} ℓ = 3 flake, 140 resonators, J = −66 MHz,
κ_int = 0.7 MHz, two ports of 1 MHz), 10⁴ frequencies; the ℓ = 8 line-graph device (19,698 resonators),
2,000 frequencies. CHOLMOD is no peer here: ω − H + iΓ/2 is complex symmetric, not Hermitian, and CHOLMOD
factorises only Hermitian matrices. Project and peer run in this process, interleaved (best of REPEAT);
the peer of the large case is timed on a strided subset of the frequencies and scaled (stated).

Memory: the project's peak of traced allocations (numpy, tracemalloc) during the call; the peer's
factor size (entries of L + U, 16 bytes each, plus indices) per frequency.

Run: ``PYTHONPATH=src nice -n 5 python benchmarks/bench_device.py [--quick]``
"""

from __future__ import annotations

import argparse
import os
import sys
import time
import tracemalloc

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

sys.path.insert(0, os.path.dirname(__file__))
from _machine import machine  # noqa: E402

from hyperlattice.device import resonator_device, transmission  # noqa: E402
from hyperlattice.graph.lattice import ring_lattice  # noqa: E402


def _peer(dev, omegas):
    """One splu per frequency: S = 1 - i sqrt(k k) G_PP, G = (omega - H + i Gamma/2)^-1."""
    h = dev.hamiltonian().tocsc().astype(np.complex128)
    n = h.shape[0]
    idx = np.asarray(dev.port_index)
    kap = np.asarray(dev.port_kappa)
    gam = np.full(n, dev.kappa_int)
    gam[idx] += kap
    base = (sp.diags(0.5j * gam) - h).tocsc()
    eye = sp.identity(n, format="csc")
    rhs = np.zeros((n, idx.size), np.complex128)
    rhs[idx, np.arange(idx.size)] = 1.0
    out = np.empty((len(omegas), idx.size, idx.size), np.complex128)
    entries = 0
    for f, w in enumerate(omegas):
        lu = spla.splu((base + w * eye).tocsc())
        g = lu.solve(rhs)[idx]
        out[f] = np.eye(idx.size) - 1j * np.sqrt(np.outer(kap, kap)) * g
        entries = lu.L.nnz + lu.U.nnz
    return out, entries


def _project(dev, omegas):
    tracemalloc.start()
    tr = transmission(dev, omegas)
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    return tr, peak


def _case(name, dev, omegas, peer_stride, repeat):
    t_proj = t_peer = float("inf")
    sub = omegas[::peer_stride]
    for _ in range(repeat):
        t0 = time.perf_counter()
        tr, peak = _project(dev, omegas)
        t_proj = min(t_proj, time.perf_counter() - t0)
        t0 = time.perf_counter()
        ref, entries = _peer(dev, sub)
        t_peer = min(t_peer, (time.perf_counter() - t0) * peer_stride)
    err = float(np.max(np.abs(tr.s[::peer_stride] - ref)))
    print(f"{name}: {dev.size:,} resonators, {omegas.size:,} frequencies, 2 ports")
    print(f"  hyperlattice ({tr.method}{', %d moments' % tr.moments if tr.moments else ''}): {t_proj:8.2f} s, "
          f"peak traced memory {peak / 2**20:.1f} MB")
    scaled = f" (timed on every {peer_stride}th frequency, x{peer_stride})" if peer_stride > 1 else ""
    print(f"  splu per frequency:              {t_peer:8.2f} s{scaled}, factor {entries:,} entries "
          f"= {entries * 20 / 2**20:.1f} MB")
    print(f"  ratio {t_peer / t_proj:.1f}x; max |S_project - S_peer| = {err:.1e}"
          + (f"; stated error bound {np.nanmax(tr.error_bound):.1e}" if tr.method == "chebyshev" else ""))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="the 140-resonator case only")
    args = ap.parse_args()
    print(machine())
    print(f"load average {os.getloadavg()[0]:.2f} {os.getloadavg()[1]:.2f} {os.getloadavg()[2]:.2f}")
    ports = {"0-1": 1.0}
    lat3 = ring_lattice(7, 3, 3)
    e = lat3.edges[-1]
    dev = resonator_device(lat3, line_graph=True, omega0=7000.0, J=-66.0, kappa_int=0.7,
                           ports={**ports, f"{min(e)}-{max(e)}": 1.0})
    transmission(dev, [7000.0])                      # warm-up (imports)
    _case("Kollár device (line graph of {7,3} ℓ = 3)", dev, np.linspace(6840.0, 7290.0, 10_000), 1, 3)
    if args.quick:
        return
    lat8 = ring_lattice(7, 3, 8)
    e = lat8.edges[-1]
    dev8 = resonator_device(lat8, line_graph=True, omega0=7000.0, J=-66.0, kappa_int=0.7,
                            ports={**ports, f"{min(e)}-{max(e)}": 1.0})
    transmission(dev8, np.array([7000.0, 7001.0]), method="chebyshev")      # compile the kernels
    _case("ℓ = 8 line-graph device", dev8, np.linspace(6840.0, 7290.0, 2_000), 10, 1)


if __name__ == "__main__":
    main()
