"""``hyperlattice qubits``: circuit-QED qubits below the band: bound state, its size, exchange J(d)."""

from __future__ import annotations

import csv
import sys

from ..paper_labels import cite
from ._common import add_pq, finite_float, positive_int, print_json

NAME = "qubits"
ORDER = 53
HELP = "qubits coupled to the lattice below the band: photon bound state, its size, exchange J(d) graph vs continuum"
DESCRIPTION = (
    "A qubit of frequency omega_q below the band coupled with strength g to one site (or, with --line-graph, "
    "one resonator). Prints the exact single-excitation bound state (energy, qubit weight, size <d>, decay "
    "length) against its leading-order form G_{i,j0}(omega_q), and the effective exchange J(d) = g^2 G(omega_q) "
    "to a second qubit at hyperbolic distance d, graph vs continuum (" + cite("eq21") + "), as a table of binned means. "
    "--out writes that J(d) table as CSV (columns d,J_graph,J_continuum,rel_diff); --edges writes the effective "
    "spin model of qubits on --qubit-sites as an edge list CSV (columns i,j,site_i,site_j,J)."
)

TABLE_COLUMNS = ["d", "J_graph", "J_continuum", "rel_diff"]
EDGE_COLUMNS = ["i", "j", "site_i", "site_j", "J"]


def _sites(text: str) -> list[int]:
    import argparse

    try:
        vals = [int(v) for v in text.split(",") if v.strip()]
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected comma-separated site indices like 0,10,25, got {text!r}") from None
    if not vals:
        raise argparse.ArgumentTypeError("give at least one site index")
    return vals


def add_arguments(parser: argparse.ArgumentParser) -> None:
    add_pq(parser)
    parser.add_argument("--rings", type=positive_int, default=6, help="number of rings l (default 6)")
    parser.add_argument("--line-graph", action="store_true", help="couple to the resonators (line graph)")
    parser.add_argument("--omega-q", type=finite_float, default=-3.1,
                        help="qubit frequency below the band (default -3.1; about -4.1 suits the line graph)")
    parser.add_argument("--g", type=finite_float, default=0.05, help="qubit-photon coupling (default 0.05)")
    parser.add_argument("--site", type=int, default=0, help="site of the first qubit (default 0)")
    parser.add_argument("--qubit-sites", type=_sites, default=None, metavar="I,J,...",
                        help="sites of the qubits of the effective spin model (for --edges)")
    parser.add_argument("--threshold", type=finite_float, default=0.0,
                        help="drop couplings below this fraction of the largest in --edges (default 0)")
    parser.add_argument("--out", default=None, metavar="FILE.csv",
                        help="J(d) table as CSV (columns: " + ",".join(TABLE_COLUMNS) + "); '-' for stdout")
    parser.add_argument("--edges", default=None, metavar="FILE.csv",
                        help="spin-model edge list (columns: " + ",".join(EDGE_COLUMNS) + ")")
    parser.add_argument("--json", action="store_true", help="print one JSON object")


def _same_file(a, b) -> bool:
    """True if two output paths are one file (same resolved path, or hard links / symlinks to one)."""
    import os

    if os.path.abspath(a) == os.path.abspath(b) or os.path.realpath(a) == os.path.realpath(b):
        return True
    try:
        return os.path.samefile(a, b)
    except OSError:         # one of them does not exist yet: different files
        return False


def run(args: argparse.Namespace) -> int:
    from .. import _validate
    from ..compare.qubits import exchange_comparison
    from ..graph.lattice import line_graph, ring_lattice
    from ..graph.qubits import BelowBandResolvent, bound_state, spin_model

    out = _validate.output_path("--out", args.out, suffixes=(".csv",)) if args.out not in (None, "-") else None
    edges = _validate.output_path("--edges", args.edges, suffixes=(".csv",)) if args.edges is not None else None
    if out is not None and edges is not None and _same_file(out, edges):
        # both tables would be written into one file, the second over the first
        raise ValueError(f"--out and --edges name the same file {str(out)!r}; give two different files.")
    if edges is not None and args.qubit_sites is None:
        raise ValueError("--edges needs --qubit-sites (the sites of the qubits of the spin model).")
    threshold = _validate.real("--threshold", args.threshold, minimum=0.0, maximum=1.0)
    lat = ring_lattice(args.p, args.q, args.rings)
    if args.line_graph:
        lat = line_graph(lat)
    if not 0 <= args.site < lat.sites:
        raise ValueError(f"--site {args.site} is not a site of this lattice (valid: 0..{lat.sites - 1}).")
    res = BelowBandResolvent(lat)
    bs = bound_state(lat, args.site, args.omega_q, args.g, resolvent=res)
    ex = exchange_comparison(lat, args.omega_q, args.g, args.site, resolvent=res)
    table = ex.table()
    model = spin_model(lat, args.qubit_sites, args.omega_q, args.g, resolvent=res) \
        if args.qubit_sites is not None else None
    if args.out is not None:
        handle = sys.stdout if args.out == "-" else open(out, "w", newline="", encoding="utf-8")
        try:
            w = csv.writer(handle, lineterminator="\n")
            w.writerow(TABLE_COLUMNS)
            for row in table:
                w.writerow([repr(v) for v in row])
        finally:
            if handle is not sys.stdout:
                handle.close()
    if edges is not None:
        with open(edges, "w", newline="", encoding="utf-8") as fh:
            w = csv.writer(fh, lineterminator="\n")
            w.writerow(EDGE_COLUMNS)
            for i, j, J in model.edges(threshold):
                w.writerow([i, j, int(model.sites[i]), int(model.sites[j]), repr(J)])
    summary = {"bound_state": bs.summary(), "exchange": ex.summary(),
               "table": [dict(zip(TABLE_COLUMNS, r)) for r in table]}
    if model is not None:
        summary["spin_model"] = model.summary()
    if args.json:
        print_json(summary)
    elif args.out != "-":
        kind = "line graph of " if args.line_graph else ""
        print(f"{kind}{{{lat.p},{lat.q}}} rings={lat.rings} sites={lat.sites}; qubit on site {bs.site}, "
              f"omega_q = {bs.omega_q:g}, g = {bs.g:g}")
        print(f"bound state: E_b = {bs.energy:.10f} (leading order {bs.energy_leading:.10f}), qubit weight "
              f"{bs.qubit_weight:.6f}, <d> = {bs.size:.4f}, decay length {bs.decay_length:.4f}, "
              f"|exact - leading profile| = {bs.profile_error:.2e}, residual {bs.residual:.1e}")
        print(f"exchange J = g^2 G(omega_q): relative L2 graph vs continuum {ex.rel_l2:.4f}; decay length graph "
              f"{ex.decay_length_graph:.4f}, continuum {ex.decay_length_continuum:.4f}")
        print("   d        J_graph       J_continuum   rel_diff")
        for d, a, b, r in table[:12]:
            print(f"{d:6.3f}  {a:13.6e}  {b:13.6e}  {r:+.3f}")
        if model is not None:
            s = model.summary()
            print(f"spin model: {s['qubits']} qubits, largest J {s['max_coupling']:.4e}")
    return 0


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
