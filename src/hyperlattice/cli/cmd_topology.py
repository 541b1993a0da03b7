"""``hyperlattice topology``: Chern invariants of QWZ, Haldane and Kane–Mele models.

Tasks:

* ``flake``    a {p,q} flake: the hyperbolic local marker at the centre and by ring, Kitaev's sum,
               the Bott index and the bulk gap at the centre (dense up to 9,000 rows; above, the
               centre marker by a Chebyshev expansion of the projector, Bott omitted); for
               kane-mele (any ``--rashba``) also ``z2``, ``spin_bott`` and ``spin_gap`` (the gap
               of P s_z P); ``--frame transport`` for qwz in the parallel-transport frame
* ``cluster``  a periodic cluster: the first Chern numbers C_ij of the Abelian bands on every
               2-subtorus, their gcd and Pfaffian, the smallest gap on the grid; with
               ``--chern2`` the second Chern numbers on the 4-subtori, with ``--spin-chern``
               (kane-mele) the spin Chern numbers and the Z2 index, with ``--z2`` (kane-mele,
               any ``--rashba``) the Z2 index of every time-reversal-symmetric 2-subtorus by
               Wilson loops, with ``--frame covariant`` (qwz) the rotation-system frame with the
               spin connection; ``--filling`` or ``--fermi-level`` away from half filling;
               ``--model dirac4 --cluster one-site -p 8 -q 8`` the four-band Dirac model on the
               {8,8} map with one site (second Chern numbers)
* ``landau``   a periodic cluster in a field of N_phi flux quanta: the lowest Landau bands,
               their Chern matrices against the continuum (degeneracy, energy, intersection form)
* ``conductance``  a {p,q} flake between two wide-band leads on two arcs of its edge: the two-terminal
               conductance (Landauer–Caroli) at the given energies, in units of e^2/h
"""

from __future__ import annotations

import argparse

import numpy as np

from .. import _validate
from ._common import add_pq, cluster_pq, finite_float, positive_int, print_json

FRAMES = ("chord", "tangent", "transport")

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


#: models of ``topology cluster``: the flake models and the {8,8} Dirac model (hyperlattice.topology.dartmaps)
_CLUSTER_MODELS = _MODELS + ("dirac4",)


def _model_flags(parser, *, disorder: bool, models=_MODELS) -> None:
    parser.add_argument("--model", choices=models, default="qwz", help="the model (default qwz)")
    add_pq(parser, default_p=8)
    parser.add_argument("--M", type=finite_float, default=1.0,
                        help="QWZ mass, or Haldane / Kane-Mele sublattice mass (default 1)")
    parser.add_argument("--t2", type=finite_float, default=0.2,
                        help="Haldane / Kane-Mele second-neighbour amplitude (default 0.2)")
    parser.add_argument("--phi", type=finite_float, default=float(np.pi / 2),
                        help="Haldane phase in radians (default pi/2)")
    parser.add_argument("--rashba", type=finite_float, default=0.0,
                        help="Kane-Mele Rashba coupling lambda_R (default 0)")
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
    f.add_argument("--frame", choices=FRAMES, default="chord",
                   help="qwz bond frame: the chord angle (default), the geodesic tangent at the lower-numbered "
                        "end, or the chart frame with the Levi-Civita connection (parallel transport)")
    f.add_argument("--fermi", type=finite_float, default=None,
                   help="Fermi level in units of t (default: half filling)")
    c = sub.add_parser("cluster", help="Chern numbers C_ij on all 2-subtori of a periodic cluster")
    _model_flags(c, disorder=False, models=_CLUSTER_MODELS)
    c.add_argument("--cluster", required=True, help="a cluster name (hyperlattice cluster --list), e.g. bolza; "
                   "for dirac4 one-site or two-site ({8,8} maps)")
    fill = c.add_mutually_exclusive_group()
    fill.add_argument("--filling", type=_fraction, default=None,
                      help="fraction of the bands occupied, e.g. 5/16 (default one half)")
    fill.add_argument("--fermi-level", type=finite_float, default=None,
                      help="Fermi level (units of t): the bands below it are occupied; checked to lie in a gap "
                           "on every grid")
    c.add_argument("--frame", choices=("lift", "covariant"), default="lift",
                   help="qwz bond frame: the disk lift of the cluster (default) or the rotation-system frame "
                        "with the spin connection (labelling independent)")
    c.add_argument("--chern2", action="store_true",
                   help="also the second Chern numbers on every 4-subtorus (genus >= 2; tens of seconds)")
    c.add_argument("--spin-chern", action="store_true",
                   help="kane-mele only: spin Chern numbers (C_up - C_down)/2 and the Z2 index per 2-subtorus")
    c.add_argument("--z2", action="store_true",
                   help="kane-mele only: the Z2 index on every time-reversal-symmetric 2-subtorus by Wilson loops "
                        "(with or without --rashba)")
    la = sub.add_parser("landau", help="Landau bands of a cluster in a field and their Chern numbers")
    add_pq(la, default_p=7)
    la.add_argument("--cluster", required=True, help="a cluster name (hyperlattice cluster --list), e.g. klein")
    la.add_argument("--nphi", type=positive_int, required=True, help="total flux quanta through the cluster")
    la.add_argument("--levels", type=positive_int, default=1, help="lowest band groups to report (default 1)")
    la.add_argument("--json", action="store_true", help="print JSON")
    g = sub.add_parser("conductance", help="two-terminal conductance (e^2/h) of a flake through leads on its edge")
    _model_flags(g, disorder=True)
    g.add_argument("--rings", type=positive_int, default=3, help="rings of the flake (default 3)")
    g.add_argument("--energies", type=_float_list, default=[0.0],
                   help="comma-separated energies in units of t (default 0)")
    g.add_argument("--coupling", type=finite_float, default=2.0,
                   help="wide-band lead coupling gamma per contact orbital, units of t (default 2)")
    g.add_argument("--arc", type=finite_float, default=0.25,
                   help="fraction of the full turn each contact spans on the outer edge (default 0.25)")


def _fraction(text: str) -> float:
    from fractions import Fraction

    try:
        v = float(Fraction(text.strip()))
    except (ValueError, ZeroDivisionError, OverflowError):
        raise argparse.ArgumentTypeError(f"expected a fraction such as 5/16 or 0.3125, got {text!r}") from None
    if not 0.0 < v < 1.0:
        raise argparse.ArgumentTypeError(f"a filling lies strictly between 0 and 1, got {text!r}")
    return v


def _occupied_from_filling(filling, rows: int):
    """Bands below the Fermi level for a filling, which must be a whole number of the rows bands."""
    if filling is None:
        return None
    occ = filling * rows
    if abs(occ - round(occ)) > 1e-9 * rows or not 1 <= round(occ) <= rows - 1:
        raise ValueError(f"--filling {filling:g} of {rows} bands is not a whole number of bands between 1 and "
                         f"{rows - 1}.")
    return int(round(occ))


def _dirac4_cluster(args) -> int:
    from ..topology.closed import second_chern
    from ..topology.dartmaps import dirac4_terms, named_dart_map
    from ..topology.surfaces import _all_subtori, _pf

    from ._common import DefaultInt

    p = 8 if isinstance(args.p, DefaultInt) else int(args.p)
    q = 8 if isinstance(args.q, DefaultInt) else int(args.q)
    if (p, q) != (8, 8):
        raise ValueError(f"the dirac4 model lives on {{8,8}} maps: give -p 8 -q 8 (got -p {args.p} -q {args.q}).")
    if args.spin_chern or args.frame != "lift":
        raise ValueError("--spin-chern and --frame apply to the flake models, not to dirac4.")
    if args.z2 or args.rashba != 0.0:
        raise ValueError("--z2 and --rashba belong to --model kane-mele, not to dirac4.")
    mp = named_dart_map(args.cluster)
    terms = dirac4_terms(mp, args.M)
    rows = terms.sites * terms.orbitals
    occ = _occupied_from_filling(args.filling, rows)
    if args.fermi_level is not None:
        from ..topology.models import bloch_model_hamiltonian

        e0 = np.linalg.eigvalsh(bloch_model_hamiltonian(terms, np.zeros((1, terms.windings.shape[1])))[0])
        occ = int(np.count_nonzero(e0 < args.fermi_level))
        if occ in (0, rows):
            raise ValueError(f"the Fermi level {args.fermi_level:g} is outside the spectrum at k = 0.")
    occ = rows // 2 if occ is None else occ
    g2 = terms.windings.shape[1]
    raw = np.zeros((g2, g2))
    gaps, edges = [], []
    n = _all_subtori(terms, g2, occ, 12, 96, raw, gaps, [], edges)
    window = (max(x for x, _ in edges), min(y for _, y in edges))
    if args.fermi_level is not None and not window[0] < args.fermi_level < window[1]:
        raise ValueError(f"the Fermi level {args.fermi_level:g} lies in a band on the grids "
                         f"[{window[0]:.4g}, {window[1]:.4g}].")
    chern = np.rint(raw).astype(np.int64)
    vals = [abs(int(x)) for x in chern[np.triu_indices(g2, 1)]]
    import math

    out = {"model": "dirac4", "cluster": mp.name, "genus": mp.genus, "sites": mp.sites, "chern": chern.tolist(),
           "gcd": math.gcd(*vals), "pfaffian": int(round(_pf(chern.astype(float)))), "gap": float(min(gaps)),
           "grid": n, "occupied": occ, "fermi_window": list(window), "fermi_level": args.fermi_level,
           "parameters": {"m": args.M}}
    extra = []
    if args.chern2:
        c2 = second_chern(terms, occupied=occ, grid=8, max_grid=24, tol=0.01)
        out.update(c2.summary() | {"model": "dirac4", "cluster": mp.name, "genus": mp.genus, "occupied": occ})
        extra.append(f"  second Chern numbers on the 4-subtori {c2.subtori.tolist()}: {c2.chern2.tolist()} "
                     f"(Pf of C there {c2.pfaffian.tolist()}, grid {c2.grid.tolist()}, error {max(c2.error):.1e}, "
                     f"smallest gap {c2.gap:.4g})")
    if args.json:
        print_json(out)
        return 0
    print(f"{{8,8}} map {mp.name} ({mp.sites} site(s), genus {mp.genus}), model dirac4, m = {args.M:g}, "
          f"{occ} of {rows} bands occupied, grid {n} x {n}")
    _print_chern(out["chern"], out["gcd"], out["pfaffian"], out["gap"])
    for line in extra:
        print(line)
    return 0


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
                             rashba=args.rashba, disorder=W, seed=args.seed, fermi=args.fermi, frame=args.frame)
        out = res.summary()
    else:
        from ..topology.kpm_marker import centre_marker

        if args.rashba != 0.0 or args.frame != "chord":
            raise ValueError(f"above {MAX_DENSE_ROWS:,} rows the Chebyshev route supports neither --rashba nor "
                             "--frame; use fewer --rings.")
        res = centre_marker(ring_lattice(p, q, rings), args.model, M=args.M, t2=args.t2, phi=args.phi,
                            disorder=W, seed=args.seed, fermi=0.0 if args.fermi is None else args.fermi)
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
    if out.get("spin_gap") is not None:
        print(f"  Z2 {out['z2']} (spin Chern marker mod 2), spin Bott {out['spin_bott']:+.4f}, "
              f"gap of P s_z P {out['spin_gap']:.4g}")
    return 0


def _print_chern(chern, gcd, pfaffian, gap) -> None:
    """The Chern matrix, one row a line, then its gcd, Pfaffian and the smallest gap on the grid."""
    for row in chern:
        print("  " + " ".join(f"{x:+d}" for x in row))
    print(f"  gcd {gcd}, Pfaffian {pfaffian}, smallest gap on the grid {gap:.4g}")


def _cluster(args) -> int:
    from ..graph.clusters import pbc_cluster
    from ..topology.surfaces import cluster_chern

    if args.model == "dirac4":
        return _dirac4_cluster(args)
    name = args.cluster
    p, q = cluster_pq(args, name)
    cl = pbc_cluster(p, q, name)
    if (args.filling is not None or args.fermi_level is not None) and (args.frame != "lift" or args.spin_chern):
        raise ValueError("--filling and --fermi-level apply to the Chern numbers of the default frame, without "
                         "--frame covariant or --spin-chern.")
    if args.spin_chern and args.model != "kane-mele":
        raise ValueError("--spin-chern needs --model kane-mele.")
    if args.z2 and args.model != "kane-mele":
        raise ValueError("--z2 needs --model kane-mele.")
    if args.rashba != 0.0 and args.model != "kane-mele":
        raise ValueError("--rashba belongs to --model kane-mele.")
    if args.spin_chern and args.rashba != 0.0:
        raise ValueError("--spin-chern needs s_z conserved (--rashba 0); the Z2 index with Rashba is --z2.")
    if args.spin_chern and args.z2:
        raise ValueError("--spin-chern and --z2 both report z2: choose one.")
    if args.frame == "covariant":
        if args.model != "qwz":
            raise ValueError("--frame covariant applies to the qwz model.")
        if args.chern2:
            raise ValueError("--chern2 is computed in the default frame; drop --frame covariant.")
        from ..topology.frames import frame_invariants, qwz_frame_terms

        inv = frame_invariants(qwz_frame_terms(cl, M=args.M))
        out = {"model": "qwz", "cluster": cl.name, "genus": cl.genus, "frame": "covariant", "chern": inv["chern"],
               "gcd": inv["gcd"], "pfaffian": inv["pfaffian"], "gap": inv["gap"], "grid": inv["grid"],
               "occupied": cl.sites, "parameters": {"M": args.M}}
        if args.json:
            print_json(out)
            return 0
        print(f"{{{p},{q}}} cluster {cl.name} (genus {cl.genus}), model qwz (covariant frame), "
              f"grid {inv['grid']} x {inv['grid']}")
        _print_chern(inv["chern"], inv["gcd"], inv["pfaffian"], inv["gap"])
        return 0
    from ..topology.models import orbitals

    occ = _occupied_from_filling(args.filling, cl.sites * orbitals(args.model))
    res = cluster_chern(cl, args.model, M=args.M, t2=args.t2, phi=args.phi, rashba=args.rashba, occupied=occ,
                        fermi_level=args.fermi_level)
    out = res.summary()
    extra = []
    if args.z2:
        from ..topology.z2 import z2_index

        zi = z2_index(cl, M=args.M, t2=args.t2, phi=args.phi, rashba=args.rashba)
        out.update(zi.summary())
        extra.append(f"  Z2 {zi.z2.tolist()} on the subtori {zi.subtori.tolist()} (other momenta / pi: "
                     f"{zi.fixed.tolist()}), gap {zi.gap:.4g}, grid {zi.grid}")
    if args.chern2:
        from ..topology.closed import second_chern

        c2 = second_chern(cl, args.model, M=args.M, t2=args.t2, phi=args.phi, grid=4, occupied=res.occupied)
        out.update(c2.summary() | {"model": out["model"], "cluster": out["cluster"], "genus": out["genus"],
                                   "occupied": out["occupied"]})
        extra.append(f"  second Chern numbers on the 4-subtori {c2.subtori.tolist()}: {c2.chern2.tolist()} "
                     f"(Pf of C there {c2.pfaffian.tolist()}, c2 {c2.c2.tolist()}, grid {c2.grid.tolist()}, "
                     f"error {max(c2.error):.1e})")
    if args.spin_chern:
        from ..topology.closed import spin_chern

        sc = spin_chern(cl, M=args.M, t2=args.t2, phi=args.phi)
        out.update(sc.summary() | {"cluster": out["cluster"], "genus": out["genus"]})
        extra.append(f"  spin Chern numbers {sc.spin_chern.tolist()}, Z2 {sc.z2.tolist()}")
    if args.json:
        print_json(out)
        return 0
    print(f"{{{p},{q}}} cluster {cl.name} (genus {cl.genus}), model {args.model}, grid {res.grid} x {res.grid}, "
          f"{res.occupied} bands occupied (between {res.fermi_window[0]:.4g} and {res.fermi_window[1]:.4g})")
    _print_chern(res.chern.tolist(), res.gcd, res.pfaffian, res.gap)
    for line in extra:
        print(line)
    return 0


def _landau(args) -> int:
    from ..graph.clusters import pbc_cluster
    from ..topology.landau import landau_bands

    name = args.cluster
    p, q = cluster_pq(args, name)
    cl = pbc_cluster(p, q, name)
    res = landau_bands(cl, args.nphi, levels=args.levels)
    out = res.summary()
    if args.json:
        print_json(out)
        return 0
    print(f"{{{p},{q}}} cluster {cl.name} (genus {cl.genus}, {res.faces} faces), N_phi = {res.n_phi} "
          f"(flux {res.flux:.4g} per p-gon, B = {res.field:.4g})")
    print("  level  bands  continuum D_N  lattice E range      continuum E_N  gcd  Pf  C = +-Q")
    for i in range(len(res.level)):
        print(f"  {res.level[i]:5d}  {res.bands[i]:5d}  {res.degeneracy[i]:13d}  "
              f"[{res.energy_min[i]:+.4f}, {res.energy_max[i]:+.4f}]  {res.energy_continuum[i]:+13.4f}  "
              f"{res.gcd[i]:3d}  {res.pfaffian[i]:+d}  {bool(res.matches[i])}")
    return 0


def _conductance(args) -> int:
    from ..graph.lattice import ring_lattice
    from ..topology.transport import conductance

    p, q = _validate.pq(args.p, args.q)
    rings = _validate.integer("--rings", args.rings, minimum=1, maximum=12)
    W = _validate.real("--disorder", args.disorder, minimum=0.0, maximum=1e6)
    res = conductance(ring_lattice(p, q, rings), args.model, energies=args.energies, M=args.M, t2=args.t2,
                      phi=args.phi, rashba=args.rashba, disorder=W, seed=args.seed, coupling=args.coupling, arc=args.arc)
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
    return {"flake": _flake, "cluster": _cluster, "landau": _landau, "conductance": _conductance}[args.task](args)


from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
