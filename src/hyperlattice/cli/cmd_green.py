"""``hyperlattice green``: graph Green function (H - omega)^-1 against the continuum (the paper's Eq. (19))."""

from __future__ import annotations

import csv
import sys

from ..paper_labels import cite
from ._common import (add_max_seconds, add_pq, check_work, complex_value, estimate_sites, output_file,
                      positive_int, print_json, tolerance)

NAME = "green"
ORDER = 50
HELP = f"graph Green function G_ij(omega) for one source vs the continuum Green function ({cite('eq21')})"

COLUMNS = ["site", "ring", "re_z", "im_z", "distance", "graph_re", "graph_im", "continuum_re", "continuum_im"]


def add_arguments(parser: argparse.ArgumentParser) -> None:
    add_pq(parser)
    parser.add_argument("--rings", type=positive_int, default=6, help="number of rings l (default 6)")
    parser.add_argument("--omega", type=complex_value, default=complex(-2.95),
                        help="frequency, real or complex, e.g. --omega=-2.5+0.1j (default -2.95)")
    parser.add_argument("--site", type=int, default=10,
                        help="source site j, 0-based (default 10, on ring 2)")
    parser.add_argument("--tol", type=tolerance, default=1e-12,
                        help="truncation tolerance of the continuum Fourier series (default 1e-12)")
    parser.add_argument("--out", default=None, metavar="FILE",
                        help="write one CSV row per target site (columns: " + ",".join(COLUMNS) + "); '-' for stdout")
    parser.add_argument("--json", action="store_true", help="print the summary as one JSON object")
    add_max_seconds(parser)


def _write_csv(handle, lat, cmp) -> None:
    w = csv.writer(handle, lineterminator="\n")
    w.writerow(COLUMNS)
    for i in range(lat.sites):
        g, c = cmp.graph[i], cmp.continuum[i]
        w.writerow([i, int(lat.ring[i]), repr(float(lat.z[i].real)), repr(float(lat.z[i].imag)),
                    repr(float(cmp.distance[i])), repr(float(g.real)), repr(float(g.imag)),
                    repr(float(c.real)), repr(float(c.imag))])


#: seconds per (site x series order) of the continuum column: 53 s for 92,575 sites x 4,001
#: orders ({7,7}, 4 rings) on the project's 2-core machine (2026-11-24)
SECONDS_PER_SITE_ORDER = 1.5e-7


def _continuum_work(lat, omega, site: int, tol: float) -> tuple[float, int]:
    """Estimated seconds of the continuum column, from the series orders its outermost sites need.

    The orders grow fast with q (the outer ring lies ever closer to the disk's edge):
    ``green --rings 4 -q 10`` needs the 4,000-order cap at 404,320 sites. A probe of 32 sites
    takes milliseconds.
    """
    import warnings

    import numpy as np

    from ..continuum.green import continuum_green
    from ..dictionary import dictionary_parameters

    lam, _ = dictionary_parameters(omega, lat.p, lat.q)
    outer = np.argsort(np.abs(lat.z))[-32:]
    outer = outer[outer != site]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the full run reports the series' accuracy itself
        _, info = continuum_green(lat.z[outer], lat.z[site], lam, lat.radius, tol=tol, extend=True,
                                  return_info=True)
    orders = max(int(info.terms), 1)
    return lat.sites * orders * SECONDS_PER_SITE_ORDER, orders


def run(args: argparse.Namespace) -> int:
    from ..compare.green import compare_green
    from ..graph.lattice import ring_lattice

    out = output_file("--out", args.out) if args.out not in (None, "-") else None  # before computing
    n = estimate_sites(args.p, args.q, args.rings)  # before the build
    if not 0 <= args.site < n:
        raise ValueError(f"--site {args.site} is not a site of this lattice (valid: 0..{n - 1}).")
    lat = ring_lattice(args.p, args.q, args.rings)
    seconds, orders = _continuum_work(lat, args.omega, args.site, args.tol)
    check_work("green", seconds, args.max_seconds,
               f"{lat.sites:,} sites x {orders:,} orders of the continuum series")
    cmp = compare_green(lat, args.omega, args.site, tol=args.tol)
    if args.out == "-":
        _write_csv(sys.stdout, lat, cmp)
    elif out is not None:
        with open(out, "w", newline="") as fh:
            _write_csv(fh, lat, cmp)
    summary = cmp.summary()
    if args.json:
        print_json(summary)
    elif args.out != "-":
        print(f"{{{lat.p},{lat.q}}} lattice, {lat.rings} rings ({lat.sites} sites), source {cmp.source} "
              f"(ring {int(lat.ring[cmp.source])})")
        print(f"omega = {cmp.omega:g}, lambda = 4(omega+q)/(q h^2) = {cmp.lam:.6g}, L = {cmp.radius:.10f}, "
              f"prefactor 4A/(q h^2) = {cmp.prefactor:.6f}")
        print(f"relative L2 distance graph vs continuum (source excluded): {cmp.rel_l2:.4f}")
        print(f"continuum series: {cmp.terms} orders, estimated truncation error {cmp.tail_estimate:.1e}")
    return 0


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
