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
