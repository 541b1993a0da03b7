"""The massive scalar map omega <-> lambda <-> m^2 <-> Delta, the BF bound, the conformal boundary forms."""

import math

import numpy as np
import pytest

from hyperlattice.continuum import massive as mv
from hyperlattice.continuum.green import continuum_green, green_nu
from hyperlattice.dictionary import lambda_from_energy


def test_delta_at_bf_bound_is_one_half():
    assert mv.delta_from_mass2(-1.0) == 0.5
    assert mv.delta_from_mass2(-1.0, branch="minus") == 0.5
    bf = mv.bf_bound(7, 3)
    assert bf.mass2 == -1.0 and bf.lam == 1.0 and bf.delta == 0.5
    assert bf.omega == pytest.approx(-2.94295, abs=5e-6)          # the paper's E_inf (spec2)
    # reached through the dictionary (rounding of lambda = 1): still 1/2
    assert mv.delta_from_omega(bf.omega) == pytest.approx(0.5, abs=1e-7)
    # square-root approach: Delta - 1/2 = sqrt(1 + m^2)/2
    for eps in (1e-2, 1e-4, 1e-8):
        assert mv.delta_from_mass2(-1.0 + eps) - 0.5 == pytest.approx(0.5 * math.sqrt(eps), rel=1e-6)


def test_below_bf_bound_refused():
    with pytest.raises(ValueError, match="Breitenlohner-Freedman"):
        mv.delta_from_mass2(-1.01)
    with pytest.raises(ValueError, match="Breitenlohner-Freedman"):
        mv.delta_from_omega(-2.9)          # above E_inf: m^2 < -1


@pytest.mark.parametrize("m", [10.0, 1e3, 1e5])
def test_large_mass(m):
    # Delta = 1/2 + sqrt(1/4 + m^2 R^2) = m R + 1/2 + 1/(8 m R) - 1/(128 (m R)^3) + O(m^-5), R = 1/2
    d = mv.delta_from_mass2(m * m)
    assert abs(d - (0.5 * m + 0.5 + 1.0 / (4.0 * m) - 1.0 / (16.0 * m**3))) <= 1.0 / m**5 + 4e-16 * d
    assert mv.delta_from_mass2(m * m, branch="minus") == pytest.approx(1.0 - d)


def test_delta_relation_and_inverses():
    m2 = np.array([-1.0, -0.75, 0.0, 0.5, 3.0, 40.0])
    d = mv.delta_from_mass2(m2)
    assert np.allclose(d * (d - 1.0), m2 * mv.ADS_RADIUS**2, rtol=1e-13, atol=1e-15)
    assert np.allclose(mv.mass2_from_delta(d), m2, rtol=1e-13, atol=1e-14)
    assert np.allclose(mv.mass2_from_delta(1.0 - d), m2, rtol=1e-13, atol=1e-14)   # both branches
    om = np.array([-3.7, -3.2, -3.0, -2.95])
    assert np.allclose(mv.omega_from_mass2(mv.mass2_from_omega(om)), om, rtol=1e-14)
    assert np.allclose(mv.mass2_from_omega(om), -lambda_from_energy(om), rtol=1e-15)
    assert mv.mass2_from_omega(-3.0) == 0.0 and mv.delta_from_omega(-3.0) == 1.0   # massless: Delta = d = 1
    assert np.allclose(mv.omega_from_delta(mv.delta_from_omega(om)), om, rtol=1e-13)
    assert mv.lambda_from_mass2(mv.mass2_from_lambda(0.3)) == 0.3


@pytest.mark.parametrize("lam", [0.9, 0.5, -3.0, -20.0])
def test_delta_is_legendre_degree_plus_one(lam):
    assert mv.delta_from_mass2(-lam) == pytest.approx(green_nu(lam).real + 1.0, rel=1e-14)


# reference: the continuum Green function (L = 1) of continuum/green.py, its own implementation
@pytest.mark.parametrize("lam", [0.99, 0.5, -3.0, -20.0, -200.0])
def test_two_point_near_boundary_matches_conformal_form(lam):
    delta = mv.delta_from_mass2(-lam)
    r = 1.0 - 1e-10
    th = np.array([0.01, 0.3, 1.0, 2.0, math.pi])
    z = r * np.exp(1j * th)
    exact = continuum_green(z, r, lam, 1.0).real
    conf = mv.conformal_two_point(z, r, delta)
    assert np.max(np.abs(conf / exact - 1.0)) < 1e-8
    # the [sin(theta/2)]^(-2 Delta) form on the circle differs only by (r r')^(-Delta)
    eps = 1.0 - r * r
    bnd = mv.boundary_two_point(th, delta, eps)
    assert np.allclose(bnd, conf * r ** (2 * delta), rtol=1e-12)


def test_conformal_form_error_shrinks_with_cutoff():
    # relative difference O(eps eps'/|z - z'|^2): 1e-6 from the circle gives ~1e-8, 1e-8 gives ~1e-12
    errs = []
    for gap in (1e-4, 1e-6):
        r = 1.0 - gap
        z = r * np.exp(1j * np.array([0.5, 1.5]))
        errs.append(np.max(np.abs(mv.conformal_two_point(z, r, 1.5) / continuum_green(z, r, -3.0, 1.0).real - 1)))
    assert errs[1] < 2e-4 * errs[0]


def test_bulk_to_boundary_kernel_is_the_limit():
    delta, lam = 1.5, -3.0
    rp = 1.0 - 1e-10
    thp = 0.7
    z = np.array([0.0, 0.3 + 0.2j, -0.5j, 0.9 * np.exp(0.6j)])
    exact = continuum_green(z, rp * np.exp(1j * thp), lam, 1.0).real
    eps_p = 1.0 - rp * rp
    pred = mv.conformal_prefactor(delta) * (eps_p / 4.0) ** delta * mv.bulk_to_boundary_kernel(z, thp, delta)
    assert np.allclose(pred, exact, rtol=1e-8)


def test_radial_falloff_exponent():
    # the derivation: phi ~ (1 - r)^Delta near the boundary, seen in the continuum propagator
    lam = -3.0
    delta = mv.delta_from_mass2(-lam)
    r1, r2 = 1 - 1e-6, 1 - 1e-7
    g1 = continuum_green(r1, 0.0, lam, 1.0).real
    g2 = continuum_green(r2, 0.0, lam, 1.0).real
    slope = math.log(g1 / g2) / math.log((1 - r1) / (1 - r2))
    assert slope == pytest.approx(delta, rel=1e-6)


def test_conformal_prefactor_large_delta():
    # log-gamma: finite beyond Gamma's overflow, and ~ 1/(2 sqrt(pi Delta))
    assert mv.conformal_prefactor(400.0) == pytest.approx(1 / (2 * math.sqrt(math.pi * 400.0)), rel=1e-3)


def test_bad_points():
    with pytest.raises(ValueError, match="coincide"):
        mv.conformal_two_point(0.5, 0.5, 1.0)
    with pytest.raises(ValueError, match="multiple of 2 pi"):
        mv.boundary_two_point(0.0, 1.0)
    with pytest.raises(ValueError):
        mv.delta_from_mass2(0.0, branch="both")
