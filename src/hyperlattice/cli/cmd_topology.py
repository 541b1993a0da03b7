"""``hyperlattice topology``: Chern invariants of QWZ, Haldane and Kane–Mele models.

Tasks:

* ``flake``    a {p,q} flake: the hyperbolic local marker at the centre and by ring, Kitaev's sum,
               the Bott index and the bulk gap at the centre (dense up to 9,000 rows; above, the
               centre marker by a Chebyshev expansion of the projector, Bott omitted)
* ``cluster``  a periodic cluster: the first Chern numbers C_ij of the Abelian bands on every
               2-subtorus, their gcd and Pfaffian, the smallest gap on the grid
* ``conductance``  a {p,q} flake between two wide-band leads on two arcs of its edge: the two-terminal
               conductance (Landauer–Caroli) at the given energies, in units of e^2/h
"""

from __future__ import annotations

import argparse

import numpy as np

from .. import _validate
from ._common import add_pq, cluster_pq, finite_float, positive_int, print_json

NAME = "topology"
ORDER = 60
HELP = "Chern markers on flakes and Chern numbers on clusters (QWZ, Haldane, Kane-Mele)"
DESCRIPTION = __doc__

_MODELS = ("qwz", "haldane", "kane-mele")


def _nonnegative_int(text: str) -> int:
    from ._common import integer

    v = integer(text)
    if v < 0:
        raise argparse.ArgumentTypeError(f"expected a non-negative integer, got {text!r}")
    return v


def _model_flags(parser, *, disorder: bool) -> None:
    parser.add_argument("--model", choices=_MODELS, default="qwz", help="the model (default qwz)")
    add_pq(parser, default_p=8)
    parser.add_argument("--M", type=finite_float, default=1.0,
                        help="QWZ mass, or Haldane / Kane-Mele sublattice mass (default 1)")
    parser.add_argument("--t2", type=finite_float, default=0.2,
                        help="Haldane / Kane-Mele second-neighbour amplitude (default 0.2)")
    parser.add_argument("--phi", type=finite_float, default=float(np.pi / 2),
                        help="Haldane phase in radians (default pi/2)")
    if disorder:
        parser.add_argument("--disorder", type=finite_float, default=0.0,
                            help="box disorder width W (on-site energies in [-W/2, W/2]; default 0)")
        parser.add_argument("--seed", type=_nonnegative_int, default=0, help="disorder seed (default 0)")
    parser.add_argument("--json", action="store_true", help="print JSON")


def add_arguments(parser: argparse.ArgumentParser) -> None:
    sub = parser.add_subparsers(dest="task", metavar="TASK", parser_class=type(parser))
    sub.required = True
    f = sub.add_parser("flake", help="local marker by ring, Kitaev's sum, Bott index and gap of a flake")
    _model_flags(f, disorder=True)
    f.add_argument("--rings", type=positive_int, default=3, help="rings of the flake (default 3)")
    c = sub.add_parser("cluster", help="Chern numbers C_ij on all 2-subtori of a periodic cluster")
    _model_flags(c, disorder=False)
    c.add_argument("--cluster", required=True, help="a cluster name (hyperlattice cluster --list), e.g. bolza")
    g = sub.add_parser("conductance", help="two-terminal conductance (e^2/h) of a flake through leads on its edge")
    _model_flags(g, disorder=True)
    g.add_argument("--rings", type=positive_int, default=3, help="rings of the flake (default 3)")
    g.add_argument("--energies", type=_float_list, default=[0.0],
                   help="comma-separated energies in units of t (default 0)")
    g.add_argument("--coupling", type=finite_float, default=2.0,
                   help="wide-band lead coupling gamma per contact orbital, units of t (default 2)")
    g.add_argument("--arc", type=finite_float, default=0.25,
                   help="fraction of the full turn each contact spans on the outer edge (default 0.25)")


def _float_list(text: str) -> list:
    items = [t for t in text.split(",") if t.strip()]
    if not items:
        raise argparse.ArgumentTypeError(f"expected comma-separated numbers, got {text!r}")
    return [finite_float(t) for t in items]


def _flake(args) -> int:
    from ..graph.lattice import ring_lattice, site_count
    from ..topology.markers import MAX_DENSE_ROWS, flake_topology
    from ..topology.models import orbitals

    p, q = _validate.pq(args.p, args.q)
    rings = _validate.integer("--rings", args.rings, minimum=1, maximum=12)
    W = _validate.real("--disorder", args.disorder, minimum=0.0, maximum=1e6)
    n = site_count(p, q, rings)
    rows = n * orbitals(args.model)
    if rows <= MAX_DENSE_ROWS:
        res = flake_topology(ring_lattice(p, q, rings), args.model, M=args.M, t2=args.t2, phi=args.phi,
                             disorder=W, seed=args.seed)
        out = res.summary()
    else:
        from ..topology.kpm_marker import centre_marker

        res = centre_marker(ring_lattice(p, q, rings), args.model, M=args.M, t2=args.t2, phi=args.phi,
                            disorder=W, seed=args.seed)
        out = res.summary()
    if args.json:
        print_json(out)
        return 0
    print(f"{{{p},{q}}} flake, {rings} rings, {out['sites']} sites, model {args.model} ({out['method']})")
    print(f"  local marker at the centre: {out['marker']:+.4f}   by ring: "
          + " ".join(f"{x:+.3f}" for x in out["marker_by_ring"]))
    print(f"  Kitaev sum: {out['kitaev']:+.4f}   Bott index: "
          + ("n/a" if out["bott"] is None else f"{out['bott']:+.4f}"
             + ("" if out.get("bott_reliable", True) else " (unreliable: edge states)")))
    print(f"  bulk gap at the centre: {out['gap']:.4g}")
    return 0


def _cluster(args) -> int:
    from ..graph.clusters import pbc_cluster
    from ..topology.surfaces import cluster_chern

    name = args.cluster
    p, q = cluster_pq(args, name)
    cl = pbc_cluster(p, q, name)
    res = cluster_chern(cl, args.model, M=args.M, t2=args.t2, phi=args.phi)
    out = res.summary()
    if args.json:
        print_json(out)
        return 0
    print(f"{{{p},{q}}} cluster {cl.name} (genus {cl.genus}), model {args.model}, grid {res.grid} x {res.grid}")
    for row in res.chern.tolist():
        print("  " + " ".join(f"{x:+d}" for x in row))
    print(f"  gcd {res.gcd}, Pfaffian {res.pfaffian}, smallest gap on the grid {res.gap:.4g}")
    return 0


def _conductance(args) -> int:
    from ..graph.lattice import ring_lattice
    from ..topology.transport import conductance

    p, q = _validate.pq(args.p, args.q)
    rings = _validate.integer("--rings", args.rings, minimum=1, maximum=12)
    W = _validate.real("--disorder", args.disorder, minimum=0.0, maximum=1e6)
    res = conductance(ring_lattice(p, q, rings), args.model, energies=args.energies, M=args.M, t2=args.t2,
                      phi=args.phi, disorder=W, seed=args.seed, coupling=args.coupling, arc=args.arc)
    out = res.summary()
    if args.json:
        print_json(out)
        return 0
    print(f"{{{p},{q}}} flake, {rings} rings, {res.sites} sites, model {args.model}; leads on {len(res.left)} and "
          f"{len(res.right)} edge sites, coupling {args.coupling:g} t")
    print("  E (t)        G (e^2/h)")
    for e, g in zip(res.energies, res.conductance):
        print(f"  {e:+.4f}    {g:.6f}")
    return 0


def run(args: argparse.Namespace) -> int:
    return {"flake": _flake, "cluster": _cluster, "conductance": _conductance}[args.task](args)


from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
