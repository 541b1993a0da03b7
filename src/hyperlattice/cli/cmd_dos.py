"""``hyperlattice dos``: density of states of a flake interior or a periodic cluster by KPM."""

from __future__ import annotations

import csv
import math

from .. import _validate
from ._common import add_checkpoint, add_pq, cluster_pq, interrupted, open_checkpoint, plot_file, positive_int, print_json

NAME = "dos"
ORDER = 46
HELP = "density of states by the kernel polynomial method (flake interior or periodic cluster)"
DESCRIPTION = (
    "Density of states per site of H = -A (t = 1) by the kernel polynomial method: Chebyshev moments "
    "with the Jackson kernel and a stochastic trace over random vectors (error bars from their spread). "
    "--rings R: the interior of an R-ring {p,q} flake (the outer --exclude rings are left out of the "
    "trace; default R // 2), --cluster NAME: a periodic cluster (see 'hyperlattice cluster --list'; its "
    "uniform state at E = -q is left out unless --keep-uniform). --site I: the exact local DOS at site I "
    "instead. --out writes a CSV (energy, dos, error, integrated), --plot a figure. --checkpoint DIR keeps "
    "the moments of every finished block of random vectors: after Ctrl-C the same command resumes."
)

#: most energies in the CSV
MAX_POINTS = 1_000_000


def add_arguments(parser: argparse.ArgumentParser) -> None:
    add_pq(parser)
    what = parser.add_mutually_exclusive_group()
    what.add_argument("--rings", type=positive_int, default=None, help="flake of this many rings (default 8)")
    what.add_argument("--cluster", default=None, metavar="NAME", help="periodic cluster name, e.g. klein, PSL(2,29)")
    parser.add_argument("--moments", type=positive_int, default=None,
                        help="Chebyshev moments (default: 512; for a flake interior its proven exact count)")
    parser.add_argument("--vectors", type=positive_int, default=16, help="random vectors (default 16)")
    parser.add_argument("--seed", type=int, default=0, help="seed of the random vectors (default 0)")
    parser.add_argument("--kind", choices=("rademacher", "phase"), default="rademacher",
                        help="random vectors: real +-1 or complex random phases")
    parser.add_argument("--exclude", type=positive_int, default=None,
                        help="flake: outer rings left out of the trace (default rings // 2)")
    parser.add_argument("--site", type=int, default=None, help="exact local DOS at this site instead of the trace")
    parser.add_argument("--keep-uniform", action="store_true",
                        help="cluster: keep the uniform state at E = -q (and +q if bipartite) in the trace")
    parser.add_argument("--points", type=positive_int, default=None,
                        help="energies in the CSV (default 2 * moments + 1, on [-q, q])")
    parser.add_argument("--out", default=None, metavar="FILE.csv", help="CSV: energy, dos, error, integrated")
    parser.add_argument("--plot", default=None, metavar="FILE", help="figure (.png, .svg, ...)")
    parser.add_argument("--json", action="store_true", help="print one JSON object (the summary)")
    add_checkpoint(parser, "block of random vectors")


def _write_csv(path, result, points) -> None:
    e = result.energy_grid(points)
    _, rho, err = result.density(e)
    _, n, _ = result.integrated(e)
    with open(path, "w", newline="", encoding="utf-8") as fh:
        w = csv.writer(fh, lineterminator="\n")
        w.writerow(["energy", "dos", "error", "integrated"])
        for row in zip(e.tolist(), rho.tolist(), err.tolist(), n.tolist()):
            w.writerow(["nan" if isinstance(v, float) and math.isnan(v) else repr(float(v)) for v in row])


def run(args: argparse.Namespace) -> int:
    """Compute the DOS and write the CSV / figure; bad input raises ValueError (exit 2)."""
    from ..graph.kpm import MAX_MOMENTS, MAX_VECTORS, block_width, bulk_dos, kpm_dos, local_dos
    from ..graph.lattice import ring_lattice

    # every output and every number is checked before the computation
    out = _validate.output_path("--out", args.out, suffixes=(".csv",)) if args.out is not None else None
    fig = plot_file("--plot", args.plot) if args.plot is not None else None
    p, q = _validate.pq(args.p, args.q)
    moments = (None if args.moments is None
               else _validate.integer("--moments", args.moments, minimum=2, maximum=MAX_MOMENTS))
    vectors = _validate.positive_int("--vectors", args.vectors, maximum=MAX_VECTORS)
    seed = _validate.integer("--seed", args.seed, minimum=0, maximum=2**63 - 1)
    points = None if args.points is None else _validate.integer("--points", args.points, minimum=2,
                                                                 maximum=MAX_POINTS)
    if args.cluster is not None and args.exclude is not None:
        raise ValueError("--exclude applies to a flake (--rings), not to a cluster.")
    if args.cluster is None and args.keep_uniform:
        raise ValueError("--keep-uniform applies to a cluster (--cluster); a flake has no uniform state.")
    if args.site is not None and args.checkpoint is not None:
        raise ValueError("--checkpoint keeps blocks of random vectors; --site computes exact moments without them.")
    cache = open_checkpoint(args)
    if args.cluster is not None:
        from ..graph.clusters import pbc_cluster

        p, q = cluster_pq(args, args.cluster)
        graph = pbc_cluster(p, q, args.cluster)
    else:
        rings = 8 if args.rings is None else args.rings
        graph = ring_lattice(p, q, rings)
        if args.exclude is not None:
            _validate.integer("--exclude", args.exclude, minimum=1, maximum=max(rings - 1, 1))
    # the KPM loops show a bar over the random vectors (--progress / --no-progress)
    if args.site is not None:
        site = _validate.site_index("--site", args.site, int(graph.sites))
        result = local_dos(graph, site, 512 if moments is None else moments)
    else:
        try:
            if args.cluster is not None:
                result = kpm_dos(graph, 512 if moments is None else moments, vectors=vectors, seed=seed,
                                 kind=args.kind, deflate=not args.keep_uniform, checkpoint=cache)
            else:
                result = bulk_dos(graph, moments, exclude=args.exclude, vectors=vectors, seed=seed,
                                  kind=args.kind, checkpoint=cache)
        except KeyboardInterrupt:
            blocks = -(-vectors // block_width(int(graph.sites), vectors, args.kind))
            raise interrupted(cache, blocks, "blocks of random vectors", args.checkpoint) from None
    if out is not None:
        _write_csv(out, result, points)
    if fig is not None:
        import matplotlib

        matplotlib.use("Agg")
        from ..plots.dos import dos_figure

        dos_figure(result, path=fig)
    summary = result.summary()
    if args.json:
        print_json(summary)
        return 0
    what = f"site {result.site}" if result.method == "local" else f"{result.traced_sites:,} traced sites"
    print(f"{result.label}: {result.moments} moments, {what}, {result.vectors} vector(s), "
          f"time {summary['time']:.2f} s")
    if result.exact_moments is not None:
        print(f"moments equal to the infinite lattice's (proven): n < {result.exact_moments}")
    if result.deflated:
        print(f"left out of the trace: {result.deflated} state(s) at E = -q / +q (not in the infinite lattice)")
    for name, path in (("table", out), ("figure", fig)):
        if path is not None:
            print(f"{name}: {path}")
    return 0


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
