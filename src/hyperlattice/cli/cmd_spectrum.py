"""``hyperlattice spectrum``: lowest levels of H = -A on a {p,q} ring lattice, with their sector and the continuum (n, m)
they continue."""

from __future__ import annotations

from ..graph.lattice import line_graph, ring_lattice
from ..graph.spectrum import lowest_levels
from ..graph.symmetry import signed_sector
from ._common import add_pq, estimate_sites, finite_float, positive_int, print_json

NAME = "spectrum"
ORDER = 30
HELP = "lowest levels of H = -A with their rotation sector, the continuum (n, m) they continue, and residuals"
DESCRIPTION = (
    "Lowest eigenvalues of the hopping Hamiltonian H = -A (t = 1) of the {p,q} ring lattice, each with its "
    "rotation sector k = m mod p (all the lattice knows of the angular momentum), the continuum Dirichlet level "
    "(n, m) it continues (the j-th level of sector k matched to the j-th continuum level with m = k mod p; ties "
    "marked ambiguous), its lattice degeneracy and residual ||H psi - E psi||. Degenerate states are listed "
    "+m first; a continuum pair (n, +-m) that falls into one sector and is split by the lattice is reported "
    "with its splitting. JSON keys: n, m (continuum labels), sector, energies, residuals, continuum_energies, "
    "ambiguous, split."
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
        # before the build (--rings 9 would ask LAPACK for 12.2 GiB, and --rings 14 would build 5 M sites
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
    what = "line graph of " if args.line_graph else ""
    return _report(args, spec, f"{what}{{{args.p},{args.q}}} rings={args.rings} sites={spec.sites} method={spec.method} "
                               f"time={spec.timings.get('total', 0.0):.2f} s"
                               + (f" flux={args.flux:g}" if args.flux is not None else ""))


def _report(args, spec, header: str) -> int:
    """Label the levels with the continuum (n, m) they continue, then print the table or the JSON."""
    from ..compare.levels import continuum_labels

    try:
        spec = continuum_labels(spec)
    except ValueError as exc:
        # the continuum solvers refuse requests beyond their cost limit: the graph levels stand alone
        why = str(exc)
        if args.json:
            out = spec.summary()
            out.update(n=None, m=None, sector=[int(k) for k in spec.sector], labels_note=why)
            if args.flux is not None:
                out["flux"] = float(args.flux)
            print_json(out)
            return 0
        print(header)
        print(f"{'#':>4} {'E':>20} {'sector':>6} {'residual':>10}")
        for i, (e, k, r) in enumerate(zip(spec.energies, spec.sector, spec.errors)):
            print(f"{i + 1:4d} {e:20.14f} {k:6d} {r:10.1e}")
        print(f"no continuum labels: {why}")
        return 0
    if args.json:
        out = spec.summary()
        if args.flux is not None:
            # the contract: with --flux the key is always there, also for --flux 0
            out["flux"] = float(args.flux)
        print_json(out)
        return 0
    print(header)
    # a field splits sector k from p - k: no degeneracy column then
    deg = not spec.flux
    print(f"{'#':>4} {'E':>20} {'n':>3} {'m':>4} {'sector':>6}" + (f" {'deg':>3}" if deg else "") + f" {'residual':>10}")
    for i, (e, n, m, k, d, r, a) in enumerate(zip(spec.energies, spec.n, spec.m, spec.sector, spec.degeneracy,
                                                  spec.errors, spec.ambiguous)):
        print(f"{i + 1:4d} {e:20.14f} {n:3d} {m:4d} {k:6d}" + (f" {d:3d}" if deg else "") + f" {r:10.1e}"
              + ("  ambiguous" if a else ""))
    print(f"sector = m mod p is what the lattice knows; {spec.labels}")
    if not spec.flux:
        print("deg: degeneracy on the lattice (2: sectors k and p - k are complex conjugates).")
    for line in spec.notes():
        print(line)
    return 0


def _sector_only(args, sector) -> bool:
    """The request is one the sector-only route answers, and its blocks are big enough to pay: the API's
    rule (graph.spectrum._flake_route_applies), asked before any lattice is built."""
    from ..graph.lattice import _check_pq, _type_counts
    from ..graph.spectrum import _flake_route_applies

    plain = not (args.line_graph or sector is not None or args.flux)
    if not plain:
        return False
    p, q = _check_pq(args.p, args.q)
    sites = sum(_type_counts(p, q, args.rings, stop_above=2**62)[0])
    return _flake_route_applies(p, sites, args.levels, args.method, plain=True, built=False)


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
    return _report(args, spec, f"{{{args.p},{args.q}}} rings={args.rings} sites={spec.sites} method={spec.method} "
                               f"time={spec.timings.get('total', 0.0):.2f} s")


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
