"""The DOS comparison: routes converge to the exact moments; continuum Plancherel density."""

from __future__ import annotations

import math

import numpy as np
import pytest

from hyperlattice import dictionary, geometry
from hyperlattice.compare.dos import (DosComparison, continuum_dos, continuum_integrated_dos, dos_comparison,
                                      jackson_density, quantile_energy)
from hyperlattice.results import Result

SMALL = dict(clusters=("klein", "PSL(2,29)"), rings=(5, 6), moments=64, resolution=24, vectors=4, walk_length=23,
             abelian_samples=16)


@pytest.fixture(scope="module")
def cmp():
    return dos_comparison(7, 3, **SMALL)


def test_continuum_density_is_plancherel_through_the_dictionary():
    e = np.linspace(-3.0, -2.0, 2001)
    rho = continuum_dos(e)
    bottom = dictionary.energy_from_lambda(1.0, 7, 3)
    assert np.all(rho[e <= bottom] == 0) and np.all(rho[e > bottom + 1e-9] > 0)
    # Weyl's law far above the bottom: A/(4 pi) per unit lambda
    far = continuum_dos(np.array([3.0]))[0] * dictionary.hopping_scale(7, 3)
    assert far == pytest.approx(geometry.site_area(7, 3) / (4 * math.pi), rel=1e-12)
    # near the bottom N = A k^3 / 12 - A pi^2 k^5 / 240 + O(k^7) (tanh x = x - x^3/3 + ...)
    a = geometry.site_area(7, 3)
    for k in (0.01, 0.05):
        ek = dictionary.energy_from_k(k, 7, 3)
        series = a * k**3 / 12 - a * math.pi**2 * k**5 / 240
        assert continuum_integrated_dos(np.array([ek]))[0] == pytest.approx(series, rel=2e-5)
    # the integrated density is the integral of the density
    n = continuum_integrated_dos(e)
    assert np.trapezoid(rho, e) == pytest.approx(n[-1], rel=1e-4)  # trapezoid rule over the sqrt onset
    # the improved map starts at its own band bottom
    imp = continuum_integrated_dos(np.array([dictionary.improved_band_bottom(7, 3) - 1e-9, -2.9]),
                                   dictionary_name="improved")
    assert imp[0] == 0 and imp[1] > 0


def test_routes_converge_to_exact_moments(cmp):
    cl = [i for i, k in enumerate(cmp.kinds) if k == "cluster"]
    assert cmp.distance[cl[-1]] < cmp.distance[cl[0]] / 5  # bigger cluster, closer to the lattice
    assert all(cmp.exact_moments[i] >= 8 for i in cl)  # systoles
    fl = [i for i, k in enumerate(cmp.kinds) if k == "flake"]
    assert cmp.exact_moments[fl[-1]] > cmp.exact_moments[fl[0]]
    # the exact reference is normalised and positive (Jackson)
    assert np.trapezoid(cmp.reference, cmp.energies) == pytest.approx(1.0, abs=2e-3)
    assert cmp.reference.min() > -1e-12


def test_band_bottom_interval_and_edges(cmp):
    assert 2 * math.sqrt(2) <= cmp.rho_lower < cmp.rho_upper < 3  # the covering tree's rho at least
    # every cluster's 0.1% quantile lies above -q (the uniform state is left out) and the continuum
    # bottoms lie inside the proven interval
    cl = [i for i, k in enumerate(cmp.kinds) if k == "cluster"]
    assert np.all(cmp.bottom[cl] > -3)
    for e in cmp.continuum_bottom.values():
        assert -cmp.rho_upper < e < -cmp.rho_lower
    assert cmp.continuum_agreement().dtype == bool
    assert 0 <= cmp.continuum_window() <= 0.3
    assert "uniform state" in cmp.statement()


def test_abelian_or_note(cmp):
    assert "abelian" in cmp.kinds or any("Abelian" in n for n in cmp.notes)


def test_round_trip(cmp):
    again = Result.from_dict(cmp.as_dict())
    assert isinstance(again, DosComparison) and np.array_equal(again.density, cmp.density)
    assert cmp.summary()["curves"][0]["label"] == cmp.labels[0]


def test_helpers():
    e = np.linspace(0, 1, 11)
    assert quantile_energy(e, e, 0.35) == pytest.approx(0.35)
    assert math.isnan(quantile_energy(e, e * 0.1, 0.5))
    # the Jackson density of mu = (1, 0) is the Chebyshev weight 1/(pi a sqrt(1 - x^2))
    x = np.linspace(-2.9, 2.9, 20001)
    expect = 2 / math.pi * math.asin(2.9 / 3.0)
    assert np.trapezoid(jackson_density(np.array([1.0, 0.0]), 3.0, x), x) == pytest.approx(expect, rel=1e-6)


@pytest.mark.slow
def test_report_section(tmp_path):
    import matplotlib

    matplotlib.use("Agg")
    from hyperlattice.report.infinite import infinite_section

    sec = infinite_section(tmp_path, lambda m: None)
    assert sec.title == "The infinite lattice: densities of states and band edges" and sec.part == "beyond"
    assert (tmp_path / "fig_dos_infinite.png").stat().st_size > 10_000
    names = [t.name for t in sec.tables]
    assert names == ["dos_routes", "band_edges"]
    edges = sec.tables[1].rows
    assert sec.tables[1].columns == ["quantity", "E", "E_error", "interval_lower", "interval_upper", "note"]
    lo, hi = float(edges[0][3]), float(edges[0][4])
    assert -3 < lo < hi < -2.8  # the proven band-bottom interval
    assert "uniform state" in sec.text[0]
