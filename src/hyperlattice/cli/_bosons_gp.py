"""``hyperlattice bosons gp``: Gross–Pitaevskii condensate of a flake against its continuum disk."""

from __future__ import annotations

import argparse

from .. import _validate
from ._common import add_pq, finite_float, print_json

NAME = "gp"
ORDER = 30
HELP = "Gross-Pitaevskii ground state and Bogoliubov spectrum, flake vs continuum disk (paper dictionary)"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    add_pq(parser)
    parser.add_argument("--rings", type=int, required=True, help="the flake's ring count l")
    size = parser.add_mutually_exclusive_group()     # --filling beside --particles was silently ignored
    size.add_argument("--filling", type=finite_float, default=None,
                      help="bosons per site n = N / sites (default 1); or give --particles")
    size.add_argument("--particles", type=finite_float, default=None, help="N, the total number of bosons")
    parser.add_argument("--U", type=finite_float, required=True, help="on-site interaction U (>= 0)")
    parser.add_argument("--t", type=finite_float, default=1.0, help="hopping t (default 1)")
    parser.add_argument("--modes", type=int, default=5,
                        help="Bogoliubov frequencies compared, the Goldstone mode included (default 5)")
    parser.add_argument("--json", action="store_true", help="print one JSON object")


def run(args: argparse.Namespace) -> int:
    from ..compare.bosons import gp_comparison
    from ..graph.lattice import site_count

    rings = _validate.integer("--rings", args.rings, minimum=1, maximum=12)
    filling = 1.0 if args.filling is None else args.filling
    if args.particles is not None:
        filling = _validate.positive_real("--particles", args.particles) / site_count(args.p, args.q, rings)
    cmp = gp_comparison(args.p, args.q, (rings,), filling=filling, U=args.U, t=args.t, modes=args.modes)
    row = cmp.rows[0]
    out = {"p": cmp.p, "q": cmp.q, "rings": rings, "sites": row["sites"], "particles": row["particles"],
           "filling": cmp.filling, "U": cmp.U, "t": cmp.t,
           "graph": {"mu": row["mu_graph"], "bogoliubov": row["bogoliubov_graph"], "residual": row["residual_graph"]},
           "continuum": {"mu": row["mu_continuum"], "bogoliubov": row["bogoliubov_continuum"],
                         "bogoliubov_j": row["bogoliubov_j"], "residual": row["residual_continuum"],
                         "healing_length": row["xi"]},
           "mu_rel_diff": row["mu_rel_diff"], "xi_over_d0": row["xi_over_d0"], "d0": cmp.d0,
           "profile": cmp.profiles[0]}
    if args.json:
        print_json(out)
        return 0
    print(f"{{{cmp.p},{cmp.q}}} flake l = {rings}: {row['sites']} sites, N = {row['particles']:g} bosons "
          f"(n = {cmp.filling:g}), U = {cmp.U:g}, t = {cmp.t:g}")
    print(f"  mu  graph {row['mu_graph']:.8f}   continuum {row['mu_continuum']:.8f}   "
          f"(relative difference {row['mu_rel_diff']:+.2e})")
    print(f"  healing length xi = {row['xi']:.4g} = {row['xi_over_d0']:.3g} d0   (the continuum needs xi >> d0)")
    if row["bogoliubov_graph"]:
        print("  Bogoliubov  graph: " + " ".join(f"{w:.5f}" for w in row["bogoliubov_graph"]))
        print("          continuum: " + " ".join(f"{w:.5f}" for w in row["bogoliubov_continuum"])
              + "   (j = " + " ".join(str(j) for j in row["bogoliubov_j"]) + ")")
    print("  density per site by ring (graph | continuum): "
          + "  ".join(f"{g:.3f}|{c:.3f}" for g, c in zip(cmp.profiles[0]["graph"], cmp.profiles[0]["continuum"])))
    return 0


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
