"""``hyperlattice lattice``: build a {p,q} ring lattice (or its line graph), summarize or export it."""

from __future__ import annotations

from pathlib import Path

from ..graph.lattice import line_graph, ring_lattice
from ._common import add_pq, print_json

NAME = "lattice"
ORDER = 20
HELP = "build a {p,q} ring lattice; print its size or write coordinates (.dat) / arrays (.npz)"


def add_arguments(parser):
    add_pq(parser)
    parser.add_argument("--rings", type=int, default=6, help="number of rings l >= 1 (default 6)")
    parser.add_argument("--line-graph", action="store_true",
                        help="use the line graph (sites at edge midpoints), the circuit-QED layout")
    parser.add_argument("--out", metavar="FILE",
                        help="write the lattice: .dat (paper's coordinates.dat: Re z, Im z per line) or .npz")
    parser.add_argument("--json", action="store_true", help="print a JSON summary")


def summary(lat) -> dict:
    return {
        "p": lat.p,
        "q": lat.q,
        "rings": lat.rings,
        "kind": lat.kind,
        "sites": lat.sites,
        "edges": int(lat.edges.shape[0]),
        "sites_per_ring": lat.sites_per_ring.tolist(),
        "d0": lat.d0,
        "h": lat.h,
        "radius": lat.radius,
    }


def run(args) -> int:
    if args.rings < 1:
        raise ValueError(f"rings must be at least 1, got {args.rings}.")
    if args.out is not None and Path(args.out).suffix.lower() not in (".dat", ".npz"):
        raise ValueError(f"unknown output format {Path(args.out).suffix!r}: use .dat or .npz.")
    lat = ring_lattice(args.p, args.q, args.rings)
    if args.line_graph:
        lat = line_graph(lat)
    if args.out is not None:
        try:
            lat.save(args.out)
        except OSError as exc:
            raise ValueError(f"cannot write {args.out}: {exc.strerror}.") from None
    info = summary(lat)
    if args.json:
        print_json(info)
        return 0
    what = "line graph of " if args.line_graph else ""
    print(f"{what}{{{lat.p},{lat.q}}} lattice, {lat.rings} rings: {lat.sites} sites, {info['edges']} edges")
    print(f"  sites per ring: {' '.join(map(str, info['sites_per_ring']))}")
    print(f"  d0 = {lat.d0:.9f}, h = tanh(d0) = {lat.h:.9f}, effective disk radius L = {lat.radius:.9f}")
    if args.out is not None:
        print(f"  written to {args.out}")
    return 0
