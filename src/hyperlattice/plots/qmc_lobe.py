"""Figures of the QMC Mott lobe (:mod:`hyperlattice.compare.qmc_lobe`): QMC points over mean field and strong coupling."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from . import new_axes

if TYPE_CHECKING:
    from matplotlib.axes import Axes

    from ..compare.qmc_lobe import QMCLobe

__all__ = ["plot_qmc_lobe_system", "plot_qmc_lobe", "qmc_lobe_figure", "qmc_tip_figure"]

_MARKERS = ("o", "s", "^", "D")
_COLOURS = ("k", "tab:red", "tab:green", "tab:purple")
_NAMES = {"flake": "{7,3} flake, ℓ = ", "cluster": "{7,3} cluster ", "square": "square lattice, L = "}


def _check(lobe) -> None:
    if not (hasattr(lobe, "systems") and hasattr(lobe, "rows") and hasattr(lobe, "square")):
        raise ValueError(f"lobe must be a QMCLobe (from compare.qmc_lobe.qmc_lobe), got {type(lobe).__name__}.")


def _finish(fig, path, rect=None):
    """Lay out ``fig`` (leaving ``rect`` free for a figure legend) and write it to ``path`` when given."""
    from .. import _validate

    fig.tight_layout(rect=rect)
    if path is not None:
        fig.savefig(_validate.output_path("path", path, suffixes=(".png", ".svg")), dpi=130)
    return fig


def _title(spec: str, sites: int) -> str:
    kind, _, arg = spec.partition(":")
    return f"{_NAMES.get(kind, kind)}{arg} ({sites} sites)"


def plot_qmc_lobe_system(lobe: QMCLobe, system: str, ax: Axes | None = None) -> Axes:
    """One graph of ``lobe``: QMC μ±/U with error bars, mean field (dashed), strong coupling (solid).

    Parameters
    ----------
    lobe : QMCLobe
        From :func:`~hyperlattice.compare.qmc_lobe.qmc_lobe`.
    system : str
        Its system spec (``"flake:3"``, ``"cluster:klein"``, ``"square:6"``).
    ax : matplotlib.axes.Axes, optional
        Where to draw; a new figure when None.

    Returns
    -------
    matplotlib.axes.Axes
        t/U horizontal, μ/U vertical; the legend names the three sources.

    Raises
    ------
    ValueError
        If ``system`` is not in ``lobe``.
    """
    _check(lobe)
    if not isinstance(system, str):
        raise ValueError(f"system must be a string such as 'flake:3', got {type(system).__name__}.")
    spec = next((s for s in lobe.systems if s["system"] == system), None)
    if spec is None:
        raise ValueError(f"system {system!r} is not in this lobe; it has {[s['system'] for s in lobe.systems]}.")
    ax = new_axes(ax, size=(4.0, 3.2))
    x = np.asarray(spec["t_line"])
    ax.plot(x, spec["mf_plus"], "--", color="tab:blue", lw=1.2, label="Gutzwiller mean field")
    ax.plot(x, spec["mf_minus"], "--", color="tab:blue", lw=1.2)
    ax.plot(x, spec["sc_plus"], "-", color="tab:orange", lw=1.2, label="strong coupling, 3rd order")
    ax.plot(x, spec["sc_minus"], "-", color="tab:orange", lw=1.2)
    rows = [r for r in lobe.rows if r["system"] == system and math.isfinite(r["mu"])]
    # one style per (beta t, nmax) over the whole lobe, so that every panel and the legend agree
    every = sorted({(r["beta_t"], r.get("nmax", 3)) for r in lobe.rows}, key=lambda k: (-k[0], -k[1]))
    groups = sorted({(r["beta_t"], r.get("nmax", 3)) for r in rows}, key=every.index)
    for beta, nmax in groups:
        k = every.index((beta, nmax))
        sel = [r for r in rows if r["beta_t"] == beta and r.get("nmax", 3) == nmax]
        tx = [r["t_over_U"] for r in sel]
        mu = [r["mu"] for r in sel]
        err = [r["mu_err"] if math.isfinite(r["mu_err"]) else 0.0 for r in sel]
        label = f"QMC, βt = {beta:g}" + ("" if nmax == 3 else f", nmax = {nmax}")
        ax.errorbar(tx, mu, yerr=err, fmt=_MARKERS[k % len(_MARKERS)], ms=4, color=_COLOURS[k % len(_COLOURS)],
                    mfc="none" if k else None, capsize=2, label=label)
    ax.set_xlim(0.0, x[-1])
    ax.set_ylim(-0.05, 1.05)
    ax.set_xlabel("t/U")
    ax.set_ylabel("μ/U")
    ax.set_title(_title(system, spec["sites"]), fontsize=9)
    return ax


def plot_qmc_lobe(lobe: QMCLobe, ax: Axes | None = None) -> Axes:
    """The first graph of ``lobe`` (the drawing :meth:`QMCLobe.plot` uses); see :func:`qmc_lobe_figure` for all."""
    _check(lobe)
    return plot_qmc_lobe_system(lobe, lobe.systems[0]["system"], ax=ax)


def qmc_lobe_figure(lobe: QMCLobe, path=None):
    """All graphs of ``lobe``, one panel each, with one legend; saved to ``path`` when given.

    Parameters
    ----------
    lobe : QMCLobe
        From :func:`~hyperlattice.compare.qmc_lobe.qmc_lobe`.
    path : str or path, optional
        A .png or .svg file to write.

    Returns
    -------
    matplotlib.figure.Figure
    """
    import matplotlib.pyplot as plt

    _check(lobe)
    k = len(lobe.systems)
    cols = min(3, k)
    rows = (k + cols - 1) // cols
    fig, axes = plt.subplots(rows, cols, figsize=(3.6 * cols, 3.0 * rows + 0.5), squeeze=False)
    for ax, spec in zip(axes.ravel(), lobe.systems):
        plot_qmc_lobe_system(lobe, spec["system"], ax=ax)
    for ax in axes.ravel()[k:]:
        ax.set_visible(False)
    seen: dict = {}
    for ax in axes.ravel()[:k]:
        for h, lab in zip(*ax.get_legend_handles_labels()):
            seen.setdefault(lab, h)
    fig.legend(list(seen.values()), list(seen.keys()), loc="lower center", ncol=min(len(seen), 5), fontsize=8,
               frameon=False)
    return _finish(fig, path, rect=(0, 0.06, 1, 1))


def qmc_tip_figure(lobe: QMCLobe, path=None):
    """The tip analysis: the QMC gap against t/U with its two straight-line fits, and the pseudo-tips against 1/M.

    Left: Δ = μ+ − μ− of each graph (filled: the lowest temperature, open: the others) with the
    straight lines in Δ (solid) and Δ² (dotted, drawn as its square root) through the three largest
    t/U. Right: the pseudo-tip of each graph and temperature against 1/M, with the mean-field tips
    (3 − 2√2)/3 of any 3-regular graph and (3 − 2√2)/ρ of the infinite lattice through ρ, and the
    1/M extrapolations of the periodic clusters.

    Parameters
    ----------
    lobe : QMCLobe
        From :func:`~hyperlattice.compare.qmc_lobe.qmc_lobe`.
    path : str or path, optional
        A .png or .svg file to write.

    Returns
    -------
    matplotlib.figure.Figure
    """
    import matplotlib.pyplot as plt

    _check(lobe)
    from ..compare.qmc_lobe import MIN_SITES_EXTRAPOLATION

    # constrained layout places the legends below the panels at draw time, after the report has
    # enlarged small text and lettered the panels, so nothing is clipped
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(10.0, 7.6), layout="constrained")
    big = [s for s in lobe.systems if any(len(d["gaps"]) >= 2 for d in s.get("tips", []))
           and s["sites"] >= MIN_SITES_EXTRAPOLATION]
    series = []
    for s in big:
        # the fitted, filled series first: the lowest temperature with the production cutoff nmax = 3
        tips = sorted(s["tips"], key=lambda d: (d["nmax"] != 3, -d["beta_t"], d["nmax"]))
        series += [(s, j, d) for j, d in enumerate(tips) if d["gaps"]]
    # one colour and one marker per series (no colour is used twice); black and grey are kept for
    # the reference lines of panel (b)
    styles = _series_styles(len(series))
    for (s, j, d), (colour, marker) in zip(series, styles):
        g = np.array(d["gaps"])
        lab = f"{_title(s['system'], s['sites'])}, βt = {d['beta_t']:g}" + ("" if d["nmax"] == 3 else
                                                                            f", nmax = {d['nmax']}")
        filled = j == 0
        a1.errorbar(g[:, 0], g[:, 1], yerr=g[:, 2], fmt=marker, ms=5, color=colour, mfc=None if filled else "none",
                    capsize=2, label=lab)
        if filled and math.isfinite(d["tip_linear"]) and math.isfinite(d["tip_sqrt"]):
            fx = np.array(d.get("fit_points", g[-3:, 0]))
            xl = np.linspace(fx.min(), d["tip_linear"], 20)
            gl = np.interp(fx, g[:, 0], g[:, 1])
            pl = np.polyfit(fx, gl, 1)
            a1.plot(xl, np.polyval(pl, xl), "-", color=colour, lw=0.8)
            xs = np.linspace(fx.min(), d["tip_sqrt"], 40)
            ps = np.polyfit(fx, gl**2, 1)
            a1.plot(xs, np.sqrt(np.clip(np.polyval(ps, xs), 0, None)), ":", color=colour, lw=0.8)
        if math.isfinite(d["tip"]) and d["nmax"] == 3:
            a2.errorbar([1.0 / s["sites"]], [d["tip"]], yerr=[d["tip_err"]], fmt=marker, ms=6, color=colour,
                        mfc=None if filled else "none", capsize=2)
    a1.axhline(0.0, color="0.6", lw=0.6)
    a1.set_xlabel("t/U")
    a1.set_ylabel("gap (μ+ − μ−)/U")
    a1.set_title("the Mott gap and its two straight-line fits", fontsize=10)
    a1.legend(fontsize=8, frameon=False, loc="upper center", bbox_to_anchor=(0.5, -0.12), ncol=1)
    a2.axhline(lobe.infinite_tip_mean_field, ls="--", color="0.45", lw=1,
               label=f"mean field, infinite lattice (ρ): {lobe.infinite_tip_mean_field:.4f}")
    z3 = (3.0 - 2.0 * math.sqrt(2.0)) / 3.0
    a2.axhline(z3, ls="-.", color="0.45", lw=1, label=f"mean field, 3-regular cluster: {z3:.4f}")
    for f in lobe.finite_size:
        if f["kind"] != "cluster":
            continue
        m = np.array(f["sites"], dtype=float)
        u = np.linspace(0.0, 1.0 / m.min() * 1.05, 60)
        chi = "" if f["dof"] < 1 else f", χ²/dof = {f['chi2']:.2f}/{f['dof']}"
        lowest = f["beta_t"] == max(g["beta_t"] for g in lobe.finite_size if g["kind"] == "cluster")
        a2.errorbar([0.0], [f["tip"]], yerr=[math.hypot(f["tip_err"], f["systematic"])], fmt="*", ms=10,
                    color="k", mfc=None if lowest else "none", capsize=2,
                    label=f"clusters → 1/M = 0, βt = {f['beta_t']:g}{chi}")
        if lowest:
            # the weighted fits of the cluster tips: x∞ + c/M (solid) and x∞ + c/√M (dotted)
            a2.plot(u, f["tip"] + f["slope"] * u, "k-", lw=0.6, label=f"x∞ + c/M, βt = {f['beta_t']:g}")
            a2.plot(u, f["tip_sqrt_form"] + f["slope_sqrt_form"] * np.sqrt(u), "k:", lw=0.8,
                    label=f"x∞ + c/√M, βt = {f['beta_t']:g}")
    a2.set_xlabel("1/M (M = number of sites)")
    a2.set_ylabel("(t/U) at the tip")
    a2.set_title("pseudo-tips against 1/M (markers as on the left)", fontsize=10)
    a2.set_xlim(left=-0.001)
    a2.xaxis.set_major_locator(plt.MaxNLocator(5))
    a2.legend(fontsize=8, frameon=False, loc="upper center", bbox_to_anchor=(0.5, -0.12), ncol=1)
    if path is not None:
        from .. import _validate

        fig.savefig(_validate.output_path("path", path, suffixes=(".png", ".svg")), dpi=130)
    return fig


#: distinct colours for data series: tab10 without its grey, then darker hues of tab20b/tab20c
_SERIES_COLOURS = ("tab:blue", "tab:orange", "tab:green", "tab:red", "tab:purple", "tab:brown", "tab:pink",
                   "tab:olive", "tab:cyan", "#393b79", "#637939", "#8c6d31", "#843c39", "#7b4173", "#3182bd",
                   "#e6550d", "#31a354", "#756bb1", "#d6616b", "#17becf")
_SERIES_MARKERS = ("o", "s", "^", "D", "v", "P", "X", "<", ">", "p", "h", "*")


def _series_styles(n: int) -> list[tuple[str, str]]:
    """``n`` (colour, marker) pairs, no colour repeated for up to 20 series, markers cycling alongside."""
    return [(_SERIES_COLOURS[k % len(_SERIES_COLOURS)], _SERIES_MARKERS[k % len(_SERIES_MARKERS)]) for k in range(n)]
