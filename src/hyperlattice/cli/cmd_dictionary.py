"""``hyperlattice dictionary``: continuum parameters (t', mu', U') of a lattice Bose-Hubbard model."""

from __future__ import annotations

from ..dictionary import continuum_parameters, lattice_parameters
from ._common import add_pq, finite_float, print_json

NAME = "dictionary"
ORDER = 60
HELP = "map lattice (t, mu, U) on {p,q} to the continuum (t', mu', U') of Eqs. (11)-(12), or back"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    add_pq(parser)
    parser.add_argument("--t", type=finite_float, default=1.0, help="hopping t (default 1)")
    parser.add_argument("--mu", type=finite_float, default=0.0, help="chemical potential mu (default 0)")
    parser.add_argument("--U", type=finite_float, default=0.0, help="on-site interaction U (default 0)")
    parser.add_argument("--inverse", action="store_true",
                        help="read --t/--mu/--U as the continuum t', mu', U' and return the lattice values")
    parser.add_argument("--json", action="store_true", help="print JSON")


def run(args: argparse.Namespace) -> int:
    fn = lattice_parameters if args.inverse else continuum_parameters
    c = fn(args.t, args.mu, args.U, args.p, args.q)
    if args.json:
        print_json(c.summary())
        return 0
    print(f"{{{c.p},{c.q}}}: h = tanh(d0) = {c.h:.6f}, area per site A = {c.site_area:.6f}")
    print(f"  lattice:   t  = {c.t:.10g}   mu  = {c.mu:.10g}   U  = {c.U:.10g}")
    print(f"  continuum: t' = {c.t_prime:.10g}   mu' = {c.mu_prime:.10g}   U' = {c.U_prime:.10g}")
    print("  (t' = (q/4) h^2 t, mu' = mu + q t, U' = A U)")
    print(f"  field: alpha(z_i) = {c.field_scale:.10g} a_i   (= a_i / sqrt(A))")
    return 0


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
