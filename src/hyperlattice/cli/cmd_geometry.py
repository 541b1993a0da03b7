"""``hyperlattice geometry``: constants r0, d0, h and area per site of {p,q} tilings."""

from __future__ import annotations

from ..geometry import tiling_constants
from ._common import p_value, pq_int, print_json

NAME = "geometry"
ORDER = 10
HELP = "constants r0, d0, h = tanh(d0) and area per site of {p,q} tessellations"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("-p", type=p_value, nargs="+", default=[7, 8, 9, 10, float("inf")],
                        help="one or more polygon sizes (integers or 'inf'); default 7 8 9 10 inf")
    parser.add_argument("-q", type=pq_int, default=3, help="coordination number (default 3)")
    parser.add_argument("--json", action="store_true", help="print a JSON list instead of a table")


def run(args: argparse.Namespace) -> int:
    rows = [tiling_constants(p, args.q).summary() for p in args.p]  # the Result's CLI view
    if args.json:
        print_json(rows)
        return 0
    print(f"{'p':>5} {'q':>3} {'r0':>12} {'d0':>12} {'h':>12} {'site_area':>12}")
    for r in rows:
        print(f"{str(r['p']):>5} {r['q']:>3} {r['r0']:12.8f} {r['d0']:12.8f} {r['h']:12.8f} {r['site_area']:12.8f}")
    return 0


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
