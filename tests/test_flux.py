"""Uniform magnetic flux on the graph (issue 11, items 1-2): Peierls phases, faces, spectra."""

from types import SimpleNamespace

import numpy as np
import pytest
import scipy.linalg as sla
import scipy.sparse as sp

from hyperlattice import geometry, ring_lattice
from hyperlattice.graph import flux as F
from hyperlattice.graph.butterfly import butterfly
from hyperlattice.graph.lattice import line_graph
from hyperlattice.graph.operators import hamiltonian
from hyperlattice.graph.operators import full_table
from hyperlattice.graph.spectrum import Spectrum, full_spectrum, lowest_levels
from hyperlattice.graph.symmetry import sector_hamiltonian, sector_table, signed_sector
from hyperlattice.results import Result

LATTICES = {
    "7,3,l1": lambda: ring_lattice(7, 3, 1),
    "7,3,l2": lambda: ring_lattice(7, 3, 2),
    "7,3,l3": lambda: ring_lattice(7, 3, 3),
    "7,3,l4": lambda: ring_lattice(7, 3, 4),
    "8,3,l3": lambda: ring_lattice(8, 3, 3),
    "4,5,l3": lambda: ring_lattice(4, 5, 3),
    "line 7,3,l1": lambda: line_graph(ring_lattice(7, 3, 1)),
    "line 7,3,l2": lambda: line_graph(ring_lattice(7, 3, 2)),
    "line 7,3,l3": lambda: line_graph(ring_lattice(7, 3, 3)),
    "line 8,3,l2": lambda: line_graph(ring_lattice(8, 3, 2)),
}


def _pgon_area(p, q):
    # written out here (not taken from flux.py): Gauss-Bonnet in curvature -4
    return ((p - 2) * np.pi - 2 * np.pi * p / q) / 4


def _matrix_from_phases(lat, theta, t=1.0):
    e = lat.edges.astype(np.int64)
    hop = -t * np.exp(1j * theta)
    rows = np.concatenate([e[:, 0], e[:, 1]])
    cols = np.concatenate([e[:, 1], e[:, 0]])
    return sp.csr_matrix((np.concatenate([hop, hop.conj()]), (rows, cols)),
                         shape=(lat.sites, lat.sites)).toarray()


# ----------------------------------------------------------------------------
# the gauge
# ----------------------------------------------------------------------------

def test_triangle_area_is_the_line_integral_of_a():
    """0.5 arg(1 - a conj b) against quadrature of A = B Im(conj z dz)/(2(1-|z|^2)) along the geodesic."""
    rng = np.random.default_rng(3)
    for _ in range(5):
        a, b = (complex(*rng.uniform(-0.65, 0.65, 2)) for _ in range(2))
        # Gauss-Legendre in the geodesic parameter: the integrand is smooth
        x, w = np.polynomial.legendre.leggauss(60)
        s = 0.5 * (x + 1)
        zs = geometry.geodesic_point(a, b, s)
        h = 1e-6
        dz = (geometry.geodesic_point(a, b, np.clip(s + h, 0, 1)) - geometry.geodesic_point(a, b, np.clip(s - h, 0, 1)))
        dz /= (np.clip(s + h, 0, 1) - np.clip(s - h, 0, 1))
        integral = 0.5 * np.sum(w * np.imag(np.conj(zs) * dz) / (2 * (1 - np.abs(zs) ** 2)))
        assert abs(integral - F.triangle_area(a, b)) < 1e-8


def test_triangle_area_is_the_angle_defect():
    rng = np.random.default_rng(4)
    for _ in range(20):
        a, b = (complex(*rng.uniform(-0.7, 0.7, 2)) for _ in range(2))
        signed = F.triangle_area(a, b)
        ccw = np.array([0, 1, 2] if signed > 0 else [0, 2, 1])
        pts = SimpleNamespace(z=np.array([0, a, b]))  # face_areas only reads the positions
        assert abs(abs(signed) - F.face_areas(pts, [ccw])[0]) < 1e-13


def test_pgon_area_and_field():
    assert F.pgon_area(7, 3) == pytest.approx(np.pi / 12, rel=1e-15)
    for p, q in ((7, 3), (8, 3), (4, 5)):
        # q faces meet at a site and a face has p sites: area per site = A_p q / p
        assert F.pgon_area(p, q) * q / p == pytest.approx(geometry.site_area(p, q), rel=1e-14)
    assert F.field_strength(1.0, 7, 3) == pytest.approx(24.0, rel=1e-15)
    assert F.field_strength(0.0, 7, 3) == 0.0
    # the graph and the dictionary agree on B x A_p = 2 pi f
    for p, q in ((7, 3), (8, 3), (4, 5)):
        assert F.field_strength(0.3, p, q) * F.pgon_area(p, q) == pytest.approx(0.6 * np.pi, rel=1e-14)


@pytest.mark.parametrize("name", list(LATTICES))
def test_face_fluxes(name):
    """Every bounded face carries 2 pi f x (its angle-defect area / p-gon area) to 1e-12."""
    lat = LATTICES[name]()
    cycles = F.faces(lat)
    # a disk-like planar graph: the bounded faces are a basis of the cycle space (Euler)
    assert len(cycles) == lat.edges.shape[0] - lat.sites + 1
    areas = F.face_areas(lat, cycles)
    assert np.all(areas > 0)
    if lat.kind == "sites":
        # every bounded face of a {p,q} flake is a p-gon
        assert np.all([len(c) == lat.p for c in cycles])
        assert np.max(np.abs(areas - _pgon_area(lat.p, lat.q))) < 1e-13
    for f in (0.37, -1.3, 5.0):
        got = F.face_fluxes(lat, f, cycles)
        want = 2 * np.pi * f * areas / _pgon_area(lat.p, lat.q)
        assert np.max(np.abs(got - want)) <= 1e-12 * max(1.0, 2 * np.pi * abs(f))
        assert F.check_face_fluxes(lat, f) <= 1e-12 * max(1.0, 2 * np.pi * abs(f))


def test_faces_need_a_plane_graph():
    """The line graph for q = 5 has crossing edges (K5 around each vertex): no faces, a plain error."""
    lg = line_graph(ring_lattice(4, 5, 2))
    with pytest.raises(ValueError, match="not a plane graph"):
        F.faces(lg)
    with pytest.raises(ValueError, match="not a plane graph"):
        F.check_face_fluxes(lg, 0.3)
    # the Peierls Hamiltonian itself is still fine and rotation symmetric
    dense = sla.eigvalsh(hamiltonian(lg, flux=0.3).toarray())
    assert np.max(np.abs(full_spectrum(lg, flux=0.3) - dense)) < 1e-12


def test_phases_are_rotation_invariant():
    for lat in (ring_lattice(7, 3, 3), line_graph(ring_lattice(7, 3, 2)), ring_lattice(4, 5, 3)):
        h = hamiltonian(lat, flux=0.41)
        perm = sp.csr_matrix((np.ones(lat.sites), (lat.rotation, np.arange(lat.sites))),
                             shape=(lat.sites, lat.sites))
        assert abs(perm @ h @ perm.T - h).max() < 1e-14


# ----------------------------------------------------------------------------
# the Hamiltonian and its sectors
# ----------------------------------------------------------------------------

def test_zero_flux_is_todays_hamiltonian_and_levels():
    lat = ring_lattice(7, 3, 4)
    h0, h = hamiltonian(lat), hamiltonian(lat, flux=0.0)
    assert h.dtype == np.float64 and (h0 != h).nnz == 0
    a, b = lowest_levels(lat, 8), lowest_levels(lat, 8, flux=0.0)
    assert np.array_equal(a.energies, b.energies) and np.array_equal(a.m, b.m)
    assert np.array_equal(a.n, b.n) and np.array_equal(a.errors, b.errors)
    assert np.array_equal(full_spectrum(lat), full_spectrum(lat, flux=0.0))
    assert "flux" not in b.summary() and b.flux == 0.0


def test_hamiltonian_with_flux_is_complex_hermitian():
    lat = ring_lattice(7, 3, 3)
    h = hamiltonian(lat, t=0.7, onsite=0.2, flux=0.25)
    assert h.dtype == np.complex128 and h.has_sorted_indices
    assert abs(h - h.conj().T).max() == 0
    assert np.allclose(h.diagonal(), 0.2)
    assert np.allclose(np.abs(h.data[h.data != 0.2]), 0.7)
    assert np.array_equal(full_table(lat, 0.7, 0.2, 0.25).to_csr().toarray(), h.toarray())


@pytest.mark.parametrize("name", ["7,3,l3", "7,3,l4", "8,3,l3", "4,5,l3", "line 7,3,l3"])
def test_sector_spectra_union_is_the_dense_spectrum(name):
    lat = LATTICES[name]()
    for f in (0.13, 0.5, -0.77):
        dense = sla.eigvalsh(hamiltonian(lat, flux=f).toarray())
        blocks = np.sort(np.concatenate([sla.eigvalsh(sector_hamiltonian(lat, m, flux=f).toarray())
                                         for m in range(lat.p)]))
        assert np.max(np.abs(blocks - dense)) < 1e-12
        assert np.max(np.abs(full_spectrum(lat, flux=f) - dense)) < 1e-12


def test_sectors_with_flux_are_not_conjugate_pairs():
    lat = ring_lattice(7, 3, 3)
    h1 = sector_table(lat, 1, flux=0.3).to_csr().toarray()
    hm1 = sector_table(lat, -1, flux=0.3).to_csr().toarray()
    assert np.max(np.abs(hm1 - h1.conj())) > 1e-3
    e1, em1 = sla.eigvalsh(h1), sla.eigvalsh(hm1)
    assert np.max(np.abs(e1 - em1)) > 1e-3
    # f -> -f maps sector m to -m (complex conjugation)
    assert np.max(np.abs(sla.eigvalsh(sector_table(lat, -1, flux=-0.3).to_csr().toarray()) - e1)) < 1e-12


def test_random_gauge_transformation_and_sign_of_f():
    rng = np.random.default_rng(7)
    for lat in (ring_lattice(7, 3, 3), line_graph(ring_lattice(7, 3, 2)), ring_lattice(4, 5, 3)):
        for f in (0.21, 0.8):
            ref = full_spectrum(lat, flux=f)
            chi = rng.uniform(0, 2 * np.pi, lat.sites)
            e = lat.edges.astype(np.int64)
            theta = F.edge_phases(lat, f) + chi[e[:, 0]] - chi[e[:, 1]]
            assert np.max(np.abs(sla.eigvalsh(_matrix_from_phases(lat, theta)) - ref)) < 1e-12
            assert np.max(np.abs(full_spectrum(lat, flux=-f) - ref)) < 1e-12


@pytest.mark.parametrize("pq", [(7, 3), (8, 3), (4, 5)])
def test_one_flux_quantum_per_pgon_is_a_gauge(pq):
    """All bounded faces of a site flake are p-gons, so f -> f + 1 changes no face flux mod 2 pi."""
    lat = ring_lattice(*pq, 3)
    for f in (0.0, 0.3, -0.45):
        assert np.max(np.abs(full_spectrum(lat, flux=f + 1) - full_spectrum(lat, flux=f))) < 1e-11
    # the line graph has triangles as well: there it is not a gauge
    lg = line_graph(ring_lattice(*pq, 2))
    assert np.max(np.abs(full_spectrum(lg, flux=1.3) - full_spectrum(lg, flux=0.3))) > 1e-3


def _least_norm_phases(lat, f):
    """Phases from the face-flux equations alone (least-norm solve): no vector potential used."""
    cycles = F.faces(lat)
    e = lat.edges.astype(np.int64)
    index = {}
    for k, (i, j) in enumerate(e.tolist()):
        index[(i, j)] = (k, 1.0)   # theta_k is the phase of the hop j -> i
        index[(j, i)] = (k, -1.0)
    rows, cols, vals = [], [], []
    for c, cyc in enumerate(cycles):
        for u, v in zip(cyc.tolist(), np.roll(cyc, -1).tolist()):
            k, sgn = index[(v, u)]  # going u -> v is the hop u -> v
            rows.append(c)
            cols.append(k)
            vals.append(sgn)
    mat = sp.csr_matrix((vals, (rows, cols)), shape=(len(cycles), e.shape[0])).toarray()
    phi = 2 * np.pi * f * F.face_areas(lat, cycles) / _pgon_area(lat.p, lat.q)
    theta, *_ = np.linalg.lstsq(mat, phi, rcond=None)
    assert np.max(np.abs(mat @ theta - phi)) < 1e-11
    return theta


@pytest.mark.parametrize("name", ["7,3,l2", "7,3,l4", "8,3,l3", "4,5,l3", "line 7,3,l3"])
def test_independent_gauge_gives_the_same_spectrum(name):
    lat = LATTICES[name]()
    for f in (0.17, 0.6):
        theta = _least_norm_phases(lat, f)
        other = sla.eigvalsh(_matrix_from_phases(lat, theta))
        assert np.max(np.abs(other - full_spectrum(lat, flux=f))) < 1e-10


@pytest.mark.slow
def test_independent_gauge_l5():
    lat = ring_lattice(7, 3, 5)
    theta = _least_norm_phases(lat, 0.23)
    other = sla.eigvalsh(_matrix_from_phases(lat, theta))
    assert np.max(np.abs(other - full_spectrum(lat, flux=0.23))) < 1e-10


# ----------------------------------------------------------------------------
# lowest_levels with flux
# ----------------------------------------------------------------------------

@pytest.mark.parametrize("name", ["7,3,l3", "4,5,l3", "line 7,3,l2"])
def test_lowest_levels_with_flux(name):
    lat = LATTICES[name]()
    f = 0.3
    h = hamiltonian(lat, flux=f)
    dense = sla.eigvalsh(h.toarray())
    spec = lowest_levels(lat, 8, flux=f, eigenvectors=True)
    assert isinstance(spec, Spectrum) and spec.flux == f and spec.method == "sector-dense"
    assert np.max(np.abs(spec.energies - dense[:8])) < 1e-12
    # the lifted sector states are eigenstates of the full Peierls matrix with their m
    v = spec.eigenvectors
    res = np.linalg.norm(h @ v - v * spec.energies[None, :], axis=0)
    assert np.max(res) < 1e-12 and np.max(spec.errors) < 1e-12
    omega = np.exp(2j * np.pi * spec.m / lat.p)
    assert np.max(np.abs(v[lat.rotation, :] - v * omega[None, :])) < 1e-12
    # the dense path labels the same levels with the same m
    full = lowest_levels(lat, 8, flux=f, method="dense")
    assert np.max(np.abs(full.energies - spec.energies)) < 1e-12
    assert np.array_equal(full.m, spec.m) and full.flux == f
    # f -> -f: same energies, m -> -m
    neg = lowest_levels(lat, 8, flux=-f)
    assert np.max(np.abs(neg.energies - spec.energies)) < 1e-12
    assert sorted(neg.m.tolist()) == sorted(signed_sector((-m) % lat.p, lat.p) for m in spec.m.tolist())


def test_lowest_levels_with_flux_sparse_paths():
    lat = ring_lattice(7, 3, 6)  # sector blocks of 320 sites: dense; the full matrix via ARPACK
    f = 0.1
    spec = lowest_levels(lat, 6, flux=f)
    sparse = lowest_levels(lat, 6, flux=f, method="sparse")
    assert sparse.method == "sparse"
    assert np.max(np.abs(sparse.energies - spec.energies)) < 1e-10
    assert np.array_equal(sparse.m, spec.m)
    one = lowest_levels(lat, 3, flux=f, sector=2)
    assert np.all(one.m == 2)
    assert np.max(np.abs(one.energies[0] - spec.energies[spec.m == 2][0])) < 1e-12


def test_spectrum_records_flux():
    spec = lowest_levels(ring_lattice(7, 3, 2), 3, flux=-0.25)
    out = spec.summary()
    assert out["flux"] == -0.25
    back = Result.from_dict(spec.as_dict())
    assert back.flux == -0.25 and np.array_equal(back.energies, spec.energies)
    assert "flux f = -0.25" in spec.description


@pytest.mark.parametrize("bad", ["0.1", float("nan"), float("inf"), True, None, 1j, [0.1], 1e300, -2e6])
def test_bad_flux(bad):
    lat = ring_lattice(7, 3, 2)
    for call in (lambda: hamiltonian(lat, flux=bad), lambda: lowest_levels(lat, 2, flux=bad),
                 lambda: full_spectrum(lat, flux=bad), lambda: sector_table(lat, 1, flux=bad),
                 lambda: full_table(lat, flux=bad), lambda: F.edge_phases(lat, bad),
                 lambda: F.check_face_fluxes(lat, bad)):
        with pytest.raises(ValueError, match="flux"):
            call()


def test_largest_flux_accepted():
    lat = ring_lattice(7, 3, 2)
    big = F.MAX_FLUX
    # an integer flux on a site flake is a gauge: the spectrum is that of f = 0 up to the phase rounding
    assert np.max(np.abs(full_spectrum(lat, flux=big) - full_spectrum(lat))) < 1e-8


# ----------------------------------------------------------------------------
# the butterfly
# ----------------------------------------------------------------------------

def test_butterfly_matches_the_dense_spectrum():
    lat = ring_lattice(7, 3, 3)
    fluxes = np.array([0.0, 0.1, 0.35, 1.0, -0.2])
    bf = butterfly(lat, fluxes)
    assert bf.energies.shape == (5, lat.sites) and bf.m.shape == (5, lat.sites)
    for k, f in enumerate(fluxes):
        dense = sla.eigvalsh(hamiltonian(lat, flux=f).toarray())
        assert np.max(np.abs(bf.energies[k] - dense)) < 1e-12
        # every sector holds N/p levels
        assert np.all(np.bincount(bf.m[k] % lat.p) == lat.sites // lat.p)
    # the lowest level and its sector agree with lowest_levels
    spec = lowest_levels(lat, 1, flux=0.35)
    assert abs(bf.energies[2, 0] - spec.energies[0]) < 1e-12 and bf.m[2, 0] == spec.m[0]
    # f = 1 is a gauge on a site flake
    assert np.max(np.abs(bf.energies[3] - bf.energies[0])) < 1e-11
    cols = bf.columns()
    assert cols["flux"].shape == cols["energy"].shape == cols["m"].shape == (5 * lat.sites,)
    out = bf.summary()
    assert out["fluxes"] == 5 and out["flux_max"] == 1.0 and out["sites"] == lat.sites
    back = Result.from_dict(bf.as_dict())
    assert np.array_equal(back.energies, bf.energies) and np.array_equal(back.m, bf.m)


def test_butterfly_labels_of_degenerate_levels_do_not_follow_the_rounding(monkeypatch):
    """At f = 0 every m != 0 level is the pair +-m, and f = 1/2 and 1 pair other sectors; the two
    energies of a pair come out of different blocks, equal or a few ulps apart in either order
    (by BLAS kernel). The labels of a pair are listed by |m|, +m first, whatever those last bits,
    and the energies stay ascending. Checked by moving every level by up to +-2 ulps of the norm
    with several random patterns, as another machine's LAPACK may."""
    import hyperlattice.graph.butterfly as bmod

    lat = ring_lattice(7, 3, 3)
    fluxes = np.array([0.0, 0.5, 1.0])
    ref = butterfly(lat, fluxes)
    assert np.all(np.diff(ref.energies, axis=1) >= 0)
    pair = np.flatnonzero(np.diff(ref.energies[0]) < 1e-12)
    assert pair.size == 48                          # the +-m pairs of m = 1, 2, 3 at f = 0
    first, second = ref.m[0, pair], ref.m[0, pair + 1]
    assert np.all(first > 0) and np.all(second == -first)
    real = bmod.sla.eigvalsh
    for seed in range(4):
        rng = np.random.default_rng(seed)

        def noisy(a, *args, **kwargs):
            w = real(a, *args, **kwargs)
            return np.sort(w + 2 * np.finfo(float).eps * 3.0 * rng.uniform(-1, 1, w.shape))

        monkeypatch.setattr(bmod.sla, "eigvalsh", noisy)
        got = butterfly(lat, fluxes)
        monkeypatch.undo()
        assert np.array_equal(got.m, ref.m), seed
        assert np.all(np.diff(got.energies, axis=1) >= 0)
        np.testing.assert_allclose(got.energies, ref.energies, rtol=0, atol=1e-14)


def test_butterfly_line_graph_and_plot():
    import matplotlib.pyplot as plt

    lg = line_graph(ring_lattice(7, 3, 2))
    bf = butterfly(lg, np.linspace(0, 1, 4))
    assert bf.kind == "line_graph"
    assert np.max(np.abs(bf.energies[2] - sla.eigvalsh(hamiltonian(lg, flux=2 / 3).toarray()))) < 1e-12
    ax = bf.plot()
    assert ax.get_xlabel() == "flux f per p-gon"
    plt.close(ax.figure)


@pytest.mark.parametrize("bad", [[], [[0.1]], ["a"], [np.nan], [0.1, 2e6]])
def test_butterfly_bad_fluxes(bad):
    with pytest.raises(ValueError):
        butterfly(ring_lattice(7, 3, 2), bad)


def test_butterfly_refuses_large_before_allocating():
    lat = ring_lattice(7, 3, 4)
    with pytest.raises(ValueError, match="max_sites"):
        butterfly(lat, [0.1], max_sites=100)
    with pytest.raises(ValueError, match="too large"):
        butterfly(lat, np.zeros(700_000))
    with pytest.raises(ValueError, match="rotation"):
        butterfly(lat, [0.1], onsite=np.arange(lat.sites, dtype=float))


@pytest.mark.slow
def test_sector_sparse_with_flux():
    """Blocks above DENSE_MAX go through shift-invert (graph/factor, complex Hermitian blocks) with flux."""
    lat = ring_lattice(7, 3, 8)  # 15,435 sites, blocks of 2,205
    spec = lowest_levels(lat, 6, flux=0.05)
    assert spec.method == "sector-shift-invert" and np.max(spec.errors) < 1e-10
    assert spec.backend in ("cholmod", "superlu")
    for m in (0, -3):
        e = sla.eigvalsh(sector_table(lat, m, flux=0.05).to_csr().toarray(), subset_by_index=[0, 1])
        sel = spec.energies[spec.m == m]
        assert sel.size >= 1 and np.max(np.abs(e[:sel.size] - sel)) < 1e-12


def test_sign_convention_lowest_levels_have_positive_m():
    """f > 0 is counterclockwise: the -B L_z term of (grad - iA)^2 puts m = 0, 1, 2, ... lowest."""
    lat = ring_lattice(7, 3, 6)
    spec = lowest_levels(lat, 6, flux=0.1)
    assert (spec.m % 7).tolist() == [0, 1, 2, 3, 4, 5]
    spec = lowest_levels(lat, 6, flux=-0.1)
    assert ((-spec.m) % 7).tolist() == [0, 1, 2, 3, 4, 5]
    # and the phases of a ccw face sum to +2 pi f
    cycles = F.faces(ring_lattice(7, 3, 1))
    assert F.face_fluxes(ring_lattice(7, 3, 1), 0.1, cycles)[0] == pytest.approx(0.2 * np.pi, abs=1e-14)


@pytest.mark.parametrize("pq", [(7, 3), (8, 3), (4, 5)])
def test_one_flux_quantum_shifts_the_sector_by_one(pq):
    """f -> f + 1 is a gauge whose gauge function winds once around the central p-gon, so the
    sector blocks are relabelled m -> m + 1: spectrum of H_{m+1}(f+1) = spectrum of H_m(f)."""
    lat = ring_lattice(*pq, 3)
    p = pq[0]
    for m in range(p):
        a = sla.eigvalsh(sector_table(lat, (m + 1) % p, flux=1.3).to_csr().toarray())
        b = sla.eigvalsh(sector_table(lat, m, flux=0.3).to_csr().toarray())
        assert np.max(np.abs(a - b)) < 1e-12


def test_degeneracy_is_one_in_a_field():
    # m and -m split in a field: no level is a symmetry pair any more (graph and continuum)
    from hyperlattice.continuum.magnetic import magnetic_levels
    from hyperlattice.graph.lattice import ring_lattice
    from hyperlattice.graph.spectrum import lowest_levels

    spec = lowest_levels(ring_lattice(7, 3, 3), 4, flux=0.1)
    assert spec.degeneracy.tolist() == [1, 1, 1, 1]
    cont = magnetic_levels(7, 3, rings=3, levels=4, flux=0.1)
    assert cont.degeneracy.tolist() == [1, 1, 1, 1]
    assert lowest_levels(ring_lattice(7, 3, 3), 3).degeneracy.tolist() == [1, 2, 2]


def test_butterfly_figure_mirror_draws_the_other_half_of_the_period():
    """E(1 - f) = E(f) on a site flake: the mirrored half draws the computed whole period.

    Pixel for pixel, except where a level lies within rounding of an energy-bin edge: the computed
    E(1 - f) and E(f) differ in their last bits (by BLAS kernel and thread count), so such a level
    may land in either of the two bins that share the edge on another machine."""
    import matplotlib.pyplot as plt

    from hyperlattice.plots.magnetic import butterfly_figure

    lat = ring_lattice(7, 3, 3)
    half = butterfly(lat, np.linspace(0.0, 0.5, 6))
    whole = butterfly(lat, np.linspace(0.0, 1.0, 11))
    # the physics first: the computed levels at 1 - f are those at f, to rounding
    assert np.allclose(whole.energies[::-1][:5], whole.energies[:5], atol=1e-10)
    a = butterfly_figure(half, continuum=False, density=True, energy_bins=60, mirror=True)
    b = butterfly_figure(whole, continuum=False, density=True, energy_bins=60)
    img_a, img_b = np.asarray(a.images[0].get_array()), np.asarray(b.images[0].get_array())
    assert img_a.shape == img_b.shape == (60, 11)
    assert np.array_equal(img_a.sum(axis=0), img_b.sum(axis=0))   # every level drawn once per flux
    ext = b.images[0].get_extent()
    assert a.images[0].get_extent() == pytest.approx(ext)
    edges = np.linspace(ext[2], ext[3], 61)
    tie = np.zeros(img_b.shape, dtype=bool)    # pixels next to an edge that a level sits on
    for col, levels in enumerate(whole.energies):
        for k in np.nonzero(np.min(np.abs(levels[:, None] - edges[None, 1:-1]), axis=0) < 1e-9)[0]:
            tie[k:k + 2, col] = True
    assert np.array_equal(img_a[~tie], img_b[~tie])
    with pytest.raises(ValueError, match=r"\[0, 1/2\]"):
        butterfly_figure(whole, continuum=False, density=True, mirror=True)
    with pytest.raises(ValueError, match="site flake"):
        butterfly_figure(butterfly(line_graph(ring_lattice(7, 3, 2)), [0.0, 0.5]), continuum=False, mirror=True)
    for bad in ("x", -1, float("nan")):      # refused before any drawing, not an AttributeError
        with pytest.raises(ValueError, match="zoom_ax must be a matplotlib Axes"):
            butterfly_figure(half, continuum=True, zoom_ax=bad)
    plt.close("all")


def test_butterfly_figure_band_bottom_panel():
    import matplotlib.pyplot as plt

    from hyperlattice.plots.magnetic import butterfly_figure

    bf = butterfly(ring_lattice(7, 3, 3), np.linspace(0.0, 0.5, 11))
    fig, (ax, zoom) = plt.subplots(1, 2)
    butterfly_figure(bf, max_flux=0.3, points=4, levels=2, ax=ax, density=True, mirror=True, zoom_ax=zoom)
    # one curve per continuum level (n, m) that is among the 2 lowest at some flux (issue 28 item 3)
    assert len(zoom.lines) >= 2 and zoom.get_xlim() == (0.0, 0.3)
    assert all(ln.get_gid().startswith("continuum n=") for ln in zoom.lines)
    low, high = zoom.get_ylim()
    assert low < bf.energies[0, 0] < high   # the lowest level at f = 0 is in view
    plt.close(fig)
