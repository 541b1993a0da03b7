"""How close :func:`hyperlattice.bosons.qmc_memory` is to what a chain really uses.

Runs one chain in this process (the kernels loaded first) and compares the estimate with the
growth of the resident set (peak ``VmHWM`` minus ``VmRSS`` before the chain) and of the address
space (``VmPeak`` minus ``VmSize``), read from /proc/self/status (Linux).

Usage::

    python benchmarks/qmc_memory_check.py --rings 5 --beta 2 --sweeps 300
"""

from __future__ import annotations

import argparse
import sys
import warnings


def _status() -> dict:
    out = {}
    with open("/proc/self/status") as fh:
        for line in fh:
            key, _, rest = line.partition(":")
            if key in ("VmPeak", "VmSize", "VmHWM", "VmRSS"):
                out[key] = int(rest.split()[0]) * 1024
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--rings", type=int, default=5)
    ap.add_argument("--beta", type=float, default=2.0)
    ap.add_argument("--sweeps", type=int, default=300)
    ap.add_argument("--nmax", type=int, default=3)
    ap.add_argument("--U", type=float, default=6.0)
    ap.add_argument("--mu", type=float, default=3.0)
    ap.add_argument("--no-green", action="store_true", help="do not measure G(i, j)")
    args = ap.parse_args(argv)

    import hyperlattice as hl
    from hyperlattice.bosons import qmc, qmc_memory, sse

    lat = hl.ring_lattice(7, 3, args.rings)
    kw = dict(U=args.U, mu=args.mu, beta=args.beta, nmax=args.nmax)
    # load the kernels and BLAS first (a tiny chain), so that only the chain's own memory is measured
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        qmc(hl.ring_lattice(7, 3, 1), U=4.0, mu=1.0, beta=1.0, nmax=2, sweeps=20, seed=0, progress=False)
    est = qmc_memory(lat, measure_green=not args.no_green, **kw)
    before = _status()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        r = qmc(lat, sweeps=args.sweeps, thermalization=max(100, args.sweeps // 5), seed=1, progress=False,
                measure_green=not args.no_green, **kw)
    after = _status()
    rss = after["VmHWM"] - before["VmRSS"]
    vm = after["VmPeak"] - before["VmSize"]
    mib = 2**20
    print(f"l = {args.rings} ({lat.sites} sites), beta = {args.beta:g}, nmax = {args.nmax}, "
          f"G {'off' if args.no_green else 'on'}: string {r.string_length:,} slots, {r.mean_operators:,.0f} operators")
    print(f"qmc_memory {est / mib:.1f} MiB; measured peak RSS growth {rss / mib:.1f} MiB "
          f"({rss / est:.2f} of the estimate), address space growth {vm / mib:.1f} MiB ({vm / est:.2f})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
