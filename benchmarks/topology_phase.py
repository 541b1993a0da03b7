"""The {8,3} QWZ phase diagram in M and the Haldane scan in t2: flake markers next to Abelian Chern numbers.

For each M: the hyperbolic local marker at the centre of the l-ring flake (Chebyshev projector,
E_F = 0) with its error estimate and the ring-1 LDOS gap, Kitaev's sum at the centre, and the
first Chern numbers C_ij of the Abelian bands of the Bolza cluster ({8,3}, genus 2) with their gcd,
Pfaffian and smallest gap on the grid (None where the gap closes on the grid). Then Haldane
(M = 0, phi = pi/2) on the flake for several t2, with the gap.

Writes docs/img/topology_qwz_phase.png and prints a JSON table.

Usage: ``python benchmarks/topology_phase.py [--rings 4] [--moments 256] [--out docs/img/topology_qwz_phase.png]``.
"""

from __future__ import annotations

import argparse
import json
import warnings

import numpy as np


def print_markdown(rows, hal) -> None:
    """The two tables of docs/topology.md."""
    print("| M | marker (centre) | error estimate | Kitaev | LDOS gap | Bolza gcd | Bolza Pf | Bolza gap |")
    print("|---|---|---|---|---|---|---|---|")
    for r in rows:
        cl = (f"{r['gcd']} | {r['pfaffian']} | {r['cluster_gap']:.3f}" if r["gcd"] is not None
              else "gap closes | | ")
        print(f"| {r['M']:.2f} | {r['marker']:.4f} | {r['error']:.0e} | {r['kitaev']:.4f} | {r['gap']:.3f} | {cl} |")
    print()
    print("| t2 | marker (centre) | error estimate | Kitaev | LDOS gap |")
    print("|---|---|---|---|---|")
    for r in hal:
        print(f"| {r['t2']:.2f} | {r['marker']:.4f} | {r['error']:.0e} | {r['kitaev']:.4f} | {r['gap']:.3f} |")


def plot(rows, rings, out) -> None:
    """The figure of docs/topology.md."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7, 4))
    Ms = [r["M"] for r in rows]
    ax.plot(Ms, [r["marker"] for r in rows], "o-", label=f"local marker, flake ℓ = {rings} (centre)")
    ax.plot(Ms, [r["kitaev"] for r in rows], "s--", ms=4, label="Kitaev sum at the centre")
    ax.plot(Ms, [(-r["pfaffian"] if r["pfaffian"] is not None else np.nan) for r in rows], "^",
            label="−Pf C (Bolza cluster, Abelian bands)")
    ax.plot(Ms, [(r["gcd"] if r["gcd"] is not None else np.nan) for r in rows], "v",
            label="gcd C (Bolza)")
    ax.plot(Ms, [r["gap"] for r in rows], ":", color="grey", label="ring-1 LDOS gap (flake)")
    ax.set_xlabel("M")
    ax.set_ylabel("invariant / gap")
    ax.axhline(0, color="k", lw=0.5)
    ax.set_title("{8,3} QWZ: flake marker vs Abelian Chern numbers")
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(out, dpi=120)


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--rings", type=int, default=4)
    ap.add_argument("--moments", type=int, default=256)
    ap.add_argument("--out", default="docs/img/topology_qwz_phase.png")
    ap.add_argument("--markdown", action="store_true", help="print the tables in Markdown (docs/topology.md)")
    ap.add_argument("--from-json", help="format and plot the JSON a previous run printed (its last line), "
                    "compute nothing")
    args = ap.parse_args()
    if args.from_json:
        with open(args.from_json) as fh:
            data = json.loads(fh.read().strip().splitlines()[-1])
        print_markdown(data["qwz"], data["haldane"])
        plot(data["qwz"], args.rings, args.out)
        return

    import hyperlattice as hl
    from hyperlattice.topology.kpm_marker import centre_marker
    from hyperlattice.topology.surfaces import cluster_chern

    lat = hl.ring_lattice(8, 3, args.rings)
    bolza = hl.pbc_cluster(8, 3, "bolza")
    rows = []
    for M in np.round(np.arange(-4.0, 4.01, 0.25), 2):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            r = centre_marker(lat, "qwz", M=float(M), moments=args.moments)
        row = dict(M=float(M), marker=r.marker, error=r.marker_error, kitaev=r.kitaev, gap=r.gap)
        try:
            c = cluster_chern(bolza, "qwz", M=float(M))
            row.update(chern=c.chern.tolist(), gcd=c.gcd, pfaffian=c.pfaffian, cluster_gap=c.gap, grid=c.grid)
        except Exception as exc:  # noqa: BLE001 - the gap closes on the grid: recorded as such
            row.update(chern=None, gcd=None, pfaffian=None, cluster_gap=None, note=str(exc)[:80])
        rows.append(row)
        if not args.markdown:
            print(json.dumps(row), flush=True)
    hal = []
    for t2 in (0.05, 0.1, 0.15, 0.2, 0.3, 0.4):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            r = centre_marker(lat, "haldane", M=0.0, t2=t2, moments=2 * args.moments)
        row = dict(t2=t2, marker=r.marker, error=r.marker_error, kitaev=r.kitaev, gap=r.gap)
        hal.append(row)
        if not args.markdown:
            print(json.dumps(row), flush=True)
    if args.markdown:
        print_markdown(rows, hal)
        return

    plot(rows, args.rings, args.out)
    print(json.dumps({"qwz": rows, "haldane": hal}))


if __name__ == "__main__":
    main()
