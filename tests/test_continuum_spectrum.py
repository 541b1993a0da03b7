"""Continuum Dirichlet spectrum (spec2), energies, asymptotics and eigenfunctions."""

import math
import tracemalloc

import mpmath as mp
import numpy as np
import pytest
from scipy.special import jv

from hyperlattice.dictionary import hopping_scale

from hyperlattice.continuum.spectrum import (asymptotic_energies, asymptotic_k0, asymptotic_k1,
                                             continuum_levels, dirichlet_levels, dirichlet_roots,
                                             disk_argument, energy_infinity, level_energy, psi_K,
                                             radial_g)
from hyperlattice.paper_values import paper_value

# SuppTab1 (= Tab1 continuum row), printed to 3 decimals: (ell, E0 exact, E0 asym, E1 exact, E1 asym)
SUPP_TAB1 = [(ell, *(paper_value(key, ell).value for key in ("E0_continuum", "E0_asymptotic", "E1_continuum",
                                                             "E1_asymptotic")))
             for ell in range(1, 11)]


def _n73(ell):
    g = (3 + math.sqrt(5)) / 2
    return round(7 * (g**ell + (1 / g) ** ell - 2))


@pytest.mark.parametrize("ell,e0,e0a,e1,e1a", SUPP_TAB1)
def test_supp_tab1_continuum_rows(ell, e0, e0a, e1, e1a):
    spec = continuum_levels(7, 3, rings=ell, levels=2)
    assert list(spec.m) == [0, 1] and list(spec.n) == [1, 1]
    # the paper's h = 0.275798 and our exact h give the same 3-decimal rounding
    assert round(spec.energies[0], 3) == pytest.approx(e0, abs=1e-9)
    assert round(spec.energies[1], 3) == pytest.approx(e1, abs=1e-9)
    a = spec.asymptotic
    digits = 2 if abs(e1a) > 10 else 3           # 15.58 is printed with 2 decimals
    assert round(a["E0"], 3) == pytest.approx(e0a, abs=1e-9)
    assert round(a["E1"], digits) == pytest.approx(e1a, abs=1e-9)
    # Tab1 radius row (and the closed form of N)
    assert spec.radius == pytest.approx(math.sqrt(_n73(ell) / (_n73(ell) + 28)), rel=1e-14)


@pytest.mark.parametrize("radius,m,n", [(0.5, 0, 1), pytest.param(0.7454, 2, 2, marks=pytest.mark.slow),
                                         pytest.param(0.99, 1, 3, marks=pytest.mark.slow), (0.2, 4, 1)])
def test_roots_against_mpmath_findroot(radius, m, n):
    """Independent reference: mpmath.legenp at 30 digits and findroot from our bracket mid."""
    k = dirichlet_roots(m, radius, n_roots=n)[n - 1]
    mp.mp.dps = 30
    x = (1 + mp.mpf(radius) ** 2) / (1 - mp.mpf(radius) ** 2)
    ref = mp.findroot(lambda kk: mp.re(mp.legenp(mp.mpc(-0.5, kk / 2), m, x, type=3)), k * (1 + 1e-6))
    assert k == pytest.approx(float(ref), rel=1e-12)


@pytest.mark.slow
def test_roots_robust_over_radii_with_node_check():
    for radius in (0.1, 0.3, 0.9, 1 - 1e-4, 1 - 1e-9):
        k = dirichlet_roots(np.arange(11), radius, n_roots=5, check_nodes=True)
        assert k.shape == (11, 5) and np.all(np.isfinite(k)) and np.all(k > 0)
        assert np.all(np.diff(k, axis=1) > 0)
        assert np.all(np.diff(k[:, 0]) > 0)


def test_small_disk_is_euclidean():
    """L -> 0: k_nm L' -> j_{m,n} with L' = artanh(L)*2/2 ... Bessel zeros of the flat disk."""
    from scipy.special import jn_zeros
    radius = 0.01
    k = dirichlet_roots(3, radius, n_roots=3)
    # hyperbolic radius of the disk in the metric ds = |dz|/(1-|z|^2) is artanh(L)
    assert k * math.atanh(radius) == pytest.approx(jn_zeros(3, 3), rel=1e-3)


def test_asymptotic_k0_k1_approached():
    prev0 = prev1 = np.inf
    for radius in (1 - 1e-3, 1 - 1e-5, 1 - 1e-7, 1 - 1e-9):
        _, x = disk_argument(radius)
        k = dirichlet_roots([0, 1], radius, n_roots=1)[:, 0]
        d0 = abs(k[0] / asymptotic_k0(x) - 1)
        d1 = abs(k[1] / asymptotic_k1(x) - 1)
        assert d0 < prev0 and d1 < prev1
        prev0, prev1 = d0, d1
    assert prev0 < 2e-3 and prev1 < 2e-2


def test_energy_q_dependence_and_e_inf():
    h = paper_value("geometry_h", 7).value
    assert energy_infinity(7, 3) == pytest.approx(-3 + 0.75 * h * h, abs=1e-6)
    assert round(energy_infinity(7, 3), 5) == paper_value("E_inf").value
    assert level_energy(1.3, 7, 3) == pytest.approx(-3 + 0.75 * 0.2757977789799760**2 * (1 + 1.69))
    from hyperlattice.geometry import lattice_h
    hh = lattice_h(5, 4)
    assert level_energy(0.5, 5, 4) == pytest.approx(-4 + hh * hh * 1.25)


@pytest.mark.parametrize("p", [8, 9, 10])
def test_other_p_levels_finite_and_ordered(p):
    for rings in (2, 5, 8):
        spec = continuum_levels(p, 3, rings=rings, levels=8)
        e = spec.energies
        assert np.all(np.isfinite(e)) and np.all(np.diff(e) >= 0)
        assert e[0] > -3 and e[0] > energy_infinity(p, 3)
        assert list(spec.m[:3]) == [0, 1, -1]
    small = continuum_levels(p, 3, rings=3, levels=1).energies[0]
    large = continuum_levels(p, 3, rings=6, levels=1).energies[0]
    assert large < small


def test_level_ordering_convention_and_degeneracy():
    spec = continuum_levels(7, 3, radius=0.95, levels=9)
    labels = list(zip(spec.n.tolist(), spec.m.tolist()))
    assert labels[:4] == [(1, 0), (1, 1), (1, -1), (1, 2)]
    for i, (n, m) in enumerate(labels):
        if m > 0 and i + 1 < len(labels):
            assert labels[i + 1] == (n, -m) and spec.energies[i + 1] == spec.energies[i]
    # the K lowest states are the K lowest of a brute-force table
    table = dirichlet_levels(7, 3, radius=0.95, n_max=6, m_max=6)
    flat = sorted([table.energies[n, 0] for n in range(6)]
                  + [e for m in range(1, 7) for n in range(6) for e in (table.energies[n, m],) * 2])
    assert np.allclose(spec.energies, flat[:9], rtol=1e-13)


def test_bad_input():
    for bad in (0.0, 1.0, -0.3, 1.2, float("nan")):
        with pytest.raises(ValueError):
            dirichlet_roots(0, bad, 2)
    with pytest.raises(ValueError):
        continuum_levels(6, 3, radius=0.5)
    with pytest.raises(ValueError):
        continuum_levels(7, 3, radius=0.5, rings=3)
    with pytest.raises(ValueError):
        dirichlet_roots(-1.5, 0.5, 2)


BAD_VALUES = {"none": None, "nan": float("nan"), "inf": float("inf"), "bool": True, "str": "seven",
              "ragged": [[1, 2], [3]], "complex": 1 + 2j, "object": object()}

# (id, call with the spoiled value, tags the argument legitimately accepts)
ENTRY_POINTS = [
    ("levels", lambda v: continuum_levels(7, 3, radius=0.9, levels=v), set()),
    ("rings", lambda v: continuum_levels(7, 3, rings=v, levels=2), set()),
    ("radius", lambda v: continuum_levels(7, 3, radius=v, levels=2), set()),
    ("check_nodes", lambda v: continuum_levels(7, 3, radius=0.9, levels=2, check_nodes=v), {"bool"}),
    ("m", lambda v: dirichlet_roots(v, 0.5, 2), set()),
    ("n_roots", lambda v: dirichlet_roots(1, 0.5, v), set()),
    ("x", lambda v: dirichlet_roots(1, x=v, n_roots=2), set()),
    ("n_max", lambda v: dirichlet_levels(7, 3, radius=0.5, n_max=v, m_max=2), set()),
    ("m_max", lambda v: dirichlet_levels(7, 3, radius=0.5, n_max=2, m_max=v), set()),
    ("k", lambda v: level_energy(v), set()),
    ("k0 x", lambda v: asymptotic_k0(v), set()),
    ("k1 x", lambda v: asymptotic_k1(v), set()),
    ("psi z", lambda v: psi_K(v, 1.0), {"complex"}),
    ("psi k", lambda v: psi_K(0.1, v), set()),
    ("g k", lambda v: radial_g(v, 1, 0.5), set()),
    ("g m", lambda v: radial_g(1.0, v, 0.5), set()),
    ("g r", lambda v: radial_g(1.0, 1, v), set()),
    ("g method", lambda v: radial_g(1.0, 1, 0.5, method=v), set()),
    ("disk radius", lambda v: disk_argument(v), set()),
    ("asymptotic form", lambda v: asymptotic_energies(7, 3, radius=0.9, form=v), set()),
]


@pytest.mark.parametrize("name,call,ok", ENTRY_POINTS, ids=[e[0] for e in ENTRY_POINTS])
def test_every_entry_point_refuses_bad_values_with_valueerror(name, call, ok):
    """None/NaN/inf/bool/str/ragged/complex/object give ValueError with a plain sentence (issue 10,
    item 2: continuum_levels(levels=None) leaked TypeError, rings=nan a numpy conversion error)."""
    for tag, bad in BAD_VALUES.items():
        if tag in ok:
            continue
        with pytest.raises(ValueError) as exc:
            call(bad)
        msg = str(exc.value)
        assert msg.endswith(".") and len(msg) < 300, (tag, msg)


def test_levels_none_is_a_valueerror_not_typeerror():
    with pytest.raises(ValueError, match="levels"):
        continuum_levels(levels=None, radius=0.5)
    with pytest.raises(ValueError, match="rings"):
        continuum_levels(rings=float("nan"))


@pytest.mark.parametrize("m", [0, 1, 2, -1, -3, 5])
def test_radial_g_closed_form_equals_integral(m):
    r = np.array([0.05, 0.3, 0.6, 0.9])
    for k in (0.4, 2.3, 9.0):
        a = radial_g(k, m, r, method="closed")
        b = radial_g(k, m, r, method="integral")
        assert np.allclose(a, b, rtol=1e-10, atol=1e-13)


def test_partial_wave_sum_reconstructs_psi_and_euclidean_limit():
    k, r, phi = 1.7, 0.4, 0.9
    z = r * np.exp(1j * phi)
    total = sum((1j) ** m * radial_g(k, m, r) * np.exp(1j * m * phi) for m in range(-40, 41))
    assert total == pytest.approx(psi_K(z, k), rel=1e-12)          # eig15 with beta = 0
    # Euclidean limit r << 1, k >> 1: g_km(r) ~ J_m(k r)
    kk, rr = 400.0, 0.004
    for m in (0, 2):
        assert radial_g(kk, m, rr).real == pytest.approx(jv(m, kk * rr), abs=2e-2)


def test_psi_K_is_eigenfunction():
    """Delta_g psi = -(1+k^2) psi (eig12b), by central differences in x and y."""
    k, beta, z0, h = 1.3, 0.7, 0.3 + 0.2j, 1e-3
    f = lambda z: psi_K(z, k, beta)
    lap = (f(z0 + h) + f(z0 - h) + f(z0 + 1j * h) + f(z0 - 1j * h) - 4 * f(z0)) / h**2
    dg = (1 - abs(z0) ** 2) ** 2 * lap
    assert dg == pytest.approx(-(1 + k * k) * f(z0), rel=1e-5)


# ----------------------------------------------------------------------------
# issue 10: small disks are cheap, large requests are refused before the work
# ----------------------------------------------------------------------------

def _peak_mb(func, *args, **kwargs):
    tracemalloc.start()
    try:
        out = func(*args, **kwargs)
        return out, tracemalloc.get_traced_memory()[1] / 1e6
    finally:
        tracemalloc.stop()


def test_small_disk_levels_fit_in_a_few_megabytes():
    """continuum_levels(7, 3, radius=0.001, levels=50) grew to 23 GB (the k grid had a fixed step
    while the roots scale like 1/L); the grid step now follows the root spacing."""
    spec, peak = _peak_mb(continuum_levels, 7, 3, radius=0.001, levels=50)
    assert peak < 32 and len(spec) == 50
    spec2, peak2 = _peak_mb(continuum_levels, 7, 3, radius=1e-5, levels=2)     # the CLI case: was 2.9 GB
    assert peak2 < 8
    # flat-disk limit: k artanh(L) -> Bessel zeros j_{m,n} (curvature corrections O(L^2))
    from scipy.special import jn_zeros
    s = math.atanh(1e-5)
    dk = spec2.errors / (2 * hopping_scale(7, 3) * spec2.k)        # the bound, converted to k
    for (k, m, d) in zip(spec2.k, spec2.m, dk):
        j = jn_zeros(abs(int(m)), 1)[0]
        assert abs(k * s - j) <= d * s + 1e-8 * j


def test_grid_resolves_roots_on_tiny_and_huge_disks():
    for radius in (1e-4, 1e-3, 1 - 1e-12):
        k = dirichlet_roots(np.arange(6), radius, n_roots=4, check_nodes=True)
        assert np.all(np.diff(k, axis=1) > 0) and np.all(np.diff(k[:, 0]) > 0)


def test_requests_beyond_the_limits_are_refused_before_allocating():
    from hyperlattice.continuum.spectrum import MAX_LEVELS, MAX_ORDER
    for call in (lambda: dirichlet_roots(0, 0.5, n_roots=10**6),
                 lambda: dirichlet_roots(MAX_ORDER + 1, 0.5, 2),
                 lambda: dirichlet_levels(7, 3, radius=0.5, n_max=3, m_max=MAX_ORDER + 1),
                 lambda: continuum_levels(7, 3, radius=0.5, levels=MAX_LEVELS + 1),
                 lambda: continuum_levels(7, 3, radius=1e-8, levels=2)):
        tracemalloc.start()
        try:
            with pytest.raises(ValueError):
                call()
            assert tracemalloc.get_traced_memory()[1] < 2e6
        finally:
            tracemalloc.stop()


# ----------------------------------------------------------------------------
# the error bounds are true bounds
# ----------------------------------------------------------------------------

def _mp_root(radius, m, k0):
    mp.mp.dps = 40
    x = (1 + mp.mpf(radius) ** 2) / (1 - mp.mpf(radius) ** 2)      # exact x of the float radius
    return mp.findroot(lambda kk: mp.re(mp.legenp(mp.mpc(-0.5, kk / 2), m, x, type=3)), mp.mpf(k0))


@pytest.mark.parametrize("radius,levels", [(0.5, 1), (0.95, 1), (0.999999, 1),
                                           pytest.param(0.01, 2, marks=pytest.mark.slow), (1e-4, 1)])
def test_error_bound_holds_against_a_40_digit_root(radius, levels):
    spec = continuum_levels(7, 3, radius=radius, levels=levels)
    assert spec.error_kind == "energy error bound" and spec.method == "dirichlet-roots"
    s = mp.mpf(hopping_scale(7, 3))
    for k, m, e, err in zip(spec.k, spec.m, spec.energies, spec.errors):
        k_ref = _mp_root(radius, abs(int(m)), k)
        actual = abs(float(s * (mp.mpf(k) ** 2 - k_ref ** 2)))      # E(k) - E(k_exact) with the same h
        assert actual <= err
        # and the bound is not vacuous: below 1e-5 of the level's distance to E_inf
        assert err < 1e-5 * (e - energy_infinity(7, 3))


def test_ring_form_of_eq19_is_a_curve_in_real_l():
    # Fig2 draws eq19 against a continuous l; integer l gives the SuppTab1 rows
    a = asymptotic_energies(7, 3, rings=4.5, form="rings")
    lo, hi = asymptotic_energies(7, 3, rings=4, form="rings"), asymptotic_energies(7, 3, rings=5, form="rings")
    assert hi["E0"] < a["E0"] < lo["E0"]
    with pytest.raises(ValueError):
        asymptotic_energies(7, 3, rings=0.5, form="rings")


# ----------------------------------------------------------------------------
# the dictionary keyword (issue 13)
# ----------------------------------------------------------------------------

def test_dictionary_default_is_the_paper_map_bit_for_bit():
    from hyperlattice.continuum.spectrum import continuum_levels, energy_infinity, level_energy

    a = continuum_levels(7, 3, rings=7, levels=4)
    b = continuum_levels(7, 3, rings=7, levels=4, dictionary="paper")
    assert np.array_equal(a.energies, b.energies) and np.array_equal(a.errors, b.errors)
    assert a.radius == b.radius and a.asymptotic == b.asymptotic and a.dictionary == "paper"
    assert level_energy(0.3, 7, 3) == level_energy(0.3, 7, 3, dictionary="paper")
    assert energy_infinity(7, 3) == -3 + hopping_scale(7, 3)


def test_improved_levels_are_the_improved_map_on_the_shifted_disk():
    from hyperlattice.continuum.spectrum import continuum_levels, dirichlet_levels, dirichlet_roots
    from hyperlattice.dictionary import improved_disk_for_rings, improved_energy_from_k

    c = continuum_levels(7, 3, rings=9, levels=3, dictionary="improved")
    L, x = improved_disk_for_rings(9)
    assert c.radius == L and c.x == x and c.dictionary == "improved"
    k0 = dirichlet_roots(0, x=x, n_roots=1)[0]
    assert c.k[0] == pytest.approx(k0, rel=1e-13)
    assert c.energies[0] == pytest.approx(improved_energy_from_k(k0), abs=1e-14)
    assert np.all(c.errors < 1e-12)
    assert set(c.summary()) == set(continuum_levels(7, 3, rings=9, levels=3).summary())
    t = dirichlet_levels(7, 3, rings=9, n_max=1, m_max=1, dictionary="improved")
    assert t.energies[0, 0] == pytest.approx(c.energies[0], abs=1e-13)
    # a given radius is used as it is: only the energy map changes
    r = continuum_levels(7, 3, radius=0.9, levels=1, dictionary="improved")
    assert r.radius == 0.9 and r.energies[0] == pytest.approx(improved_energy_from_k(r.k[0]), abs=1e-14)


def test_improved_asymptotics_and_edge():
    from hyperlattice.continuum.spectrum import asymptotic_energies, energy_infinity

    assert energy_infinity(7, 3, dictionary="improved") == pytest.approx(-2.940960613699, abs=1e-11)
    a = asymptotic_energies(7, 3, rings=12, dictionary="improved")
    assert set(a) == {"E0", "E1", "E_inf"} and a["E_inf"] < a["E0"] < a["E1"]
    with pytest.raises(ValueError, match="ring form"):
        asymptotic_energies(7, 3, rings=12, form="rings", dictionary="improved")
    with pytest.raises(ValueError):
        asymptotic_energies(7, 3, rings=12, dictionary="better")
