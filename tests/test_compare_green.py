"""GreenComparison and BinnedCorrelation as results: round trips, plots, and bad input."""

import dataclasses
import json

import numpy as np
import pytest

from hyperlattice.compare.correlation import (BinnedCorrelation, bin_by_distance, collapse_measure,
                                              correlation_pairs, sorted_pairs)
from hyperlattice.compare.green import GreenComparison, compare_green, relative_l2
from hyperlattice.graph.lattice import ring_lattice
from hyperlattice.results import Result, load_result


@pytest.fixture(scope="module")
def lat3():
    return ring_lattice(7, 3, 3)


@pytest.fixture(scope="module")
def cmp(lat3):
    return compare_green(lat3, -2.5 + 0.1j, 10)


def test_green_comparison_is_a_frozen_result(cmp):
    assert isinstance(cmp, Result)
    with pytest.raises(dataclasses.FrozenInstanceError):
        cmp.rel_l2 = 0.0
    with pytest.raises(ValueError):
        cmp.graph[0] = 1.0  # read-only arrays
    assert (cmp == cmp) is True and (cmp == dataclasses.replace(cmp)) is False  # identity, never an array truth value
    with pytest.raises(TypeError):
        GreenComparison(7, 3)  # keyword-only


def test_summary_is_the_cli_contract(cmp, lat3):
    s = cmp.summary()
    assert set(s) == {"p", "q", "rings", "site", "omega", "lambda", "radius", "rel_l2"}
    assert (s["p"], s["q"], s["rings"], s["site"]) == (7, 3, 3, 10)
    assert s["omega"] == -2.5 + 0.1j and s["radius"] == lat3.radius and s["rel_l2"] == cmp.rel_l2


@pytest.mark.parametrize("suffix", [".json", ".npz"])
def test_green_comparison_round_trip(cmp, suffix, tmp_path):
    json.dumps(cmp.as_dict(), allow_nan=False)  # strict JSON: the infinite source entry is encoded
    for back in (GreenComparison.from_dict(cmp.as_dict()), load_result(cmp.save(tmp_path / f"g{suffix}"))):
        assert isinstance(back, GreenComparison)
        for name in ("graph", "continuum", "distance"):
            np.testing.assert_array_equal(getattr(back, name), getattr(cmp, name))
        assert np.isinf(back.continuum[cmp.source].real)
        assert back.omega == cmp.omega and back.lam == cmp.lam and back.terms == cmp.terms
        assert back.summary() == cmp.summary()


def test_collapse_and_plot(cmp, lat3):
    import matplotlib.pyplot as plt

    keep = np.arange(lat3.sites) != cmp.source
    assert cmp.collapse() == (collapse_measure(cmp.distance[keep], cmp.graph[keep].real),
                              collapse_measure(cmp.distance[keep], cmp.continuum[keep].real))
    ax = cmp.plot()
    assert ax.get_xlabel() == r"hyperbolic distance $d_{ij}$" and len(ax.containers) == 2
    from hyperlattice.plots.green import plot_distance_profile

    ax2 = plot_distance_profile(cmp, lat3)  # the older call with the lattice
    for a, b in zip(ax.containers, ax2.containers):
        np.testing.assert_array_equal(a.lines[0].get_ydata(), b.lines[0].get_ydata())
    with pytest.raises(ValueError):
        plot_distance_profile(cmp, ring_lattice(7, 3, 2))
    plt.close("all")


def test_sorted_pairs_agree_with_correlation_pairs(cmp, lat3):
    a = correlation_pairs(lat3, cmp.source, cmp.graph.real)
    b = sorted_pairs(cmp.distance, cmp.graph.real, cmp.source)
    for x, y in zip(a, b):
        np.testing.assert_array_equal(x, y)


@pytest.mark.parametrize("values", [np.linspace(1.0, 2.0, 9), np.linspace(1.0, 2.0, 9) * (1 + 0.5j)])
def test_binned_correlation_round_trip_and_plot(values, tmp_path):
    import matplotlib.pyplot as plt

    b = bin_by_distance(np.linspace(0.0, 1.0, 9), values, width=0.25)
    assert isinstance(b, BinnedCorrelation) and b.count.sum() == 9
    back = load_result(b.save(tmp_path / "b.npz"))
    again = BinnedCorrelation.from_dict(json.loads(json.dumps(b.as_dict())))
    for r in (back, again):
        for name in ("edges", "centre", "mean", "std", "count"):
            np.testing.assert_array_equal(getattr(r, name), getattr(b, name))
    assert b.plot().get_xlabel()
    plt.close("all")


def test_binning_with_edges():
    b = bin_by_distance([0.1, 0.2, 0.6], [1.0, 3.0, 5.0], edges=[0.0, 0.5, 1.0])
    assert b.mean.tolist() == [2.0, 5.0] and b.std.tolist() == [1.0, 0.0] and b.count.tolist() == [2, 1]


D = np.linspace(0.0, 1.0, 5)
V = np.arange(1.0, 6.0)


@pytest.mark.parametrize("dist, values, kwargs", [
    (None, V, {}),
    ("abc", V, {}),
    (D, None, {}),
    (D, "abcde", {}),
    (D, V[:-1], {}),
    (D[:, None], V[:, None], {}),
    ([], [], {}),
    (np.where(D > 0.5, np.nan, D), V, {}),
    (D, np.where(V > 3, np.inf, V), {}),
    (-D - 1, V, {}),
    (D, V, {"width": 0.0}),
    (D, V, {"width": -1.0}),
    (D, V, {"width": float("nan")}),
    (D, V, {"width": "0.1"}),
    (D, V, {"width": True}),
    (D, V, {"edges": [0.0]}),
    (D, V, {"edges": [0.0, 0.5, 0.5, 1.0]}),
    (D, V, {"edges": [1.0, 0.0]}),
    (D, V, {"edges": "ab"}),
])
def test_bin_by_distance_bad_input(dist, values, kwargs):
    with pytest.raises(ValueError):
        bin_by_distance(dist, values, **kwargs)
    if "edges" not in kwargs:
        with pytest.raises(ValueError):
            collapse_measure(dist, values, **kwargs)


def test_collapse_of_vanishing_values_is_refused():
    with pytest.raises(ValueError, match="vanish"):
        collapse_measure(D, np.zeros(5))


G = np.array([1.0, 2.0j, 3.0, 4.0])


@pytest.mark.parametrize("graph, continuum, exclude", [
    (G, G[:-1], None),
    (G[:, None], G[:, None], None),
    (None, G, None),
    (G, None, None),
    (G, "abcd", None),
    ("abcd", G, None),
    (np.array([1.0, np.nan, 3.0, 4.0]), G, None),
    (G, np.array([1.0, np.inf, 3.0, 4.0]), None),   # infinite outside the excluded site
    (G, np.array([1.0, np.inf, 3.0, 4.0]), 0),
    (G, G, 4),
    (G, G, -1),
    (G, G, "1"),
    (G, G, 1.5),
    (np.zeros(4), G, None),
])
def test_relative_l2_bad_input(graph, continuum, exclude):
    with pytest.raises(ValueError):
        relative_l2(graph, continuum, exclude=exclude)


def test_relative_l2_accepts_infinite_source():
    c = G.copy()
    c[1] = np.inf
    assert relative_l2(G, c, exclude=1) == 0.0
    assert relative_l2(G, 2 * G) == pytest.approx(1.0, rel=1e-15)
