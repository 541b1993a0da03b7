"""``hyperlattice fluxmap``: graph vs continuum lowest levels with flux on an (f, l) grid."""

from __future__ import annotations

import csv

from .. import _validate
from ._common import (add_checkpoint, add_pq, finite_float, interrupted, open_checkpoint, plot_file,
                      positive_int, print_json)

NAME = "fluxmap"
ORDER = 36
HELP = "graph vs continuum lowest levels in a uniform field over the (flux, rings) plane: table, error map"
DESCRIPTION = (
    "The K lowest levels of the Peierls Hamiltonian of each {p,q} flake (rings RINGS) next to the "
    "Dirichlet levels of the magnetic Laplacian on the flake's disk (field B = 2 pi f / area of one "
    "p-gon), matched by (n, m), at FLUXES equally spaced fluxes f in [0, FMAX]. Prints where the "
    "relative error stays below 1e-3 and why it grows; --out draws the error map (format by "
    "suffix), --table writes one CSV row per (rings, flux, level). --checkpoint DIR keeps every finished "
    "(l, f) point in DIR: after Ctrl-C the same command resumes where it stopped."
)

#: largest number of flux values and of flakes (each (l, f) is one sector solve on each side)
MAX_FLUXES = 200
MAX_FLAKES = 12


def _rings(text: str) -> list[int]:
    """'3-12', '3,5,8' or '7' as a sorted list of distinct ring counts."""
    out: set[int] = set()
    for part in str(text).split(","):
        part = part.strip()
        lo, sep, hi = part.partition("-")
        try:
            a = int(lo)
            b = int(hi) if sep else a
        except ValueError:
            raise ValueError(f"--rings must look like 3-12 or 3,5,8, got {text!r}.") from None
        if a < 1 or b < a:
            raise ValueError(f"--rings ranges must be 1 <= a <= b, got {part!r}.")
        if b - a >= MAX_FLAKES:  # refuse before building a set of that size (1-99999999999)
            raise ValueError(f"--rings names {b - a + 1:,} flakes; at most {MAX_FLAKES}.")
        out.update(range(a, b + 1))
    if len(out) > MAX_FLAKES:
        raise ValueError(f"--rings names {len(out)} flakes; at most {MAX_FLAKES}.")
    return sorted(out)


def add_arguments(parser: argparse.ArgumentParser) -> None:
    add_pq(parser)
    parser.add_argument("--rings", default="3-7", help="flakes: a range 3-12 or a list 3,5,8 (default 3-7; l <= 12)")
    parser.add_argument("--fluxes", type=positive_int, default=7,
                        help="number of flux values in [0, FMAX] (default 7)")
    parser.add_argument("--fmax", type=finite_float, default=0.3, help="largest flux per p-gon (default 0.3)")
    parser.add_argument("--levels", type=positive_int, default=2, help="lowest levels compared (default 2)")
    parser.add_argument("--out", default=None, metavar="FILE", help="error-map figure (.png, .svg, ...)")
    parser.add_argument("--table", default=None, metavar="FILE.csv",
                        help="CSV: rings, flux, level, n, m, E_graph, E_continuum, rel_error, lB_over_d0, lB_over_R")
    parser.add_argument("--json", action="store_true", help="print one JSON object (the summary)")
    add_checkpoint(parser, "(l, f) point")


def _write_table(path, result) -> None:
    cols = result.columns()
    names = list(cols)
    with open(path, "w", newline="", encoding="utf-8") as fh:
        w = csv.writer(fh, lineterminator="\n")
        w.writerow(names)
        for row in zip(*(cols[k].tolist() for k in names)):
            w.writerow([repr(v) if isinstance(v, float) else v for v in row])


def run(args: argparse.Namespace) -> int:
    """Compute the comparison and write the figure / table; bad input raises ValueError (exit 2)."""
    import numpy as np

    from ..compare.magnetic import magnetic_comparison

    out = plot_file("--out", args.out) if args.out is not None else None
    table = _validate.output_path("--table", args.table, suffixes=(".csv",)) if args.table is not None else None
    rings = _rings(args.rings)
    nflux = _validate.positive_int("--fluxes", args.fluxes, maximum=MAX_FLUXES)
    fmax = _validate.real("--fmax", args.fmax, minimum=0.0, maximum=1.0)
    cache = open_checkpoint(args)
    try:
        result = magnetic_comparison(args.p, args.q, rings=rings, fluxes=np.linspace(0.0, fmax, nflux),
                                     levels=args.levels, checkpoint=cache)
    except KeyboardInterrupt:
        raise interrupted(cache, len(rings) * nflux, "points", args.checkpoint) from None
    if out is not None:
        import matplotlib.pyplot as plt

        fig, ax = plt.subplots(figsize=(6.4, 4.4), layout="constrained")
        result.plot(ax=ax)
        fig.savefig(out, dpi=150)
        plt.close(fig)
    if table is not None:
        _write_table(table, result)
    summary = result.summary()
    summary["time"] = float(result.timings.get("total", 0.0))
    if args.json:
        print_json(summary)
        return 0
    print(summary["statement"])
    for name, path in (("figure", out), ("table", table)):
        if path is not None:
            print(f"{name}: {path}")
    return 0


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
