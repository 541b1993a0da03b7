"""Haldane on {8,3}: where is it a clean Chern insulator? A scan of t2, phi and M.

For each (t2, phi, M) the l-ring flake is diagonalised (dense; Haldane has one orbital per site) and
the gaps of the ring-1 local density of states are found (states with at least a tenth of the mean
ring-1 weight count as bulk states, as in ``flake_topology``). For the widest centre gap and for the
gap at half filling (E_F = 0 when phi = pi/2 and M = 0: the spectrum is symmetric) the row holds
the Fermi level (the gap's middle), the filling, the gap, the hyperbolic local marker at the centre
(mean over two ring-1 sites, disk of four bond lengths) and the two-terminal conductance at E_F
(e²/h, leads on two quarter arcs of the edge, coupling 2 t). A clean Chern insulator has a wide gap,
a marker near an integer C and G = |C|.

Then the confirmation stage (``--stage confirm``): the chosen rows on the next flake, l + 1 rings:
the marker by the Chebyshev projector with disks of four and six bond lengths, and the conductance.

Writes one JSON line (``{"meta": ..., "scan": [...], "confirm": [...]}``) on stdout; with
``--from-json FILE`` prints the Markdown tables of docs/topology.md and draws the figure.

Usage::

    python benchmarks/topology_haldane_scan.py > /tmp/haldane.json
    python benchmarks/topology_haldane_scan.py --from-json docs/data/topology_haldane_scan.json --out haldane.png
"""

from __future__ import annotations

import argparse
import json
import time
import warnings

import numpy as np

T2 = (0.1, 0.2, 0.3, 0.5, 0.7, 1.0)
PHI = (np.pi / 2, np.pi / 4)
MASS = (0.0, 0.5, 1.0)
#: (t2, phi, M, which gap) confirmed on the next flake
CONFIRM = ((0.5, np.pi / 2, 0.0, "widest"), (0.2, np.pi / 2, 0.0, "widest"), (0.3, np.pi / 2, 0.0, "half"),
           (1.0, np.pi / 2, 0.0, "widest"))


def _gaps(occ):
    """(lower, upper) of the widest ring-1 LDOS gap and of the one containing half filling."""
    e, w = occ.energies, occ.centre_weight
    bulk = np.flatnonzero(w >= 0.1 * w.mean())
    eb = e[bulk]
    d = np.diff(eb)
    k = int(np.argmax(d))
    half = 0.5 * (e[len(e) // 2 - 1] + e[len(e) // 2])
    j = int(np.searchsorted(eb, half)) - 1
    out = {"widest": (eb[k], eb[k + 1])}
    if 0 <= j < len(eb) - 1:
        out["half"] = (eb[j], eb[j + 1])
    return out


def _fermi(e, lo, hi):
    """The gap's middle, moved off any (edge) level by a little."""
    ef = 0.5 * (lo + hi)
    while np.any(np.abs(e - ef) < 1e-6):
        ef += 1e-4 * (hi - lo)
    return float(ef)


def scan(rings: int) -> list:
    import hyperlattice as hl
    from hyperlattice.topology import local_markers, occupied_states
    from hyperlattice.topology.transport import conductance

    lat = hl.ring_lattice(8, 3, rings)
    ring1 = np.flatnonzero(lat.ring == 1)[:2]
    rows = []
    for t2 in T2:
        for phi in PHI:
            for M in MASS:
                t0 = time.perf_counter()
                occ = occupied_states(lat, "haldane", M=M, t2=t2, phi=phi)
                for which, (lo, hi) in _gaps(occ).items():
                    ef = _fermi(occ.energies, lo, hi)
                    o2 = occupied_states(lat, "haldane", M=M, t2=t2, phi=phi, fermi=ef)
                    mk = float(local_markers(lat, o2, ring1).mean())
                    g = float(conductance(lat, "haldane", M=M, t2=t2, phi=phi, energies=[ef]).conductance[0])
                    rows.append(dict(t2=t2, phi=phi, M=M, gap_kind=which, fermi=ef,
                                     filling=float(np.mean(occ.energies < ef)), gap=float(hi - lo), marker=mk,
                                     conductance=g))
                print(f"# t2={t2} phi={phi:.3f} M={M} {time.perf_counter() - t0:.1f}s", flush=True,
                      file=__import__("sys").stderr)
    return rows


def confirm(rows: list, rings: int) -> list:
    import hyperlattice as hl
    from hyperlattice import geometry
    from hyperlattice.errors import ConvergenceWarning
    from hyperlattice.topology.kpm_marker import centre_marker
    from hyperlattice.topology.transport import conductance

    lat = hl.ring_lattice(8, 3, rings)
    out = []
    for t2, phi, M, which in CONFIRM:
        r = next(x for x in rows if x["t2"] == t2 and abs(x["phi"] - phi) < 1e-12 and x["M"] == M
                 and x["gap_kind"] == which)
        ef = r["fermi"]
        res = {"t2": t2, "phi": phi, "M": M, "gap_kind": which, "fermi": ef}
        for R in (4, 6):
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", ConvergenceWarning)
                c = centre_marker(lat, "haldane", M=M, t2=t2, phi=phi, fermi=ef, moments=512,
                                  radius=R * geometry.d0(8, 3))
            res[f"marker_R{R}"], res[f"error_R{R}"] = float(c.marker), float(c.marker_error)
        res["conductance"] = float(conductance(lat, "haldane", M=M, t2=t2, phi=phi, energies=[ef]).conductance[0])
        out.append(res)
    return out


def _phi(x: float) -> str:
    return {round(np.pi / 2, 9): "π/2", round(np.pi / 4, 9): "π/4"}.get(round(x, 9), f"{x:.3f}")


def print_markdown(data: dict, brief: bool = False) -> None:
    """The tables of docs/topology.md (``brief``: the scan's rows at phi = pi/2, M = 0 only)."""
    print("| t2 | φ | M | gap | E_F | filling | LDOS gap | marker | G (e²/h) |")
    print("|---|---|---|---|---|---|---|---|---|")
    for r in data["scan"]:
        if brief and (r["M"] != 0 or abs(r["phi"] - np.pi / 2) > 1e-9):
            continue
        print(f"| {r['t2']:.1f} | {_phi(r['phi'])} | {r['M']:.1f} | {r['gap_kind']} | {r['fermi']:.3f} | "
              f"{r['filling']:.3f} | {r['gap']:.3f} | {r['marker']:.3f} | {r['conductance']:.3f} |")
    print()
    print("| t2 | φ | M | gap | E_F | marker (R = 4) | marker (R = 6) | G (e²/h) |")
    print("|---|---|---|---|---|---|---|---|")
    for r in data["confirm"]:
        print(f"| {r['t2']:.1f} | {_phi(r['phi'])} | {r['M']:.1f} | {r['gap_kind']} | {r['fermi']:.3f} | "
              f"{r['marker_R4']:.3f} | {r['marker_R6']:.3f} | {r['conductance']:.4f} |")


def plot(data: dict, out: str) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(9, 3.6))
    for ax, kind in zip(axes, ("widest", "half")):
        for phi, mk in zip(PHI, ("o", "s")):
            for M, col in zip(MASS, ("C0", "C1", "C2")):
                rs = [r for r in data["scan"] if r["gap_kind"] == kind and abs(r["phi"] - phi) < 1e-9 and r["M"] == M]
                if not rs:
                    continue
                ax.plot([r["t2"] for r in rs], [r["conductance"] for r in rs], mk + "-", color=col, ms=4,
                        label=f"G, φ = {_phi(phi)}, M = {M:g}")
                ax.plot([r["t2"] for r in rs], [r["gap"] for r in rs], mk + ":", color=col, ms=3, alpha=0.6)
        ax.set_title(f"{'widest centre gap' if kind == 'widest' else 'half filling'} (dotted: LDOS gap)")
        ax.set_xlabel("t2")
        ax.axhline(1, color="k", lw=0.5)
        ax.axhline(2, color="k", lw=0.5, ls="--")
    axes[0].set_ylabel("G (e²/h), gap (t)")
    axes[0].legend(fontsize=6)
    fig.suptitle(f"Haldane on {{8,3}}, ℓ = {data['meta']['rings']} flake")
    fig.tight_layout()
    fig.savefig(out, dpi=120)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rings", type=int, default=4)
    ap.add_argument("--from-json")
    ap.add_argument("--out")
    ap.add_argument("--brief", action="store_true", help="with --from-json: the rows at phi = pi/2, M = 0")
    args = ap.parse_args()
    if args.from_json:
        from pathlib import Path

        data = json.loads(Path(args.from_json).read_text())
        print_markdown(data, args.brief)
        if args.out:
            plot(data, args.out)
        return
    rows = scan(args.rings)
    conf = confirm(rows, args.rings + 1)
    print(json.dumps({"meta": {"rings": args.rings, "confirm_rings": args.rings + 1}, "scan": rows,
                      "confirm": conf}))


if __name__ == "__main__":
    main()
