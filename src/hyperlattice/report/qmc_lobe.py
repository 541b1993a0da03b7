"""Report section "Beyond mean field: the Mott lobe from quantum Monte Carlo" (issue 27, item 4).

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

__all__ = ["stored_scan", "qmc_lobe_section"]

SCAN_FILE = "qmc_lobe_scan.json"
SCAN_COMMAND = "PYTHONPATH=src python benchmarks/qmc_lobe_scan.py"


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
    from ..plots.qmc_lobe import qmc_lobe_figure

    out = _validate.directory("out", out)
    progress("beyond the paper: the Mott lobe from quantum Monte Carlo")
    scan = stored_scan()
    lobe = qmc_lobe(scan)
    fig = qmc_lobe_figure(lobe)
    figs = [_save_figure(fig, out, "qmc_lobe", "The n = 1 Mott lobe (μ/U against t/U) of each graph: QMC "
                         "boundaries μ± (points, ⟨N⟩ = M ± 1/2 at the stated βt, error bars from the QMC errors of "
                         "⟨N⟩ and κ), Gutzwiller mean field (dashed) and the third-order strong-coupling expansion "
                         "(solid) on the same graph.")]
    rows = [[r["system"], str(r["sites"]), f"{r['t_over_U']:.2f}", f"{r['beta_t']:g}", r["side"],
             f"{r['mu']:.4f} ± {_f(r['mu_err'])}", _f(r["mu_mean_field"]), _f(r["mu_strong_coupling"])]
            for r in lobe.rows]
    t1 = Table("qmc_lobe_boundaries", ["graph", "sites", "t/U", "βt", "side", "μ/U QMC", "μ/U mean field",
                                       "μ/U strong coupling"], rows,
               "Boundaries of the n = 1 Mott lobe: QMC (stored scan) against mean field and the third-order "
               "strong-coupling expansion on the same graph (units of U).")
    srows = []
    for s in lobe.systems:
        tq = s["tip_qmc_extrapolated"]
        srows.append([s["system"], str(s["sites"]), f"{s['lambda_max']:.4f}", f"{s['tip_mean_field']:.4f}",
                      _f(s["tip_strong_coupling"]),
                      f"{tq:.3f} ± {s['tip_qmc_extrapolated_err']:.3f}" if math.isfinite(tq) else "—",
                      f"{s['beta_splitting']:.1f}"])
    t2 = Table("qmc_lobe_tips", ["graph", "sites", "λ_max", "tip mean field", "tip strong coupling",
                                 "QMC pseudo-tip", "βδ"], srows,
               "Lobe tips (t/U)_c per graph: mean field (3 − 2√2)/λ_max, the strong-coupling series' μ+ = μ−, and "
               "the QMC gap μ+ − μ− continued linearly to zero from its two largest t/U (a finite graph keeps a "
               "gap; this is its pseudo-tip). βδ: β times the splitting of the two lowest first-order particle "
               "levels, 2t(λ1 − λ2); βδ ≫ 1 means the finite-temperature boundary is the ground state's.")
    sq = lobe.square
    text = [
        "Beyond mean field: where the n = 1 Mott lobe of the Bose–Hubbard model ends on a "
        "{7,3} graph, from a sign-free quantum Monte Carlo (SSE), against Gutzwiller mean field and the third-order "
        "strong-coupling expansion of Freericks and Monien written for the graph's own walk counts. Each QMC point "
        "is the chemical potential where ⟨N⟩ = M ± 1/2: on a finite graph the ground state's E0(M±1) − E0(M).",
        f"Mean field on the infinite {{7,3}} lattice (through ρ = {lobe.rho:.5f}) ends the lobe at t/U = "
        f"{lobe.infinite_tip_mean_field:.6f}; the continuum's band bottom (the paper's dictionary, λ = "
        f"{lobe.continuum['lambda_max']:.6f}) gives {lobe.continuum['tip_mean_field']:.6f}. On the square lattice "
        f"mean field gives {sq['mean_field']:.4f} against the exact {sq['exact']:.5f} (Capogrosso-Sansone et al. "
        f"2008): {1 - sq['mean_field'] / sq['exact']:.0%} too small; the third-order series gives "
        f"{sq['strong_coupling']:.4f}.",
    ]
    meta = scan.get("meta", {})
    provenance = [f"The QMC boundaries are the stored scan {SCAN_FILE} (βt = {meta.get('beta_t')}, "
                  f"{meta.get('sweeps_per_step')} sweeps per Newton step, nmax = {meta.get('nmax')}); regenerate "
                  f"with `{SCAN_COMMAND}`. Mean field, strong coupling and the references are computed by this run."]
    return Section("Beyond mean field: the Mott lobe from quantum Monte Carlo", ("eq13",), text, [t1, t2], figs,
                   anchor="qmc-lobe", part="beyond", provenance=provenance)


# every public function above checks its annotated argument types at the door (issue 19)
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
