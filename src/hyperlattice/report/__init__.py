r"""``hyperlattice reproduce``: every table and figure of the paper, recomputed, in one report.

The report puts the paper's printed values beside the package's numbers and flags every
printed value that differs from the computed one by more than half a unit of its last printed
digit, with the reason where it is known (misprint, rounding, or the paper's ~3-digit sparse
estimates for l >= 8). Outputs in ``out_dir``:

* ``report.md`` and ``report.html`` (self-contained: figures embedded as base64 PNG),
* ``table_*.csv`` / ``table_*.json`` for every table (``table_s1.csv`` is SuppTab1),
* ``fig_*.png`` and ``fig_*.svg`` for every figure,
* ``timings.json`` (wall-clock times; kept out of the report so that it is deterministic).

Expensive results (graph spectra, Green functions) are cached with :class:`hyperlattice.cache.Cache`.
"""

from __future__ import annotations

import base64
import csv
import html
import io
import json
import math
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

import numpy as np

from .. import __version__, geometry
from ..cache import Cache
from ..graph.lattice import ring_lattice, ring_sizes

__all__ = ["reproduce", "PAPER"]

# ----------------------------------------------------------------------------
# the paper's printed values (strings, so that their printed precision is known)
# ----------------------------------------------------------------------------

PAPER = {
    # Tab1 / AppTab1
    "N": ["7", "35", "112", "315", "847", "2240", "5887", "15435", "40432", "105875"],
    "N_ring": ["7", "28", "77", "203", "532", "1393", "3647", "9548"],
    "L": ["0.447", "0.745", "0.894", "0.958", "0.984", "0.994", "0.998", "0.9990", "0.9997", "0.9999"],
    # SuppTab1 (rows of Tab1 repeated there)
    "E0_graph": ["-2", "-2.636", "-2.787", "-2.847", "-2.877", "-2.894", "-2.905", "-2.91", "-2.92", "-2.92"],
    "E0_continuum": ["-1.500", "-2.570", "-2.770", "-2.842", "-2.876", "-2.895", "-2.906", "-2.914", "-2.920",
                     "-2.924"],
    "E0_asymptotic": ["-2.535", "-2.738", "-2.820", "-2.861", "-2.884", "-2.899", "-2.909", "-2.916", "-2.921",
                      "-2.924"],
    "E1_graph": ["-1.274", "-2.283", "-2.627", "-2.762", "-2.827", "-2.863", "-2.884", "-2.90", "-2.91", "-2.91"],
    "E1_continuum": ["0.620", "-2.085", "-2.578", "-2.746", "-2.821", "-2.861", "-2.884", "-2.899", "-2.908",
                     "-2.915"],
    "E1_asymptotic": ["15.58", "-1.633", "-2.507", "-2.728", "-2.815", "-2.858", "-2.883", "-2.898", "-2.908",
                      "-2.915"],
    # table of App. AppFS
    "geometry": {7: ("0.283128", "0.275798"), 8: ("0.36352", "0.348311"), 9: ("0.409595", "0.388129"),
                 10: ("0.439590", "0.413304"), "inf": ("1", "1/2")},
    "E_inf": "-2.94295",
    "b_counting": "-9.096",
}

#: Known reasons for printed values that disagree with the computation.
EXPLANATIONS = {
    ("E1_graph", 1): "misprint: l = 1 is a single heptagon with E1 = -2cos(2pi/7) = -1.2470 exactly "
                     "(the printed -1.274 transposes two digits).",
    ("L", 8): "rounding slip: sqrt(15435/15463) = 0.999094 rounds to 0.9991.",
    ("geometry_d0", "inf"): "misprint: the p -> inf limit of d0 is (1/2) ln 3 = 0.549306 (the printed h = 1/2 "
                            "is tanh of that; tanh(1) would be 0.762).",
    ("b_counting", 4): "least-squares fit through the distinct radii gives -9.0954; the last digit depends on "
                       "fit details (e.g. rounding of the radii moves b by ~4e-4), see docs/scaling.md.",
}


def _decimals(printed: str) -> int:
    return len(printed.split(".")[1]) if "." in printed else 0


def _printed_value(printed: str) -> float:
    if "/" in printed:
        a, b = printed.split("/")
        return float(a) / float(b)
    return float(printed)


def compare(printed: str, computed: float, key, index, *, decimals: int | None = None) -> tuple[str, str]:
    """Flag if |computed - printed| exceeds half a unit of the printed last digit.

    Returns (flag, note): flag is "" (agrees), "≠" (disagrees, explained) or "≠?" (disagrees,
    no explanation known); graph values for l >= 8 are the paper's sparse estimates.
    """
    tol = 0.5 * 10.0 ** (-(_decimals(printed) if decimals is None else decimals)) * (1 + 1e-9)
    if abs(computed - _printed_value(printed)) <= tol:
        return "", ""
    note = EXPLANATIONS.get((key, index))
    if note is None and key in ("E0_graph", "E1_graph") and isinstance(index, int) and index >= 8:
        note = "the paper's value for l >= 8 is a ~3-digit sparse Lanczos estimate (SuppTab1 caption)."
    return ("≠", note) if note else ("≠?", "no explanation known")


# ----------------------------------------------------------------------------
# report structure
# ----------------------------------------------------------------------------

@dataclass
class Table:
    name: str
    columns: list[str]
    rows: list[list]
    caption: str = ""

    def write(self, out: Path) -> None:
        with open(out / f"table_{self.name}.csv", "w", newline="") as fh:
            w = csv.writer(fh)
            w.writerow(self.columns)
            w.writerows(self.rows)
        with open(out / f"table_{self.name}.json", "w") as fh:
            json.dump([dict(zip(self.columns, r)) for r in self.rows], fh, indent=1)


@dataclass
class Figure:
    name: str
    caption: str
    png: bytes = b""


@dataclass
class Section:
    title: str
    labels: str  # paper labels reproduced, e.g. "Tab1, SuppTab1"
    text: list[str] = field(default_factory=list)
    tables: list[Table] = field(default_factory=list)
    figures: list[Figure] = field(default_factory=list)


def _fmt(x, digits: int = 12) -> str:
    if isinstance(x, str):
        return x
    if isinstance(x, (int, np.integer)):
        return str(int(x))
    if x is None or (isinstance(x, float) and math.isnan(x)):
        return ""
    return f"{x:.{digits}f}"


def _save_figure(fig, out: Path, name: str, caption: str) -> Figure:
    import matplotlib.pyplot as plt

    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=110, metadata={"Software": None})
    png = buf.getvalue()
    (out / f"fig_{name}.png").write_bytes(png)
    fig.savefig(out / f"fig_{name}.svg", format="svg", metadata={"Date": None})
    plt.close(fig)
    return Figure(name=name, caption=caption, png=png)


# ----------------------------------------------------------------------------
# computations (cached)
# ----------------------------------------------------------------------------

def _graph_levels(cache: Cache, rings: int, timings: dict) -> dict:
    def compute():
        from ..graph.spectrum import lowest_levels

        t0 = time.perf_counter()
        spec = lowest_levels(ring_lattice(7, 3, rings), levels=2)
        return {"E0": float(spec.energies[0]), "E1": float(spec.energies[1]), "method": spec.method,
                "m": [int(v) for v in spec.m], "residuals": [float(v) for v in spec.residuals],
                "seconds": time.perf_counter() - t0}

    value = cache.get("graph_levels", {"p": 7, "q": 3, "rings": rings, "levels": 2}, compute)
    timings[f"graph_levels_l{rings}"] = value["seconds"]
    return value


def _continuum_levels(rings: int) -> dict:
    from ..continuum.spectrum import asymptotic_energies, continuum_levels

    spec = continuum_levels(7, 3, rings=rings, levels=2)
    asym = asymptotic_energies(7, 3, rings=rings)
    return {"E0": float(spec.energies[0]), "E1": float(spec.energies[1]), "k0": float(spec.k[0]),
            "k1": float(spec.k[1]), "E0_asym": asym["E0"], "E1_asym": asym["E1"], "E_inf": asym["E_inf"],
            "radius": spec.radius}


# ----------------------------------------------------------------------------
# sections
# ----------------------------------------------------------------------------

def _section_geometry() -> Section:
    rows = []
    flags = []
    for p in (7, 8, 9, 10, "inf"):
        pp = math.inf if p == "inf" else p
        c = geometry.tiling_constants(pp, 3)
        d0_p, h_p = PAPER["geometry"][p]
        # the p = inf entries are printed as "1" and "1/2": compare them at the table's 6 decimals
        dec = 6 if p == "inf" else None
        f1, n1 = compare(d0_p, c.d0, "geometry_d0", p, decimals=dec)
        f2, n2 = compare(h_p, c.h, "geometry_h", p, decimals=dec)
        rows.append([p, _fmt(c.r0, 9), _fmt(c.d0, 9), d0_p, f1, _fmt(c.h, 9), h_p, f2,
                     _fmt(c.site_area, 9), _fmt(c.radius_constant, 6)])
        flags += [n for n in (n1, n2) if n]
    table = Table("geometry", ["p", "r0", "d0", "d0_paper", "d0_flag", "h", "h_paper", "h_flag", "site_area",
                               "radius_constant"], rows,
                  "Constants of {p,3}: r0 (Eqr0), d0 = d(r0, r0 e^{2pi i/p}), h = tanh d0 (adj6), area per site "
                  "pi(1-6/p)/4 (sum1c) and c = 4p/(p-6) in L = sqrt(N/(N+c)) (eq12).")
    text = ["The p = ∞ column is computed as a limit: cosh d0 = cos(π/p)/sin(π/q) → 1/sin(π/3), "
            "so d0 → ½ ln 3 and h → cos(π/3) = 1/2."]
    text += [f"Flagged: {n}" for n in flags]
    return Section("Geometry of {p,3} tessellations", "table in App. AppFS, Eqr0, adj6, eq12", text, [table])


def _section_counts(max_rings: int) -> Section:
    sizes = ring_sizes(7, 3, max(max_rings, 10))
    rows = []
    notes = []
    for ell in range(1, len(sizes) + 1):
        n = int(sizes[:ell].sum())
        L = geometry.effective_radius(n)
        pn = PAPER["N"][ell - 1] if ell <= 10 else ""
        pr = PAPER["N_ring"][ell - 1] if ell <= 8 else ""
        pl = PAPER["L"][ell - 1] if ell <= 10 else ""
        fl, nl = compare(pl, L, "L", ell) if pl else ("", "")
        closed = round(7 * (((3 + 5**0.5) / 2) ** ell + ((3 - 5**0.5) / 2) ** ell - 2))
        ok = "" if (not pn or int(pn) == n) else "≠?"
        rows.append([ell, int(sizes[ell - 1]), pr, n, pn, ok, closed, _fmt(L, 10), pl, fl])
        if nl:
            notes.append(f"l = {ell}: {nl}")
    table = Table("tab1_sizes", ["rings", "N_ring", "N_ring_paper", "N", "N_paper", "N_flag", "N_closed_form",
                                 "L", "L_paper", "L_flag"], rows,
                  "Sites per ring and in total (Tab1, AppTab1), the closed form of Tab1's caption, and the "
                  "effective disk radius L = sqrt(N/(N+28)) (eq12).")
    text = ["Counts come from the combinatorial ring construction; the closed form "
            "N = 7[((3+√5)/2)^ℓ + ((3−√5)/2)^ℓ − 2] is printed as an independent check."]
    text += [f"Flagged: {n}" for n in notes]
    return Section("Lattice sizes and effective radius", "Tab1, AppTab1, eq12", text, [table])


def _open_question(records: list[dict]) -> list[str]:
    """Describe how the signed graph-continuum relative error behaves as l grows (App. AppSpec)."""
    out = []
    for key in ("E0", "E1"):
        rel = np.array([(r[f"{key}_graph"] - r[f"{key}_continuum"]) / abs(r[f"{key}_graph"]) for r in records])
        rings = np.array([r["rings"] for r in records])
        sign_change = np.nonzero(np.diff(np.sign(rel)) != 0)[0]
        parts = [f"{key}: (E_graph - E_cont)/|E_graph| = " + ", ".join(f"{v:+.2e}" for v in rel) +
                 f" for l = 1..{rings[-1]}."]
        if sign_change.size:
            i = sign_change[-1]
            parts.append(f"It changes sign between l = {rings[i]} and {rings[i + 1]} (the graph level moves from "
                         "below to above the continuum level),")
            tail = rel[i + 1:]
            if tail.size >= 3 and np.all(np.diff(tail) > 0):
                d1, d2 = tail[-2] - tail[-3], tail[-1] - tail[-2]
                limit = tail[-1] - d2 * d2 / (d2 - d1) if d2 < d1 else float("nan")
                parts.append(f"then grows monotonically with shrinking increments ({d1:.1e}, {d2:.1e} over the "
                             f"last rings): it saturates (Aitken estimate of the limit {limit:.2e}) instead of "
                             "decreasing to zero.")
            else:
                parts.append("and does not settle into a monotone trend within the computed range.")
        elif np.all(np.diff(np.abs(rel)) < 0):
            parts.append("Its magnitude decreases monotonically over the computed range.")
        out.append(" ".join(parts))
    if records[-1]["rings"] >= 10:
        worst = max(r["residual_max"] for r in records)
        out.insert(0, "The paper's open question (App. AppSpec): does the relative error between graph and "
                      "continuum keep decreasing as l -> infinity? The computed levels (largest residual "
                      f"||H psi - E psi|| = {worst:.1e}) say:")
    return out


def _section_spectrum(cache: Cache, max_rings: int, timings: dict, progress: Callable[[str], None]) -> tuple[Section, list[dict]]:
    rows_out, records, notes = [], [], []
    for ell in range(1, max_rings + 1):
        progress(f"graph and continuum levels, l = {ell}/{max_rings}")
        g = _graph_levels(cache, ell, timings)
        c = _continuum_levels(ell)
        n = int(ring_sizes(7, 3, ell).sum())
        rec = {"rings": ell, "sites": n, "radius": c["radius"], "E0_graph": g["E0"], "E0_continuum": c["E0"],
               "E0_asymptotic": c["E0_asym"], "E1_graph": g["E1"], "E1_continuum": c["E1"],
               "E1_asymptotic": c["E1_asym"], "method": g["method"],
               "residual_max": max(g["residuals"]), "m_E1": g["m"][1]}
        records.append(rec)
        row = [ell, n, _fmt(c["radius"], 10)]
        for key in ("E0_graph", "E0_continuum", "E0_asymptotic", "E1_graph", "E1_continuum", "E1_asymptotic"):
            row.append(_fmt(rec[key], 12))
        rows_out.append(row)
        if ell <= 10:
            for key in ("E0_graph", "E0_continuum", "E0_asymptotic", "E1_graph", "E1_continuum", "E1_asymptotic"):
                flag, note = compare(PAPER[key][ell - 1], rec[key], key, ell)
                if flag:
                    notes.append((ell, key, PAPER[key][ell - 1], rec[key], flag, note))
    table = Table("s1", ["rings", "sites", "radius", "E0_graph", "E0_continuum", "E0_asymptotic", "E1_graph",
                         "E1_continuum", "E1_asymptotic"], rows_out,
                  "SuppTab1 (and the energy rows of Tab1): lowest levels of H = -A on the l-ring {7,3} graph, of "
                  "H_cont = -3 - (3/4)h^2 Delta_g on the disk of radius L (spec1, spec2), and the asymptotic "
                  "formulas spec11/spec17 (eq19).")
    # side by side with the paper
    side_rows = []
    for rec in records:
        ell = rec["rings"]
        if ell > 10:
            continue
        row = [ell]
        for key in ("E0_graph", "E0_continuum", "E0_asymptotic", "E1_graph", "E1_continuum", "E1_asymptotic"):
            flag, _ = compare(PAPER[key][ell - 1], rec[key], key, ell)
            row += [_fmt(rec[key], 6), PAPER[key][ell - 1], flag]
        side_rows.append(row)
    cols = ["rings"]
    for key in ("E0_graph", "E0_continuum", "E0_asymptotic", "E1_graph", "E1_continuum", "E1_asymptotic"):
        cols += [key, f"{key}_paper", f"{key}_flag"]
    side = Table("s1_vs_paper", cols, side_rows,
                 "Computed values (6 decimals) beside the paper's printed ones; ≠ marks a difference larger than "
                 "half a unit of the last printed digit.")
    rel_rows = []
    for rec in records:
        r0 = (rec["E0_graph"] - rec["E0_continuum"]) / abs(rec["E0_graph"])
        r1 = (rec["E1_graph"] - rec["E1_continuum"]) / abs(rec["E1_graph"])
        rel_rows.append([rec["rings"], rec["sites"], f"{r0:.3e}", f"{r1:.3e}", rec["method"],
                         f"{rec['residual_max']:.1e}"])
    rel = Table("graph_vs_continuum", ["rings", "sites", "rel_err_E0", "rel_err_E1", "graph_method",
                                       "max_residual"], rel_rows,
                "Relative difference (E_graph - E_continuum)/|E_graph| and the residual ||H psi - E psi|| of the "
                "graph eigenpairs.")
    text = [f"E1 of the graph lies in the angular-momentum sectors m = ±1 for every l (computed: m = "
            f"{sorted({r['m_E1'] for r in records})}), the ground state in m = 0, as for the continuum "
            "levels (n, m) = (1, 0) and (1, ±1)."]
    for ell, key, printed, value, flag, note in notes:
        text.append(f"Flagged {key} at l = {ell}: printed {printed}, computed {value:.6f} ({note}).")
    text += _open_question(records)
    return Section("Ground state and first excited state: graph vs continuum", "SuppTab1, Tab1, spec1, spec2, "
                   "spec11, spec17, eq19", text, [table, side, rel]), records


def _section_fig2(records: list[dict], out: Path, progress) -> Section:
    import matplotlib.pyplot as plt

    from ..continuum.spectrum import dirichlet_levels
    from ..plots.paper import plot_levels, plot_partition
    from ..graph.spectrum import full_spectrum

    progress("Fig2: partition functions for l = 4")
    lat = ring_lattice(7, 3, 4)
    e_graph = full_spectrum(lat)
    e_graph = e_graph[e_graph < 0]
    # all continuum levels below zero: enlarge the (n, m) table until its edges are above zero
    n_max, m_max = 6, 12
    while True:
        tab = dirichlet_levels(7, 3, rings=4, n_max=n_max, m_max=m_max)
        e = tab.energies  # shape (m, n)
        if np.all(e[:, -1] > 0) and np.all(e[-1, :] > 0):
            break
        n_max, m_max = n_max + 4, m_max + 8
    mult = np.where(np.arange(e.shape[0])[:, None] == 0, 1, 2) * np.ones_like(e)
    neg = e < 0
    e_cont, w_cont = e[neg], mult[neg]
    beta = np.linspace(0.05, 6.0, 120)
    z_graph = np.exp(-beta[:, None] * e_graph[None, :]).sum(axis=1)
    z_cont = (w_cont[None, :] * np.exp(-beta[:, None] * e_cont[None, :])).sum(axis=1)
    fig, (ax, ax2) = plt.subplots(1, 2, figsize=(12.0, 4.8), layout="constrained",
                                  gridspec_kw={"width_ratios": [1.6, 1.0]})
    plot_levels(records, ax=ax)
    ax.set_title("(a) lowest levels vs rings (l = 1 is off scale)", fontsize=11)
    plot_partition(beta, z_graph, z_cont, float(e_graph.min()), ax=ax2)
    ax2.set_title(r"(b) $\ell=4$: $Z=\sum_n\Theta(-E_n)\,e^{-\beta E_n}$", fontsize=11)
    ax2.xaxis.label.set_size(12)
    ax2.yaxis.label.set_size(12)
    ax2.tick_params(labelsize=10)
    ax2.legend(fontsize=10)
    fig_obj = _save_figure(fig, out, "fig2", "Fig2: (a) E0 (blue) and E1 (orange) of the graph (filled) and the "
                           "continuum disk (open) vs number of rings, with the asymptotes of Eq. (eq19); (b, the "
                           "paper's inset) partition function over negative energies for l = 4, graph vs disk.")
    zt = Table("fig2_partition_l4", ["beta", "Z_graph", "Z_continuum"],
               [[_fmt(b, 4), _fmt(a, 8), _fmt(c, 8)] for b, a, c in zip(beta[::10], z_graph[::10], z_cont[::10])],
               f"Z(beta) for l = 4 over {e_graph.size} negative graph levels and {int(w_cont.sum())} negative "
               "continuum states (degenerate ±m counted twice).")
    return Section("Spectrum vs number of rings; partition function", "Fig2", [], [zt], [fig_obj])


def _section_fig1(out: Path) -> Section:
    import matplotlib.pyplot as plt

    from ..plots.paper import plot_tessellation

    fig, ax = plt.subplots(figsize=(6.2, 5.4), layout="constrained")
    plot_tessellation(rings=3, background_rings=7, ax=ax)
    f = _save_figure(fig, out, "fig1", "Fig1: the {7,3} tessellation in the Poincaré disk (grey, 7 rings) and "
                     "the l = 3 graph (black) with its sites coloured by ring; edges drawn as geodesics.")
    return Section("The {7,3} lattice in the Poincaré disk", "Fig1, AppGraph", [], [], [f])


def _section_scaling(out: Path, progress) -> Section:
    import matplotlib.pyplot as plt

    from ..compare.sums import fit_counting
    from ..plots.scaling import plot_counting, plot_formal_operator, plot_frame_angles
    from ..compare.scaling import frame_angles

    progress("FigS1, FigScos3delta, FigSh")
    figs = []
    lat4 = ring_lattice(7, 3, 4)
    fit = fit_counting(lat4)
    fig, ax = plt.subplots(figsize=(6.0, 4.2), layout="constrained")
    plot_counting(lat4, ax=ax)
    figs.append(_save_figure(fig, out, "figS1", "FigS1: counting function N(r) of the l = 4 lattice against "
                             "rho = (1+r^2)/(1-r^2) with the fitted line s*rho + b (sum4)."))
    angles = frame_angles(ring_lattice(7, 3, 5))
    fig, ax = plt.subplots(figsize=(6.0, 4.2), layout="constrained")
    plot_frame_angles(angles, ax=ax)
    figs.append(_save_figure(fig, out, "figScos3delta", "FigScos3delta: cos(3 delta_i), delta_i = chi_i - phi_i, "
                             "averaged at equal radius for l = 5; red bars mark radii where r -> delta is not "
                             "unique."))
    hs = (angles.h, 0.15, 0.05)
    fig, axes = plt.subplots(1, 3, figsize=(13.5, 4.0), layout="constrained")
    for h, ax in zip(hs, axes):
        plot_formal_operator(angles, h=h, ax=ax)
    figs.append(_save_figure(fig, out, "figSh", "FigSh: A_h f - 3f for f = cos[pi d(r,0)] (adj34) with the "
                             "quadratic (adj35) and cubic (adj36) approximations, at the lattice h = 0.275798 and "
                             "two smaller h."))
    flag, note = compare(PAPER["b_counting"], fit.intercept, "b_counting", 4)
    t = Table("figS1_fit", ["rings", "slope", "slope_expected", "b", "b_paper", "b_flag"],
              [[4, _fmt(fit.slope, 4), _fmt(fit.expected_slope, 1), _fmt(fit.intercept, 4), PAPER["b_counting"],
                flag]], "Fit of N(r) = s*rho + b over the distinct site radii of the l = 4 lattice.")
    text = [f"Flagged b: {note}"] if flag else []
    return Section("Sums as integrals and the formal operator A_h", "FigS1, FigScos3delta, FigSh, sum4, adj34–adj36",
                   text, [t], figs)


def _section_green(cache: Cache, max_rings: int, out: Path, progress) -> Section:
    import matplotlib.pyplot as plt

    from ..compare.correlation import collapse_measure
    from ..compare.green import compare_green
    from ..plots.green import plot_fig3_row

    source = 10  # a site on ring 2, as in the paper's Fig3
    omegas = (-2.95, complex(-2.5, 0.1))
    figs = []
    for tag, omega in zip(("a", "b"), omegas):
        progress(f"Fig3: Green functions at omega = {omega}")
        fig, axes = plt.subplots(2, 3, figsize=(13.0, 8.2), layout="constrained",
                                 gridspec_kw={"width_ratios": [1, 1, 1.4]})
        for row, ell in zip(axes, (6, 3)):
            plot_fig3_row(ring_lattice(7, 3, ell), omega, source, axes=row)
            row[0].set_ylabel(fr"$\ell = {ell}$", fontsize=13)
        part = "" if isinstance(omega, float) else " (real part)"
        figs.append(_save_figure(fig, out, f"fig3{tag}", f"Fig3 ({'upper' if tag == 'a' else 'lower'} panel): "
                                 f"omega = {omega}{part}, source site {source} on ring 2; top row l = 6, bottom "
                                 "row l = 3 (the paper's insets). Left: graph G_ij, middle: continuum prediction of "
                                 "eq21 (dot size ~ |F|^(1/2), blue > 0, red < 0); right: mean ± standard deviation "
                                 "versus hyperbolic distance, graph and continuum."))

    def compute(ell, omega):
        cmp = compare_green(ring_lattice(7, 3, ell), omega, source)
        keep = np.arange(cmp.graph.shape[0]) != source
        return {"rel_l2": cmp.rel_l2, "terms": cmp.terms, "tail": cmp.tail_estimate,
                "collapse_graph": collapse_measure(cmp.distance[keep], cmp.graph[keep].real),
                "collapse_continuum": collapse_measure(cmp.distance[keep], cmp.continuum[keep].real)}

    rows = []
    for ell in range(3, max(8, min(max_rings, 10)) + 1):
        progress(f"Fig3: graph vs continuum Green function, l = {ell}")
        for omega in omegas:
            key = {"rings": ell, "omega": [omega.real, omega.imag] if isinstance(omega, complex) else omega,
                   "source": source}
            v = cache.get("green_compare", key, lambda: compute(ell, omega))
            rows.append([ell, str(omega), f"{v['rel_l2']:.4f}", f"{v['collapse_graph']:.4f}",
                         f"{v['collapse_continuum']:.4f}", v["terms"], f"{v['tail']:.1e}"])
    table = Table("fig3_green", ["rings", "omega", "rel_l2", "collapse_graph", "collapse_continuum",
                                 "m_terms", "tail_estimate"], rows,
                  "Relative L2 distance between the graph column G_ij(omega) and the right-hand side of eq21 "
                  "over all sites but the source (site 10, ring 2); collapse = spread within distance bins "
                  "relative to the mean (0 for a function of hyperbolic distance alone); m_terms and "
                  "tail_estimate describe the truncated sum of green36.")
    text = ["The paper shows the agreement of Fig3 graphically; the relative L2 distances quantify it. The "
            "collapse number of the graph data measures how far G_ij is from a function of d(z_i, z_j) alone "
            "(emergent conformal symmetry for large l)."]
    return Section("Green functions: graph vs continuum and emergent conformal symmetry",
                   "Fig3, eq20–eq23, green33–green38, path8", text, [table], figs)


# ----------------------------------------------------------------------------
# writers
# ----------------------------------------------------------------------------

def _md_table(t: Table) -> list[str]:
    lines = [f"*{t.caption}* (`table_{t.name}.csv`)", "", "| " + " | ".join(t.columns) + " |",
             "|" + "---|" * len(t.columns)]
    for r in t.rows:
        lines.append("| " + " | ".join(_fmt(v) for v in r) + " |")
    return lines + [""]


def _write_md(sections: list[Section], header: list[str], out: Path) -> None:
    lines = list(header)
    for s in sections:
        lines += [f"## {s.title}", "", f"Reproduces: {s.labels}", ""]
        for p in s.text:
            lines += [p, ""]
        for t in s.tables:
            lines += _md_table(t)
        for f in s.figures:
            lines += [f"![{f.name}](fig_{f.name}.png)", "", f"*{f.caption}* (vector: `fig_{f.name}.svg`)", ""]
    (out / "report.md").write_text("\n".join(lines))


def _write_html(sections: list[Section], header: list[str], out: Path) -> None:
    e = html.escape
    parts = ["<!DOCTYPE html>", '<html lang="en">', "<head>", '<meta charset="utf-8">',
             "<title>hyperlattice: reproduction of Boettcher et al., PRA 102, 032208</title>",
             "<style>body{font-family:sans-serif;max-width:1100px;margin:2em auto;line-height:1.4}"
             "table{border-collapse:collapse;font-size:0.85em;margin:0.5em 0}"
             "td,th{border:1px solid #bbb;padding:2px 6px;text-align:right}"
             "th{background:#eee}td.flag{color:#b00;font-weight:bold}"
             "img{max-width:100%}figcaption{font-size:0.9em;color:#333}.cap{font-style:italic}</style>",
             "</head>", "<body>"]
    for line in header:
        if line.startswith("# "):
            parts.append(f"<h1>{e(line[2:])}</h1>")
        elif line:
            parts.append(f"<p>{e(line)}</p>")
    for s in sections:
        parts.append(f"<h2>{e(s.title)}</h2>")
        parts.append(f"<p><b>Reproduces:</b> {e(s.labels)}</p>")
        for p in s.text:
            parts.append(f"<p>{e(p)}</p>")
        for t in s.tables:
            parts.append(f'<p class="cap">{e(t.caption)} (<code>table_{e(t.name)}.csv</code>)</p>')
            parts.append("<table><thead><tr>" + "".join(f"<th>{e(c)}</th>" for c in t.columns) + "</tr></thead><tbody>")
            for r in t.rows:
                cells = []
                for c, v in zip(t.columns, r):
                    cls = ' class="flag"' if c.endswith("flag") and v else ""
                    cells.append(f"<td{cls}>{e(_fmt(v))}</td>")
                parts.append("<tr>" + "".join(cells) + "</tr>")
            parts.append("</tbody></table>")
        for f in s.figures:
            b64 = base64.b64encode(f.png).decode("ascii")
            parts.append(f'<figure><img alt="{e(f.name)}" src="data:image/png;base64,{b64}">'
                         f"<figcaption>{e(f.caption)}</figcaption></figure>")
    parts += ["</body>", "</html>", ""]
    (out / "report.html").write_text("\n".join(parts))


# ----------------------------------------------------------------------------
# entry point
# ----------------------------------------------------------------------------

def reproduce(out_dir: str | Path = "reproduction", max_rings: int = 10, *, cache: Cache | None = None,
              progress: Callable[[str], None] | None = None) -> dict:
    """Recompute the paper's tables and figures into ``out_dir``; return a summary dict.

    Parameters
    ----------
    out_dir : path
        Output directory (created if needed).
    max_rings : int
        Largest number of rings in the spectrum tables (1..14; the paper's tables stop at 10).
    cache : Cache, optional
        Result cache (default: :class:`Cache` in the default directory).
    progress : callable, optional
        Called with a short message before each stage.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    if isinstance(max_rings, bool) or not isinstance(max_rings, (int, np.integer)) or not 2 <= max_rings <= 14:
        raise ValueError(f"max_rings must be an integer between 2 and 14, got {max_rings!r}.")
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    cache = cache if cache is not None else Cache()
    progress = progress or (lambda msg: None)
    timings: dict = {}
    t_start = time.perf_counter()
    plt.rcParams["svg.hashsalt"] = "hyperlattice"  # deterministic SVG ids

    sections = [_section_geometry(), _section_counts(max_rings), _section_fig1(out)]
    spec_section, records = _section_spectrum(cache, max_rings, timings, progress)
    sections += [spec_section, _section_fig2(records, out, progress)]
    sections.append(_section_green(cache, max_rings, out, progress))
    sections.append(_section_scaling(out, progress))

    header = ["# Reproduction of Boettcher, Bienias, Belyansky, Kollár, Gorshkov, PRA 102, 032208 (2020)", "",
              f"Computed by hyperlattice {__version__} with max_rings = {max_rings}. Every number below is computed "
              "by the package; the paper's printed values stand beside them. A flag (≠) marks a printed value "
              "that differs from the computation by more than half a unit of its last printed digit; the reason "
              "is given where known.", ""]
    for s in sections:
        for t in s.tables:
            t.write(out)
    _write_md(sections, header, out)
    _write_html(sections, header, out)
    timings["total"] = time.perf_counter() - t_start
    (out / "timings.json").write_text(json.dumps(timings, indent=1, sort_keys=True))
    return {"out_dir": str(out), "sections": [s.title for s in sections], "records": records,
            "cache_hits": cache.hits, "cache_misses": cache.misses, "seconds": timings["total"]}
