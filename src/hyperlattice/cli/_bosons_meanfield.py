"""``hyperlattice bosons meanfield``: the mean-field Mott lobe of a flake or a periodic cluster."""

from __future__ import annotations

import argparse

from .. import _validate
from ._common import add_pq, cluster_pq, finite_float, plot_file, print_json

NAME = "meanfield"
ORDER = 20
HELP = "mean-field (Gutzwiller) Mott lobe: t_c/U against mu/U from lambda_max of the graph"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    add_pq(parser)
    where = parser.add_mutually_exclusive_group(required=True)
    where.add_argument("--rings", type=int, help="a flake of this many rings")
    where.add_argument("--cluster", help="a periodic cluster by name (see `hyperlattice cluster --list`)")
    where.add_argument("--infinite", action="store_true",
                       help="the infinite {p,q} lattice: lambda_max = rho, the extrapolated band bottom (with its "
                            "error), from the stored flake levels")
    parser.add_argument("--filling", type=int, default=1, help="Mott filling n (default 1)")
    parser.add_argument("--points", type=int, default=21,
                        help="grid points in mu/U over [n-1, n], ends included (default 21)")
    parser.add_argument("--continuum", action="store_true",
                        help="also the continuum lobe of the flake's Dirichlet disk (paper dictionary)")
    parser.add_argument("--t", type=finite_float, default=None,
                        help="also solve the self-consistent Gutzwiller state at this t/U and --mu")
    parser.add_argument("--mu", type=finite_float, default=None, help="mu/U of the Gutzwiller state (with --t)")
    parser.add_argument("--plot", default=None, metavar="FILE", help="save the lobe to this image file (.png, .pdf, "
                        ".svg, ...)")
    parser.add_argument("--json", action="store_true", help="print one JSON object")


def run(args: argparse.Namespace) -> int:
    from ..bosons.meanfield import gutzwiller, largest_adjacency_eigenvalue, mott_lobe

    # checked before any work (its argparse type took two arguments: --plot could never work)
    plot = plot_file("--plot", args.plot) if args.plot is not None else None
    rho_error = None
    if args.infinite:
        from ..compare.limits import band_bottom

        if args.continuum:
            raise ValueError("--continuum needs --rings (the infinite lattice has no disk).")
        p, q = _validate.pq(args.p, args.q)
        bottom = band_bottom(p, q, schur_window=None)
        system, rho_error = None, float(bottom.error)
        label = f"infinite {{{p},{q}}} lattice"
    elif args.cluster is not None:
        from ..graph.clusters import pbc_cluster

        args.p, args.q = cluster_pq(args, args.cluster)
        system = pbc_cluster(args.p, args.q, args.cluster)
        label = f"{{{args.p},{args.q}}} cluster {system.name} ({system.sites} sites)"
        if args.continuum:
            raise ValueError("--continuum needs --rings (a periodic cluster has no disk).")
    else:
        from ..graph.lattice import ring_lattice

        rings = _validate.integer("--rings", args.rings, minimum=1, maximum=20)
        system = ring_lattice(args.p, args.q, rings)
        label = f"{{{args.p},{args.q}}} flake, l = {rings}"
    if (args.t is None) != (args.mu is None):
        raise ValueError("give --t and --mu together (the Gutzwiller state at t/U and mu/U).")
    lam = float(bottom.rho) if args.infinite else largest_adjacency_eigenvalue(system)
    lobe = mott_lobe(lam, args.filling, args.points, label=label)
    out = {"label": label, "sites": None if system is None else int(system.sites), "filling": lobe.filling,
           "lambda_max": lam,
           "mu_over_U": lobe.mu_over_U.tolist(), "t_c_over_U": lobe.t_c_over_U.tolist(),
           "tip": {"mu_over_U": lobe.tip_mu_over_U, "t_c_over_U": lobe.tip_t_over_U}}
    cont = None
    if args.continuum:
        from ..continuum.spectrum import continuum_levels

        lam_c = -float(continuum_levels(args.p, args.q, rings=rings, levels=1).energies[0])
        cont = mott_lobe(lam_c, args.filling, args.points, label=f"continuum disk of l = {rings}")
        out["continuum"] = {"lambda_max": lam_c, "t_c_over_U": cont.t_c_over_U.tolist(),
                            "tip": {"mu_over_U": cont.tip_mu_over_U, "t_c_over_U": cont.tip_t_over_U}}
    if rho_error is not None:
        # t_c = g_n / lambda_max: its relative error is rho's
        out["lambda_max_error"] = rho_error
        out["tip"]["t_c_over_U_error"] = lobe.tip_t_over_U * rho_error / lam
    if args.t is not None:
        if system is None:
            raise ValueError("--t and --mu solve the Gutzwiller state of a graph: give --rings or --cluster.")
        st = gutzwiller(system, args.t, args.mu, 1.0)
        out["gutzwiller"] = st.summary()
    if plot is not None:
        import matplotlib.pyplot as plt

        ax = lobe.plot()
        if cont is not None:
            ax.plot(cont.t_c_over_U, cont.mu_over_U, "--", label=cont.label)
        ax.legend(fontsize=8, frameon=False)
        ax.figure.savefig(plot, dpi=130)
        plt.close(ax.figure)
    if args.json:
        print_json(out)
        return 0
    if rho_error is not None:
        print(f"{label}: lambda_max = rho = {lam:.6f} +- {rho_error:.1e} (band bottom extrapolated from the stored "
              f"flake levels), filling n = {lobe.filling}")
        print(f"lobe tip: mu/U = {lobe.tip_mu_over_U:.6f}, t_c/U = {lobe.tip_t_over_U:.6f} "
              f"+- {out['tip']['t_c_over_U_error']:.1e}")
    else:
        print(f"{label}: lambda_max = {lam:.8f} (largest adjacency eigenvalue), filling n = {lobe.filling}")
        print(f"lobe tip: mu/U = {lobe.tip_mu_over_U:.6f}, t_c/U = {lobe.tip_t_over_U:.6f}"
              + (f"   (continuum: t_c/U = {cont.tip_t_over_U:.6f})" if cont is not None else ""))
    print(f"{'mu/U':>8} {'t_c/U':>10}" + (f" {'continuum':>10}" if cont is not None else ""))
    for i, (m, t) in enumerate(zip(lobe.mu_over_U, lobe.t_c_over_U)):
        print(f"{m:8.4f} {t:10.6f}" + (f" {cont.t_c_over_U[i]:10.6f}" if cont is not None else ""))
    if args.t is not None:
        s = out["gutzwiller"]
        print(f"Gutzwiller at t/U = {args.t:g}, mu/U = {args.mu:g}: psi_max = {s['psi_max']:.6g}, "
              f"<n> = {s['density_mean']:.6g}, {'superfluid' if s['superfluid'] else 'Mott'} "
              f"({s['iterations']} iterations, residual {s['residual']:.1e})")
    return 0


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
