"""Graph vs continuum levels: side by side, the relative-error trend (open question), Z and level counts."""

import math

import numpy as np
import pytest

from hyperlattice.compare.levels import (LevelComparison, LevelCount, PartitionComparison, RelativeErrorTrend,
                                         continuum_levels_below, graph_levels_below, levels_side_by_side,
                                         partition_functions, relative_error_trend)
from hyperlattice.graph.lattice import ring_lattice
from hyperlattice.results import Levels, load_result


def _energies(rel, e_graph=-2.9):
    """Graph and continuum energies with the given signed relative errors (E_g - E_c)/|E_g|."""
    g = np.full(len(rel), e_graph)
    return g, g - np.asarray(rel) * abs(e_graph)


# ----------------------------------------------------------------------------
# the relative-error trend (App. AppSpec's open question)
# ----------------------------------------------------------------------------

def test_trend_sign_change_monotone_and_aitken_exact_for_geometric_tail():
    # x_l = L - C r^l is extrapolated exactly by Aitken's Delta^2 from any three values
    limit, r = 6.5e-4, 0.55
    rel = [-2e-2, -4e-3, -6e-4] + [limit - 1e-3 * r ** k for k in range(1, 6)]
    g, c = _energies(rel)
    t = relative_error_trend(range(1, 9), g, c, level="E0")
    assert isinstance(t, RelativeErrorTrend) and t.level == "E0"
    np.testing.assert_allclose(t.relative_error, rel, rtol=1e-12)
    assert t.rings.tolist() == list(range(1, 9)) and t.rings.dtype.kind == "i"
    assert t.sign_change.tolist() == [3, 4] and t.rising is True
    assert t.monotone and t.saturates and not t.magnitude_decreasing
    d = np.diff(rel)[-2:]
    np.testing.assert_allclose(t.increments, d, rtol=1e-10)
    assert t.aitken_limit == pytest.approx(limit, rel=1e-9)


def test_trend_without_sign_change():
    g, c = _energies([-3e-2, -1e-2, -4e-3, -1e-3])
    t = relative_error_trend([1, 2, 3, 4], g, c)
    assert t.sign_change is None and t.rising is None and not t.monotone
    assert t.magnitude_decreasing and t.increments.size == 0 and math.isnan(t.aitken_limit)
    g, c = _energies([-3e-2, -1e-2, -2e-2])
    assert not relative_error_trend([1, 2, 3], g, c).magnitude_decreasing


def test_trend_after_sign_change_not_monotone_or_too_short():
    g, c = _energies([-1e-2, 2e-4, 5e-4, 3e-4, 6e-4])
    t = relative_error_trend(range(5), g, c)
    assert t.sign_change.tolist() == [0, 1] and not t.monotone and math.isnan(t.aitken_limit)
    g, c = _energies([-1e-2, 2e-4, 5e-4])  # two values after the sign change: no trend claimed
    assert not relative_error_trend(range(3), g, c).monotone


def test_trend_growing_increments_give_no_limit():
    g, c = _energies([-1e-2, 1e-4, 2e-4, 4e-4, 8e-4])
    t = relative_error_trend(range(1, 6), g, c)
    assert t.monotone and not t.saturates and math.isnan(t.aitken_limit)
    np.testing.assert_allclose(t.increments, [2e-4, 4e-4], rtol=1e-9)


def test_trend_downward_sign_change_grows_in_magnitude():
    """Graph level moving from above to below the continuum: the trend is read on |error|."""
    g, c = _energies([1e-2, -1e-4, -3e-4, -4e-4])
    t = relative_error_trend([1, 2, 3, 4], g, c)
    assert t.rising is False and t.monotone and t.saturates
    assert t.aitken_limit == pytest.approx(-4e-4 - (-1e-4) ** 2 / (-1e-4 - (-2e-4)), rel=1e-9)


@pytest.mark.parametrize("rings, graph, continuum", [
    ([], [], []),
    ([1, 2], [-2.0], [-2.0, -2.1]),
    ([1, 1], [-2.0, -2.1], [-2.0, -2.1]),
    ([2, 1], [-2.0, -2.1], [-2.0, -2.1]),
    ([1.5, 2], [-2.0, -2.1], [-2.0, -2.1]),
    ([1, 2], [-2.0, float("nan")], [-2.0, -2.1]),
    ([1, 2], [0.0, -2.1], [-2.0, -2.1]),
    (None, [-2.0], [-2.0]),
    ([1, 2], "ab", [-2.0, -2.1]),
    ([[1, 2]], [[-2.0, -2.1]], [[-2.0, -2.1]]),
])
def test_trend_bad_input(rings, graph, continuum):
    with pytest.raises(ValueError):
        relative_error_trend(rings, graph, continuum)
    with pytest.raises(ValueError):
        relative_error_trend([1], [-2.0], [-2.0], level=None)


@pytest.mark.parametrize("rel", [[-2e-2, -4e-3, 1e-4, 3e-4, 4e-4], [-3e-2, -1e-2]])
@pytest.mark.parametrize("suffix", [".json", ".npz"])
def test_trend_round_trip(rel, suffix, tmp_path):
    g, c = _energies(rel)
    t = relative_error_trend(range(1, len(rel) + 1), g, c, level="E1")
    back = RelativeErrorTrend.from_dict(t.as_dict())
    loaded = load_result(t.save(tmp_path / f"t{suffix}"))
    for b in (back, loaded):
        assert isinstance(b, RelativeErrorTrend) and b.level == "E1"
        np.testing.assert_array_equal(b.relative_error, t.relative_error)
        np.testing.assert_array_equal(b.rings, t.rings)
        assert (b.sign_change is None) == (t.sign_change is None)
        assert b.monotone == t.monotone and b.rising == t.rising
        assert (math.isnan(b.aitken_limit) and math.isnan(t.aitken_limit)) or b.aitken_limit == t.aitken_limit
    with pytest.raises(ValueError):
        t.relative_error[0] = 1.0  # read-only


def test_trend_plot():
    import matplotlib.pyplot as plt

    g, c = _energies([-2e-2, -4e-3, 1e-4, 3e-4, 4e-4])
    ax = relative_error_trend(range(1, 6), g, c).plot()
    assert ax.get_ylabel()
    plt.close("all")


# ----------------------------------------------------------------------------
# levels side by side
# ----------------------------------------------------------------------------

def _levels(energies, n, m, kind, method, p=7):
    return Levels(energies=np.asarray(energies), n=np.asarray(n), m=None if m is None else np.asarray(m),
                  errors=np.full(len(energies), 1e-14), error_kind=kind, method=method, description="test", p=p, q=3)


def test_side_by_side_level_by_level():
    g = _levels([-2.847, -2.762, -2.762, -2.6], [1, 1, 1, 2], [0, 1, -1, 0], "residual", "sector-dense")
    c = _levels([-2.842, -2.746, -2.746], [1, 1, 1], [0, 1, -1], "energy error bound", "dirichlet-roots")
    cmp = levels_side_by_side(g, c)
    assert isinstance(cmp, LevelComparison) and len(cmp) == 3
    np.testing.assert_allclose(cmp.relative_difference, (g.energies[:3] - c.energies) / np.abs(g.energies[:3]))
    assert cmp.labels_agree.tolist() == [True, True, True]
    rows = cmp.table()
    assert rows[1]["m_graph"] == 1 and rows[1]["m_continuum"] == 1 and rows[1]["E_continuum"] == -2.746
    assert cmp.summary()["graph_method"] == "sector-dense"
    c2 = _levels([-2.842, -2.746, -2.7], [1, 1, 2], [0, 1, 0], "energy error bound", "dirichlet-roots")
    assert levels_side_by_side(g, c2).labels_agree.tolist() == [True, True, False]
    g_nom = _levels([-2.8, -2.7], [1, 2], None, "residual", "dense")
    assert levels_side_by_side(g_nom, c).labels_agree is None


def test_side_by_side_bad_input():
    g = _levels([-2.8], [1], [0], "residual", "dense")
    with pytest.raises(ValueError):
        levels_side_by_side(g, [-2.8])
    with pytest.raises(ValueError):
        levels_side_by_side(None, g)
    with pytest.raises(ValueError, match="same tiling"):
        levels_side_by_side(g, _levels([-2.8], [1], [0], "energy error bound", "roots", p=8))


def test_side_by_side_round_trip_and_plot(tmp_path):
    import matplotlib.pyplot as plt

    g = _levels([-2.847, -2.762, -2.762], [1, 1, 1], [0, 1, -1], "residual", "sector-dense")
    c = _levels([-2.842, -2.746, -2.746], [1, 1, 1], [0, 1, -1], "energy error bound", "dirichlet-roots")
    cmp = levels_side_by_side(g, c)
    back = load_result(cmp.save(tmp_path / "cmp.json"))
    assert isinstance(back, LevelComparison) and isinstance(back.graph, Levels)
    np.testing.assert_array_equal(back.relative_difference, cmp.relative_difference)
    np.testing.assert_array_equal(back.continuum.energies, c.energies)
    assert cmp.plot().get_xlabel()
    plt.close("all")


def test_side_by_side_with_the_package_spectra():
    """A graph Spectrum and ContinuumSpectrum, once both are Levels, line up as (1,0), (1,+1), (1,-1)."""
    from hyperlattice.continuum.spectrum import continuum_levels
    from hyperlattice.graph.spectrum import lowest_levels

    g = lowest_levels(ring_lattice(7, 3, 5), levels=3)
    c = continuum_levels(7, 3, rings=5, levels=3)
    if not (isinstance(g, Levels) and isinstance(c, Levels)):
        pytest.skip("Spectrum / ContinuumSpectrum are not results.Levels yet")
    cmp = levels_side_by_side(g, c)
    assert cmp.labels_agree.tolist() == [True, True, True]
    assert np.all(np.abs(cmp.relative_difference) < 5e-3)


# ----------------------------------------------------------------------------
# levels below zero and the partition functions of the Fig2 inset
# ----------------------------------------------------------------------------

# the l = 4 counts take seconds (every continuum level below zero, by root finding), so the tests
# that use them are all in the slow tier: a fast one would pay for the fixture alone
@pytest.fixture(scope="module")
def counts_l4():
    return graph_levels_below(ring_lattice(7, 3, 4)), continuum_levels_below(7, 3, rings=4)


@pytest.mark.slow
def test_continuum_count_degeneracy_matches_continuum_levels(counts_l4):
    """Regression: every m != 0 level is the pair +-m (degeneracy 2), whatever its n.

    The report's Fig2 inset used to weight the n = 1 row by 1 and every n >= 2 level by 2
    (the (n, m) table read with its axes swapped): 78 states below zero instead of 108.
    """
    from hyperlattice.continuum.spectrum import continuum_levels

    _, c = counts_l4
    assert c.side == "continuum" and c.states == 108
    assert np.all(c.degeneracy == np.where(c.m == 0, 1, 2))
    assert c.degeneracy[(c.n == 1) & (c.m == 1)].tolist() == [2]
    assert np.all(np.diff(c.energies) >= 0) and np.all(c.energies < 0)
    # expanded by degeneracy, the count is exactly the K lowest states of continuum_levels
    ref = continuum_levels(7, 3, rings=4, levels=c.states)
    np.testing.assert_allclose(np.repeat(c.energies, c.degeneracy), ref.energies, rtol=1e-13)
    assert ref.energies[-1] < 0 < continuum_levels(7, 3, rings=4, levels=c.states + 1).energies[-1]


@pytest.mark.slow
def test_graph_count_and_partition_function_agree_with_graph_spectrum(counts_l4):
    from hyperlattice.graph.spectrum import partition_function

    g, _ = counts_l4
    assert g.side == "graph" and g.states == 146 and g.at_cutoff == 2 and g.n is None
    beta = np.linspace(0.05, 6.0, 7)
    np.testing.assert_allclose(g.partition_function(beta), partition_function(ring_lattice(7, 3, 4), beta),
                               rtol=1e-13)
    assert g.counting([g.energies[0] - 1, g.energies[0], 0.0]).tolist() == [0, 1, 146]


@pytest.mark.slow
def test_partition_functions(counts_l4):
    g, c = counts_l4
    beta = np.linspace(0.05, 6.0, 120)
    z = partition_functions(g, c, beta)
    assert isinstance(z, PartitionComparison)
    assert z.graph_states == 146 and z.continuum_states == 108 and z.e0_graph == g.energies[0]
    np.testing.assert_array_equal(z.z_graph, g.partition_function(beta))
    # ln Z lies between the asymptote -beta E0 and -beta E0 + ln(states); graph and disk agree
    # well ("see the inset of Fig2"): within 2 % at the lowest temperature
    lz = np.log(z.z_graph)
    assert np.all(lz > -beta * z.e0_graph) and np.all(lz < -beta * z.e0_graph + np.log(146))
    assert lz[-1] / np.log(z.z_continuum[-1]) == pytest.approx(1.0, abs=2e-2)
    np.testing.assert_allclose(np.log(z.z_continuum), c.log_partition_function(beta), rtol=1e-12)
    with pytest.raises(ValueError):
        partition_functions(g, [1.0], beta)
    with pytest.raises(ValueError):
        partition_functions(g, c, [-1.0])


@pytest.mark.slow
def test_partition_function_overflow_is_refused_and_log_is_finite(counts_l4):
    g, _ = counts_l4
    with pytest.raises(ValueError, match="overflows"):
        g.partition_function(1000.0)
    lz = g.log_partition_function(1000.0)
    assert np.isfinite(lz).all() and lz[0] == pytest.approx(-1000.0 * g.energies[0], rel=1e-12)


@pytest.mark.slow
def test_count_round_trip_and_plot(counts_l4, tmp_path):
    import matplotlib.pyplot as plt

    g, c = counts_l4
    for res in (g, c):
        back = load_result(res.save(tmp_path / f"{res.side}.npz"))
        assert isinstance(back, LevelCount) and back.states == res.states
        np.testing.assert_array_equal(back.energies, res.energies)
    ax = c.plot()
    g.plot(ax=ax)
    z = partition_functions(g, c, np.linspace(0.1, 2, 5))
    assert z.plot().get_xlabel()
    assert isinstance(LevelCount.from_dict(c.as_dict()), LevelCount)
    plt.close("all")


def test_count_bad_input():
    with pytest.raises(ValueError, match="max_table"):
        continuum_levels_below(7, 3, rings=4, cutoff=1e3, max_table=500)
    for kwargs in ({"rings": 4, "cutoff": float("nan")}, {"rings": None}, {"rings": 4, "radius": 0.5},
                   {"radius": 1.5}, {"rings": 4, "max_table": 0}):
        with pytest.raises(ValueError):
            continuum_levels_below(7, 3, **kwargs)
    with pytest.raises(ValueError):
        graph_levels_below(None)
    with pytest.raises(ValueError):
        graph_levels_below(ring_lattice(7, 3, 2), cutoff="0")


# ----------------------------------------------------------------------------
# continuum labels of graph levels (issue 28 item 1)
# ----------------------------------------------------------------------------

def test_side_by_side_labels_agree_for_p8_where_the_lattice_splits_a_pair():
    """{8,3}: the graph's sector 4 holds the continuum pair (1, +-4), split by the lattice, and the tenth
    state continues (1, 5); compared by sector alone the labels disagreed at levels 9-10."""
    from hyperlattice.compare.levels import LabelledSpectrum
    from hyperlattice.continuum.spectrum import continuum_levels
    from hyperlattice.graph.spectrum import lowest_levels

    g = lowest_levels(ring_lattice(8, 3, 5), 10)
    assert g.m.tolist()[7:] == [4, 4, 3] and g.sector.tolist()[7:] == [4, 4, 3]   # the graph's own labels
    cmp = levels_side_by_side(g, continuum_levels(8, 3, rings=5, levels=10))
    assert cmp.labels_agree.tolist() == [True] * 10
    assert isinstance(cmp.graph, LabelledSpectrum)
    assert cmp.graph.m.tolist() == [0, 1, -1, 2, -2, 3, -3, 4, -4, 5]
    assert cmp.graph.sector.tolist() == [0, 1, 7, 2, 6, 3, 5, 4, 4, 5]
    assert cmp.graph.degeneracy.tolist() == [1, 2, 2, 2, 2, 2, 2, 1, 1, 2]
    (split,) = cmp.graph.splittings
    assert (split["n"], split["m"], split["levels"], split["resolved"]) == (1, 4, (7, 8), True)
    assert split["splitting"] == cmp.graph.energies[8] - cmp.graph.energies[7] > 0
    assert cmp.summary()["split"] == [dict(split, levels=[7, 8])]


def test_continuum_labels_round_trip_and_eigenvectors(tmp_path):
    """The cut pair is completed by the conjugate state (sector 5 = -3 listed as the continuum's (1, 5))."""
    from hyperlattice.compare.levels import continuum_labels
    from hyperlattice.graph.operators import hamiltonian
    from hyperlattice.graph.spectrum import lowest_levels

    lat = ring_lattice(8, 3, 4)
    g = lowest_levels(lat, 10, eigenvectors=True)
    lab = continuum_labels(g)
    assert lab.m.tolist()[-1] == 5 and lab.sector.tolist()[-1] == 5 and g.m.tolist()[-1] == 3
    h = hamiltonian(lat)
    v = lab.eigenvectors
    np.testing.assert_allclose(np.linalg.norm(h @ v - v * lab.energies, axis=0), 0.0, atol=1e-10)
    # the last column is the complex conjugate of the graph's sector-3 state: the sector-5 state
    np.testing.assert_allclose(v[:, -1], np.conj(g.eigenvectors[:, -1]), atol=0)
    back = load_result(lab.save(tmp_path / "lab.json"))
    assert back.m.tolist() == lab.m.tolist() and back.splittings == lab.splittings
    assert back.sector.tolist() == lab.sector.tolist()


def test_continuum_labels_report_a_tie_as_ambiguous():
    """Two graph levels of one sector at equal energy that continue different continuum levels: which
    continues which is undecidable, and both are marked."""
    from hyperlattice.compare.levels import continuum_labels
    from hyperlattice.graph.spectrum import Spectrum

    e = np.array([-2.7, -2.5, -2.5])
    spec = Spectrum(energies=e, n=np.array([1, 2, 3]), m=np.array([0, 0, 0]), errors=np.full(3, 1e-14),
                    method="sector-dense", description="test", p=7, q=3, rings=3, sites=140,
                    requested_sector=0)
    lab = continuum_labels(spec)
    assert lab.ambiguous.tolist() == [False, True, True]
    assert "ambiguous continuum label" in lab.notes()[-1]
    # apart by more than their tolerance: decided
    spec2 = Spectrum(energies=np.array([-2.7, -2.5, -2.5 + 1e-9]), n=np.array([1, 2, 3]), m=np.array([0, 0, 0]),
                     errors=np.full(3, 1e-14), method="sector-dense", description="test", p=7, q=3, rings=3,
                     sites=140, requested_sector=0)
    assert not continuum_labels(spec2).ambiguous.any()


def test_continuum_labels_refuse_what_has_no_sectors():
    from hyperlattice.compare.levels import continuum_labels
    from hyperlattice.graph.spectrum import lowest_levels

    lat = ring_lattice(7, 3, 2)
    broken = lowest_levels(lat, 2, onsite=lambda z, ring: z.real, method="dense")
    with pytest.raises(ValueError, match="no rotation sectors"):
        continuum_labels(broken)
    with pytest.raises(ValueError, match="graph Spectrum"):
        continuum_labels(_levels([-2.8], [1], [0], "residual", "dense"))
