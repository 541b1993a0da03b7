"""``hyperlattice scaling``: frame angles, the formal operator A_h, its convergence, sums as integrals.

Tasks (the paper's Appendices B, C and D):

* ``angles``      chi_i and delta_i of every site (Eqs. (B7)–(B9)), star check, Fig. 5
* ``operator``    A_h f - q f with the quadratic / cubic approximations per radius (Fig. 6)
* ``convergence`` powers of h in the errors of the order-2/3/4 approximations
* ``counting``    fit of the counting function N(r) ~ s rho + b (Eq. (D6), Fig. 7)
* ``sums``        lattice sums against (1/A) * disk integrals, Eq. (9), for several rings
"""

from __future__ import annotations

import numpy as np

from .. import _validate
from ..compare.scaling import (MAX_H_VALUES, PRESETS, SmoothFunction, angle_profile, convergence_study,
                               frame_angles, operator_profile)
from ..compare.sums import MAX_SLOPE, fit_counting, sum_check
from ..graph.lattice import ring_lattice
from ..paper_labels import cite
from ._common import add_pq, finite_float, plot_file, positive_int, print_json

NAME = "scaling"
ORDER = 55

#: most --h values of ``operator`` (one figure panel each) and --rings values of ``sums``
MAX_LIST = 50
HELP = "frame angles chi_i, the formal operator A_h and its h-expansion, sums as integrals"
DESCRIPTION = __doc__


def _common(p, *, rings_default: int, many_rings: bool = False) -> None:
    add_pq(p)
    if many_rings:
        p.add_argument("--rings", type=positive_int, nargs="+", default=list(range(4, 11)),
                       help="numbers of rings (default 4..10)")
    else:
        p.add_argument("--rings", type=positive_int, default=rings_default,
                       help=f"number of rings (default {rings_default})")
    p.add_argument("--json", action="store_true", help="print JSON")


def _plot_opt(p) -> None:
    p.add_argument("--plot", metavar="FILE.png", help="also save the figure to this file")


def add_arguments(parser: argparse.ArgumentParser) -> None:
    sub = parser.add_subparsers(dest="task", metavar="TASK", parser_class=type(parser))
    sub.required = True
    fnames = ", ".join(PRESETS)

    a = sub.add_parser("angles", help=f"chi_i, delta_i and the ideal-star check ({cite('FigScos3delta')})")
    _common(a, rings_default=5)
    _plot_opt(a)

    o = sub.add_parser("operator", help=f"A_h f - q f and its approximations per radius ({cite('FigSh')})")
    _common(o, rings_default=5)
    o.add_argument("--h", type=finite_float, nargs="+", default=None,
                   help="values of h <= tanh(d0) (default: tanh(d0), 0.1, 0.05)")
    o.add_argument("--function", choices=list(PRESETS), default="cos-distance",
                   help=f"test function (default cos-distance = cos(pi d(z,0))); one of {fnames}")
    _plot_opt(o)

    c = sub.add_parser("convergence", help="fitted powers of h in the errors of the approximations")
    _common(c, rings_default=4)
    c.add_argument("--function", choices=list(PRESETS), default="cos-distance", help="test function")
    c.add_argument("--h-min", type=finite_float, default=0.01, help="smallest h (default 0.01)")
    c.add_argument("--h-max", type=finite_float, default=0.08, help="largest h (default 0.08)")
    c.add_argument("--points", type=positive_int, default=8, help="number of h values (default 8)")

    n = sub.add_parser("counting", help=f"fit N(r) ~ s rho + b ({cite('sum4', 'FigS1')})")
    _common(n, rings_default=4)
    n.add_argument("--window", choices=["all", "complete"], default="all",
                   help="'all' radii (the paper's fit) or only radii below ring l+1 ('complete')")
    n.add_argument("--slope", type=finite_float, default=None, help="fix the slope, fit only b")
    _plot_opt(n)

    s = sub.add_parser("sums", help=f"lattice sums against (1/A) * integral over |z| <= L, {cite('eq11')}")
    _common(s, rings_default=4, many_rings=True)
    s.add_argument("--function", choices=list(PRESETS), nargs="+",
                   default=["inverse-rho-squared", "gaussian", "anisotropic"],
                   help="test functions (default inverse-rho-squared gaussian anisotropic)")


def _plot_path(args):
    """The --plot file, checked before computing (None without --plot)."""
    return plot_file("--plot", args.plot) if getattr(args, "plot", None) is not None else None


def _save(ax, path) -> None:
    if path:
        import matplotlib.pyplot as plt

        ax.figure.savefig(path, dpi=120)
        plt.close(ax.figure)


def _count(flag: str, values, most: int) -> None:
    if len(values) > most:
        raise ValueError(f"at most {most} values of {flag}, got {len(values)}.")


def _angles(args) -> int:
    plot = _plot_path(args)
    lat = ring_lattice(args.p, args.q, args.rings)
    ang = frame_angles(lat)
    prof = angle_profile(ang)
    out = {"p": lat.p, "q": lat.q, "rings": lat.rings, "sites": lat.sites,
           "full_sites": int(ang.full.sum()), "h": ang.h, "max_star_residual": ang.max_residual,
           "distinct_radii": int(prof.r.size), "non_unique_radii": int((~prof.unique).sum()),
           "profile": {"r": prof.r, "cos_q_delta_mean": prof.mean, "min": prof.min,
                       "max": prof.max, "count": prof.count, "unique": prof.unique}}
    if plot:
        from ..plots.scaling import plot_frame_angles
        _save(plot_frame_angles(ang), plot)
    if args.json:
        print_json(out)
        return 0
    print(f"{{{lat.p},{lat.q}}}, {lat.rings} rings: {lat.sites} sites, {out['full_sites']} with full coordination")
    print(f"  mapped neighbours lie on the star h e^(i chi) e^(2 pi i a/q) to {ang.max_residual:.2e} (h = {ang.h:.6f})")
    print(f"  {prof.r.size} distinct radii, cos({lat.q} delta) not unique at {out['non_unique_radii']} of them")
    print(f"  {'r':>10} {'cos(q delta)':>13} {'sites':>6}")
    for r, m, k, u in zip(prof.r, prof.mean, prof.count, prof.unique):
        print(f"  {r:10.6f} {m:13.6f} {k:6d}{'' if u else '  (not unique)'}")
    return 0


def _operator(args) -> int:
    plot = _plot_path(args)
    if args.h is not None:
        _count("--h", args.h, MAX_LIST)
    lat = ring_lattice(args.p, args.q, args.rings)
    ang = frame_angles(lat)
    f = SmoothFunction.preset(args.function)
    hs = args.h if args.h is not None else [ang.h, 0.1, 0.05]
    profiles = [operator_profile(ang, f, h) for h in hs]
    rows = [prof.summary() for prof in profiles]
    if plot:
        import matplotlib.pyplot as plt

        from ..plots.scaling import draw_operator_profile
        fig, axs = plt.subplots(1, len(hs), figsize=(5.2 * len(hs), 4.2), layout="constrained", squeeze=False)
        for prof, ax in zip(profiles, axs[0]):
            draw_operator_profile(prof, ax=ax)
        fig.savefig(plot, dpi=120)
        plt.close(fig)
    out = {"p": lat.p, "q": lat.q, "rings": lat.rings, "function": f.name, "results": rows}
    if args.json:
        print_json(out)
        return 0
    print(f"{{{lat.p},{lat.q}}}, {lat.rings} rings, f = {f.name}, {int(ang.full.sum())} fully coordinated sites")
    print(f"  {'h':>10} {'max|A_h f - A2 f|':>18} {'max|A_h f - A3 f|':>18}")
    for r in rows:
        print(f"  {r['h']:10.6f} {r['max_error_quadratic']:18.3e} {r['max_error_cubic']:18.3e}")
    return 0


def _convergence(args) -> int:
    if not 0 < args.h_min < args.h_max:
        raise ValueError("need 0 < --h-min < --h-max.")
    if args.points < 3:
        raise ValueError("need at least 3 --points for a fit.")
    if args.points > MAX_H_VALUES:  # 1e8 points ran for hours
        raise ValueError(f"--points must be at most {MAX_H_VALUES} (a fit needs about ten), got {args.points}.")
    lat = ring_lattice(args.p, args.q, args.rings)
    f = SmoothFunction.preset(args.function)
    st = convergence_study(lat, f, np.geomspace(args.h_min, args.h_max, args.points))
    if args.json:
        print_json({**st.summary(), "rings": lat.rings})
        return 0
    print(f"{{{lat.p},{lat.q}}}, {lat.rings} rings, f = {f.name}, h in [{args.h_min:g}, {args.h_max:g}]")
    print(f"  {'order':>5} {'fitted power':>13} {'expected':>9}")
    for k in st.errors:
        print(f"  {k:>5} {st.exponents[k]:13.3f} {st.expected[k]:9d}")
    return 0


def _counting(args) -> int:
    plot = _plot_path(args)
    if args.slope is not None:
        _validate.real("--slope", args.slope, minimum=-MAX_SLOPE, maximum=MAX_SLOPE)
    lat = ring_lattice(args.p, args.q, args.rings)
    fit = fit_counting(lat, slope=args.slope, window=args.window)
    if plot:
        from ..plots.scaling import plot_counting
        _save(plot_counting(lat), plot)
    if args.json:
        print_json(fit.summary())
        return 0
    kind = "fixed" if fit.slope_fixed else "fitted"
    print(f"{{{lat.p},{lat.q}}}, {lat.rings} rings: N(r) ~ s rho + b over {fit.radii.size} distinct radii ({args.window})")
    print(f"  s = {fit.slope:.4f} ({kind}; pi/(2A) = {fit.expected_slope:.4f}),  b = {fit.intercept:.4f},  rms = {fit.rms:.3f}")
    return 0


def _sums(args) -> int:
    _count("--rings", args.rings, MAX_LIST)
    _count("--function", args.function, MAX_LIST)
    funcs = [SmoothFunction.preset(name) for name in args.function]
    rows = []
    for rings in args.rings:
        lat = ring_lattice(args.p, args.q, rings)
        for f in funcs:
            rows.append(sum_check(lat, f).summary())
    if args.json:
        print_json(rows)
        return 0
    print(f"{'rings':>5} {'sites':>8} {'L':>10} {'function':>16} {'lattice sum':>14} {'integral/A':>14} {'rel. error':>11}")
    for r in rows:
        ls, it = r["lattice_sum"], r["integral"]
        ls = ls if isinstance(ls, float) else complex(ls["re"], ls["im"]).real
        it = it if isinstance(it, float) else complex(it["re"], it["im"]).real
        print(f"{r['rings']:5d} {r['sites']:8d} {r['radius']:10.7f} {r['function']:>16} {ls:14.6f} {it:14.6f} {r['rel_error']:11.2e}")
    return 0


_TASKS = {"angles": _angles, "operator": _operator, "convergence": _convergence,
          "counting": _counting, "sums": _sums}


def run(args: argparse.Namespace) -> int:
    return _TASKS[args.task](args)


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
