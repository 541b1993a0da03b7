"""``hyperlattice continuum``: lowest Dirichlet levels of the continuum Hamiltonian on a disk."""

from __future__ import annotations

from ..paper_labels import cite
from ._common import add_max_seconds, add_pq, check_work, finite_float, positive_int, print_json

#: seconds per continuum level, the slowest measured: 2000 levels took 72 s at L = 0.3 and 119 s at
#: L = 0.99 on the project's loaded 2-core machine (2026-11-26; 1.3 s for 1000 levels at rings = 10)
SECONDS_PER_LEVEL = 0.06

NAME = "continuum"
ORDER = 40
HELP = f"lowest continuum levels E = -q + (q/4) h^2 (1 + k^2) on the Dirichlet disk ({cite('spec2')})"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    add_pq(parser)
    size = parser.add_mutually_exclusive_group()
    size.add_argument("--rings", type=positive_int, default=None,
                      help=f"disk of the {{p,q}} lattice with this many rings (L from {cite('eq12')}); default 10")
    size.add_argument("--radius", type=finite_float, default=None, metavar="L",
                      help="disk radius 0 < L < 1 instead of --rings")
    parser.add_argument("--levels", type=positive_int, default=4,
                        help="number of lowest states (a +-m pair counts twice; default 4)")
    parser.add_argument("--flux", type=finite_float, default=None, metavar="F",
                        help="uniform field B = 2 pi F / (area of one p-gon): F flux quanta per p-gon, "
                        "F > 0 counterclockwise (default 0)")
    parser.add_argument("--dictionary", choices=("paper", "improved"), default="paper",
                        help="map from continuum eigenvalues to lattice energies: the paper's E = -q + (q/4) h^2 "
                        "lambda (default) or the improved E = -q P_nu(cosh 2 d0) with the Dirichlet wall half a "
                        "bond beyond the area radius (zero field only)")
    parser.add_argument("--json", action="store_true", help="print one JSON object")
    add_max_seconds(parser)


def run(args: argparse.Namespace) -> int:
    """Compute the levels (the paper's Eqs. (F1)/(F2)) and print them; bad input raises ValueError (exit 2)."""
    from ..continuum.spectrum import continuum_levels

    rings = args.rings
    if rings is None and args.radius is None:
        rings = 10
    dictionary = getattr(args, "dictionary", "paper")
    # --levels 100000 ran on for minutes unannounced: the worst case measured, before any work
    check_work("continuum", args.levels * SECONDS_PER_LEVEL, args.max_seconds, f"{args.levels:,} levels",
               "fewer --levels", upper=True)
    if args.flux is not None and args.flux != 0.0:
        from ..continuum.magnetic import magnetic_levels

        if dictionary != "paper":
            raise ValueError("--dictionary improved is available in zero field only (no --flux).")

        spec = magnetic_levels(args.p, args.q, radius=args.radius, rings=rings, levels=args.levels,
                               flux=args.flux)
    else:
        # zero field: the existing zero-field solver, so the numbers are exactly today's
        spec = continuum_levels(args.p, args.q, radius=args.radius, rings=rings, levels=args.levels,
                                dictionary=dictionary)
    out = spec.summary()
    if args.flux is not None:
        out["flux"] = float(args.flux)
    if args.json:
        print_json(out)
        return 0
    where = f"rings={spec.rings}, " if spec.rings is not None else ""
    field = "" if args.flux is None else f", flux={args.flux:g} per p-gon"
    field += "" if dictionary == "paper" else ", improved dictionary"
    print(f"{{{spec.p},{spec.q}}} continuum disk: {where}L={spec.radius:.12g}, h={spec.h:.8f}{field}")
    print(f"{'#':>3} {'n':>3} {'m':>4} {'k':>16} {'E':>16}")
    ks = out["k"]
    for i, (n, m, k, e) in enumerate(zip(spec.n, spec.m, ks, spec.energies)):
        print(f"{i:>3} {n:>3} {m:>4} {k:16.10f} {e:16.10f}")
    a = spec.asymptotic
    print(f"asymptotic: E0={a['E0']:.6f}  E1={a['E1']:.6f}  E_inf={a['E_inf']:.6f}")
    return 0


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
