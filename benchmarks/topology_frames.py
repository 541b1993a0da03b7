"""QWZ on {8,3} flakes in the chord frame and in the parallel-transport frame, against the continuum.

Two parts, printed as one JSON line (stored in docs/data/topology_frames.json):

* ``invariants``: for l = 3, 4 (dense) the local marker at the centre and on the outer ring,
  Kitaev's sum, the Bott index and the ring-1 LDOS gap, and for l = 3, 4, 5 the two-terminal
  conductance at E = 0, in both frames, for M in 0.5, 1, 1.25, 1.5, 2;
* ``gaps``: the ring-1 LDOS gap around E = 0 from a Chebyshev expansion (2,048 moments, Jackson
  kernel; resolution about 0.007 t) for l = 3..6 and M from 0.9 to 1.65, both frames, with the
  continuum's gap-closing mass on the Dirichlet disk of the same l: the Wilson term's lowest level
  M*(l) = -E_1(l)/2, with the spin connection (field B = 2, transport frame) and without (B = 0,
  the chord frame's Wilson term), from ``continuum.magnetic.magnetic_levels`` through the paper's
  dictionary.

Usage: ``python benchmarks/topology_frames.py [--rings-gap 3,4,5,6] > out.jsonl``;
``python benchmarks/topology_frames.py --from-json docs/data/topology_frames.json [--out fig.png]`` prints
the tables of docs/topology.md (and draws the figure).
"""

from __future__ import annotations

import argparse
import json
import warnings

import numpy as np

MS_INV = (0.5, 1.0, 1.25, 1.5, 2.0)
MS_GAP = tuple(np.round(np.arange(0.9, 1.651, 0.05), 3))
FRAMES = ("chord", "transport")


def invariants() -> list:
    import hyperlattice as hl
    from hyperlattice.topology import flake_topology
    from hyperlattice.topology.transport import conductance

    rows = []
    for rings in (3, 4, 5):
        lat = hl.ring_lattice(8, 3, rings)
        for M in MS_INV:
            for fr in FRAMES:
                r = dict(rings=rings, M=M, frame=fr)
                if rings <= 4:
                    with warnings.catch_warnings():
                        warnings.simplefilter("ignore")
                        top = flake_topology(lat, "qwz", M=M, frame=fr)
                    r.update(marker=top.marker, outer=float(top.marker_by_ring[-1]), kitaev=top.kitaev,
                             bott=top.bott, bott_reliable=top.bott_reliable, gap=top.gap)
                r["G"] = float(conductance(lat, "qwz", M=M, frame=fr).conductance[0])
                rows.append(r)
    return rows


def invariants_big(rings=5, Ms=(1.0, 1.25)) -> list:
    """The Chebyshev centre marker (256 moments) and Kitaev's sum on the l = 5 flake, both frames."""
    import hyperlattice as hl
    from hyperlattice.topology.kpm_marker import centre_marker

    lat = hl.ring_lattice(8, 3, rings)
    rows = []
    for M in Ms:
        for fr in FRAMES:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                r = centre_marker(lat, "qwz", M=M, moments=256, frame=fr)
            rows.append(dict(rings=rings, M=M, frame=fr, marker=r.marker, kitaev=r.kitaev, error=r.marker_error,
                             gap=r.gap))
    return rows


def gaps(rings_list, moments=2048) -> list:
    import hyperlattice as hl
    from hyperlattice.graph.solvers import single_threaded_blas
    from hyperlattice.topology.kpm_marker import _ldos_gap, projector_columns
    from hyperlattice.topology.models import model_hamiltonian, model_terms

    rows = []
    for rings in rings_list:
        lat = hl.ring_lattice(8, 3, rings)
        r1 = np.flatnonzero(np.asarray(lat.ring) == 1)
        cols = (r1[:, None] * 2 + np.arange(2)).ravel()
        for fr in FRAMES:
            for M in MS_GAP:
                H = model_hamiltonian(model_terms(lat, "qwz", M=float(M), frame=fr))
                with single_threaded_blas():
                    _, _, info = projector_columns(H, cols, fermi=0.0, moments=moments)
                rows.append(dict(rings=rings, frame=fr, M=float(M), gap=_ldos_gap(info["diag_moments"], info["scale"], 0.0),
                                 resolution=float(np.pi * info["scale"] / moments)))
    return rows


def continuum(rings_list) -> list:
    from hyperlattice.continuum.magnetic import magnetic_levels
    from hyperlattice.topology.frames import covariant_critical_mass

    out = []
    for rings in rings_list:
        b2 = magnetic_levels(8, 3, rings=rings, levels=1, flux=1 / 6)     # B = 2: the spin connection
        b0 = magnetic_levels(8, 3, rings=rings, levels=1, flux=0.0)
        out.append(dict(rings=rings, transport=float(-0.5 * b2.energies[0]), chord=float(-0.5 * b0.energies[0]),
                        kappa_transport=float(b2.kappa[0]), kappa_chord=float(b0.kappa[0])))
    from hyperlattice import dictionary

    # the infinite disk: the Wilson term's spectrum starts at kappa = 2 with the spin connection (Comtet, B = 2)
    # and at the scalar curvature gap kappa = 1 without it
    out.append(dict(rings=None, transport=covariant_critical_mass(8, 3),
                    chord=float(-0.5 * dictionary.energy_from_lambda(1.0, 8, 3))))
    return out


def bolza_closing() -> dict:
    """Where the Bolza cluster's smallest Abelian gap closes, lift (chord-like) and covariant frames.

    The smallest gap over 400 random momenta of the 4-torus on the trivial side, M = 1.6 and 1.8,
    extrapolated linearly to zero.
    """
    import hyperlattice as hl
    from hyperlattice.topology.frames import qwz_frame_terms
    from hyperlattice.topology.models import bloch_model_hamiltonian

    bolza = hl.pbc_cluster(8, 3, "bolza")
    k = np.random.default_rng(0).uniform(0, 2 * np.pi, (400, 4))
    out = {}
    for frame in ("lift", "covariant"):
        g = []
        for M in (1.6, 1.8):
            e = np.linalg.eigvalsh(bloch_model_hamiltonian(qwz_frame_terms(bolza, M=M, frame=frame), k))
            g.append(float((e[:, 16] - e[:, 15]).min()))
        out[frame] = 1.6 - g[0] * 0.2 / (g[1] - g[0])
    return out


def closing(rows, rings, frame, floor=0.1) -> float:
    """Where the trivial-side gap extrapolates to zero: a straight line through the first two points above ``floor``."""
    pts = sorted((r["M"], r["gap"]) for r in rows if r["rings"] == rings and r["frame"] == frame)
    # the trivial side: from the largest M down, while the gap keeps falling
    tail = []
    for M, g in reversed(pts):
        if g < floor:
            break
        tail.append((M, g))
    (m1, g1), (m0, g0) = tail[-1], tail[-2]
    return float(m1 - g1 * (m0 - m1) / (g0 - g1))


def tables(data) -> None:
    print("| ℓ | M | frame | marker (centre) | marker (outer ring) | Kitaev | Bott | gap | G (e²/h) |")
    print("|---|---|---|---|---|---|---|---|---|")
    for r in data["invariants"]:
        if "marker" in r:
            print(f"| {r['rings']} | {r['M']:.2f} | {r['frame']} | {r['marker']:.3f} | {r['outer']:.3f} | "
                  f"{r['kitaev']:.3f} | {r['bott']:.0f}{'' if r['bott_reliable'] else '*'} | {r['gap']:.3f} | "
                  f"{r['G']:.3f} |")
        else:
            big = [b for b in data["big"] if b["M"] == r["M"] and b["frame"] == r["frame"]]
            if big:
                b = big[0]
                print(f"| {r['rings']} | {r['M']:.2f} | {r['frame']} | {b['marker']:.3f} | | {b['kitaev']:.3f} | | "
                      f"{b['gap']:.3f} | {r['G']:.3f} |")
            else:
                print(f"| {r['rings']} | {r['M']:.2f} | {r['frame']} | | | | | | {r['G']:.3f} |")
    print()
    cont = {c["rings"]: c for c in data["continuum"]}
    print("| ℓ | M* chord (measured) | M* transport (measured) | continuum, no connection (B = 0) | "
          "continuum, spin connection (B = 2) |")
    print("|---|---|---|---|---|")
    have = sorted({r["rings"] for r in data["gaps"]})
    for rings in have:
        meas = []
        for fr in FRAMES:
            try:
                meas.append(f"{closing(data['gaps'], rings, fr):.3f}")
            except (IndexError, ZeroDivisionError):
                meas.append("")
        c = cont[rings]
        print(f"| {rings} | {meas[0]} | {meas[1]} | {c['chord']:.3f} | {c['transport']:.3f} |")
    inf = cont[None]
    print(f"| ∞ (closed surface) | {data['bolza']['lift']:.3f} (Bolza, lift frame) | "
          f"{data['bolza']['covariant']:.3f} (Bolza, covariant frame) | {inf['chord']:.3f} | {inf['transport']:.3f} |")


def plot(data, out) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7, 4))
    cont = {c["rings"]: c for c in data["continuum"]}
    colours = {3: "C0", 4: "C1", 5: "C2", 6: "C3"}
    for rings in sorted({r["rings"] for r in data["gaps"]}):
        for fr, ls in (("chord", "-"), ("transport", "--")):
            pts = sorted((r["M"], r["gap"]) for r in data["gaps"] if r["rings"] == rings and r["frame"] == fr)
            if pts:
                ax.plot(*zip(*pts), ls, color=colours.get(rings, "k"), label=f"ℓ = {rings}, {fr}")
        ax.axvline(cont[rings]["transport"], color=colours.get(rings, "k"), lw=0.6, ls=":")
    ax.axvline(cont[None]["transport"], color="k", lw=1, ls=":", label="Comtet M_c = 1.409 (B = 2, infinite disk)")
    ax.set_xlabel("M")
    ax.set_ylabel("ring-1 LDOS gap (t)")
    ax.set_title("{8,3} QWZ flakes: chord vs parallel-transport frame")
    ax.legend(fontsize=6, ncol=2)
    fig.tight_layout()
    fig.savefig(out, dpi=120)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rings-gap", default="3,4,5,6")
    ap.add_argument("--from-json")
    ap.add_argument("--out")
    ap.add_argument("--only", choices=("invariants", "gaps"))
    args = ap.parse_args()
    if args.from_json:
        with open(args.from_json) as fh:
            data = json.loads(fh.read())
        tables(data)
        if args.out:
            plot(data, args.out)
        return
    rl = [int(x) for x in args.rings_gap.split(",")]
    data = {"continuum": continuum(rl), "bolza": bolza_closing()}
    if args.only != "gaps":
        data["invariants"] = invariants()
        data["big"] = invariants_big()
    if args.only != "invariants":
        data["gaps"] = gaps(rl)
    print(json.dumps(data))


if __name__ == "__main__":
    main()
