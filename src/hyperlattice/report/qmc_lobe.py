"""Report section "Beyond mean field: the Mott lobe from quantum Monte Carlo".

The QMC boundaries are stored (``qmc_lobe_scan.json`` next to this module, written by
``benchmarks/qmc_lobe_scan.py``: a scan takes far longer than a report run); mean field, the
strong-coupling expansion and the references are computed by the run.
"""

from __future__ import annotations

import json
import math
from importlib import resources
from pathlib import Path
from typing import Callable

from .writers import Section, Table, save_figure as _save_figure

__all__ = ["stored_scan", "qmc_lobe_section", "tip_rows", "extrapolation_rows", "headline", "verdict",
           "TIP_HEADER", "EXTRAPOLATION_HEADER", "system_label"]

SCAN_FILE = "qmc_lobe_scan.json"
SCAN_COMMAND = "PYTHONPATH=src python benchmarks/qmc_lobe_scan.py --stage tip"


def stored_scan() -> dict:
    """The stored QMC lobe scan (``{"meta": ..., "boundaries": [...]}``), see :mod:`hyperlattice.compare.qmc_lobe`.

    Returns
    -------
    dict
        The scan as written by ``benchmarks/qmc_lobe_scan.py``.

    Examples
    --------
    >>> from hyperlattice.report.qmc_lobe import stored_scan
    >>> scan = stored_scan()
    >>> scan["meta"]["beta_t"] > 0 and len(scan["boundaries"]) > 0
    True
    """
    text = resources.files("hyperlattice.report").joinpath(SCAN_FILE).read_text(encoding="utf-8")
    return json.loads(text)


def _f(x: float, d: int = 4) -> str:
    return "—" if not math.isfinite(x) else f"{x:.{d}f}"


def qmc_lobe_section(out: Path, progress: Callable[[str], None]) -> Section:
    """The QMC lobe section: boundaries table, tips table, figure, the mean-field verdict.

    Parameters
    ----------
    out : Path
        The report directory (must exist); the figure ``fig_qmc_lobe.png``/``.svg`` goes there.
    progress : callable
        Called with one line of progress text.

    Returns
    -------
    Section
        Anchor ``"qmc-lobe"``, part ``"beyond"``; its provenance names the stored scan.

    Raises
    ------
    ValueError
        If ``out`` is not a path.
    """
    from .. import _validate
    from ..compare.qmc_lobe import qmc_lobe
    from ..plots.qmc_lobe import qmc_lobe_figure, qmc_tip_figure

    out = _validate.directory("out", out)
    progress("beyond the paper: the Mott lobe from quantum Monte Carlo")
    scan = stored_scan()
    lobe = qmc_lobe(scan)
    fig = qmc_lobe_figure(lobe)
    figs = [_save_figure(fig, out, "qmc_lobe", "The n = 1 Mott lobe (μ/U against t/U) of each graph: QMC "
                         "boundaries μ± (points, ⟨N⟩ = M ± 1/2 at the stated βt, error bars from the QMC errors of "
                         "⟨N⟩ and κ), Gutzwiller mean field (dashed) and the third-order strong-coupling expansion "
                         "(solid) on the same graph."),
            _save_figure(qmc_tip_figure(lobe), out, "qmc_tip", "The lobe tip from QMC. Left: the Mott gap "
                         "μ+ − μ− against t/U (filled: βt = 8, open: βt = 4) with the straight lines in Δ (solid) "
                         "and in Δ² (dotted) through the three largest t/U. Right: the pseudo-tips (their midpoint) "
                         "against 1/M, the mean-field tips of a 3-regular graph and of the infinite lattice (through "
                         "ρ), and the periodic clusters' extrapolation to 1/M = 0.")]
    rows = [[system_label(r["system"]), str(r["sites"]), f"{r['t_over_U']:.2f}", f"{r['beta_t']:g}", str(r["nmax"]), r["side"],
             f"{r['mu']:.4f} ± {_f(r['mu_err'])}", _f(r["mu_mean_field"]), _f(r["mu_strong_coupling"])]
            for r in lobe.rows]
    t1 = Table("qmc_lobe_boundaries", ["graph", "sites", "t/U", "βt", "nmax", "side", "μ/U QMC", "μ/U mean field",
                                       "μ/U strong coupling"], rows,
               "Boundaries of the n = 1 Mott lobe: QMC (stored scan) against mean field and the third-order "
               "strong-coupling expansion on the same graph (units of U).")
    t2 = Table("qmc_lobe_tips", TIP_HEADER, tip_rows(lobe),
               "Lobe tips (t/U)_c per graph and temperature: mean field (3 − 2√2)/λ_max and the strong-coupling "
               "series' μ+ = μ− on the same graph; the QMC gap μ+ − μ− continued to zero by straight lines in Δ² "
               "(the mean-field form, zν = 1/2) and in Δ (zν = 1) through its three largest t/U; the pseudo-tip is "
               "their midpoint, its error half their difference and the statistical errors; zν from a free power "
               "law where four gaps exist. βδ: β times the splitting of the two lowest first-order particle "
               "levels, 2t(λ1 − λ2); βδ ≫ 1 means the finite-temperature boundary is the ground state's.")
    t3 = Table("qmc_lobe_extrapolation", EXTRAPOLATION_HEADER, extrapolation_rows(lobe),
               "The pseudo-tips extrapolated to the infinite graph, x_c(M) = x∞ + c/M (and + c/√M: the "
               "difference is the stated systematic error), for the periodic clusters (no boundary) and the "
               "flakes (whose boundary fraction does not vanish: their limit is not the bulk); χ² of each "
               "weighted fit over its dof (sizes − 2; — with two sizes, where the line is not tested).")
    text = verdict(lobe)
    meta = scan.get("meta", {})
    provenance = [f"The QMC boundaries are the stored scan {SCAN_FILE} ({meta.get('note', '')}); regenerate "
                  f"with `{SCAN_COMMAND}`. Mean field, strong coupling, the fits and the references are computed "
                  "by this run."]
    return Section("Beyond mean field: the Mott lobe from quantum Monte Carlo", ("eq13",), text, [t1, t2, t3], figs,
                   anchor="qmc-lobe", part="beyond", provenance=provenance)


TIP_HEADER = ["graph", "sites", "βt", "nmax", "βδ", "tip mean field", "tip strong coupling", "QMC Δ² line",
              "QMC Δ line", "QMC pseudo-tip", "zν"]
EXTRAPOLATION_HEADER = ["graphs", "βt", "sizes", "x∞ (1/M)", "x∞ (1/√M)", "x∞", "χ²/dof (1/M)", "χ²/dof (1/√M)"]


def _check_lobe(lobe) -> None:
    from ..compare.qmc_lobe import QMCLobe

    if not isinstance(lobe, QMCLobe):
        raise ValueError(f"lobe must be a QMCLobe (from compare.qmc_lobe.qmc_lobe), got {type(lobe).__name__}.")


def _pm(v: float, e: float, d: int = 4) -> str:
    return "—" if not math.isfinite(v) else f"{v:.{d}f} ± {_f(e, d)}"


def system_label(spec: str) -> str:
    """The graph of a scan's system spec as a reader names it: ``"flake:3"`` -> ``"flake ℓ = 3"``,
    ``"cluster:klein"`` -> ``"cluster klein"``, ``"square:6"`` -> ``"square L = 6"``.

    Parameters
    ----------
    spec : str
        A system spec of a QMC lobe scan (``"flake:3"``, ``"cluster:klein"``, ``"square:6"``).

    Returns
    -------
    str
        The graph's name in the report's tables (an unknown kind is returned as given).

    Examples
    --------
    >>> from hyperlattice.report.qmc_lobe import system_label
    >>> system_label("flake:3"), system_label("cluster:PSL(2,13)"), system_label("square:6")
    ('flake ℓ = 3', 'cluster PSL(2,13)', 'square L = 6')
    """
    kind, _, arg = spec.partition(":")
    return {"flake": f"flake ℓ = {arg}", "cluster": f"cluster {arg}", "square": f"square L = {arg}"}.get(kind, spec)


def tip_rows(lobe) -> list:
    """The rows of the tips table (one per graph, temperature and cutoff with a QMC gap).

    Parameters
    ----------
    lobe : QMCLobe
        From :func:`hyperlattice.compare.qmc_lobe.qmc_lobe`.

    Returns
    -------
    list of list of str
        In the columns of :data:`TIP_HEADER`.
    """
    _check_lobe(lobe)
    out = []
    for s in lobe.systems:
        for d in sorted(s["tips"], key=lambda d: (-d["beta_t"], -d["nmax"])):
            if len(d["gaps"]) < 2:
                continue
            out.append([system_label(s["system"]), str(s["sites"]), f"{d['beta_t']:g}", str(d["nmax"]), f"{d['beta_splitting']:.1f}",
                        f"{s['tip_mean_field']:.4f}", _f(s["tip_strong_coupling"]),
                        _pm(d["tip_sqrt"], d["tip_sqrt_err"]), _pm(d["tip_linear"], d["tip_linear_err"]),
                        _pm(d["tip"], d["tip_err"]), _pm(d["exponent"], d["exponent_err"], 2)])
    return out


def extrapolation_rows(lobe) -> list:
    """The rows of the extrapolation table (:data:`EXTRAPOLATION_HEADER`)."""
    _check_lobe(lobe)
    out = []
    for f in lobe.finite_size:
        out.append([f["kind"] + "s", f"{f['beta_t']:g}", " + ".join(str(m) for m in f["sites"]),
                    _pm(f["tip"], f["tip_err"]), _pm(f["tip_sqrt_form"], f["tip_sqrt_form_err"]),
                    _pm(f["tip"], math.hypot(f["tip_err"], f["systematic"])), _chi2(f["chi2"], f["dof"]),
                    _chi2(f["chi2_sqrt_form"], f["dof"])])
    return out


def _chi2(chi2: float, dof: int) -> str:
    """χ²/dof as "0.52/1"; "—" when the line passes through every point (two sizes, dof = 0)."""
    return "—" if dof < 1 else f"{chi2:.2f}/{dof}"


def headline(lobe) -> dict:
    """The numbers the section's verdict quotes (largest cluster, extrapolation, mean-field offsets).

    Parameters
    ----------
    lobe : QMCLobe

    Returns
    -------
    dict
        ``cluster`` (largest periodic cluster's system, sites, beta_t, tip, tip_err), ``infinite``
        (x∞ and its total error at the lowest temperature, the cluster sizes, χ² of the 1/M and
        1/√M fits and their dof; None without two clusters), ``mf_cluster``
        ((3 − 2√2)/3), ``mf_rho``, and the fractions by which mean field lies below the QMC:
        ``off_cluster`` (same graph), ``off_infinite_cluster`` and ``off_infinite_rho`` (the two
        infinite-lattice mean-field tips against x∞), ``off_square`` (z = 4) and ``off_cubic`` (z = 6).
    """
    _check_lobe(lobe)
    z3 = (3.0 - 2.0 * math.sqrt(2.0)) / 3.0
    clusters = [s for s in lobe.systems if s["system"].startswith("cluster:")
                and any(math.isfinite(d["tip"]) and d["nmax"] == 3 for d in s["tips"])]
    out = {"mf_cluster": z3, "mf_rho": lobe.infinite_tip_mean_field, "cluster": None, "infinite": None,
           "off_square": 1.0 - lobe.square["mean_field"] / lobe.square["exact"],
           "off_cubic": 1.0 - lobe.square["cubic_mean_field"] / lobe.square["cubic_exact"]}
    if clusters:
        c = max(clusters, key=lambda s: s["sites"])
        d = max((d for d in c["tips"] if math.isfinite(d["tip"]) and d["nmax"] == 3), key=lambda d: d["beta_t"])
        out["cluster"] = {"system": c["system"], "sites": c["sites"], "beta_t": d["beta_t"], "tip": d["tip"],
                          "tip_err": d["tip_err"], "mean_field": c["tip_mean_field"]}
        out["off_cluster"] = 1.0 - c["tip_mean_field"] / d["tip"]
    fs = [f for f in lobe.finite_size if f["kind"] == "cluster"]
    if fs:
        f = max(fs, key=lambda f: f["beta_t"])
        err = math.hypot(f["tip_err"], f["systematic"])
        out["infinite"] = {"beta_t": f["beta_t"], "tip": f["tip"], "tip_err": err, "sites": f["sites"],
                           "chi2": f["chi2"], "chi2_sqrt_form": f["chi2_sqrt_form"], "dof": f["dof"]}
        out["off_infinite_cluster"] = 1.0 - z3 / f["tip"]
        out["off_infinite_rho"] = 1.0 - lobe.infinite_tip_mean_field / f["tip"]
    return out


def verdict(lobe) -> list:
    """The section's sentences, every number from :func:`headline` and the lobe."""
    _check_lobe(lobe)
    sq = lobe.square
    h = headline(lobe)
    text = [
        "Beyond mean field: where the n = 1 Mott lobe of the Bose–Hubbard model ends on a "
        "{7,3} graph, from a sign-free quantum Monte Carlo (SSE), against Gutzwiller mean field and the third-order "
        "strong-coupling expansion of Freericks and Monien written for the graph's own walk counts. Each QMC point "
        "is the chemical potential where ⟨N⟩ = M ± 1/2: on a finite graph the ground state's E0(M±1) − E0(M). "
        "A finite graph keeps a gap; its pseudo-tip is the gap μ+ − μ− continued to zero (Δ² and Δ straight "
        "lines, table 2), and the infinite lattice is reached through the periodic clusters, which have no "
        "boundary (a flake's boundary holds a finite fraction of its sites at every size).",
        f"Mean field on a 3-regular graph (every periodic cluster) ends the lobe at t/U = (3 − 2√2)/3 = "
        f"{h['mf_cluster']:.4f}; on the infinite {{7,3}} lattice through its spectral radius ρ = {lobe.rho:.5f} "
        f"(the limit of the flakes' λ_max, below the coordination 3 because the lattice is non-amenable) at "
        f"{lobe.infinite_tip_mean_field:.6f}; the continuum's band bottom (the paper's dictionary, λ = "
        f"{lobe.continuum['lambda_max']:.6f}) gives {lobe.continuum['tip_mean_field']:.6f}. On the square lattice "
        f"mean field gives {sq['mean_field']:.4f} against the exact {sq['exact']:.5f} (Capogrosso-Sansone et al. "
        f"2008): {h['off_square']:.0%} too small; the third-order series gives {sq['strong_coupling']:.4f}.",
    ]
    if h["cluster"]:
        c = h["cluster"]
        text.append(f"QMC: the largest periodic cluster ({c['system']}, {c['sites']} sites, βt = {c['beta_t']:g}) "
                    f"has its pseudo-tip at t/U = {c['tip']:.4f} ± {c['tip_err']:.4f}; mean field on the same graph "
                    f"({c['mean_field']:.4f}) is {h['off_cluster']:.0%} below it.")
    if h["infinite"]:
        f = h["infinite"]
        text.append(f"Extrapolated over the clusters (βt = {f['beta_t']:g}, 1/M and 1/√M forms), the infinite "
                    f"{{7,3}} lattice's tip is t/U = {f['tip']:.4f} ± {f['tip_err']:.4f}: mean field is "
                    f"{h['off_infinite_cluster']:.0%} too small with the uniform (z = 3) ansatz and "
                    f"{h['off_infinite_rho']:.0%} with ρ, against {h['off_square']:.0%} on the square lattice "
                    f"(z = 4) and {h['off_cubic']:.0%} on the simple cubic lattice (z = 6, exact tip "
                    f"{lobe.square['cubic_exact']:.5f}, Capogrosso-Sansone, Prokof'ev and Svistunov 2007). The "
                    f"shortfall times the coordination z is {3 * h['off_infinite_cluster']:.2f} on {{7,3}}, "
                    f"{4 * h['off_square']:.2f} on the square and {6 * h['off_cubic']:.2f} on the cubic lattice: "
                    "mean field's error on the tip's position goes as 1/z, and the curvature does not reduce it.")
        if f["dof"] >= 1:
            text.append(f"The {len(f['sites'])} cluster sizes ({', '.join(str(m) for m in f['sites'])} sites) test "
                        f"the form: χ² = {f['chi2']:.2f} for {f['dof']} degree{'s' if f['dof'] > 1 else ''} of freedom "
                        f"in 1/M and {f['chi2_sqrt_form']:.2f} in 1/√M.")
    return text


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
