"""``hyperlattice cluster``: list the periodic {p,q} clusters, or build one and export it."""

from __future__ import annotations

import numpy as np

from .. import _validate
from ..graph.clusters import list_clusters, pbc_cluster
from ._common import add_max_seconds, add_pq, check_work, cluster_pq, positive_int, print_json

NAME = "cluster"
ORDER = 22
HELP = "periodic {p,q} clusters (compact surfaces): list them, or write one's edges and faces (.npz)"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    add_pq(parser)
    parser.add_argument("--list", action="store_true",
                        help="list the available clusters (name, p, q, sites, edges, faces, genus, systole)")
    parser.add_argument("--max-sites", type=positive_int, default=100_000,
                        help="with --list: largest cluster listed (default 100000)")
    parser.add_argument("--name", help="a cluster from --list, e.g. klein, bolza, 'PSL(2,13)'")
    parser.add_argument("--min-sites", type=positive_int,
                        help="instead of --name: the smallest PSL(2,r) cluster with at least this many sites")
    parser.add_argument("--out", metavar="FILE.npz",
                        help="write arrays edges (E x 2, 0-based) and faces (F x p, counterclockwise)")
    parser.add_argument("--json", action="store_true", help="print JSON")
    add_max_seconds(parser)


def run(args: argparse.Namespace) -> int:
    _validate.pq(args.p, args.q)
    if args.list:
        if args.name is not None or args.min_sites is not None or args.out is not None:
            raise ValueError("--list takes no --name, --min-sites or --out.")
        entries = list_clusters(args.p, args.q, max_sites=args.max_sites)
        if args.json:
            print_json(entries)
            return 0
        print(f"{'name':>12} {'sites':>9} {'edges':>9} {'faces':>9} {'genus':>7} {'systole':>7}")
        for e in entries:
            print(f"{e['name']:>12} {e['sites']:>9} {e['edges']:>9} {e['faces']:>9} {e['genus']:>7} {e['systole']:>7}")
        return 0
    out = None
    if args.out is not None:
        # checked before building, so that a long build never fails at its last step
        out = _validate.output_path("--out", args.out, suffixes=(".npz",))
    if args.min_sites is not None and args.name is None:
        # estimated before anything is built (--min-sites 100000000 ran on for minutes unannounced)
        from ..graph import groups
        from ..graph.clusters import SECONDS_PER_DART, _psl2_for

        r = _psl2_for(args.p, args.q, args.min_sites)
        darts = groups.psl2_order(r)
        check_work("cluster", darts * SECONDS_PER_DART, args.max_seconds,
                   f"PSL(2,{r}): {darts // args.q:,} sites, {darts:,} darts", "a smaller --min-sites")
    p, q = (args.p, args.q) if args.name is None else cluster_pq(args, args.name)
    cluster = pbc_cluster(p, q, args.name, min_sites=args.min_sites)
    if out is not None:
        np.savez(out, edges=np.asarray(cluster.edges), faces=np.asarray(cluster.faces))
    if args.json:
        print_json(cluster.summary())
        return 0
    info = cluster.info()
    exact = "" if cluster.systole_exact else ">= "
    print(f"{{{cluster.p},{cluster.q}}} cluster {cluster.name}: {info['sites']} sites, {info['edges']} edges, "
          f"{info['faces']} faces, genus {info['genus']}, systole {exact}{info['systole']}")
    print(f"  group {cluster.group}")
    print(f"  source: {cluster.source}")
    if out is not None:
        print(f"  edges and faces written to {out}")
    return 0


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
