"""Report section "Beyond the paper: the infinite lattice": densities of states of periodic
clusters, flake interiors, the Abelian DOS and the exact moments, band edges with error bars, and
the continuum (Plancherel) density at the band bottom. Small and fast (about 4 s)."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Callable

from .writers import Section, Table, save_figure

__all__ = ["infinite_section", "REPORT_SETTINGS"]

#: what the report computes (the docs page runs larger settings: docs/dos.md)
REPORT_SETTINGS = dict(clusters=("klein", "PSL(2,29)", "PSL(2,71)"), rings=(6, 8), moments=256, resolution=40,
                       vectors=6, seed=0, quantile=1e-3, abelian_samples=100, quantile_moments=512)


def _f(x: float, digits: int = 4) -> str:
    return "" if x is None or not math.isfinite(x) else f"{x:.{digits}f}"


def infinite_section(out: Path, progress: Callable[[str], None]) -> Section:
    """Beyond the paper (issue 12): the DOS figure, the convergence table and the band edges."""
    import matplotlib.pyplot as plt

    from ..compare.dos import dos_comparison
    from ..plots.dos import comparison_figure

    progress("beyond the paper: the infinite lattice")
    cmp = dos_comparison(7, 3, **REPORT_SETTINGS, progress=lambda m: progress(f"  infinite lattice: {m}"))
    fig = comparison_figure(cmp)
    figs = [save_figure(fig, out, "dos_infinite",
                        "{7,3}: densities of states per site of H = -A by KPM (Jackson kernel, "
                        f"{cmp.moments} moments, {REPORT_SETTINGS['vectors']} random vectors). Left: the largest "
                        "periodic cluster (uniform state at E = -3 left out), the largest flake interior, the "
                        "Abelian DOS of the Klein quartic, the exact infinite-lattice DOS from closed-walk counts "
                        f"(M = {cmp.resolution}), the continuum Plancherel density and the proven band-bottom "
                        "interval (grey). Middle: L1 distance to the exact DOS at the same resolution against size. "
                        "Right: integrated DOS at the band bottom, largest cluster against the continuum.")]
    plt.close("all")
    rows = [[r["label"], r["kind"], r["sites"], r["exact_moments"], f"{r['distance']:.2g}",
             "" if not math.isfinite(r["distance_err"]) else f"{r['distance_err']:.1g}",
             _f(r["bottom"]), _f(r["bottom_err"]), _f(r["top"]), _f(r["top_err"])] for r in cmp.table()]
    conv = Table("dos_routes", ["route", "kind", "sites", "exact_moments", "L1_distance", "L1_err",
                                "E_bottom", "E_bottom_err", "E_top", "E_top_err"], rows,
                 f"Each route against the exact infinite-lattice DOS at {cmp.resolution} moments (L1 distance, "
                 "jackknife error over the random vectors); exact_moments: moments proven equal to the lattice's "
                 "(clusters: the systole; flakes: 2 d_b + 2). E_bottom / E_top: the energies below / above which "
                 f"a fraction {cmp.quantile:g} of the states lie, error = kernel width and random vectors.")
    ratio = cmp.continuum_ratio()[0]
    edge_rows = [["band bottom -rho, proven interval (exact closed walks up to n = 45; isoperimetric bound)",
                  _f(-cmp.rho_upper), _f(-cmp.rho_lower), "rigorous"],
                 ["continuum band bottom, paper's map (E = -q + q h^2/4)", _f(cmp.continuum_bottom["paper"]), "",
                  "leading order in h"],
                 ["continuum band bottom, improved map (E = -q P_{-1/2}(cosh 2 d0))",
                  _f(cmp.continuum_bottom["improved"]), "", "isotropic star summed"]]
    for nu, e, err, ec, r in zip(cmp.quantiles, cmp.quantile_lattice, cmp.quantile_lattice_err,
                                 cmp.quantile_continuum, ratio):
        edge_rows.append([f"E(nu = {nu:g}): largest cluster vs continuum (paper's map)", _f(e), _f(err),
                          f"continuum {_f(ec)}, N_cont/nu = {r:.2f}"])
    edges = Table("band_edges", ["quantity", "E", "error_or_upper", "note"], edge_rows,
                  "Band edges of the infinite {7,3} lattice with error bars: the proven interval for the band "
                  "bottom, the continuum band bottoms, and the quantile energies E(nu) of the largest cluster "
                  f"({cmp.bottom_label}) against the continuum's (N_cont/nu = 1: the continuum counts the same "
                  "states below E(nu)).")
    text = ["Not in the paper: the DOS of the infinite lattice, from periodic {7,3} clusters (compact surfaces of "
            "genus 3 to 2131, built from triangle-group quotients), the interiors of flakes (the outer half of the "
            "rings left out of the trace, since boundary sites have the wrong moments from n = 2 on), the Abelian "
            "Bloch DOS and the exact closed-walk moments. " + cmp.statement()]
    if cmp.notes:
        text.append("Left out: " + " ".join(cmp.notes))
    return Section("Beyond the paper: the infinite lattice", "issue 12 (densities of states, band edges)", text,
                   [conv, edges], figs)


# every public function above checks its annotated argument types at the door (issue 19)
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
