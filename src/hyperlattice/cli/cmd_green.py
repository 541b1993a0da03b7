"""``hyperlattice green``: graph Green function (H - omega)^-1 against the continuum (eq21)."""

from __future__ import annotations

import csv
import sys

from ._common import add_pq, complex_value, output_file, positive_int, print_json, tolerance

NAME = "green"
ORDER = 50
HELP = "graph Green function G_ij(omega) for one source vs the continuum Green function (eq21)"

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


def _write_csv(handle, lat, cmp) -> None:
    w = csv.writer(handle, lineterminator="\n")
    w.writerow(COLUMNS)
    for i in range(lat.sites):
        g, c = cmp.graph[i], cmp.continuum[i]
        w.writerow([i, int(lat.ring[i]), repr(float(lat.z[i].real)), repr(float(lat.z[i].imag)),
                    repr(float(cmp.distance[i])), repr(float(g.real)), repr(float(g.imag)),
                    repr(float(c.real)), repr(float(c.imag))])


def run(args: argparse.Namespace) -> int:
    from ..compare.green import compare_green
    from ..graph.lattice import ring_lattice

    out = output_file("--out", args.out) if args.out not in (None, "-") else None  # before computing
    lat = ring_lattice(args.p, args.q, args.rings)
    if not 0 <= args.site < lat.sites:
        raise ValueError(f"--site {args.site} is not a site of this lattice (valid: 0..{lat.sites - 1}).")
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


# every public function above checks its annotated argument types at the door (issue 19)
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
