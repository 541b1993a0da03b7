"""The report's section on the infinite lattice: the band bottom -rho with its error
bar and rigorous interval, why the graph-continuum error has a plateau, and the improved
dictionary's errors. The numbers come from :mod:`hyperlattice.compare.limits`; this module only
puts them into tables, sentences and one figure.
"""

from __future__ import annotations

from pathlib import Path
from typing import Callable

import numpy as np

from ..cache import Cache
from ..compare.limits import (
    REFERENCE_DATE,
    REFERENCE_LEVELS,
    BandBottom,
    PlateauAnalysis,
    SchurBound,
    band_bottom,
    compare_dictionaries,
    flake_levels,
    plateau_analysis,
    reference_command,
    reference_levels,
    schur_bound,
)
from ..paper_labels import cite
from .writers import Section, Table, save_figure

__all__ = ["limits_section", "LIMITS_LATTICES"]

#: The lattices of the trend in p (and one q = 4), with the Schur window W used for each
#: (None: no upper bound in the report, to keep it fast).
LIMITS_LATTICES = (((7, 3), 8), ((8, 3), 8), ((9, 3), None), ((10, 3), None), ((5, 4), None))

#: Flakes the pattern scan of the Schur bound uses in the report (closure checked).
_SCHUR_RINGS = {(7, 3): 10, (8, 3): 8}


def _blank_bounds_sentence() -> str:
    """Why the lower end and the Schur column of the band-bottom table are blank for some lattices."""
    skipped = [f"{{{p},{q}}}" for (p, q), window in LIMITS_LATTICES if window is None]
    if not skipped:
        return ""
    names = ", ".join(skipped[:-1]) + (" and " if len(skipped) > 1 else "") + skipped[-1]
    return (f"The rigorous lower end and the Schur column are blank for {names}: the report does not run the "
            "Schur test there (to keep the report fast), so only the upper end "
            "E0(l_max) is proven; docs/limits.md gives their Schur bounds.")


def _levels_73(cache: Cache, max_rings: int, progress, extra_levels) -> tuple[np.ndarray, np.ndarray, np.ndarray,
                                                                              list]:
    """{7,3} flake levels: computed (cached) up to ``max_rings``, stored beyond (up to l = 14), and
    ``extra_levels`` ({l: (E0, E1)}, e.g. l = 15, 16 from the sector-only solver) on top."""
    source = {}
    rings = list(range(1, max_rings + 1))
    progress(f"infinite lattice: flake levels l = 1..{max_rings}")
    got = flake_levels(7, 3, rings, cache=cache)
    table = {x: (a, b) for x, a, b in zip(got["rings"], got["E0"], got["E1"])}
    source.update({x: "computed" for x in table})
    for x, v in REFERENCE_LEVELS[(7, 3)].items():
        if x not in table:
            table[x], source[x] = v, "stored"
    for x, v in (extra_levels or {}).items():
        x = int(x)
        if x not in table:
            table[x], source[x] = (float(v[0]), float(v[1])), "supplied"
    ell = np.array(sorted(table))
    return ell, np.array([table[x][0] for x in ell]), np.array([table[x][1] for x in ell]), \
        [source[x] for x in ell]


def _schur(cache: Cache, p: int, q: int, window: int) -> dict:
    rings = _SCHUR_RINGS.get((p, q))
    sb = cache.get("schur_bound", {"p": p, "q": q, "window": window, "rings": rings},
                   lambda: schur_bound(p, q, window=window, rings=rings), expect=SchurBound)
    return sb.summary()


def limits_section(cache: Cache, max_rings: int, out: Path, progress: Callable[[str], None],
                   extra_levels: dict | None = None) -> Section:
    """Section "The infinite lattice": band bottom, plateau, improved dictionary (table + figure).

    Parameters
    ----------
    cache : Cache
        Flake levels share the report's ``graph_levels`` entries; Schur bounds are cached too.
    max_rings : int
        {7,3} flakes up to this l are computed; larger ones up to l = 14 come from
        :data:`~hyperlattice.compare.limits.REFERENCE_LEVELS` (marked "stored").
    out : Path
        Directory for the figure.
    progress : callable
        Receives one-line progress messages.
    extra_levels : dict, optional
        ``{l: (E0, E1)}`` of larger flakes (l = 15, 16 of the sector-only solver), used as well.

    Returns
    -------
    Section
        The section "The band bottom, the plateau explained, an improved dictionary" (anchor
        ``"band-bottom"``, part ``"beyond"``) with four tables (band bottom per lattice, fits,
        plateau terms, dictionaries), one figure and the provenance of the stored levels.

    Raises
    ------
    ValueError
        If an argument has the wrong type (e.g. ``out`` is not a path).

    See Also
    --------
    hyperlattice.compare.limits.band_bottom, hyperlattice.compare.limits.plateau_analysis,
    hyperlattice.compare.limits.compare_dictionaries, hyperlattice.plots.limits.limits_figure

    Examples
    --------
    The section takes tens of seconds (Schur bounds, all flakes up to ``max_rings``); the
    argument check is immediate:

    >>> import tempfile
    >>> from hyperlattice.cache import Cache
    >>> from hyperlattice.report.limits import limits_section
    >>> with tempfile.TemporaryDirectory() as d:
    ...     limits_section(Cache(d), 10, 42, print)
    Traceback (most recent call last):
        ...
    ValueError: out must be a path, got 42.
    """
    ell, e0, e1, source = _levels_73(cache, max_rings, progress, extra_levels)
    progress("infinite lattice: band bottom and Schur bounds")
    bands: dict[tuple, BandBottom] = {}
    rows = []
    for (p, q), window in LIMITS_LATTICES:
        if (p, q) == (7, 3):
            keep = ell >= 3
            lv = (ell[keep], e0[keep], e1[keep])
        else:
            lv = reference_levels(p, q)
            keep = lv[0] >= 3
            lv = tuple(a[keep] for a in lv)
        band = cache.get("band_bottom", {"p": p, "q": q, "rings": lv[0].tolist(), "E0": lv[1].tolist(),
                                         "E1": lv[2].tolist()},
                         lambda p=p, q=q, lv=lv: band_bottom(p, q, *lv, schur_window=None), expect=BandBottom)
        schur = _schur(cache, p, q, window) if window is not None else None
        if schur is not None:
            band = BandBottom(**{**{f: getattr(band, f) for f in band.__dataclass_fields__},
                                 "lower": -schur["bound"], "schur": schur})
        bands[(p, q)] = band
        rows.append([f"{{{p},{q}}}", f"{int(band.rings[0])}..{int(band.rings[-1])}", f"{band.estimate:.6f}",
                     f"{band.error:.1e}", f"{band.lower:.5f}" if np.isfinite(band.lower) else "",
                     f"{band.upper:.5f}", "" if schur is None else f"W={schur['window']}, closed={schur['closed']}",
                     f"{band.paper_edge:.6f}", f"{band.improved_edge:.6f}",
                     f"{band.estimate - band.improved_edge:+.1e}", f"{band.band_mass:.5f}",
                     f"{band.paper_edge + q:.5f}"])
    t_band = Table("band_bottom", ["lattice", "rings_fitted", "band_bottom", "error", "rigorous_lower",
                                   "rigorous_upper", "schur", "E_inf_paper", "E_inf_improved",
                                   "band_minus_improved", "band_mass", "paper_mass"], rows,
                   "Band bottom -rho of the infinite lattice: extrapolation of the flake levels (disk model, "
                   "error = largest deviation of 11 fit variants), the rigorous interval -c <= -rho <= E0(l_max) "
                   "(c from the Schur test), the edges E_inf of the paper's and the improved map, and the band "
                   "curvature M = dE/dlambda of the fit against q h^2/4. "
                   + _blank_bounds_sentence())
    b73 = bands[(7, 3)]
    progress("infinite lattice: plateau and dictionaries")
    keep = ell >= 3
    plateau = cache.get("plateau_analysis", {"band": b73.estimate, "error": b73.error, "rings": ell[keep].tolist(),
                                             "E0": e0[keep].tolist(), "E1": e1[keep].tolist()},
                        lambda: plateau_analysis(b73, ell[keep], e0[keep], e1[keep]), expect=PlateauAnalysis)
    keep = ell >= 6
    cmp = compare_dictionaries(ell[keep], e0[keep], e1[keep], band=b73)
    # the extrapolation test: fitted on l <= 11, asked for l = 12..14
    test = band_bottom(7, 3, ell[ell >= 3], e0[ell >= 3], e1[ell >= 3], schur_window=None, max_rings=11)
    later = ell[(ell >= 12) & (ell <= 14)]
    pred, perr = test.predict(later)
    actual = e0[np.isin(ell, later)]
    top = int(ell[-1])
    prev = band_bottom(7, 3, ell[ell >= 3], e0[ell >= 3], e1[ell >= 3], schur_window=None, max_rings=top - 1)
    p_top = [prev.predict([top], level=lv) for lv in (0, 1)]
    central = next(v for v in b73.variants if v["central"])
    partner = next(v for v in b73.variants if v["level"] == 1 and v["model"] == "disk"
                   and v["rings"] == central["rings"])
    fit_rows = []
    for x, r0_, r1_ in zip(central["fit_rings"], central["residuals"], partner["residuals"]):
        i = list(ell).index(x)
        # the fitted values to 9 decimals: the fit residuals are >= 1e-9 and the least-squares solution
        # moves in the 12th digit with the BLAS thread count
        fit_rows.append([int(x), f"{e0[i]:.12f}", f"{e0[i] + r0_:.9f}", f"{r0_:+.1e}", f"{e1[i]:.12f}",
                         f"{e1[i] + r1_:.9f}", f"{r1_:+.1e}"])
    t_fit = Table("band_fit", ["rings", "E0", "E0_fit", "E0_residual", "E1", "E1_fit", "E1_residual"], fit_rows,
                  "The central extrapolation fits ({7,3}, disk model E_b + M k_m(R_A + s)^2 over the last six "
                  "flakes, m = 0 for E0 and m = 1 for E1) and their residuals.")
    t_terms = Table("plateau_terms", ["term", "value", "share_of_total"], [
        ["-rho - E_inf (total)", f"{plateau.terms['total']:.4e} ± {plateau.terms['total_error']:.1e}", "1"],
        ["isotropic h^4: (7q/64) h^4", f"{plateau.terms['isotropic_h4']:.4e}",
         f"{plateau.terms['isotropic_h4'] / plateau.terms['total']:.3f}"],
        ["isotropic h^6 and beyond (exact -q P_-1/2(cosh 2d0))", f"{plateau.terms['isotropic_rest']:.4e}",
         f"{plateau.terms['isotropic_rest'] / plateau.terms['total']:.3f}"],
        [f"anisotropic m = ±q, ±2q, ... (h³ D of {cite('adj32')} and beyond): the rest",
         f"{plateau.terms['anisotropic']:.4e} ± {plateau.terms['anisotropic_error']:.1e}",
         f"{plateau.terms['share_anisotropic']:.3f}"]],
        "The gap between the lattice's band bottom and the paper map's E_inf = -3 + (3/4)h^2, split into the "
        "terms of the expansion of the star ({7,3}).")
    t_dict = Table("dictionaries", ["rings", "source", "paper_E0", "improved_E0", "paper_E1", "improved_E1"],
                   [[int(x), source[list(ell).index(x)], f"{a:+.3e}", f"{b:+.3e}", f"{c:+.3e}", f"{d:+.3e}"]
                    for x, a, b, c, d in zip(cmp.rings, cmp.paper_E0, cmp.improved_E0, cmp.paper_E1,
                                             cmp.improved_E1)],
                   "Relative error (E_graph - E_cont)/|E_graph| of E0 and E1 with the paper's map "
                   f"(E = -3 + (3/4)h^2 lambda on the disk of {cite('eq12')}) and the improved one (E = -3 P_nu(cosh 2d0) "
                   "on the disk half a bond larger); source: computed now, stored (REFERENCE_LEVELS) or supplied.")
    from ..plots.limits import limits_figure

    fig = limits_figure(b73, plateau, cmp)
    figure = save_figure(fig, out, "limits", "{7,3}. (a) Band bottom (extrapolation with its error band, "
                         "rigorous bounds, both maps' E_inf). (b) Residuals of the disk and rational fits of E0 and "
                         "E1 over the last six flakes. (c) The paper map's relative error, the fitted E0 continued "
                         "to l = 60 and the predicted limit (-rho - E_inf)/rho. (d) |Relative error| of E0 and E1 "
                         "for both maps.")
    gain = cmp.gain()
    last = int(cmp.rings[-1])
    r0 = plateau.relative_E0
    if r0[-1] > r0[-2]:
        trend = f"The computed E0 errors are still rising at l = {last} ({r0[-1]:.4e})."
    else:
        i_max = int(np.argmax(r0))
        trend = (f"The computed E0 errors have turned over: largest {r0[i_max]:.4e} at l = {int(plateau.rings[i_max])}, "
                 f"{r0[-1]:.4e} at l = {last}.")
    sch = b73.schur or {}
    text = [
        f"Band bottom. The flake levels approach -rho like E_b + M k0(R)^2 with k0 ~ pi/(R + c) the lowest "
        f"Dirichlet root of a disk of geodesic radius R growing linearly in l (exponent 2, derived in "
        f"hyperlattice.compare.limits). Fitted to E0 for l = {int(b73.rings[-6])}..{int(b73.rings[-1])}: -rho(7,3) "
        f"= {b73.estimate:.6f} ± {b73.error:.1e} (largest residual "
        f"{max(v['max_residual'] for v in b73.variants if v['central']):.1e}; the error bar is the spread of "
        f"the disk and the rational model on E0 and E1 over the last 5, 6, 7 flakes). Rigorous: "
        f"{b73.lower:.5f} <= -rho <= {b73.upper:.5f} (the l = {last} flake is a subgraph; the upper bound on rho is "
        f"a Schur test with a positive ring-word function, window W = {sch.get('window')}, "
        f"{sch.get('patterns')} local patterns, closed = {sch.get('closed')}), inside the paper's "
        f"[-2.966, -2.862].",
        "Extrapolation test: fitted on l <= 11, the model predicts E0 at l = "
        + ", ".join(f"{int(x)}: {v - a:+.1e} (bar {e:.1e})" for x, v, a, e in zip(later, pred, actual, perr))
        + " (prediction - computed); "
        + ("every prediction lies inside its error bar." if np.all(np.abs(pred - actual) <= perr)
           else "NOT every prediction lies inside its error bar.")
        + f" Fitted on l <= {top - 1}, it predicts the largest flake, l = {top}: E0 {p_top[0][0][0] - e0[-1]:+.1e} "
        f"(bar {p_top[0][1][0]:.1e}), E1 {p_top[1][0][0] - e1[-1]:+.1e} (bar {p_top[1][1][0]:.1e})"
        + (", inside the bars." if abs(p_top[0][0][0] - e0[-1]) <= p_top[0][1][0]
           and abs(p_top[1][0][0] - e1[-1]) <= p_top[1][1][0] else ", NOT inside the bars.")
        if later.size else "Extrapolation test: needs l = 12..14.",
        f"Why the plateau. The graph levels go to -rho, the paper map's continuum levels to E_inf = "
        f"{b73.paper_edge:.6f}, so the relative error tends to (-rho - E_inf)/rho = {plateau.limit:.3e} ± "
        f"{plateau.limit_error:.1e}; the fitted levels continued to large l give {plateau.fitted_limit_E0:.3e} "
        f"(E0) and {plateau.fitted_limit_E1:.3e} (E1). " + trend + f" The fitted E0 curve peaks at "
        f"{plateau.peak_value:.3e} near l = "
        f"{plateau.peak_rings:.0f} and falls back to the limit like 1/l^2, because the lattice's band curvature M = "
        f"{b73.band_mass:.5f} exceeds the paper's (3/4)h^2 = {b73.paper_edge + 3:.5f}. The gap is the isotropic "
        f"O(h^4) term of the star, (7q/64)h^4 = {plateau.terms['isotropic_h4']:.3e}, plus "
        f"{plateau.terms['isotropic_rest']:.1e} from higher isotropic orders; the anisotropic O(h^3) term D "
        f"({cite('adj32')}) would average to zero over uniformly spread star orientations (on the ring lattice <cos 3(chi - phi)> "
        f"= 0.17): the anisotropic orders leave only {plateau.terms['anisotropic']:.1e}.",
        f"Improved dictionary. Summing the isotropic part of the star exactly (mean-value property of "
        f"eigenfunctions: E = -q P_nu(cosh 2d0), nu = (-1 + ik)/2) and putting the Dirichlet wall where the "
        f"lattice puts it (on the missing neighbours, half a bond beyond the area radius of {cite('eq12')}) lowers the "
        f"relative error at l = {last} from {abs(cmp.paper_E0[-1]):.2e} to {abs(cmp.improved_E0[-1]):.2e} (E0, "
        f"{gain['E0']:.0f}x) and from {abs(cmp.paper_E1[-1]):.2e} to {abs(cmp.improved_E1[-1]):.2e} (E1, "
        f"{gain['E1']:.0f}x). The rest does not vanish as l -> infinity: it tends to (-rho - E_inf^impr)/rho = "
        f"{cmp.improved_limit:.1e} ± {cmp.improved_limit_error:.1e}, the net shift of the anisotropic "
        "m = ±q part of the star; at finite l a positive boundary term (the flake is not a disk) decays like "
        "1/l^2, so the improved error crosses zero near the largest computed flakes and settles at that limit.",
        "Trend in p: -rho against the two maps' edges (and how much of the paper map's miss -rho - E_inf is "
        "left by the improved map's isotropic sum): " + "; ".join(
            f"{{{pq[0]},{pq[1]}}}: -rho = {bands[pq].estimate:.5f} ± {bands[pq].error:.0e}, E_inf = "
            f"{bands[pq].paper_edge:.5f} (paper), {bands[pq].improved_edge:.5f} (improved), "
            f"{100 * abs((bands[pq].estimate - bands[pq].improved_edge) / (bands[pq].estimate - bands[pq].paper_edge)):.0f}% left"
            for pq, _ in LIMITS_LATTICES) + ". The band bottom rises with p toward the tree value −2√2 of "
        "{∞,3}; the anisotropic remainder grows quickly with h (0.276, 0.348, 0.388, 0.413 for p = 7..10), so "
        "the isotropic sum helps most for {7,3}; for q = 4 the anisotropic orders are m = ±4.",
    ]
    stored = [int(x) for x, s in zip(ell, source) if s == "stored"]
    supplied = [int(x) for x, s in zip(ell, source) if s == "supplied"]
    computed = [int(x) for x, s in zip(ell, source) if s == "computed"]
    provenance = [f"{{7,3}} flake levels E0, E1 for l = {computed[0]}..{computed[-1]} are computed by this run "
                  "(cached); the fits, the plateau analysis, the dictionaries and the Schur bounds are computed "
                  "from them now."]
    if stored:
        provenance.append(
            f"{{7,3}} flake levels for l = {stored[0]}..{stored[-1]} (the band-bottom fit, the extrapolation test "
            "and the rows marked \"stored\" of the dictionary table) are not computed by this run: they are "
            "REFERENCE_LEVELS in src/hyperlattice/compare/limits.py, stored on "
            f"{REFERENCE_DATE} (residuals ≤ 4e-13; l ≥ 15 from the sector-only solver, ≤ 7e-15). "
            f"Regenerate them with `{reference_command(7, 3, stored)}`.")
    if supplied:
        provenance.append(f"{{7,3}} flake levels for l = {', '.join(map(str, supplied))} were supplied by the caller.")
    others = [pq for pq, _ in LIMITS_LATTICES if pq != (7, 3)]
    if others:
        provenance.append(
            "The trend in p uses the stored levels of " + ", ".join(f"{{{a},{b}}}" for a, b in others)
            + f" (REFERENCE_LEVELS, stored {REFERENCE_DATE}); e.g. `"
            + reference_command(*others[0], sorted(REFERENCE_LEVELS[others[0]])) + "` regenerates the first.")

    return Section("The band bottom, the plateau explained, an improved dictionary",
                   ("AppSpec", "AppAdj", "adj26", "adj32", "adj33", "eq12", "spec2"), text,
                   [t_band, t_fit, t_terms, t_dict], [figure], anchor="band-bottom", part="beyond",
                   provenance=provenance)


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
