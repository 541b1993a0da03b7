"""The spin-1/2 Heisenberg antiferromagnet on {8,3}: ground state by SSE, extrapolated in beta and size,
bulk against boundary (docs/spins-quantum.md, "Physics").

Graphs: the {8,3} flakes l = 2, 3, 4 (48, 200, 768 sites) and the bipartite {8,3} clusters of the
package (bolza, 16 sites; dyck, 32 sites; PSL(2,17) and PSL(2,31) have odd cycles: the antiferromagnet
has a sign problem there and is refused). For each graph, beta = 8, 16, 32, 64, 128 (J = 1, Delta = 1).

Per point: the energy per site e, the squared staggered moment m_s^2 = 3 s_pi / N = 3 <(M_s^z/N)^2>
(SU(2): three components), and on flakes, by ring r, the staggered correlation mu_r (mean over ring r
of eps_i <S^z_i M_s^z> / N) and the ring's staggered moment m_r = 3 mu_r / m_s (for long-range order,
mu_i = m_i m_bar / 3 and m_bar^2 = m_s^2: m_r is the local moment of ring r; the ring-weighted mean of
m_r is m_s), and the bond energies <S_i.S_j> of the bonds inside ring 1 (bulk) and inside the outer
ring (boundary).

Extrapolation in beta: a graph's ground-state value is that of the largest beta, provided the two
largest betas agree within 2 sigma (``plateau``); otherwise none is quoted. Extrapolation in size:
on H^2 a massless mode's propagator decays as exp(-d) (its Laplacian spectrum starts at 1/4, a
curvature gap), so the influence of the boundary on the central octagon falls geometrically with
each ring; the bulk values of ring 1 (moment, bond energy) are extrapolated from l = 2, 3, 4 by
Aitken's delta-squared (a geometric sequence f_l = f + A r^l), with the error from 2000 Gaussian
resamplings, and quoted only when the ratio r lies in (0, 1).

Usage::

    python benchmarks/spins_afm83.py run --graphs l2 l3 bolza dyck      # store in benchmarks/spins_afm83.json
    python benchmarks/spins_afm83.py run --graphs l4 --betas 8 16 32 64
    python benchmarks/spins_afm83.py run --graphs l4 --betas 128 --sweeps 8000
    python benchmarks/spins_afm83.py table                              # tables, extrapolations, figure

(the three runs may go at once; the stored points took about 9 CPU minutes on a loaded machine, most of
it l = 4 at beta = 64 and 128).

``run`` adds its points to the JSON file (a point run again replaces the old one); ``table`` reads it,
prints the Markdown tables of docs/spins-quantum.md and writes docs/img/spins_afm83.png.
"""

from __future__ import annotations

import argparse
import json
import os
import tempfile
import time
import warnings
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
STORE = HERE / "spins_afm83.json"
IMG = HERE.parent / "docs" / "img"
GRAPHS = {"l2": ("flake", 2), "l3": ("flake", 3), "l4": ("flake", 4), "bolza": ("cluster", "bolza"),
          "dyck": ("cluster", "dyck")}
BETAS = (8.0, 16.0, 32.0, 64.0, 128.0)


def _system(key: str):
    import hyperlattice as hl
    from hyperlattice.graph.clusters import pbc_cluster

    kind, arg = GRAPHS[key]
    return hl.ring_lattice(8, 3, arg) if kind == "flake" else pbc_cluster(8, 3, arg)


def point(key: str, beta: float, sweeps: int, seed: int) -> dict:
    """One chain: the row stored in the JSON file."""
    from hyperlattice.spins.quantum import xxz_qmc

    system = _system(key)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        c0 = time.process_time()
        r = xxz_qmc(system, J=1.0, Delta=1.0, beta=beta, sweeps=sweeps, thermalization=max(2000, sweeps // 5),
                    seed=seed, progress=False)
        cpu = time.process_time() - c0
    n = r.sites
    row = {"graph": key, "system": r.system, "sites": n, "beta": beta, "sweeps": sweeps, "seed": seed,
           "e": r.e, "e_err": r.e_err, "ms2": 3 * r.s_pi / n, "ms2_err": 3 * r.s_pi_err / n,
           "tau_e": r.tau_int["energy"], "tau_s_pi": r.tau_int["s_pi"], "cpu": cpu,
           "converged": bool(r.converged), "notes": [str(w.message) for w in caught]}
    if r.ring is not None:
        sdot = r.bond_zz + r.bond_xy
        sdot_err = np.hypot(r.bond_zz_err, r.bond_xy_err)
        ri, rj = r.ring[r.bonds[:, 0]], r.ring[r.bonds[:, 1]]
        last = int(r.ring.max())
        row["ring_sites"] = [int(np.sum(r.ring == k + 1)) for k in range(last)]
        row["mu"] = r.ring_stag.tolist()
        row["mu_err"] = r.ring_stag_err.tolist()
        for name, sel in (("bond_bulk", (ri == 1) & (rj == 1)), ("bond_boundary", (ri == last) & (rj == last))):
            row[name] = float(sdot[sel].mean())
            row[name + "_err"] = float(np.sqrt(np.sum(sdot_err[sel] ** 2)) / sel.sum())
    return row


def _load() -> list:
    return json.loads(STORE.read_text()) if STORE.exists() else []


def run(args) -> None:
    from filelock import FileLock

    print(f"load average {os.getloadavg()[0]:.2f}", flush=True)
    for key in args.graphs:
        for beta in args.betas:
            row = point(key, beta, args.sweeps, args.seed)
            with FileLock(os.path.join(tempfile.gettempdir(), STORE.name + ".lock")):    # runs may add points at once
                rows = [x for x in _load() if not (x["graph"] == key and x["beta"] == beta)] + [row]
                STORE.write_text(json.dumps(rows, indent=1))
            print(f"{key:<6} beta {beta:>5g}: e = {row['e']:.5f} +- {row['e_err']:.5f}, m_s^2 = {row['ms2']:.5f} "
                  f"+- {row['ms2_err']:.5f} ({row['cpu']:.0f} CPU s{'' if row['converged'] else ', NOT converged'})",
                  flush=True)


# ----------------------------------------------------------------------------
# analysis
# ----------------------------------------------------------------------------

def ring_moments(row: dict) -> tuple[np.ndarray, np.ndarray]:
    """m_r = 3 mu_r / m_s by ring, with errors (mu_r and m_s^2 errors propagated as independent)."""
    mu, mu_err = np.array(row["mu"]), np.array(row["mu_err"])
    ms = np.sqrt(row["ms2"])
    m = 3 * mu / ms
    err = np.hypot(3 * mu_err / ms, m * 0.5 * row["ms2_err"] / row["ms2"])
    return m, err


def plateau(rows: list, key: str, name: str, err_name: str | None = None):
    """(value, error, beta, reached) of the largest beta, and whether it agrees with the next within 2 sigma."""
    err_name = err_name or name + "_err"
    pts = sorted((r for r in rows if r["graph"] == key), key=lambda r: r["beta"])
    if len(pts) < 2:
        return None
    a, b = pts[-2], pts[-1]
    va, ea = _get(a, name, err_name)
    vb, eb = _get(b, name, err_name)
    return vb, eb, b["beta"], bool(abs(va - vb) <= 2 * np.hypot(ea, eb))


def _get(row, name, err_name):
    if name == "m1":
        m, e = ring_moments(row)
        return float(m[0]), float(e[0])
    if name == "mlast":
        m, e = ring_moments(row)
        return float(m[-1]), float(e[-1])
    return float(row[name]), float(row[err_name])


def aitken(vals, errs, seed: int = 1, draws: int = 2000):
    """f + A r^l from three equally spaced values: (f, error, r), or None when r is not in (0, 1)."""
    v = np.asarray(vals, float)
    d1, d2 = v[1] - v[0], v[2] - v[1]
    if d1 == 0 or not 0 < d2 / d1 < 1:
        return None
    r = d2 / d1
    f = v[2] + d2 * r / (1 - r)          # the geometric tail d2 (r + r^2 + ...)
    gen = np.random.default_rng(seed)
    s = v[None, :] + gen.normal(size=(draws, 3)) * np.asarray(errs, float)[None, :]
    a1, a2 = s[:, 1] - s[:, 0], s[:, 2] - s[:, 1]
    ok = (a1 != 0) & (a2 / np.where(a1 == 0, 1, a1) > 0) & (a2 / np.where(a1 == 0, 1, a1) < 1)
    rr = a2[ok] / a1[ok]
    fs = s[ok, 2] + a2[ok] * rr / (1 - rr)
    lo, hi = np.percentile(fs, [16, 84])
    return float(f), float((hi - lo) / 2), float(r), float(ok.mean())


def _fmt(v, e):
    """v(e) with two significant digits of the error."""
    if not np.isfinite(e) or e <= 0:
        return f"{v:.4f}"
    digits = max(0, 1 - int(np.floor(np.log10(e))))
    return f"{v:.{digits}f}({int(round(e * 10 ** digits))})"


def table(args) -> None:
    rows = _load()
    print(f"{len(rows)} points from {STORE.name}")
    print("\n| graph | N | β | e per site | $m_s^2$ | $m_1$ (ring 1) | $m_\\ell$ (outer ring) | ⟨S·S⟩ ring 1 | ⟨S·S⟩ outer ring |")
    print("|---|---|---|---|---|---|---|---|---|")
    for key in GRAPHS:
        for r in sorted((x for x in rows if x["graph"] == key), key=lambda x: x["beta"]):
            extra = "| | | | "
            if "mu" in r:
                m, me = ring_moments(r)
                extra = (f"| {_fmt(m[0], me[0])} | {_fmt(m[-1], me[-1])} | {_fmt(r['bond_bulk'], r['bond_bulk_err'])} "
                         f"| {_fmt(r['bond_boundary'], r['bond_boundary_err'])} ")
            print(f"| {key} | {r['sites']} | {r['beta']:g} | {_fmt(r['e'], r['e_err'])} | "
                  f"{_fmt(r['ms2'], r['ms2_err'])} {extra}|")
    print("\nGround state (largest beta; 'yes' when it agrees with the next smaller beta within 2 sigma):\n")
    print("| graph | N | β | e per site | plateau | $m_s$ | plateau |")
    print("|---|---|---|---|---|---|---|")
    ground = {}
    for key in GRAPHS:
        pe = plateau(rows, key, "e")
        pm = plateau(rows, key, "ms2")
        if pe is None:
            continue
        n = next(r["sites"] for r in rows if r["graph"] == key)
        ms, ms_err = np.sqrt(pm[0]), 0.5 * pm[1] / np.sqrt(pm[0])
        ground[key] = {"e": pe, "ms": (ms, ms_err, pm[2], pm[3])}
        print(f"| {key} | {n} | {pe[2]:g} | {_fmt(pe[0], pe[1])} | {'yes' if pe[3] else 'no'} | "
              f"{_fmt(ms, ms_err)} | {'yes' if pm[3] else 'no'} |")
    flakes = [k for k in ("l2", "l3", "l4") if k in ground]
    if len(flakes) == 3:
        print("\nBulk (ring 1 of the flakes, ground state) and its extrapolation in l (Aitken, geometric in l):\n")
        print("| quantity | l = 2 | l = 3 | l = 4 | l → ∞ | ratio r |")
        print("|---|---|---|---|---|---|")
        for label, name in (("$m_1$ (ring-1 moment)", "m1"), ("$e_1 = \\tfrac32$⟨S·S⟩ ring 1", "bond_bulk"),
                            ("$m_\\ell$ (outer-ring moment)", "mlast")):
            vals, errs = [], []
            for k in flakes:
                row = max((x for x in rows if x["graph"] == k), key=lambda x: x["beta"])
                v, e = _get(row, name, name + "_err")
                scale = 1.5 if name == "bond_bulk" else 1.0
                vals.append(scale * v)
                errs.append(scale * e)
            ext = aitken(vals, errs) if name != "mlast" else None
            tail = "| — | — |" if ext is None else f"| {_fmt(ext[0], ext[1])} | {ext[2]:.2f} |"
            print(f"| {label} | " + " | ".join(_fmt(v, e) for v, e in zip(vals, errs)) + f" {tail}")
    _figure(rows)


def _figure(rows) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(1, 3, figsize=(13, 3.8))
    for key in GRAPHS:
        pts = sorted((x for x in rows if x["graph"] == key), key=lambda x: x["beta"])
        if not pts:
            continue
        b = np.array([p["beta"] for p in pts])
        lab = f"{key} (N = {pts[0]['sites']})"
        top = pts[-1]
        ax[0].errorbar(b, [p["e"] - top["e"] for p in pts], [p["e_err"] for p in pts], marker="o", capsize=3,
                       label=lab)
        ax[1].errorbar(b, [p["ms2"] / top["ms2"] for p in pts], [p["ms2_err"] / top["ms2"] for p in pts],
                       marker="o", capsize=3, label=lab)
    for a, t in ((ax[0], "$e(\\beta) - e(\\beta_{max})$"), (ax[1], "$m_s^2(\\beta) / m_s^2(\\beta_{max})$")):
        a.set_xscale("log", base=2)
        a.set_xlabel("β (1/J)")
        a.set_title(t)
        a.axhline(0.0 if a is ax[0] else 1.0, color="0.6", lw=0.8)
    ax[0].legend(fontsize=7)
    for key in ("l2", "l3", "l4"):
        pts = [x for x in rows if x["graph"] == key]
        if not pts:
            continue
        row = max(pts, key=lambda x: x["beta"])
        m, me = ring_moments(row)
        ax[2].errorbar(np.arange(1, m.size + 1), m, me, marker="o", capsize=3,
                       label=f"{key}, β = {row['beta']:g}")
    ax[2].set_xlabel("ring r (1 = centre)")
    ax[2].set_title("staggered moment by ring $m_r = 3\\mu_r/m_s$")
    ax[2].legend(fontsize=7)
    fig.suptitle("Heisenberg antiferromagnet on {8,3}: SSE (J = 1)")
    fig.tight_layout()
    IMG.mkdir(parents=True, exist_ok=True)
    fig.savefig(IMG / "spins_afm83.png", dpi=110)
    print(f"\nwrote {IMG / 'spins_afm83.png'}")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sub = ap.add_subparsers(dest="what", required=True)
    r = sub.add_parser("run", help="run points and add them to the JSON file")
    r.add_argument("--graphs", nargs="+", choices=list(GRAPHS), default=list(GRAPHS))
    r.add_argument("--betas", type=float, nargs="+", default=list(BETAS))
    r.add_argument("--sweeps", type=int, default=20000)
    r.add_argument("--seed", type=int, default=11)
    sub.add_parser("table", help="tables, extrapolations and the figure from the JSON file")
    args = ap.parse_args(argv)
    if args.what == "run":
        run(args)
    else:
        table(args)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
