"""``hyperlattice lattice``: build a {p,q} ring lattice (or its line graph), summarize or export it."""

from __future__ import annotations

from .. import _validate
from ..graph.lattice import _check_line_graph_fits, line_graph, ring_lattice
from ._common import add_pq, print_json

NAME = "lattice"
ORDER = 20
HELP = "build a {p,q} ring lattice; print its size or write coordinates (.dat) / arrays (.npz)"

_FORMATS = (".dat", ".npz")


def add_arguments(parser: argparse.ArgumentParser) -> None:
    add_pq(parser)
    parser.add_argument("--rings", type=int, default=6, help="number of rings l >= 1 (default 6)")
    parser.add_argument("--line-graph", action="store_true",
                        help="use the line graph (sites at edge midpoints), the circuit-QED layout")
    parser.add_argument("--out", metavar="FILE",
                        help="write the lattice: .dat (paper's coordinates.dat: Re z, Im z per line) or .npz")
    parser.add_argument("--json", action="store_true", help="print a JSON summary")


def run(args: argparse.Namespace) -> int:
    rings = _validate.positive_int("rings", args.rings)
    out = None
    if args.out is not None:
        # checked before building, so that a long build never fails at its last step
        out = _validate.output_path("--out", args.out)
        if out.suffix.lower() not in _FORMATS:
            raise ValueError(f"unknown output format {out.suffix!r}: use .dat or .npz.")
    if args.line_graph:
        _check_line_graph_fits(args.p, args.q, rings)  # refuse before the parent is built
    lat = ring_lattice(args.p, args.q, rings)
    if args.line_graph:
        lat = line_graph(lat)
    if out is not None:
        lat.save(out)
    info = lat.summary()
    if args.json:
        print_json(info)
        return 0
    what = "line graph of " if args.line_graph else ""
    print(f"{what}{{{lat.p},{lat.q}}} lattice, {lat.rings} rings: {lat.sites} sites, {info['edges']} edges")
    print(f"  sites per ring: {' '.join(map(str, info['sites_per_ring']))}")
    print(f"  d0 = {lat.d0:.9f}, h = tanh(d0) = {lat.h:.9f}, effective disk radius L = {lat.radius:.9f}")
    if out is not None:
        print(f"  written to {args.out}")
    return 0


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
