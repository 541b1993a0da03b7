"""``hyperlattice spectrum``: lowest levels of H = -A on a {p,q} ring lattice, labelled by (n, m)."""

from __future__ import annotations

from ..graph.lattice import line_graph, ring_lattice
from ..graph.spectrum import lowest_levels
from ..graph.symmetry import signed_sector
from ._common import add_pq, estimate_sites, finite_float, positive_int, print_json

NAME = "spectrum"
ORDER = 30
HELP = "lowest levels of H = -A with angular-momentum labels (n, m) and residuals"
DESCRIPTION = (
    "Lowest eigenvalues of the hopping Hamiltonian H = -A (t = 1) of the {p,q} ring lattice, "
    "each with its radial index n, signed angular momentum m in (-p/2, p/2] (sectors m and -m "
    "are degenerate and listed +m first) and residual ||H psi - E psi||."
)


def _sector(text: str) -> int:
    try:
        return int(text)
    except ValueError:
        raise ValueError(f"sector m must be an integer, got {text!r}.") from None


def add_arguments(parser: argparse.ArgumentParser) -> None:
    add_pq(parser)
    parser.add_argument("--rings", type=positive_int, default=4, help="number of rings (default 4)")
    parser.add_argument("--levels", type=positive_int, default=2, help="number of lowest states (default 2)")
    parser.add_argument("--sector", default=None, metavar="M",
                        help="only sector M (0..p-1 or signed, e.g. -1 = p-1)")
    parser.add_argument("--line-graph", action="store_true", help="use the line graph (resonator layout)")
    parser.add_argument("--method", choices=("auto", "sector", "dense", "sparse", "shift-invert", "pair"),
                        default="auto",
                        help="eigensolver (default auto: the fastest route for the request, recorded as "
                        "'method' in the output: shift-invert on the sector blocks built without the lattice for "
                        "large plain flakes, else angular-momentum sectors); pair: E0 and E1 only, from the "
                        "sector blocks without building the lattice (large flakes, l = 15..17)")
    parser.add_argument("--flux", type=finite_float, default=None, metavar="F",
                        help="uniform field: F flux quanta per p-gon, F > 0 counterclockwise (default 0)")
    parser.add_argument("--tol", type=float, default=1e-10, help="largest acceptable residual (default 1e-10)")
    parser.add_argument("--json", action="store_true", help="print one JSON object")


def run(args: argparse.Namespace) -> int:
    sector = None
    if args.sector is not None:
        sector = signed_sector(_sector(args.sector), args.p)
    if args.method == "pair":
        return _run_pair(args)
    if args.method in ("auto", "shift-invert") and _sector_only(args, sector):
        return _run_pair(args, levels=args.levels)
    if args.method == "dense":
        # before the build (issue 19: --rings 9 asked LAPACK for 12.2 GiB, --rings 14 built 5 M sites
        # first): the same refusal lowest_levels makes, from the ring-count recursion
        from .. import _validate

        n = estimate_sites(args.p, args.q, args.rings, line_graph=args.line_graph)
        _validate.require_memory(f"method='dense' on {n:,} sites (LAPACK eigh of the full matrix)",
                                 3.0 * n**2 * (16 if args.flux else 8))
    lattice = ring_lattice(args.p, args.q, args.rings)
    if args.line_graph:
        lattice = line_graph(lattice)
    flux = 0.0 if args.flux is None else args.flux
    # the sector routes show a bar over the sectors (--progress / --no-progress)
    spec = lowest_levels(lattice, args.levels, method=args.method, sector=sector, tol=args.tol, flux=flux)
    if args.json:
        out = spec.summary()
        if args.flux is not None:
            # the contract: with --flux the key is always there, also for --flux 0
            out["flux"] = float(args.flux)
        print_json(out)
        return 0
    what = "line graph of " if args.line_graph else ""
    print(f"{what}{{{args.p},{args.q}}} rings={args.rings} sites={spec.sites} method={spec.method} "
          f"time={spec.timings.get('total', 0.0):.2f} s"
          + (f" flux={args.flux:g}" if args.flux is not None else ""))
    if args.flux:
        # a field splits m from -m: the degeneracy column of the zero-field table would be wrong
        print(f"{'E':>20} {'n':>3} {'m':>4} {'residual':>10}")
        for e, n, m, r in zip(spec.energies, spec.n, spec.m, spec.errors):
            print(f"{e:20.14f} {n:3d} {m:4d} {r:10.1e}")
        return 0
    print(f"{'E':>20} {'n':>3} {'m':>4} {'deg':>3} {'residual':>10}")
    for e, n, m, d, r in zip(spec.energies, spec.n, spec.m, spec.degeneracy, spec.errors):
        print(f"{e:20.14f} {n:3d} {m:4d} {d:3d} {r:10.1e}")
    print("deg = 2: sectors m and -m (= p - m) are degenerate.")
    return 0


def _sector_only(args, sector) -> bool:
    """The request is one the sector-only route answers, and its blocks are big enough to pay (the API's rule)."""
    from ..graph.lattice import _check_pq, _type_counts
    from ..graph.spectrum import _SECTOR_ONLY_MIN

    if args.line_graph or sector is not None or args.flux:
        return False
    p, q = _check_pq(args.p, args.q)
    if args.method == "shift-invert":
        return True
    counts, _ = _type_counts(p, q, args.rings, stop_above=2**62)
    sites = sum(counts)
    return sites // p > _SECTOR_ONLY_MIN and args.levels <= sites // 2


def _run_pair(args, levels: int | None = None) -> int:
    """``--method pair``: E0 and E1 from the sector-only build (graph.sectors.lowest_pair); with ``levels``
    (the default route for large flakes) the ``levels`` lowest (graph.sectors.lowest_sector_levels)."""
    from ..graph.sectors import lowest_sector_levels

    if levels is None:
        for flag, bad in (("--line-graph", args.line_graph), ("--sector", args.sector is not None),
                          ("--flux", bool(args.flux)), ("--levels other than 2", args.levels != 2)):
            if bad:
                raise ValueError(f"--method pair computes E0 and E1 of the flake only; {flag} is not supported "
                                 "with it.")
    spec = lowest_sector_levels(args.p, args.q, args.rings, 2 if levels is None else levels, tol=args.tol)
    if args.json:
        out = spec.summary()
        if args.flux is not None:
            out["flux"] = float(args.flux)
        print_json(out)
        return 0
    print(f"{{{args.p},{args.q}}} rings={args.rings} sites={spec.sites} method={spec.method} "
          f"time={spec.timings.get('total', 0.0):.2f} s")
    print(f"{'E':>20} {'n':>3} {'m':>4} {'deg':>3} {'residual':>10}")
    for e, n, m, d, r in zip(spec.energies, spec.n, spec.m, spec.degeneracy, spec.errors):
        print(f"{e:20.14f} {n:3d} {m:4d} {d:3d} {r:10.1e}")
    return 0


# every public function above checks its annotated argument types at the door (issue 19)
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
