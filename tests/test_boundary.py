"""Boundary correlators of the massive scalar on the outer ring, lattice vs continuum (holography)."""

import math

import numpy as np
import pytest
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from hyperlattice.compare import boundary as cb
from hyperlattice.continuum.green import continuum_green
from hyperlattice.continuum.massive import bf_bound, conformal_two_point, delta_from_omega
from hyperlattice.dictionary import green_prefactor, lambda_from_energy
from hyperlattice.graph.lattice import ring_lattice
from hyperlattice.graph.operators import hamiltonian
from hyperlattice.graph.qubits import BelowBandResolvent
from hyperlattice.graph.spectrum import lowest_levels
from hyperlattice.results import Result


@pytest.fixture(scope="module")
def lat5():
    return ring_lattice(7, 3, 5)


@pytest.mark.parametrize("omega", [-3.6, -3.0, -2.95])
def test_correlators_match_direct_sparse_solve(lat5, omega):
    bc = cb.boundary_correlator(lat5, omega)
    ring = cb.outer_ring(lat5)
    assert bc.source == ring[0] and np.array_equal(bc.sites, ring)
    b = np.zeros(lat5.sites)
    b[bc.source] = 1.0
    ref = spla.spsolve((hamiltonian(lat5) - omega * sp.identity(lat5.sites)).tocsc(), b)
    assert np.allclose(bc.graph, ref[ring], rtol=1e-12, atol=0)
    assert np.all(bc.graph > 0)            # below the band every entry of G is positive


def test_band_bottom_checked_exactly(lat5):
    e0 = lowest_levels(lat5, 1).energies[0]
    res = BelowBandResolvent(lat5)
    assert np.all(res.column(e0 - 1e-6, 0) > 0)
    with pytest.raises(ValueError, match="1 level"):
        res.column(e0 + 1e-6, 0)
    with pytest.raises(ValueError, match="not below the band"):
        cb.boundary_correlator(lat5, -2.0)


def test_fit_recovers_exact_conformal_data():
    rng = np.random.default_rng(1)
    theta = rng.uniform(-math.pi, math.pi, 400)
    r = 1 - rng.uniform(1e-4, 4e-4, 400)        # a ragged "outer ring"
    z = r * np.exp(1j * theta)
    vals = conformal_two_point(z, 1 - 2e-4, 1.37)
    delta, se, n, amp, beta = cb.fit_delta(theta, vals, 1 - r * r, 0.1)
    # exact up to the O(1 - r) factors (r r')^Delta of the conformal form, which the covariate
    # ln(1 - r^2) nearly absorbs
    assert delta == pytest.approx(1.37, rel=1e-5) and beta == pytest.approx(1.37, rel=2e-3)
    assert se < 1e-5 and n == np.count_nonzero(np.abs(np.sin(theta / 2)) >= math.sin(0.05))


def test_window_justification(lat5):
    # the window edge is where the geodesic between the pair reaches depth rings inside the outer ring
    th = cb.fit_window(lat5, 2)
    off = lat5.ring_offsets
    gap = np.median(1 - np.abs(lat5.z[off[2]:off[3]]))
    assert 1 - math.tan(math.pi / 4 - th / 4) == pytest.approx(gap, rel=1e-12)
    assert cb.fit_window(lat5, 3) > th > cb.fit_window(lat5, 1)
    assert cb.fit_window(ring_lattice(7, 3, 7), 2) < th     # shrinks as the flake grows
    with pytest.raises(ValueError, match="at least 3 rings"):
        cb.fit_window(ring_lattice(7, 3, 2), 2)


def test_continuum_column_is_eq21_whole_disk(lat5):
    bc = cb.boundary_correlator(lat5, -3.2)
    ring = bc.sites
    lam = lambda_from_energy(-3.2)
    keep = ring != bc.source
    ref = green_prefactor() * continuum_green(lat5.z[ring[keep]], lat5.z[bc.source], lam, 1.0).real
    assert np.allclose(bc.continuum[keep], ref, rtol=1e-14)
    assert math.isinf(bc.continuum[~keep][0])
    assert bc.delta_continuum == pytest.approx(delta_from_omega(-3.2))


def test_beyond_continuum_bf_bound(lat5):
    # E_inf < omega < E0(l): the lattice propagator exists, the infinite-disk continuum does not
    e0 = lowest_levels(lat5, 1).energies[0]
    omega = 0.5 * (bf_bound().omega + e0)
    assert bf_bound().omega < omega < e0
    bc = cb.boundary_correlator(lat5, omega)
    assert math.isnan(bc.delta_continuum) and np.all(np.isnan(bc.continuum))
    assert bc.mass2 < -1 and np.all(bc.graph > 0)
    s = bc.summary()
    assert list(s)[:9] == ["p", "q", "rings", "omega", "lambda", "mass2", "delta_continuum", "delta_lattice",
                           "delta_lattice_err"]
    assert list(s)[9:] == ["mass2_ads_radius_1", "ads_radius", "mass2_input", "delta_formulas",
                           "delta_continuum_improved", "delta_lattice_stat", "delta_lattice_window",
                           "delta_lattice_sys", "delta_lattice_sys_rings", "delta_lattice_sys_spacing",
                           "delta_lattice_total_err"]


# measured Delta_lattice vs Delta_continuum (docs/below-band.md); ell = 8 for the trend, ~0.1 s per fit
def test_lattice_delta_vs_continuum():
    fits = {ell: {w: cb.boundary_correlator(ring_lattice(7, 3, ell), w) for w in (-3.5, -3.0, -2.95)}
            for ell in (6, 7, 8)}
    for ell, row in fits.items():
        for w, bc in row.items():
            assert bc.delta_lattice_err > 0
            # heavy masses: within 3 % of the continuum already at l = 6
            if w <= -3.0:
                assert bc.delta_lattice == pytest.approx(bc.delta_continuum, rel=0.03)
    # near the BF bound the lattice Delta approaches the continuum one as l grows
    gaps = [fits[ell][-2.95].delta_lattice - fits[ell][-2.95].delta_continuum for ell in (6, 7, 8)]
    assert gaps[0] > gaps[1] > gaps[2] > 0
    # heavy mass: converged in l (changes below 1 %)
    assert fits[8][-3.5].delta_lattice == pytest.approx(fits[6][-3.5].delta_lattice, rel=0.01)


def test_delta_curve_and_roundtrip():
    lat = ring_lattice(7, 3, 6)
    curve = cb.delta_curve(lat, [-3.5, -3.2, -3.0])
    assert np.all(np.diff(curve.delta_lattice) < 0)        # lighter -> smaller Delta
    assert np.allclose(curve.delta_continuum, delta_from_omega(curve.omegas))
    back = Result.from_dict(curve.as_dict())
    assert np.array_equal(back.delta_lattice, curve.delta_lattice)
    bc = cb.boundary_correlator(lat, -3.2)
    back = Result.from_dict(bc.as_dict())
    assert np.array_equal(back.graph, bc.graph) and back.summary() == bc.summary()


def test_delta_curve_is_boundary_correlator_per_mass_and_caches_are_per_lattice():
    # delta_curve skips the result object per mass and reuses the fit geometry: the same numbers
    # as one boundary_correlator per frequency (to rounding: SuperLU reuses its first column order
    # for the later shifts, a fresh resolvent computes it again)
    import gc
    import weakref

    from hyperlattice.graph import qubits

    lat = ring_lattice(7, 3, 7)                 # large enough for the mirror-even block
    omegas = [-3.6, -3.1, -2.95]
    curve = cb.delta_curve(lat, omegas)
    for k, w in enumerate(omegas):
        bc = cb.boundary_correlator(lat, w, continuum=False)
        assert curve.delta_lattice[k] == pytest.approx(bc.delta_lattice, rel=1e-12, abs=0)
        assert curve.delta_lattice_err[k] == pytest.approx(bc.delta_lattice_err, rel=1e-9, abs=0)
        assert curve.delta_continuum[k] == bc.delta_continuum or math.isnan(bc.delta_continuum)
    # the fit geometry of a source is kept (bounded) while its lattice lives
    ring = cb.outer_ring(lat)
    for j in ring[:cb._FIT_CACHE + 3]:
        assert cb._ring_fit(lat, int(j), ring, 2) is cb._ring_fit(lat, int(j), ring, 2)
    assert len(cb._FITS[lat]) == cb._FIT_CACHE
    # H and the mirror-even blocks are shared by the resolvents of one lattice, the factors are not
    a, b = BelowBandResolvent(lat), BelowBandResolvent(lat, method="superlu")
    j = int(ring[0])
    xa, xb = a.column(-3.3, j), b.column(-3.3, j)
    assert np.max(np.abs(xa / xb - 1)) < 1e-11
    assert a.H is b.H and a._mirrors[0].structure is b._mirrors[0].structure
    assert a._mirrors[0]._factor is not b._mirrors[0]._factor and b._mirrors[0]._factor.backend == "superlu"
    assert BelowBandResolvent(lat, t=2.0).H is not a.H
    np.testing.assert_allclose(BelowBandResolvent(lat, t=2.0).column(-6.6, j), xa / 2, rtol=1e-12)
    # ... and freed with it (the caches hold no reference back to the lattice)
    ref = weakref.ref(lat)
    del lat, a, b, curve, bc
    gc.collect()
    assert ref() is None
    assert all(r is not None for r in qubits._Structure._cache.keys()) and ref() not in cb._FITS


def test_lattice_bf_bound_above_continuum():
    bf = cb.lattice_bf_bound(7, 3, (3, 4, 5, 6))
    assert np.all(np.diff(bf.e0) < 0)                       # moves down with l
    assert np.all(bf.e0 > bf.omega_continuum)               # and stays above E_inf here
    assert np.all(bf.mass2 < -1)
    assert "window" in bf.statement()


def test_bulk_to_boundary():
    lat = ring_lattice(7, 3, 7)
    b = cb.bulk_to_boundary(lat, -3.2)
    # measured: delta_fit 1.5469 vs 1.5613, kernel_rel_l2 0.119 (docs/below-band.md)
    assert b.delta_fit == pytest.approx(b.delta_continuum, rel=0.02)
    assert b.kernel_rel_l2 < 0.2 and b.rel_l2 > 0
    assert np.all(np.isfinite(b.kernel[b.bulk]))
    with pytest.raises(ValueError, match="outer ring"):
        cb.bulk_to_boundary(lat, -3.2, source=0)


def test_refusals(lat5):
    with pytest.raises(ValueError, match="outer ring"):
        cb.boundary_correlator(lat5, -3.2, source=0)
    with pytest.raises(ValueError, match="must be real"):
        cb.boundary_correlator(lat5, -3.2 + 0.1j)
    from hyperlattice.graph.lattice import line_graph
    with pytest.raises(ValueError, match="line graph"):
        cb.boundary_correlator(line_graph(ring_lattice(7, 3, 3)), -4.0)
    with pytest.raises(ValueError, match="at least 10"):
        cb.fit_delta([0.5, 1.0], [1.0, 0.5], [0.1, 0.1], 0.1)


def test_default_resolvent_matches_superlu_and_resolves_tiny_entries():
    # the default backend (CHOLMOD when installed) against the SuperLU route, entry by entry in
    # relative terms, down to the smallest outer-ring values (M-matrix: no cancellation)
    lat = ring_lattice(7, 3, 6)
    ring = cb.outer_ring(lat)
    fast, slow = BelowBandResolvent(lat), BelowBandResolvent(lat, method="superlu")
    assert slow.backend == "superlu" and fast.backend in ("cholmod", "superlu")
    for w in (-3.8, -2.9):
        a, b = fast.column(w, ring[0]), slow.column(w, ring[0])
        assert np.max(np.abs(a / b - 1)) < 1e-11 and a.min() > 0
    assert fast.column(-3.8, ring[0])[ring].min() < 1e-10          # spans many decades
    e0 = lowest_levels(lat, 1).energies[0]
    with pytest.raises(ValueError, match="1 level"):
        fast.column(e0 + 1e-6, 0)
    with pytest.raises(ValueError, match="method"):
        BelowBandResolvent(lat, method="cg")



@pytest.mark.parametrize("backend", ["superlu", pytest.param("cholmod", marks=pytest.mark.skipif(
    not __import__("hyperlattice.graph.factor", fromlist=["x"]).cholmod_available(), reason="no scikit-sparse"))])
def test_source_on_a_mirror_axis_uses_the_even_block_without_losing_tiny_entries(backend):
    # l = 7: the outer-ring site on the real axis; its column from the mirror-even block (half the
    # size) against the full factorisation, entry by entry in relative terms (both M-matrix solves,
    # relative error ~1e-14 each; 1e-11 leaves room for the condition near E0 at -2.93)
    lat = ring_lattice(7, 3, 7)
    ring = cb.outer_ring(lat)
    j = int(ring[np.argmin(np.abs(np.angle(lat.z[ring])))])
    res = BelowBandResolvent(lat, method=backend)
    for w in (-3.6, -2.93):
        a = res.column(w, j)
        b = res.columns(w, [j])[:, 0]          # several sources: the full matrix
        assert np.max(np.abs(a / b - 1)) < 1e-11 and a[ring].min() < 1e-4 * a.max()   # many decades
    assert len(res._mirrors) == 1 and res._mirrors[0].dim < 0.51 * lat.sites
    res.column(-3.6, j)
    assert res.route.startswith(backend) and "mirror-even block" in res.route
    assert "mirror-even block" in cb.boundary_correlator(lat, -3.6, j, resolvent=res, continuum=False).solver
    assert res._mirrors[0]._factor.backend == backend
    # the even block keeps the ground state: omega above E0 is refused there as well
    e0 = lowest_levels(lat, 1).energies[0]
    with pytest.raises(ValueError, match="mirror-even block"):
        res.column(e0 + 1e-6, j)
    # a source off every axis takes the full factorisation
    off = int(ring[np.argmin(np.abs(np.angle(lat.z[ring]) - 0.1))])
    np.testing.assert_allclose(res.column(-3.6, off), res.columns(-3.6, [off])[:, 0], rtol=1e-13)
    assert off in res._no_mirror and "of H (5,887 rows)" in res.route


# -- continuum side: whole disk vs Dirichlet disk of radius L (issue 14, item 2) --

@pytest.mark.parametrize("omega", [-3.5, -3.2])
@pytest.mark.slow
def test_dirichlet_disk_continuum_is_closer_to_the_lattice(lat5, omega):
    from hyperlattice.dictionary import disk_radius_for_rings

    whole = cb.boundary_correlator(lat5, omega)
    assert np.array_equal(whole.continuum, cb.boundary_correlator(lat5, omega, continuum_disk="whole").continuum)
    dir_ = cb.boundary_correlator(lat5, omega, continuum_disk="dirichlet")
    assert dir_.delta_lattice == whole.delta_lattice              # the fit does not depend on the model
    L = disk_radius_for_rings(5)[0]
    z = np.abs(ring_lattice(7, 3, 5).z[dir_.sites])
    src = dir_.sites == dir_.source
    assert np.isinf(dir_.continuum[src]).all()
    assert np.all(np.isnan(dir_.continuum[z >= L])) and np.all(np.isfinite(dir_.continuum[(z < L) & ~src]))
    assert np.all(dir_.continuum[(z < L) & ~src] > 0)
    k = np.isfinite(dir_.continuum)
    rel = lambda c: np.linalg.norm(dir_.graph[k] - c[k]) / np.linalg.norm(dir_.graph[k])
    # measured: 0.212 vs 0.255 (omega = -3.5), 0.249 vs 0.465 (-3.2)
    assert rel(dir_.continuum) < rel(whole.continuum) - 0.03
    # pointwise the Dirichlet column lies below the whole-disk one (G_L < G_1: the maximum principle)
    assert np.all(dir_.continuum[k] < whole.continuum[k])
    mapped = cb.boundary_correlator(lat5, omega, continuum_disk="mapped")
    assert np.all(np.isfinite(mapped.continuum[~src])) and np.all(mapped.continuum[~src] > 0)


def test_dirichlet_disk_refused_beyond_its_series():
    lat7 = ring_lattice(7, 3, 7)
    ring = cb.outer_ring(lat7)
    for disk in ("dirichlet", "mapped"):
        with pytest.raises(ValueError, match="Fourier orders"):
            cb.continuum_boundary_column(lat7, -3.2, int(ring[0]), ring, disk=disk)
    with pytest.raises(ValueError, match="one of"):
        cb.boundary_correlator(ring_lattice(7, 3, 4), -3.2, continuum_disk="L")


def test_plot_names_the_continuum_model_used():
    """Regression: the figure said "L = 1" also when the Dirichlet-disk column was drawn."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from hyperlattice.compare.boundary import boundary_correlator
    from hyperlattice.graph.lattice import ring_lattice

    bc = boundary_correlator(ring_lattice(7, 3, 5), -3.2, continuum_disk="dirichlet")
    assert bc.continuum_disk == "dirichlet"
    ax = bc.plot()
    labels = [t.get_text() for t in ax.get_legend().get_texts()] if ax.get_legend() else \
        [h.get_label() for h in ax.get_lines()]
    assert any("Dirichlet disk of radius L" in t for t in labels), labels
    plt.close(ax.figure)


# ----------------------------------------------------------------------------
# issue 28 item 2: the mass in the user's convention, and the systematic error beside the fit's
# ----------------------------------------------------------------------------

def test_mass2_in_the_convention_named(lat5):
    """m^2 = 1 in unit-radius AdS2 is Delta = 1.618 (4 in the paper's metric), not the paper-metric 1.207."""
    from hyperlattice.continuum.massive import omega_from_mass2

    bc1 = cb.boundary_correlator(lat5, mass2=1.0, ads_radius=1, systematic=False)
    assert bc1.mass2 == pytest.approx(4.0, abs=1e-12) and bc1.delta_continuum == pytest.approx((1 + 5**0.5) / 2)
    assert (bc1.ads_radius, bc1.mass2_input) == (1.0, 1.0)
    assert bc1.delta_formulas == pytest.approx({"ads_radius_1": 1.6180339887, "ads_radius_0.5": 1.2071067812})
    half = cb.boundary_correlator(lat5, mass2=1.0, ads_radius=0.5, systematic=False)
    assert half.mass2 == pytest.approx(1.0, abs=1e-12) and half.delta_continuum == pytest.approx(0.5 + 0.5 * 2**0.5)
    # the same physics as the frequency of that mass
    by_omega = cb.boundary_correlator(lat5, float(omega_from_mass2(4.0)), systematic=False)
    assert by_omega.delta_lattice == pytest.approx(bc1.delta_lattice, rel=1e-12)
    assert by_omega.ads_radius == 0.5 and by_omega.mass2_input == pytest.approx(4.0)
    s = bc1.summary()
    assert s["mass2_ads_radius_1"] == pytest.approx(1.0) and s["ads_radius"] == 1.0


@pytest.mark.parametrize("kwargs,match", [
    (dict(mass2=1.0), "needs ads_radius"),
    (dict(mass2=1.0, ads_radius=2.0), "names the convention"),
    (dict(omega=-3.5, mass2=1.0, ads_radius=1), "not both"),
    (dict(omega=-3.5, ads_radius=1), "give it with mass2"),
    (dict(), "give the frequency omega"),
])
def test_mass2_refusals(lat5, kwargs, match):
    with pytest.raises(ValueError, match=match):
        cb.boundary_correlator(lat5, **kwargs)


def test_systematic_error_covers_the_known_offset():
    """{7,3}, l = 6, omega = -3.5: the lattice Delta is 2 % below the paper-dictionary continuum Delta,
    ~3 fit errors, but inside its systematic error (the paper's against the improved dictionary), and
    it lies between the two dictionaries' continuum values."""
    lat = ring_lattice(7, 3, 6)
    bc = cb.boundary_correlator(lat, -3.5)
    offset = abs(bc.delta_lattice - bc.delta_continuum)
    assert offset > 2.5 * bc.delta_lattice_err                       # "many sigma" with the fit error alone
    assert offset < bc.delta_lattice_total_err                       # not with the systematic beside it
    assert bc.delta_continuum_improved < bc.delta_lattice < bc.delta_continuum
    assert bc.delta_lattice_sys_spacing == pytest.approx(abs(bc.delta_continuum - bc.delta_continuum_improved))
    # finite l: the same fit on the 5-ring flake
    five = cb.boundary_correlator(ring_lattice(7, 3, 5), -3.5, systematic=False)
    assert bc.delta_lattice_sys_rings == pytest.approx(abs(bc.delta_lattice - five.delta_lattice), rel=1e-9)
    assert bc.delta_lattice_sys == pytest.approx(math.hypot(bc.delta_lattice_sys_spacing, bc.delta_lattice_sys_rings))
    # without it: NaN, and the total is the fit error
    bare = cb.boundary_correlator(lat, -3.5, systematic=False)
    assert math.isnan(bare.delta_lattice_sys) and bare.delta_lattice_total_err == bare.delta_lattice_err


def test_delta_curve_carries_the_systematic_error(lat5):
    dc = cb.delta_curve(lat5, [-3.5, -4.0])
    one = [cb.boundary_correlator(lat5, w) for w in (-3.5, -4.0)]
    np.testing.assert_allclose(dc.delta_lattice_sys, [b.delta_lattice_sys for b in one], rtol=1e-9)
    np.testing.assert_allclose(dc.delta_continuum_improved, [b.delta_continuum_improved for b in one], rtol=1e-12)
    by_mass = cb.delta_curve(lat5, mass2=dc.mass2 / 4, ads_radius=1, systematic=False)
    np.testing.assert_allclose(by_mass.omegas, dc.omegas, rtol=1e-12)
    assert np.all(np.isnan(by_mass.delta_lattice_sys))
    with pytest.raises(ValueError, match="needs ads_radius"):
        cb.delta_curve(lat5, mass2=[1.0])
