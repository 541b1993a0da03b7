"""The report's figures as a referee reads them (issue 28 item 3): legends off the data, the continuum
levels of the butterfly drawn as levels, the cos 3δ figure spread out."""

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

import hyperlattice as hl  # noqa: E402
from hyperlattice.continuum.magnetic import magnetic_levels  # noqa: E402


def _overlaps(a, b) -> bool:
    return a.x0 < b.x1 and b.x0 < a.x1 and a.y0 < b.y1 and b.y0 < a.y1


def test_formal_operator_figure_has_one_legend_below_the_panels():
    from hyperlattice.report.sections import formal_operator_figure

    fig = formal_operator_figure(hl.frame_angles(hl.ring_lattice(7, 3, 3)))
    fig.canvas.draw()
    r = fig.canvas.get_renderer()
    assert all(ax.get_legend() is None for ax in fig.axes) and len(fig.legends) == 1
    box = fig.legends[0].get_window_extent(r)
    for ax in fig.axes:
        assert not _overlaps(box, ax.get_window_extent(r))
        assert box.y1 <= ax.get_window_extent(r).y0
    plt.close(fig)


def test_frame_angle_figure_against_distance_keeps_the_legend_off_the_data():
    from hyperlattice.plots.scaling import plot_frame_angles

    fig, ax = plt.subplots(figsize=(8.0, 4.8), layout="constrained")
    plot_frame_angles(hl.ring_lattice(7, 3, 4), ax=ax, distance=True)
    from matplotlib.text import Text

    fig.findobj(Text)   # the report's save_figure walks every text, minor ticks of the top axis included
    fig.canvas.draw()
    r = fig.canvas.get_renderer()
    assert not _overlaps(ax.get_legend().get_window_extent(r), ax.get_window_extent(r))
    x = ax.lines[0].get_xdata()
    r_sites = np.abs(hl.ring_lattice(7, 3, 4).z)
    assert float(np.max(x)) == pytest.approx(float(np.arctanh(r_sites.max())))
    # the outer ring spread out: its radii span a larger share of the axis than against r
    assert (np.max(x) - np.percentile(x, 50)) / np.ptp(x) > (r_sites.max() - np.percentile(np.tanh(x), 50)) / np.ptp(np.tanh(x))
    plt.close(fig)


def test_butterfly_continuum_curves_follow_one_level_each():
    """Each red curve is one continuum level (n, m) through the flux: no corner where two levels cross."""
    from hyperlattice.plots.magnetic import butterfly_figure

    bf = hl.butterfly(hl.ring_lattice(7, 3, 3), np.linspace(0.0, 0.5, 11))
    spectra = {}
    fig, (ax, zoom) = plt.subplots(1, 2)
    butterfly_figure(bf, continuum=True, max_flux=0.3, points=7, levels=4, ax=ax, zoom_ax=zoom)
    for axes in (ax, zoom):
        red = [ln for ln in axes.lines if ln.get_color() == "tab:red"]
        assert len(red) >= 4
        for ln in red:
            n, m = (int(t.split("=")[1]) for t in ln.get_gid().split()[1:])
            for f, e in zip(ln.get_xdata(), ln.get_ydata()):
                if np.isnan(e):
                    continue
                if f not in spectra:
                    spectra[f] = magnetic_levels(7, 3, rings=3, levels=20, flux=float(f))
                sp = spectra[f]
                k = [i for i in range(sp.energies.size) if (sp.n[i], sp.m[i]) == (n, m)]
                assert k and sp.energies[k[0]] == pytest.approx(e, abs=1e-12)
    plt.close(fig)


def _synthetic_lobe(systems: int = 5, per_system: int = 3):
    """A stand-in for a QMCLobe with ``systems * per_system`` gap series (the stored scan has 15)."""
    from types import SimpleNamespace

    from hyperlattice.compare.qmc_lobe import MIN_SITES_EXTRAPOLATION

    out = []
    for k in range(systems):
        sites = MIN_SITES_EXTRAPOLATION * (k + 1)
        tips = []
        for j in range(per_system):
            x = np.array([0.06, 0.07, 0.08, 0.09])
            gap = 0.5 - 4.5 * x + 0.01 * (k + j)
            tips.append({"beta_t": 8.0 - 2 * j, "nmax": 3, "gaps": [[a, b, 0.005] for a, b in zip(x, gap)],
                         "tip_linear": 0.115, "tip_sqrt": 0.11, "tip": 0.1 + 0.001 * k, "tip_err": 0.002})
        out.append({"system": f"flake:{k + 3}", "sites": sites, "tips": tips})
    cluster = {"kind": "cluster", "sites": [56, 168, 364], "tip": 0.09, "tip_err": 0.001, "systematic": 0.001,
               "dof": 1, "chi2": 0.02, "beta_t": 8.0, "slope": 0.1, "tip_sqrt_form": 0.089, "slope_sqrt_form": 0.01}
    return SimpleNamespace(systems=out, rows=[], square={}, finite_size=[cluster], infinite_tip_mean_field=0.0583)


def test_qmc_tip_figure_uses_a_colour_per_series_and_clips_nothing():
    """``fig_qmc_tip.png``: 15 series, no colour used twice; after the report's own treatment (panel
    letters, text enlarged to 8 pt) every legend and label lies inside the figure."""
    from matplotlib.colors import to_hex
    from matplotlib.text import Text

    from hyperlattice.plots.qmc_lobe import qmc_tip_figure
    from hyperlattice.report.writers import _readable

    fig = qmc_tip_figure(_synthetic_lobe())
    left, right = fig.axes[:2]
    handles, labels = left.get_legend_handles_labels()
    assert len(handles) == 15
    colours = [to_hex(h.lines[0].get_color()) for h in handles]
    assert len(set(colours)) == 15, colours
    # the reference lines of the right panel are black or grey: no series colour is reused there
    refs = {to_hex(line.get_color()) for line in right.get_lines() if len(line.get_xdata()) > 1}
    assert not refs & set(colours), refs
    _readable(fig)
    fig.canvas.draw()
    r = fig.canvas.get_renderer()
    page = fig.bbox
    boxes = [leg.get_window_extent(r) for leg in (left.get_legend(), right.get_legend())]
    # titles, axis labels and panel letters (tick labels outside the view limits are not drawn)
    texts = [t for ax in (left, right) for t in (ax.title, ax.xaxis.label, ax.yaxis.label, *ax.texts)]
    boxes += [t.get_window_extent(r) for t in texts if t.get_text()]
    for b in boxes:
        assert page.x0 - 0.5 <= b.x0 and b.x1 <= page.x1 + 0.5 and page.y0 - 0.5 <= b.y0 and b.y1 <= page.y1 + 0.5, b
    assert any(t.get_text() == "(a)" for t in fig.findobj(Text)) and any(t.get_text() == "(b)" for t in fig.findobj(Text))
    plt.close(fig)
