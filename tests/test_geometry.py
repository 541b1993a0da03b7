"""Geometry of the Poincaré disk and {p,q} constants."""

import json
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from hyperlattice import _validate
from hyperlattice import geometry as g
from hyperlattice.paper_values import paper_value, paper_values

# The paper's table in App. AppFS (p, d0, h); source: graphs-to-geometry.tex, table after Eq. (adj36).
# The p = inf column prints d0 = 1, which is a misprint: the limit is (1/2) ln 3 = 0.549306,
# consistent with the printed h = tanh(d0) = 1/2 (tanh(1) would be 0.7616).
PAPER_TABLE = [
    # p, d0, h, printed decimals of d0, of h (hyperlattice.paper_values)
    (p, paper_value("geometry_d0", p).value, paper_value("geometry_h", p).value,
     paper_value("geometry_d0", p).decimals, paper_value("geometry_h", p).decimals)
    for p in (7, 8, 9, 10)
]


@pytest.mark.parametrize("p, d0, h, dd, dh", PAPER_TABLE)
def test_paper_d0_h_table(p, d0, h, dd, dh):
    assert round(g.d0(p, 3), dd) == pytest.approx(d0, abs=1e-12)
    assert round(g.lattice_h(p, 3), dh) == pytest.approx(h, abs=1e-12)


def test_infinite_p_limit_is_computed():
    # limit p -> inf of the closed forms, checked against large finite p
    assert g.lattice_h(math.inf, 3) == pytest.approx(0.5, abs=1e-15)
    assert g.d0(math.inf, 3) == pytest.approx(0.5 * math.log(3.0), abs=1e-15)
    assert g.d0(10**7, 3) == pytest.approx(g.d0(math.inf, 3), abs=1e-10)
    for q in (3, 4, 5):
        assert g.lattice_h(math.inf, q) == pytest.approx(math.cos(math.pi / q), abs=1e-15)


@pytest.mark.parametrize("p, q", [(7, 3), (8, 3), (9, 3), (10, 3), (4, 5), (5, 4), (3, 7), (6, 6)])
def test_d0_closed_form_equals_distance_of_central_polygon(p, q):
    # d0 from cosh d0 = cos(pi/p)/sin(pi/q) agrees with d(r0, r0 e^{2 pi i/p}) of Eq. (Eqr0)
    r0 = g.r0(p, q)
    assert g.distance(r0, r0 * np.exp(2j * np.pi / p)) == pytest.approx(g.d0(p, q), rel=1e-13)
    assert g.lattice_h(p, q) == pytest.approx(math.tanh(g.d0(p, q)), rel=1e-13)


def test_r0_paper_value():
    assert round(g.r0(7, 3), 6) == paper_value("r0", 7).value


def test_site_area_and_radius_constant():
    assert g.site_area(7, 3) == pytest.approx(math.pi / 28, rel=1e-15)
    assert g.radius_constant(7, 3) == pytest.approx(28.0, rel=1e-14)
    assert g.counting_slope(7, 3) == pytest.approx(14.0, rel=1e-14)
    for p in (7, 8, 9, 10, 12):
        assert g.radius_constant(p, 3) == pytest.approx(4 * p / (p - 6), rel=1e-14)
    # area per site times number of sites in the dual cell picture: q-gon with angles 2pi/p
    assert g.site_area(4, 5) == pytest.approx(((5 - 2) * math.pi - 5 * 2 * math.pi / 4) / 4, rel=1e-14)


def test_effective_radius_matches_table():
    # Tab1 "effective disk radius L" row, to its printed digits
    sites = [int(v.printed) for v in paper_values("N")]
    printed = [v.value for v in paper_values("L")]
    decimals = [v.decimals for v in paper_values("L")]
    assert decimals == [3] * 7 + [4] * 3
    for n, L, dec in zip(sites, printed, decimals):
        if n == 15435:
            # Tab1 prints 0.9990 for l = 8, but sqrt(15435/15463) = 0.9990942... rounds to
            # 0.9991 (l = 9, 10 are rounded correctly): a rounding slip in the paper, so
            # the check here is one unit of the last printed digit.
            assert abs(g.effective_radius(n) - L) < 1e-4
            assert round(g.effective_radius(n), dec) == pytest.approx(0.9991, abs=1e-12)
            continue
        assert round(g.effective_radius(n, 7, 3), dec) == pytest.approx(L, abs=1e-12)
    # the area of the disk of radius L is N site areas (definition of L)
    for n in sites:
        L = g.effective_radius(n)
        assert math.pi * L**2 / (1 - L**2) == pytest.approx(n * g.site_area(7, 3), rel=1e-12)


def test_distance_reduces_to_euclidean_near_origin():
    z1, z2 = 1e-5 + 2e-5j, -3e-5 + 1e-5j
    assert g.distance(z1, z2) == pytest.approx(abs(z1 - z2), rel=1e-8)
    assert g.distance(0, 0.5) == pytest.approx(math.atanh(0.5), rel=1e-15)


def test_distance_matches_eq4_with_mpmath():
    import mpmath as mp

    mp.mp.dps = 40
    rng = np.random.default_rng(1)
    for _ in range(20):
        r = 1 - 10 ** rng.uniform(-7, 0, 2)
        a = rng.uniform(0, 2 * np.pi, 2)
        z1, z2 = r[0] * np.exp(1j * a[0]), r[1] * np.exp(1j * a[1])
        Z1, Z2 = mp.mpc(z1.real, z1.imag), mp.mpc(z2.real, z2.imag)
        ref = mp.acosh(1 + 2 * abs(Z1 - Z2) ** 2 / ((1 - abs(Z1) ** 2) * (1 - abs(Z2) ** 2))) / 2
        # the coordinates themselves are exact binary numbers, so only rounding inside
        # the formula matters: full relative accuracy is the expectation
        assert g.distance(z1, z2) == pytest.approx(float(ref), rel=1e-12)


disk = st.builds(lambda r, a: r * np.exp(1j * a), st.floats(0, 0.99), st.floats(0, 2 * np.pi))


@settings(max_examples=200, deadline=None)
@given(z1=disk, z2=disk, a=disk, eta=st.floats(0, 2 * np.pi))
def test_mobius_is_an_isometry(z1, z2, a, eta):
    d = g.distance(z1, z2)
    d2 = g.distance(g.mobius(z1, a, eta), g.mobius(z2, a, eta))
    assert d2 == pytest.approx(d, rel=1e-7, abs=1e-9)


@settings(max_examples=200, deadline=None)
@given(z=disk, a=disk, eta=st.floats(0, 2 * np.pi))
def test_mobius_inverse_and_exchange(z, a, eta):
    w = g.mobius(z, a, eta)
    assert abs(g.mobius_inverse(w, a, eta) - z) < 1e-9
    assert abs(g.mobius(a, a, eta)) < 1e-12  # a -> origin
    assert abs(g.mobius(0, a, 0.0) - a) < 1e-12  # origin -> a (for eta = 0 it is an involution)


@settings(max_examples=100, deadline=None)
@given(z1=disk, z2=disk, t=st.floats(0, 1))
def test_geodesic_point_splits_distance(z1, z2, t):
    m = g.geodesic_point(z1, z2, t)
    d = g.distance(z1, z2)
    assert g.distance(z1, m) == pytest.approx(t * d, rel=1e-6, abs=1e-9)
    assert g.distance(m, z2) == pytest.approx((1 - t) * d, rel=1e-6, abs=1e-9)


@settings(max_examples=100, deadline=None)
@given(p=st.integers(-5, 40), q=st.integers(-5, 40))
def test_check_pq_accepts_exactly_the_hyperbolic_symbols(p, q):
    if p >= 3 and q >= 3 and (p - 2) * (q - 2) > 4:
        assert _validate.pq(p, q) == (p, q)
    else:
        with pytest.raises(ValueError):
            _validate.pq(p, q)


@pytest.mark.parametrize("bad", [0.5, "7", None, 7.5, float("nan")])
def test_check_pq_rejects_non_integers(bad):
    with pytest.raises(ValueError):
        _validate.pq(bad, 3)


@pytest.mark.parametrize("z", [1.0, 1.5j, complex("nan"), complex(float("inf"), 0)])
def test_distance_rejects_points_outside_disk(z):
    with pytest.raises(ValueError):
        g.distance(z, 0.1)


@pytest.mark.parametrize("n", [0, -3, float("nan"), float("inf")])
def test_effective_radius_rejects_bad_sizes(n):
    with pytest.raises(ValueError):
        g.effective_radius(n)


# ----------------------------------------------------------------------------
# input checks through _validate, and TilingConstants as a Result
# ----------------------------------------------------------------------------

_BAD_POINTS = [None, "0.1", [0.1, "x"], complex("nan"), 1.0, [0.2, 1.5j]]


@pytest.mark.parametrize("bad", _BAD_POINTS)
@pytest.mark.parametrize("call", [
    lambda z: g.distance(z, 0.1),
    lambda z: g.distance(0.1, z),
    lambda z: g.mobius(z, 0.2),
    lambda z: g.mobius(0.1, z),
    lambda z: g.mobius_inverse(z, 0.2),
    lambda z: g.rotate_about(z, 0.2, 1.0),
    lambda z: g.rotate_about(0.1, z, 1.0),
    lambda z: g.geodesic_point(z, 0.2, 0.5),
    lambda z: g.midpoint(0.1, z),
])
def test_disk_maps_refuse_bad_points(call, bad):
    # None used to raise TypeError, NaN passed silently through the maps
    with pytest.raises(ValueError):
        call(bad)


@pytest.mark.parametrize("bad", [None, "x", float("nan"), 1j, [1.0, 2.0], [0.5, 1.0]])
def test_rho_refuses_bad_radii(bad):
    with pytest.raises(ValueError):
        g.rho(bad)


@pytest.mark.parametrize("bad", [None, "x", float("nan"), [1.0, "a"]])
def test_one_minus_abs2_refuses_non_numbers(bad):
    with pytest.raises(ValueError):
        g.one_minus_abs2(bad)


@pytest.mark.parametrize("bad", [None, "100", True, [100, -1], 1j])
def test_effective_radius_rejects_bad_types(bad):
    with pytest.raises(ValueError):
        g.effective_radius(bad)


def test_checked_maps_agree_with_kernels():
    rng = np.random.default_rng(3)
    z1 = 0.9 * rng.uniform(0, 1, 50) * np.exp(2j * np.pi * rng.uniform(0, 1, 50))
    z2 = 0.9 * rng.uniform(0, 1, 50) * np.exp(2j * np.pi * rng.uniform(0, 1, 50))
    t = rng.uniform(0, 1, 50)
    assert np.array_equal(g.geodesic_point(z1, z2, t), g._geodesic_point(z1, z2, t))
    assert np.array_equal(g.rotate_about(z1, z2, t), g._rotate_about(z1, z2, t))
    assert np.array_equal(g.distance(z1, z2), g.distance(z1, z2, check=False))
    assert g.rho(0.5) == pytest.approx(1.25 / 0.75, rel=1e-15)
    assert np.allclose(g.effective_radius(np.array([7, 35])), np.sqrt([7 / 35, 35 / 63]), rtol=1e-15)


def test_tiling_constants_is_a_result(tmp_path):
    from hyperlattice.results import Result, load_result

    tc = g.tiling_constants(7, 3)
    assert isinstance(tc, Result)
    assert tc.summary() == {"p": 7, "q": 3, "r0": tc.r0, "d0": tc.d0, "h": tc.h, "site_area": tc.site_area}
    back = g.TilingConstants.from_dict(json.loads(json.dumps(tc.as_dict())))
    assert back.as_dict() == tc.as_dict()
    inf = g.tiling_constants(math.inf, 3)
    assert inf.summary()["p"] == "inf"
    back = load_result(inf.save(tmp_path / "tc.json"))
    assert back.p == math.inf and back.h == inf.h
    assert tc != g.tiling_constants(7, 3)  # eq=False: compared by identity, never element-wise
    with pytest.raises(AttributeError):
        tc.p = 8


def test_effective_radius_needs_a_finite_lattice_symbol():
    with pytest.raises(ValueError):
        g.effective_radius(112, math.inf, 3)
    with pytest.raises(ValueError):
        g.effective_radius(112, 6, 3)
