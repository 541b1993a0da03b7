"""``hyperlattice butterfly``: all levels of a {p,q} flake against the flux (hyperbolic Hofstadter butterfly)."""

from __future__ import annotations

import csv

from .. import _validate
from ._common import (DENSE_SECONDS_PER_N3, add_checkpoint, add_max_seconds, add_pq, check_work, estimate_sites,
                      interrupted, open_checkpoint, plot_file, positive_int, print_json)

NAME = "butterfly"
ORDER = 35
HELP = "hyperbolic Hofstadter butterfly: all levels against the flux f in [0, 1], sector by sector"
DESCRIPTION = (
    "All eigenvalues of the Peierls Hamiltonian H = -t sum exp(i theta_ij) c_i^+ c_j (t = 1) of a "
    "{p,q} flake at FLUXES equally spaced flux values f in [0, 1] (f flux quanta per p-gon face, "
    "f > 0 counterclockwise), computed from the p angular-momentum blocks. --out writes the figure "
    "(format by suffix), --table a CSV with columns flux, m, energy. --checkpoint DIR keeps the levels of "
    "every finished flux value in DIR: after Ctrl-C the same command resumes where it stopped."
)

#: largest number of flux values (the result holds FLUXES x N numbers)
MAX_FLUXES = 5000


def add_arguments(parser: argparse.ArgumentParser) -> None:
    add_pq(parser)
    parser.add_argument("--rings", type=positive_int, default=5, help="number of rings (default 5)")
    parser.add_argument("--fluxes", type=positive_int, default=200,
                        help="number of flux values in [0, 1] (default 200)")
    parser.add_argument("--line-graph", action="store_true", help="use the line graph (resonator layout)")
    parser.add_argument("--out", default=None, metavar="FILE", help="figure file (.png, .svg, ...)")
    parser.add_argument("--table", default=None, metavar="FILE.csv", help="CSV table: flux, m, energy")
    parser.add_argument("--continuum", action="store_true",
                        help="overlay the continuum Dirichlet levels (magnetic_levels) at small f on the figure")
    parser.add_argument("--json", action="store_true", help="print one JSON object (the summary)")
    add_max_seconds(parser)
    add_checkpoint(parser, "flux value")


def _write_table(path, result) -> None:
    cols = result.columns()
    with open(path, "w", newline="", encoding="utf-8") as fh:
        w = csv.writer(fh, lineterminator="\n")
        w.writerow(["flux", "m", "energy"])
        for f, m, e in zip(cols["flux"].tolist(), cols["m"].tolist(), cols["energy"].tolist()):
            w.writerow([repr(f), m, repr(e)])


def run(args: argparse.Namespace) -> int:
    """Compute the butterfly and write the figure / table; bad input raises ValueError (exit 2)."""
    import numpy as np

    from ..graph.butterfly import butterfly
    from ..graph.lattice import line_graph, ring_lattice

    # every output is checked before the computation, so a long run never fails at its end
    out = plot_file("--out", args.out) if args.out is not None else None
    table = _validate.output_path("--table", args.table, suffixes=(".csv",)) if args.table is not None else None
    nflux = _validate.positive_int("--fluxes", args.fluxes, maximum=MAX_FLUXES)
    # the work before the build (--rings 3 -q 10 runs for minutes, so it is announced): p dense
    # Hermitian blocks of about N/p per flux value
    n = estimate_sites(args.p, args.q, args.rings, line_graph=args.line_graph)
    block = -(-n // args.p)
    _validate.require_memory(f"the butterfly's {block:,} x {block:,} complex blocks", 3.0 * 16 * block**2)
    check_work("butterfly", nflux * args.p * block**3 * DENSE_SECONDS_PER_N3, args.max_seconds,
               f"{n:,} sites: {nflux * args.p:,} dense blocks of {block:,}")
    cache = open_checkpoint(args)
    lattice = ring_lattice(args.p, args.q, args.rings)
    if args.line_graph:
        lattice = line_graph(lattice)
    try:
        result = butterfly(lattice, np.linspace(0.0, 1.0, nflux), checkpoint=cache)
    except KeyboardInterrupt:
        raise interrupted(cache, nflux, "flux values", args.checkpoint) from None
    if out is not None:
        from ..plots.magnetic import butterfly_figure

        butterfly_figure(result, continuum=args.continuum, path=out)
    if table is not None:
        _write_table(table, result)
    summary = result.summary()
    summary["time"] = float(result.timings.get("total", 0.0))
    if args.json:
        print_json(summary)
        return 0
    what = "line graph of " if args.line_graph else ""
    print(f"{what}{{{result.p},{result.q}}} rings={result.rings} sites={result.sites} fluxes={nflux} "
          f"time={summary['time']:.2f} s  E in [{summary['energy_min']:.6f}, {summary['energy_max']:.6f}]")
    for name, path in (("figure", out), ("table", table)):
        if path is not None:
            print(f"{name}: {path}")
    return 0


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
