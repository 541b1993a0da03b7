"""``hyperlattice boundary``: boundary two-point function of the massive scalar on the outer ring (holography)."""

from __future__ import annotations

import csv
import sys

from ..paper_labels import cite
from ._common import add_pq, finite_float, plot_file, positive_int, print_json

NAME = "boundary"
ORDER = 52
HELP = "boundary correlators G_ij(omega) on the outer ring below the band, the fitted Delta vs the continuum"
DESCRIPTION = (
    "For a real frequency omega below the band (omega < E0 of the flake, checked), the graph propagator "
    "G_ij = [(H - omega)^-1]_ij with source and probes on the outermost ring is the boundary two-point "
    "function of a scalar of mass^2 = -lambda, lambda = 4(omega+q)/(q h^2) (" + cite("eq21") + "), in AdS2 of radius 1/2: "
    "G ~ [sin(theta/2)]^(-2 Delta). Prints lambda, mass2, the continuum Delta = 1/2 + sqrt(1 - lambda)/2 "
    "(null beyond the continuum BF bound omega > E_inf) and the fitted lattice Delta with its fit uncertainty and, "
    "beside it, its systematic error (finite l: the same fit with one ring less; lattice spacing: the continuum "
    "Delta of the paper's against the improved dictionary). Instead of --omega, --mass2 M2 --ads-radius R gives "
    "the mass in the convention named: R = 1 (unit-radius AdS2, Delta = 1/2 + sqrt(1/4 + m^2)) or R = 0.5 "
    "(the paper's metric, Delta = 1/2 + sqrt(1 + m^2)/2); both formulas' values at the number are printed. "
    "--out writes one CSV row per outer-ring site with columns site,theta,graph,continuum (graph = G_ij "
    "itself; continuum = " + cite("eq21") + " with the whole-disk (L = 1) propagator at the site positions, or with --continuum-disk "
    "the Dirichlet disk of radius L; inf at the source, nan where the model has no value)."
)

COLUMNS = ["site", "theta", "graph", "continuum"]


def add_arguments(parser: argparse.ArgumentParser) -> None:
    add_pq(parser)
    parser.add_argument("--rings", type=positive_int, default=6, help="number of rings l (default 6)")
    parser.add_argument("--omega", type=finite_float, default=None,
                        help="real frequency below the band, e.g. --omega=-3.2 (default -3.2 unless --mass2 is given)")
    parser.add_argument("--mass2", type=finite_float, default=None, metavar="M2",
                        help="the scalar's mass^2 instead of --omega, in the convention --ads-radius names")
    parser.add_argument("--ads-radius", type=finite_float, default=None, metavar="R",
                        help="with --mass2: 1 (unit-radius AdS2, Delta(Delta-1) = m^2) or 0.5 (the paper's metric, "
                             "Delta(Delta-1) = m^2/4)")
    parser.add_argument("--no-systematic", action="store_true",
                        help="skip the systematic error (the fit on the flake with one ring less)")
    parser.add_argument("--site", type=int, default=None,
                        help="source site j on the outer ring, 0-based (default: the first site of the outer ring)")
    parser.add_argument("--depth", type=positive_int, default=2,
                        help="fit window: geodesics between the pair reach at least this many rings inward "
                             "(default 2)")
    parser.add_argument("--continuum-disk", default="whole", choices=("whole", "dirichlet", "mapped"),
                        help="continuum column: whole-disk propagator (default), Dirichlet disk of the dictionary "
                             "radius L at the site positions (empty beyond L; up to 6 rings for {7,3}), or the "
                             "Dirichlet disk with the ring mapped to its mean depth")
    parser.add_argument("--out", default=None, metavar="FILE.csv",
                        help="CSV, one row per outer-ring site (columns: " + ",".join(COLUMNS) + "); '-' for stdout")
    parser.add_argument("--plot", default=None, metavar="FILE", help="figure file (.png, .svg, ...)")
    parser.add_argument("--json", action="store_true", help="print the summary as one JSON object")


def _write_csv(handle, bc) -> None:
    w = csv.writer(handle, lineterminator="\n")
    w.writerow(COLUMNS)
    for s, th, g, c in zip(bc.sites.tolist(), bc.theta.tolist(), bc.graph.tolist(), bc.continuum.tolist()):
        w.writerow([s, repr(float(th)), repr(float(g)), repr(float(c))])


def run(args: argparse.Namespace) -> int:
    from .. import _validate
    from ..compare.boundary import boundary_correlator
    from ..graph.lattice import ring_lattice

    out = _validate.output_path("--out", args.out, suffixes=(".csv",)) if args.out not in (None, "-") else None
    fig = plot_file("--plot", args.plot) if args.plot is not None else None
    lat = ring_lattice(args.p, args.q, args.rings)
    if args.site is not None and not 0 <= args.site < lat.sites:
        raise ValueError(f"--site {args.site} is not a site of this lattice (valid: 0..{lat.sites - 1}).")
    omega = -3.2 if args.omega is None and args.mass2 is None else args.omega
    if args.ads_radius is not None and args.mass2 is None:
        raise ValueError("--ads-radius names the convention of --mass2; give it with --mass2.")
    bc = boundary_correlator(lat, omega, args.site, mass2=args.mass2, ads_radius=args.ads_radius, depth=args.depth,
                             continuum_disk=args.continuum_disk, systematic=not args.no_systematic)
    if args.out == "-":
        _write_csv(sys.stdout, bc)
    elif out is not None:
        with open(out, "w", newline="", encoding="utf-8") as fh:
            _write_csv(fh, bc)
    if fig is not None:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        ax = bc.plot()
        ax.figure.savefig(fig)
        plt.close(ax.figure)
    if args.json:
        print_json(bc.summary())
    elif args.out != "-":
        dc = "n/a (beyond the continuum BF bound)" if bc.delta_continuum != bc.delta_continuum \
            else f"{bc.delta_continuum:.6f}"
        print(f"{{{lat.p},{lat.q}}} lattice, {lat.rings} rings ({lat.sites} sites, {bc.sites.size} on the outer ring), "
              f"source {bc.source}")
        print(f"omega = {bc.omega:.6g}, lambda = {bc.lam:.6g}")
        print(f"mass^2 = {bc.mass2:.6g} in the paper's metric (AdS radius 1/2) = {bc.mass2 / 4:.6g} in unit-radius "
              "AdS2 (m^2 R^2)" + (f"; given as {bc.mass2_input:g} with AdS radius {bc.ads_radius:g}"
                                  if args.mass2 is not None else ""))
        f = bc.delta_formulas
        given = "radius 1" if bc.ads_radius == 1.0 else "radius 1/2"

        def fmt(v):
            return "n/a (below its BF bound)" if v != v else f"{v:.6f}"

        print(f"Delta formulas at the number {bc.mass2_input:g}: radius 1/2, 1/2 + sqrt(1 + m^2)/2 = "
              f"{fmt(f['ads_radius_0.5'])}; radius 1, 1/2 + sqrt(1/4 + m^2) = {fmt(f['ads_radius_1'])} "
              f"(the {given} one applies)")
        improved = "" if bc.delta_continuum_improved != bc.delta_continuum_improved \
            else f" (paper's dictionary; {bc.delta_continuum_improved:.6f} with the improved one)"
        print(f"Delta continuum = {dc}{improved}")
        print(f"Delta lattice = {bc.delta_lattice:.6f} +- {bc.delta_lattice_err:.6f} (fit: stat "
              f"{bc.delta_lattice_stat:.6f}, window {bc.delta_lattice_window:.6f}; {bc.pairs} pairs with theta >= "
              f"{bc.theta_min:.4g}, depth {bc.depth})")
        if bc.delta_lattice_sys == bc.delta_lattice_sys:
            print(f"  +- {bc.delta_lattice_sys:.6f} systematic (lattice spacing {bc.delta_lattice_sys_spacing:.6f}, "
                  f"finite l {bc.delta_lattice_sys_rings:.6f})")
            if bc.delta_continuum == bc.delta_continuum:
                diff = bc.delta_lattice - bc.delta_continuum
                print(f"Delta lattice - Delta continuum = {diff:+.6f}, {abs(diff) / bc.delta_lattice_total_err:.2g} "
                      f"times the total error {bc.delta_lattice_total_err:.6f}")
        elif not args.no_systematic:
            print("  systematic error not available (the flake with one ring less has too few rings for the window)")
    return 0


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
