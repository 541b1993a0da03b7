"""``hyperlattice device <what>``: what an experiment measures on a device.

``transmission``: the scattering matrix S(ω) of a resonator lattice with ports (input–output
theory), ideal or with fabrication disorder. JSON keys: ``omega``, ``s_re``, ``s_im`` (each
[frequency][out port][in port]), ``resonators`` (names in the order used), ``flat_band_degeneracy``
(with ``--line-graph``: the multiplicity of the eigenvalue −2 of the line graph's adjacency; null
otherwise), then ``ports``, ``method``, ``error_bound``.

``impedance``: the two-point impedance Z_ab (``--between A B``) or the impedance to ground Z_a
(``--to-ground A``) of a circuit with ``--edge SPEC`` on every edge and ``--ground SPEC`` from every
node (SPEC ``C:1``, ``L:1,R:100``: parallel elements). JSON keys ``omega``, ``z_re``, ``z_im``, then
``nodes``, ``kind``, ``resonances`` (of the lossless LC parts), ``method``.

``fit``: least squares of ω₀, J, κ_int (ports' κ given) to a measured ``|S21|`` (``--measured`` CSV,
header ``omega,mag_db`` or ``omega,re,im``). JSON keys ``omega0``, ``J``, ``kappa_int`` and their
``_err``, then ``supported`` (parameters the trace determines), ``condition``, ``singular_values``,
``residual_rms``, ``ports``, ``statement``.
"""

from __future__ import annotations

import argparse
import json
import math

import numpy as np

from ._chain_args import seed as _seed
from ._common import add_pq, finite_float, plot_file, positive_int, print_json

NAME = "device"
ORDER = 56
HELP = "what an experiment measures: transmission S21 of a resonator lattice, impedance of a circuit"

#: most frequencies of an --omega-min/--omega-max grid or an --omegas file
MAX_POINTS = 10_000_000


def _port(text: str) -> tuple[str, float]:
    name, sep, kappa = text.rpartition(":")
    if not sep or not name.strip():
        raise argparse.ArgumentTypeError(f"expected RES:KAPPA such as 0-1:0.5 or 3:0.5, got {text!r}")
    try:
        k = float(kappa)
    except ValueError:
        raise argparse.ArgumentTypeError(f"the kappa of port {text!r} is not a number") from None
    if not math.isfinite(k) or not k > 0:
        raise argparse.ArgumentTypeError(f"the kappa of port {text!r} must be a positive number")
    return name.strip(), k


def _nonneg(text: str) -> float:
    v = finite_float(text)
    if v < 0:
        raise argparse.ArgumentTypeError(f"expected a number >= 0, got {text!r}")
    return v


def add_geometry(parser: argparse.ArgumentParser) -> None:
    """The graph of the device: a flake, a cluster or an adjacency file, and ``--line-graph``."""
    where = parser.add_mutually_exclusive_group(required=True)
    where.add_argument("--rings", type=positive_int, help="a {p,q} flake of this many rings")
    where.add_argument("--cluster", metavar="NAME", help="a periodic cluster, e.g. bolza or klein")
    where.add_argument("--adjacency", metavar="FILE",
                       help="a graph of your own: a symmetric adjacency matrix (.npz of scipy.sparse.save_npz or .npy)")
    add_pq(parser)
    parser.add_argument("--line-graph", action="store_true",
                        help="resonators on the edges of the graph (named i-j, i < j), the circuit layout")


def add_frequencies(parser: argparse.ArgumentParser) -> None:
    """``--omegas FILE`` or ``--omega-min A --omega-max B --points N``."""
    grid = parser.add_mutually_exclusive_group(required=True)
    grid.add_argument("--omegas", metavar="FILE", help="frequencies: a JSON list or one number a line")
    grid.add_argument("--omega-min", type=finite_float, metavar="A", help="lowest frequency of a uniform grid")
    parser.add_argument("--omega-max", type=finite_float, metavar="B", help="highest frequency of the grid")
    parser.add_argument("--points", type=positive_int, metavar="N", help="points of the grid")


def omegas(args: argparse.Namespace) -> np.ndarray:
    """The frequencies the command sweeps (checked: finite, at most :data:`MAX_POINTS`)."""
    from .. import _validate

    if args.omegas is not None:
        path = _validate.input_path("--omegas", args.omegas)
        try:
            text = path.read_text(encoding="utf-8")
        except (OSError, UnicodeDecodeError) as exc:
            raise ValueError(f"--omegas {str(path)!r} cannot be read: {_validate.file_problem(exc)}.") from None
        try:
            data = json.loads(text)
        except json.JSONDecodeError:
            data = None
        if isinstance(data, list):
            if not all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in data):
                raise ValueError(f"--omegas {str(path)!r} must be a JSON list of numbers.")
            vals = [float(v) for v in data]
        else:
            vals = []
            for k, line in enumerate(text.splitlines(), 1):
                if line.strip():
                    try:
                        vals.append(float(line))
                    except ValueError:
                        raise ValueError(f"--omegas {str(path)!r} line {k} is not a number: "
                                         f"{line.strip()[:30]!r}.") from None
        w = np.asarray(vals, float)
        if w.size == 0:
            raise ValueError(f"--omegas {str(path)!r} holds no frequencies.")
        if not np.all(np.isfinite(w)):
            raise ValueError(f"--omegas {str(path)!r} holds NaN or infinite frequencies.")
        if w.size > MAX_POINTS:
            raise ValueError(f"--omegas {str(path)!r} holds {w.size:,} frequencies, more than {MAX_POINTS:,}.")
        return w
    if args.omega_max is None or args.points is None:
        raise ValueError("--omega-min needs --omega-max and --points.")
    if not args.omega_max > args.omega_min:
        raise ValueError(f"--omega-max {args.omega_max:g} must exceed --omega-min {args.omega_min:g}.")
    if args.points > MAX_POINTS:
        raise ValueError(f"--points {args.points:,} is more than {MAX_POINTS:,}.")
    return np.linspace(args.omega_min, args.omega_max, args.points)


def graph(args: argparse.Namespace):
    """The graph of ``--rings``/``--cluster``/``--adjacency`` (the loaders of ``bosons qmc``)."""
    from ._chain_args import graph as _system

    return _system(args)


def _json_object(flag: str, value) -> dict:
    from .. import _validate

    path = _validate.input_path(flag, value, suffixes=(".json",))
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise ValueError(f"{flag} {str(path)!r} is not a JSON file: {_validate.file_problem(exc)}.") from None
    if not isinstance(data, dict):
        raise ValueError(f"{flag} {str(path)!r} must hold a JSON object mapping names to numbers.")
    for k, v in data.items():
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
            raise ValueError(f"{flag} {str(path)!r}: the value of {k!r} must be a finite number, got {v!r}.")
    return data


def _add_transmission(p: argparse.ArgumentParser) -> None:
    add_geometry(p)
    p.add_argument("--omega0", type=finite_float, default=0.0, metavar="W", help="bare resonator frequency (default 0)")
    p.add_argument("--J", type=finite_float, default=1.0, help="coupling J, H_kl = -J (default 1; -66 for the "
                                                                 "Kollar device in MHz)")
    p.add_argument("--kappa-int", type=_nonneg, required=True, metavar="K", help="internal loss rate of every "
                                                                                  "resonator (FWHM, >= 0)")
    p.add_argument("--port", type=_port, action="append", required=True, metavar="RES:KAPPA",
                   help="a port on resonator RES (i-j with --line-graph, else a site i) at rate KAPPA; repeat")
    add_frequencies(p)
    p.add_argument("--frequencies", metavar="FILE.json", help="explicit resonator frequencies by name")
    p.add_argument("--hoppings", metavar="FILE.json", help="explicit couplings by name 'a|b'")
    p.add_argument("--sigma-omega", type=_nonneg, default=0.0, metavar="S", help="Gaussian frequency disorder")
    p.add_argument("--sigma-J", type=_nonneg, default=0.0, metavar="S", help="relative Gaussian coupling disorder")
    p.add_argument("--seed", type=_seed, default=None, help="seed of the drawn disorder")
    p.add_argument("--plot", metavar="FILE", help="figure of |S21|^2 (PNG, PDF, SVG...)")
    p.add_argument("--json", action="store_true", help="print JSON: omega, s_re, s_im, resonators, "
                                                       "flat_band_degeneracy, ports, method, error_bound")


def _run_transmission(args: argparse.Namespace) -> int:
    from ..device import resonator_device, transmission

    out = plot_file("--plot", args.plot) if args.plot is not None else None
    w = omegas(args)
    freq = _json_object("--frequencies", args.frequencies) if args.frequencies is not None else None
    hop = _json_object("--hoppings", args.hoppings) if args.hoppings is not None else None
    drawn = args.sigma_omega > 0 or args.sigma_J > 0
    if drawn and args.seed is None:
        raise ValueError("--sigma-omega/--sigma-J need --seed N, so that the device can be drawn again.")
    dev = resonator_device(graph(args), line_graph=args.line_graph, omega0=args.omega0, J=args.J,
                           kappa_int=args.kappa_int, ports=list(args.port), frequencies=freq, hoppings=hop,
                           sigma_omega=args.sigma_omega, sigma_J=args.sigma_J, seed=args.seed)
    tr = transmission(dev, w)
    if out is not None:
        import matplotlib

        matplotlib.use("Agg")
        ax = tr.plot()
        ax.figure.savefig(out)
    if args.json:
        s = np.asarray(tr.s)
        print_json({"omega": tr.omega, "s_re": s.real, "s_im": s.imag, "resonators": list(tr.resonators),
                    "flat_band_degeneracy": tr.flat_band, "ports": list(tr.ports), "method": tr.method,
                    "error_bound": tr.error_bound})
        return 0
    print(f"{dev.size} resonators ({dev.description}), ports {', '.join(dev.ports)}; {tr.omega.size} frequencies "
          f"by the {tr.method} route")
    if tr.flat_band is not None:
        print(f"flat band: eigenvalue -2 of the line graph's adjacency, multiplicity {tr.flat_band}")
    k = int(np.argmax(tr.power))
    print(f"largest |S21|^2 = {tr.power[k]:.6g} at omega = {tr.omega[k]:.10g}")
    return 0


def _add_impedance(p: argparse.ArgumentParser) -> None:
    add_geometry(p)
    p.add_argument("--edge", required=True, metavar="SPEC",
                   help="element(s) on every edge, in parallel: C:1, L:1, R:100 or L:1,R:100")
    p.add_argument("--ground", required=True, metavar="SPEC", help="element(s) from every node to ground")
    which = p.add_mutually_exclusive_group(required=True)
    which.add_argument("--between", nargs=2, metavar=("A", "B"), help="two-point impedance Z_AB")
    which.add_argument("--to-ground", metavar="A", help="impedance of node A to ground")
    add_frequencies(p)
    p.add_argument("--json", action="store_true", help="print JSON: omega, z_re, z_im, nodes, kind, resonances")


def _run_impedance(args: argparse.Namespace) -> int:
    from ..device import impedance

    w = omegas(args)
    z = impedance(graph(args), w, edge=args.edge, ground=args.ground,
                  between=tuple(args.between) if args.between is not None else None, to_ground=args.to_ground,
                  line_graph=args.line_graph)
    if args.json:
        print_json({"omega": z.omega, "z_re": z.z_re, "z_im": z.z_im, "nodes": list(z.nodes), "kind": z.kind,
                    "resonances": z.resonances, "method": z.method})
        return 0
    what = f"Z between {z.nodes[0]} and {z.nodes[1]}" if z.kind == "two-point" else f"Z of {z.nodes[0]} to ground"
    print(f"{what} ({z.description}), {z.omega.size} frequencies by the {z.method} route")
    for x, v in list(zip(z.omega, z.z))[:12]:
        print(f"  omega = {x:.8g}: Z = {v.real:.8g} {'+' if v.imag >= 0 else '-'} {abs(v.imag):.8g}i")
    if z.resonances.size:
        print(f"{z.resonances.size} LC resonances from {z.resonances[0]:.6g} to {z.resonances[-1]:.6g}")
    return 0


def _add_fit(p: argparse.ArgumentParser) -> None:
    add_geometry(p)
    p.add_argument("--port", type=_port, action="append", required=True, metavar="RES:KAPPA",
                   help="the input port, then the output port, with their known KAPPA")
    p.add_argument("--measured", required=True, metavar="FILE.csv",
                   help="the measured trace: CSV with header omega,mag_db or omega,re,im")
    p.add_argument("--plot", metavar="FILE", help="figure of the data over the fit")
    p.add_argument("--json", action="store_true", help="print JSON: omega0, J, kappa_int and their _err, supported, "
                                                       "condition, singular_values, residual_rms")


def _run_fit(args: argparse.Namespace) -> int:
    from ..device import fit_transmission, read_trace

    out = plot_file("--plot", args.plot) if args.plot is not None else None
    w, mag = read_trace(args.measured)
    f = fit_transmission(graph(args), w, mag, ports=list(args.port), line_graph=args.line_graph)
    if out is not None:
        import matplotlib

        matplotlib.use("Agg")
        f.plot().figure.savefig(out)
    keys = ("omega0", "omega0_err", "J", "J_err", "kappa_int", "kappa_int_err", "supported", "condition",
            "singular_values", "residual_rms")
    if args.json:
        print_json({k: getattr(f, k) for k in keys} | {"ports": list(f.ports), "statement": f.sentence()})
        return 0
    print(f"omega0 = {f.omega0:.10g} +- {f.omega0_err:.3g}; J = {f.J:.10g} +- {f.J_err:.3g}; "
          f"kappa_int = {f.kappa_int:.6g} +- {f.kappa_int_err:.3g}; rms misfit {f.residual_rms:.3g}")
    print(f.sentence())
    return 0


_SUB = {
    "transmission": (_add_transmission, _run_transmission,
                     "S(omega) of a resonator lattice with ports (input-output theory), ideal or disordered"),
    "impedance": (_add_impedance, _run_impedance,
                  "node impedance of an LC(R) circuit on the graph: two-point or to ground"),
    "fit": (_add_fit, _run_fit, "fit omega0, J and kappa_int of an ideal device to a measured |S21| trace"),
}


def add_arguments(parser: argparse.ArgumentParser) -> None:
    sub = parser.add_subparsers(dest="device_command", metavar="WHAT", parser_class=type(parser))
    sub.required = True
    for name, (add, run_, help_) in _SUB.items():
        p = sub.add_parser(name, help=help_, description=help_)
        add(p)
        p.set_defaults(_device_run=run_)


def run(args: argparse.Namespace) -> int:
    return int(args._device_run(args) or 0)


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
