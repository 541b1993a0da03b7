"""Sums as integrals (Eq. eq11, App. AppSum) and the many-body dictionary (Eqs. eq13-eq14)."""

import math

import numpy as np
import pytest

from hyperlattice.compare.sums import counting_function, disk_integral, fit_counting, sum_check
from hyperlattice.dictionary import continuum_parameters, lattice_parameters
from hyperlattice.errors import ConvergenceWarning
from hyperlattice.geometry import counting_slope
from hyperlattice.graph.lattice import ring_lattice
from hyperlattice.compare.scaling import SmoothFunction
from hyperlattice.paper_values import paper_value


def test_counting_fit_reproduces_paper_b():
    """FigS1: b = -9.096 for l = 4 (printed to 3 decimals; we get -9.0954, see docs/scaling.md)."""
    fit = fit_counting(ring_lattice(7, 3, 4))
    assert fit.radii.size == 24
    assert abs(fit.intercept - paper_value("b_counting", 4).value) < 1e-3
    assert abs(fit.slope - 14) < 0.25


def test_counting_function_is_right_continuous_staircase():
    lat = ring_lattice(7, 3, 3)
    r, n = counting_function(lat)
    assert n[-1] == lat.sites and np.all(np.diff(n) > 0) and np.all(np.diff(r) > 0)
    assert n[0] == 7  # the central heptagon


@pytest.mark.parametrize("p, q, rings", [(7, 3, 8), (8, 3, 6), (5, 4, 5), (4, 5, 5), (3, 7, 6)])
def test_general_slope(p, q, rings):
    """Slope pi/(2A) = 2p/(pq-2p-2q) on the radii where N(r) is complete, to 3 %."""
    fit = fit_counting(ring_lattice(p, q, rings), window="complete")
    assert fit.slope == pytest.approx(counting_slope(p, q), rel=0.03)


def test_incomplete_outer_ring_warns():
    with pytest.warns(ConvergenceWarning):
        fit_counting(ring_lattice(7, 3, 8))


def test_fixed_slope():
    fit = fit_counting(ring_lattice(7, 3, 4), slope=14)
    assert fit.slope_fixed and fit.slope == 14
    assert fit.intercept == pytest.approx(-6.815, abs=1e-3)


def test_disk_integral_closed_forms():
    L = 0.9
    # f = 1: hyperbolic disk area pi L^2/(1-L^2)
    assert disk_integral(lambda z: np.ones(np.shape(z)), L).real == pytest.approx(
        math.pi * L * L / (1 - L * L), rel=1e-12)
    # f = rho^-2: 2 pi int r/(1+r^2)^2 dr = pi L^2/(1+L^2)
    f = SmoothFunction.inverse_rho_squared()
    assert disk_integral(f, L).real == pytest.approx(math.pi * L * L / (1 + L * L), rel=1e-12)
    # f = Re z^7 integrates to zero over the disk
    assert abs(disk_integral(lambda z: (z ** 7).real, L)) < 1e-12


# eq11 relative errors measured for l = 4..10 (docs/scaling.md); bounds leave 2x margin
EQ11_BOUNDS = {"inverse-rho-squared": 1.6e-3, "gaussian": 1.5e-3, "anisotropic": 1.2e-3}


@pytest.mark.parametrize("name", list(EQ11_BOUNDS))
def test_eq11_sums(name):
    f = SmoothFunction.preset(name)
    for rings in range(4, 11):
        chk = sum_check(ring_lattice(7, 3, rings), f)
        assert chk.rel_error < EQ11_BOUNDS[name], (rings, chk.rel_error)


def test_eq11_exact_for_constant():
    """L of Eq. (eq12) is defined so that f = 1 is exact, for any {p,q}."""
    for p, q in [(7, 3), (5, 4)]:
        chk = sum_check(ring_lattice(p, q, 4), lambda z: np.ones(np.shape(z)), name="1")
        assert chk.rel_error < 1e-12


def test_paper_dictionary_73():
    """Eq. (eq14): t' = 3/4 h^2 t, mu' = mu + 3t, U' = pi/28 U, alpha = sqrt(28/pi) a."""
    c = continuum_parameters(t=2.0, mu=0.5, U=3.0)
    h = paper_value("geometry_h", 7).value
    assert c.t_prime == pytest.approx(0.75 * h * h * 2.0, rel=1e-5)
    assert c.mu_prime == 0.5 + 6.0
    assert c.U_prime == pytest.approx(math.pi / 28 * 3.0, rel=1e-14)
    assert c.field_scale == pytest.approx(math.sqrt(28 / math.pi), rel=1e-14)


def test_dictionary_general_pq_and_inverse():
    c = continuum_parameters(1.0, -1.0, 2.0, p=5, q=4)
    assert c.mu_prime == 3.0
    assert c.t_prime == pytest.approx(c.h ** 2, rel=1e-14)  # (q/4) h^2 with q = 4
    assert c.U_prime == pytest.approx(2.0 * math.pi * (20 - 10 - 8) / 20, rel=1e-14)
    back = lattice_parameters(c.t_prime, c.mu_prime, c.U_prime, p=5, q=4)
    assert (back.t, back.mu, back.U) == pytest.approx((1.0, -1.0, 2.0), rel=1e-14)


@pytest.mark.parametrize("args", [(math.nan, 0, 0), (1, math.inf, 0), (1, 0, "a")])
def test_dictionary_bad_input(args):
    with pytest.raises(ValueError):
        continuum_parameters(*args)


def test_bad_inputs():
    with pytest.raises(ValueError):
        continuum_parameters(1, 0, 0, p=6, q=3)
    with pytest.raises(ValueError):
        fit_counting(ring_lattice(7, 3, 1))
    with pytest.raises(ValueError):
        fit_counting(ring_lattice(7, 3, 4), window="middle")
    with pytest.raises(ValueError):
        disk_integral(lambda z: z, 1.0)
    with pytest.raises(ValueError):
        sum_check(ring_lattice(7, 3, 2), lambda z: np.full(np.shape(z), np.nan))


# ---------------------------------------------------------------------------------------------
# regressions: overflow, bad scalars and arrays in the energy maps, the counting slope
# ---------------------------------------------------------------------------------------------

def test_overflow_is_valueerror():
    """dictionary --t 1e308 printed mu' = inf; the inverse map overflowed into a message about t."""
    with pytest.raises(ValueError, match="mu_prime"):
        continuum_parameters(1e308, 0.0, 0.0)
    with pytest.raises(ValueError, match="lattice t"):
        lattice_parameters(1e308, 0.0, 0.0)


@pytest.mark.parametrize("bad", [None, math.nan, math.inf, True, "x", [[1, 2], [3]], [1.0, math.nan], object()])
def test_energy_maps_refuse_bad_values(bad):
    from hyperlattice.dictionary import energy_from_k, energy_from_lambda, lambda_from_energy

    for fn in (lambda_from_energy, energy_from_lambda, energy_from_k):
        with pytest.raises(ValueError):
            fn(bad)


def test_energy_maps_keep_kind_and_numbers():
    from hyperlattice.dictionary import energy_from_k, energy_from_lambda, hopping_scale, lambda_from_energy

    s = hopping_scale(7, 3)
    assert lambda_from_energy(-2.95) == (-2.95 + 3) / s and isinstance(lambda_from_energy(-2.95), float)
    assert lambda_from_energy(-2.5 + 0.1j) == (-2.5 + 0.1j + 3) / s
    lam = lambda_from_energy([-2.9, -2.8])
    assert lam.dtype == np.float64 and np.array_equal(lam, (np.array([-2.9, -2.8]) + 3) / s)
    assert lambda_from_energy(np.array([-2.9 + 0.1j])).dtype == np.complex128
    assert energy_from_lambda(lambda_from_energy(-2.95)) == pytest.approx(-2.95, abs=1e-15)
    assert energy_from_k(0.0) == pytest.approx(-3 + s, abs=1e-15)


def test_disk_radius_and_dictionary_parameters_need_a_finite_lattice():
    from hyperlattice.dictionary import dictionary_parameters, disk_radius

    assert disk_radius(112) == pytest.approx(math.sqrt(112 / 140))
    for bad in (True, 2.5, 0, 1 + 2j, object()):
        with pytest.raises(ValueError):
            disk_radius(bad)
    with pytest.raises(ValueError):
        disk_radius(112, p=math.inf)
    with pytest.raises(ValueError):
        dictionary_parameters(-2.9, p=math.inf)


@pytest.mark.parametrize("slope", [1e308, -1e7, math.nan, True, "14"])
def test_fixed_slope_bounded(slope):
    """--slope 1e308 printed b = -inf and eight RuntimeWarnings."""
    with pytest.raises(ValueError, match="slope"):
        fit_counting(ring_lattice(7, 3, 4), slope=slope)


def test_counting_and_sum_results_round_trip():
    from hyperlattice.results import Result

    fit = fit_counting(ring_lattice(7, 3, 4))
    back = Result.from_dict(fit.as_dict())
    assert back.summary() == fit.summary() and back.radii.dtype == fit.radii.dtype
    assert not fit.radii.flags.writeable


@pytest.mark.parametrize("kwargs", [dict(f=None), dict(radius=None), dict(radius=True), dict(angular_points=None),
                                    dict(angular_points=2 ** 30), dict(rtol=None), dict(rtol=0.0)])
def test_disk_integral_bad_arguments(kwargs):
    call = {"f": lambda z: np.ones(np.shape(z)), "radius": 0.5, **kwargs}
    with pytest.raises(ValueError):
        disk_integral(**call)


def test_disk_radius_for_rings_matches_eq12_and_reaches_huge_disks():
    from hyperlattice.dictionary import disk_radius, disk_radius_for_rings
    from hyperlattice.graph.lattice import site_count

    for rings in (1, 4, 10, 43):
        L, x = disk_radius_for_rings(rings, 7, 3)
        n = site_count(7, 3, rings)
        assert L == pytest.approx(disk_radius(n, 7, 3), rel=1e-15)
        assert x == pytest.approx((2 * n + 28) / 28, rel=1e-15)
    L, x = disk_radius_for_rings(300, 7, 3)          # far beyond int64 sites: still a finite x
    assert L == 1.0 and 1e120 < x < 1e130
    with pytest.raises(ValueError, match="1e308"):
        disk_radius_for_rings(800, 7, 3)


# ----------------------------------------------------------------------------
# the improved dictionary (issue 13)
# ----------------------------------------------------------------------------

def _p_nu_mpmath(lam, d):
    import mpmath as mp

    mp.mp.dps = 30
    nu = mp.mpf(-0.5) + 0.5j * mp.sqrt(mp.mpf(lam) - 1)
    return float(mp.re(mp.hyp2f1(-nu, nu + 1, 1, (1 - mp.cosh(2 * mp.mpf(d))) / 2)))


@pytest.mark.parametrize("lam, d", [(lam, d) for lam in (0.0, 0.3, 1.0, 1.7, 12.0, 400.0)
                                    for d in (0.01, 0.2831281533676575, 1.3)] + [(1.0, 4.0), (2.5e4, 0.01)])
def test_spherical_function_against_mpmath(lam, d):
    from hyperlattice.dictionary import spherical_function

    assert spherical_function(lam, d) == pytest.approx(_p_nu_mpmath(lam, d), abs=2e-14)


def test_spherical_function_is_the_circle_average():
    """Mean-value property: the average of psi_K (an eigenfunction, eig12) over the geodesic circle
    of radius d about z equals phi_lambda(d) psi_K(z)."""
    from hyperlattice.continuum.spectrum import psi_K
    from hyperlattice.dictionary import spherical_function
    from hyperlattice.geometry import mobius_inverse

    k, d, z = 0.7, 0.3, 0.35 + 0.2j
    w = math.tanh(d) * np.exp(2j * np.pi * np.arange(256) / 256)
    pts = mobius_inverse(w, z)      # the circle of radius d about z
    avg = np.mean(psi_K(pts, k))
    assert avg == pytest.approx(spherical_function(1 + k * k, d) * psi_K(np.array([z]), k)[0], rel=1e-12)


def test_improved_map_is_the_paper_map_at_order_h2():
    """E = -q P_nu((1+h^2)/(1-h^2)) = -q + (q/4) h^2 lam + q (lam/8 - lam^2/64) h^4 + O(h^6)."""
    from hyperlattice.dictionary import laplacian_coefficient, spherical_mean_energy

    for q in (3, 4, 7):
        for lam in (0.5, 1.0, 3.0):
            for h in (0.02, 0.01, 0.005):
                e = spherical_mean_energy(lam, q, h)
                paper = -q + laplacian_coefficient(q, h) * lam
                # order h^2 agrees: the difference is O(h^4) with the predicted coefficient
                c4 = (e - paper) / h ** 4
                assert c4 == pytest.approx(q * (lam / 8 - lam * lam / 64), rel=5 * h * h * (1 + lam), abs=1e-6)


def test_improved_values_for_73():
    from hyperlattice.dictionary import (dirichlet_radius_shift, disk_radius_for_rings, improved_band_bottom,
                                         improved_disk_for_rings, improved_energy_from_k,
                                         improved_lambda_from_energy, map_energy_from_k, energy_from_k)

    assert improved_band_bottom(7, 3) == pytest.approx(-2.940960613698996, abs=1e-13)
    assert dirichlet_radius_shift(7, 3) == pytest.approx(0.1353749, abs=2e-7)
    L, x = improved_disk_for_rings(10)
    La, xa = disk_radius_for_rings(10)
    assert 0.5 * math.acosh(x) - 0.5 * math.acosh(xa) == pytest.approx(dirichlet_radius_shift(), rel=1e-9)
    assert math.atanh(L) - math.atanh(La) == pytest.approx(dirichlet_radius_shift(), rel=1e-6)
    for e in (-2.94, -2.5, 0.0, 1.0):
        lam = improved_lambda_from_energy(e)
        assert float(improved_energy_from_k(math.sqrt(max(lam - 1, 0)))) == pytest.approx(e, abs=1e-12) or lam < 1
    assert map_energy_from_k(0.4) == energy_from_k(0.4)
    assert map_energy_from_k(0.4, dictionary="improved") == improved_energy_from_k(0.4)


def test_improved_lambda_of_frequency_below_and_above_the_band():
    """Below the band the improved map -q P_nu(cosh 2 d0) with real nu (hyp2f1 form) inverts to lambda < 0;
    above the improved band bottom it is improved_lambda_from_energy; it agrees with the paper's map to
    first order in h^2."""
    import math

    from hyperlattice import geometry
    from hyperlattice.dictionary import (improved_band_bottom, improved_energy_from_lambda,
                                         improved_lambda_from_energy, improved_lambda_of_frequency,
                                         lambda_from_energy, spherical_function)

    d0 = geometry.d0(7, 3)
    for w in (-3.2, -3.5, -5.0):
        lam = improved_lambda_of_frequency(w)
        assert lam < 0
        nu = -0.5 + 0.5 * math.sqrt(1 - lam)
        assert -3 * float(__import__("mpmath").legenp(nu, 0, math.cosh(2 * d0), type=3).real) == pytest.approx(w, abs=1e-12)
    assert improved_lambda_of_frequency(-2.9) == improved_lambda_from_energy(-2.9)
    # the hyp2f1 and Mehler forms meet at the improved band bottom
    assert improved_lambda_of_frequency(improved_band_bottom()) == pytest.approx(1.0, abs=1e-9)
    assert improved_energy_from_lambda(0.5) == pytest.approx(-3 * spherical_function(0.5, d0))
    assert improved_lambda_of_frequency(-3.0) == pytest.approx(0.0, abs=1e-12)
    # the paper's map is the first order in h^2: near the band bottom lambda_paper / lambda_improved
    # = 1 + h^2/2 + O(h^4) (from E = -q + q h^2 lambda/4 + q h^4 lambda/8 + O(lambda^2, h^6))
    h = math.tanh(d0)
    ratio = lambda_from_energy(-3.0001) / improved_lambda_of_frequency(-3.0001) - 1
    assert abs(ratio - h * h / 2) < h**4
    with pytest.raises(ValueError, match="too far below the band"):
        improved_lambda_of_frequency(-1e300)
