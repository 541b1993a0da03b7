"""``hyperlattice spins classical``: the classical Ising, XY or Heisenberg model by Monte Carlo on a
flake, its line graph, a periodic cluster or a graph of your own.

Contract: ``--json`` prints one object whose first keys are ``sites``, then ``e, c, m, m2, m_abs, U4,
chi`` and the staggered ``m2_s, m_abs_s, U4_s, chi_s`` (null off bipartite graphs), each followed by
its ``_err``, then ``tau_int`` (sweeps, by observable) and ``update`` (the update that ran), then the
rest of :meth:`hyperlattice.spins.ClassicalResult.summary` (``update_reason``, the parameters,
``seed``, ``bins``, ``converged``, ``rings`` on flakes, ``notes``).
"""

from __future__ import annotations

import argparse

from ._chain_args import add_chain, add_graph, graph, show
from ._common import Interrupted, finite_float, positive_int, print_json

NAME = "classical"
ORDER = 10
HELP = "classical Ising / XY / Heisenberg Monte Carlo: energy, specific heat, magnetisation, Binder cumulant"
DESCRIPTION = ("Thermal averages of H = -sum<ij> J_ij s_i.s_j - h sum_i s_i^z (k_B = 1) for unit spins of 1 "
               "(ising), 2 (xy) or 3 (heisenberg) components, by Wolff clusters where they apply (h = 0, "
               "couplings a gauge makes ferromagnetic: ferromagnets, antiferromagnets on bipartite graphs) and "
               "heat-bath with over-relaxation otherwise; the update that ran is stated. Per site: e, c, m, m2, "
               "m_abs, U4, chi = beta N <|m|^2> (and the staggered versions on bipartite graphs), each with a "
               "binning error, and tau_int.")


def _positive(text: str) -> float:
    v = finite_float(text)
    if not v > 0:
        raise argparse.ArgumentTypeError(f"expected a number > 0, got {text!r}")
    return v


def _temperatures(text: str) -> list:
    parts = [t for t in text.replace(" ", "").split(",") if t]
    if len(parts) < 2:
        raise argparse.ArgumentTypeError(f"expected at least two temperatures separated by commas, got {text!r}")
    return [_positive(t) for t in parts]


def _model(text: str) -> str:
    v = text.strip().lower()
    if v not in ("ising", "xy", "heisenberg"):
        raise argparse.ArgumentTypeError(f"unknown model {text!r}; choose ising, xy or heisenberg")
    return v


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--model", type=_model, required=True, help="ising, xy or heisenberg")
    add_graph(parser, "a periodic cluster, e.g. bolza or klein (its p and q unless -p/-q are given)",
              "a graph of your own: a symmetric matrix of couplings A_ij (J_ij = J A_ij), .npz written by "
              "scipy.sparse.save_npz or a dense .npy; -p/-q unused")
    parser.add_argument("--line-graph", action="store_true", help="with --rings: the flake's line graph")
    parser.add_argument("--J", type=finite_float, default=1.0, help="coupling J (default 1; J < 0 antiferromagnet)")
    parser.add_argument("--h", type=finite_float, default=0.0, help="field h along s^z (default 0)")
    temp = parser.add_mutually_exclusive_group(required=True)
    temp.add_argument("--beta", type=_positive, help="inverse temperature (k_B = 1)")
    temp.add_argument("--T", type=_positive, help="temperature (k_B = 1)")
    temp.add_argument("--tempering", type=_temperatures, metavar="T1,T2,...",
                      help="parallel tempering over these temperatures (at least two; for frustrated or glassy "
                           "couplings): one chain per temperature, neighbours exchange configurations every "
                           "--exchange-every sweeps; the JSON holds the acceptance rates and one object of the "
                           "keys below per temperature")
    parser.add_argument("--update", choices=("auto", "wolff", "swendsen-wang", "local"), default="auto",
                        help="auto (default: Wolff where it applies), wolff, swendsen-wang, or local (heat-bath + "
                             "over-relaxation)")
    parser.add_argument("--exchange-every", type=positive_int, default=1, metavar="N",
                        help="with --tempering: sweeps between exchange attempts (default 1)")
    add_chain(parser, sweeps_default=10000, thermalization="max(100, sweeps/10)",
              saved=" (with --tempering: every chain), at the end and when interrupted",
              resume="more --sweeps allowed")
    parser.add_argument("--no-correlation", action="store_true",
                        help="do not measure the spin correlation by distance (measured up to 3000 sites)")
    parser.add_argument("--json", action="store_true",
                        help="print JSON: sites, e, c, m, m2, m_abs, U4, chi (and staggered) with _err, tau_int, "
                             "update first, then the parameters, seed, bins, converged, rings and notes")


def add_parser(subparsers) -> argparse.ArgumentParser:
    """Add ``classical`` to the ``spins`` subcommands (the other protocol ``cmd_spins`` accepts)."""
    p = subparsers.add_parser(NAME, help=HELP, description=DESCRIPTION)
    add_arguments(p)
    p.set_defaults(_spins_run=run)
    return p


#: the contract's keys, first in the JSON object, in this order
KEYS = ("sites", "e", "e_err", "c", "c_err", "m", "m_err", "m2", "m2_err", "m_abs", "m_abs_err", "U4", "U4_err",
        "chi", "chi_err", "m2_s", "m2_s_err", "m_abs_s", "m_abs_s_err", "U4_s", "U4_s_err", "chi_s", "chi_s_err",
        "tau_int", "update")


def run(args: argparse.Namespace) -> int:
    from .. import _validate
    from ..spins import classical_mc, tempering_mc

    tempering = args.tempering is not None
    if not tempering and args.exchange_every != 1:
        raise ValueError("--exchange-every needs --tempering.")
    checkpoint = None if args.checkpoint is None else _validate.directory("--checkpoint", args.checkpoint)
    system = graph(args, args.line_graph)
    common = dict(model=args.model, J=args.J, h=args.h, sweeps=args.sweeps, thermalization=args.thermalization,
                  seed=args.seed, update=args.update, checkpoint=checkpoint,
                  measure_correlation=False if args.no_correlation else None)
    kept = "chains are" if tempering else "chain is"
    try:
        if tempering:
            res = tempering_mc(system, T=args.tempering, exchange_every=args.exchange_every, **common)
        else:
            res = classical_mc(system, beta=args.beta, T=args.T, **common)
    except KeyboardInterrupt:
        if checkpoint is None:
            raise Interrupted(f"nothing kept (--checkpoint DIR keeps the {kept.split()[0]} for a rerun)") from None
        raise Interrupted(f"the {kept} saved in {str(checkpoint)!r}; rerun the same command to resume") from None
    if tempering:
        return _show_tempering(res, args.json)
    return show(res, KEYS, args.json, before=[f"  update: {res.update} ({res.update_reason})"])


def _show_tempering(res, as_json: bool) -> int:
    if as_json:
        summary = res.summary()
        temps = []
        for one in summary.pop("temperatures"):
            row = {k: one[k] for k in KEYS}
            row.update((k, v) for k, v in one.items() if k not in row)
            temps.append(row)
        summary["temperatures"] = temps
        print_json(summary)
        return 0
    print(str(res))
    print(f"  seed {res.seed}, {res.seconds:.1f} s")
    return 0


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
