"""``hyperlattice disorder``: level statistics of a disordered {p,q} flake (Anderson model)."""

from __future__ import annotations

from .. import _validate
from ._common import (DENSE_SECONDS_PER_N3, add_max_seconds, add_pq, check_work, estimate_sites,
                      finite_float, plot_file, positive_int, print_json)

NAME = "disorder"
ORDER = 40
HELP = "disorder ensembles: mean level-spacing ratio <r> (GOE 0.5307 / Poisson 0.3863), DOS, IPR"
DESCRIPTION = (
    "Diagonalise REALIZATIONS disorder realizations of H = -t A + diag(V) on a {p,q} flake (t = 1) and "
    "report the mean level-spacing ratio <r> over the whole spectrum (GOE 0.5307 for extended states, "
    "Poisson 0.3863 for localized ones), <r> and the inverse participation ratio in energy windows, and the "
    "averaged density of states. Default model: on-site box disorder V_i uniform in [-W/2, W/2]. "
    "Realization k of seed S is reproducible alone (numpy SeedSequence(S, spawn_key=(k,)))."
)


def add_arguments(parser: argparse.ArgumentParser) -> None:
    add_pq(parser)
    parser.add_argument("--rings", type=positive_int, default=4, help="number of rings (default 4)")
    parser.add_argument("--W", type=finite_float, default=1.0,
                        help="disorder strength W >= 0 (box width; for --model resonator the relative spread "
                             "sigma) (default 1)")
    parser.add_argument("--realizations", type=positive_int, default=10, help="number of realizations (default 10)")
    parser.add_argument("--seed", type=int, default=0, help="seed (integer >= 0, default 0)")
    parser.add_argument("--model", default="box", choices=("box", "gaussian", "hopping", "resonator"),
                        help="disorder model (default box)")
    parser.add_argument("--omega0", type=finite_float, default=None,
                        help="bare resonator frequency in units of t (resonator model only)")
    parser.add_argument("--line-graph", action="store_true", help="use the line graph (resonator layout)")
    parser.add_argument("--no-ipr", action="store_true", help="skip the eigenvectors (no IPR, about 2x faster)")
    parser.add_argument("--plot", default=None, metavar="FILE", help="figure of the averaged DOS (.png, .svg, ...)")
    parser.add_argument("--json", action="store_true", help="print one JSON object")
    add_max_seconds(parser)


def run(args: argparse.Namespace) -> int:
    """Compute the ensemble and print its summary; bad input raises ValueError (exit 2)."""
    from ..compare.disorder import disorder_ensemble
    from ..graph.lattice import line_graph, ring_lattice

    out = plot_file("--plot", args.plot) if args.plot is not None else None
    seed = _validate.integer("--seed", args.seed, minimum=0, maximum=2**63 - 1)
    _validate.real("--W", args.W, minimum=0.0)
    # the work before the build (--rings 3 -q 10 runs for minutes, so it is announced): one dense
    # eigendecomposition of all N sites per realization (without eigenvectors, --no-ipr, about half)
    n = estimate_sites(args.p, args.q, args.rings, line_graph=args.line_graph)
    _validate.require_memory(f"a dense disorder realization of {n:,} sites", 3.0 * 8 * n**2)
    reps = _validate.positive_int("--realizations", args.realizations)
    check_work("disorder", reps * n**3 * DENSE_SECONDS_PER_N3 * (0.5 if args.no_ipr else 1.0), args.max_seconds,
               f"{reps:,} dense eigendecompositions of {n:,} sites")
    lattice = ring_lattice(args.p, args.q, args.rings)
    if args.line_graph:
        lattice = line_graph(lattice)
    ens = disorder_ensemble(lattice, args.W, args.realizations, seed=seed, model=args.model,
                            omega0=args.omega0, ipr=not args.no_ipr)
    if out is not None:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        fig, ax = plt.subplots(figsize=(5.5, 4.0), layout="constrained")
        ens.plot(ax=ax)
        fig.savefig(out)
        plt.close(fig)
    summary = ens.summary()
    if args.json:
        print_json(summary)
        return 0
    what = "line graph of " if args.line_graph else ""
    print(f"{what}{{{ens.p},{ens.q}}} rings={ens.rings} sites={ens.sites} model={ens.model} W={ens.W:g} "
          f"realizations={ens.realizations} seed={ens.seed}")
    print(f"<r> = {ens.r_mean:.4f} +- {ens.r_err:.4f}  (GOE {summary['goe']:.4f}, Poisson {summary['poisson']:.4f}; "
          f"{ens.r_count} ratios)")
    if out is not None:
        print(f"figure: {out}")
    return 0


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
