"""Mean-field (Gutzwiller) Bose–Hubbard: the lobe formula, the self-consistent state, the CLI contract."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

import hyperlattice as hl
from hyperlattice.bosons import meanfield as mf
from hyperlattice.cli import main


def test_textbook_lobe_formula_and_tip():
    # van Oosten et al. PRA 63, 053601, Eq. 9: z t_c/U = (n - mu/U)(mu/U - n + 1)/(1 + mu/U)
    # for n = 1; tip (sqrt(n+1) - sqrt(n))^2 / z at mu/U = sqrt(n(n+1)) - n + (n - 1)
    mu = np.linspace(0.05, 0.95, 19)
    z = 6.0
    expected = (1 - mu) * mu / (1 + mu) / z
    assert np.allclose(mf.lobe_boundary(z, mu, 1), expected, rtol=1e-13, atol=0)
    for n in (1, 2, 3):
        tip_mu, tip_t = mf.lobe_tip(z, n)
        grid = np.linspace(n - 1 + 1e-6, n - 1e-6, 200_001)
        tc = mf.lobe_boundary(z, grid, n)
        # the closed form is the maximum of the boundary (grid spacing 5e-6: the maximum is
        # quadratic, so the grid value is within ~1e-10 relative)
        assert tip_t == pytest.approx(tc.max(), rel=1e-9)
        assert tip_mu == pytest.approx(grid[np.argmax(tc)], abs=1e-4)
    assert mf.lobe_tip(1.0, 1)[1] == pytest.approx(3 - 2 * math.sqrt(2), rel=1e-15)
    # outside (n-1, n) there is no Mott state of filling n
    assert np.isnan(mf.atomic_susceptibility(1.2, 1)) and np.isnan(mf.atomic_susceptibility(-0.1, 1))


def test_local_kernel_against_dense_eigh():
    k = np.arange(7)
    rng = np.random.default_rng(3)
    phi = np.concatenate([[0.0, 1e-9], rng.uniform(0, 2, 30)])
    out = [np.empty(phi.size) for _ in range(3)]
    mf._local_kernel(False)(phi, np.full(phi.size, np.nan), 1.0, 0.7, 6, *out)
    for i, f in enumerate(phi):
        h = np.diag(0.5 * k * (k - 1) - 0.7 * k) - f * (np.diag(np.sqrt(k[1:]), 1) + np.diag(np.sqrt(k[1:]), -1))
        w, v = np.linalg.eigh(h)
        v0 = v[:, 0]
        # 1e-12: eigh and the bisection/inverse iteration both reach ~1e-15; allow for the
        # level-spacing-limited vector error at tiny fields
        assert out[2][i] == pytest.approx(w[0], abs=1e-12)
        assert out[0][i] == pytest.approx(abs(np.sum(np.sqrt(k[1:]) * v0[:-1] * v0[1:])), abs=1e-10)
        assert out[1][i] == pytest.approx(np.sum(k * v0**2), abs=1e-10)


def test_regular_cluster_is_homogeneous_and_lambda_max_is_q():
    cl = hl.pbc_cluster(8, 3, "bolza")
    assert mf.largest_adjacency_eigenvalue(cl) == 3.0
    tc = mf.lobe_boundary(3.0, 0.4)
    st = mf.gutzwiller(cl, 1.3 * tc, 0.4, 1.0)
    assert st.converged and st.superfluid
    # a q-regular graph: every site sees the same field, so the state is homogeneous to rounding
    assert np.ptp(st.psi) < 1e-12
    # inside the lobe the order parameter dies out (the monotone iteration descends to 0)
    mott = mf.gutzwiller(cl, 0.7 * tc, 0.4, 1.0)
    assert mott.converged and not mott.superfluid
    assert np.allclose(mott.density, 1.0, atol=1e-8)


def test_flake_is_inhomogeneous_and_obeys_the_linear_criterion():
    lat = hl.ring_lattice(7, 3, 4)
    lam = mf.largest_adjacency_eigenvalue(lat)
    assert lam == pytest.approx(2.84663309, abs=1e-8)  # -E0 of the l = 4 flake (paper Tab. S1)
    tc = mf.lobe_boundary(lam, 0.4)
    sf = mf.gutzwiller(lat, 1.2 * tc, 0.4, 1.0)
    assert sf.superfluid
    # outer-ring sites have two neighbours, inner ones three: psi is largest in the centre
    ring = np.asarray(lat.ring)
    assert sf.psi[ring == 1].mean() > sf.psi[ring == lat.rings].mean()
    assert not mf.gutzwiller(lat, 0.8 * tc, 0.4, 1.0).superfluid


@pytest.mark.slow
def test_lambda_max_grows_with_the_flake_towards_rho():
    lams = [mf.largest_adjacency_eigenvalue(hl.ring_lattice(7, 3, ell)) for ell in (2, 3, 4, 5, 6)]
    assert np.all(np.diff(lams) > 0)
    from hyperlattice.compare.limits import band_bottom

    rho = band_bottom(7, 3, schur_window=None).rho
    assert lams[-1] < rho < 3.0


def test_selfconsistent_boundary_converges_to_the_linear_one():
    # the nonlinear iteration alone (no linearisation) finds the boundary; tightening the
    # self-consistency and bisection tolerances brings it closer to 1 / (lambda_max g_1)
    cl = hl.pbc_cluster(8, 3, "bolza")
    exact = mf.lobe_boundary(3.0, 0.4)
    loose = abs(mf.selfconsistent_boundary(cl, 0.4, tol=1e-4, t_tol=3e-2) / exact - 1)
    tight = abs(mf.selfconsistent_boundary(cl, 0.4, tol=1e-6, t_tol=3e-3) / exact - 1)
    assert tight < loose
    assert tight < 5e-3   # t_tol = 3e-3 of the bisection, plus the sqrt(tol) threshold's shift


def test_cutoff_weight_is_reported_and_small_by_default():
    lat = hl.ring_lattice(7, 3, 3)
    st = mf.gutzwiller(lat, 0.2, 0.5, 1.0)
    assert 0 <= st.cutoff_weight < 1e-3
    small = mf.gutzwiller(lat, 0.2, 0.5, 1.0, nmax=2)
    assert small.cutoff_weight > st.cutoff_weight


def test_unconverged_iteration_warns_with_its_residual():
    lat = hl.ring_lattice(7, 3, 3)
    from hyperlattice.errors import ConvergenceWarning

    with pytest.warns(ConvergenceWarning, match="residual"):
        st = mf.gutzwiller(lat, 0.1, 0.4, 1.0, max_iter=2)
    assert not st.converged


@pytest.mark.slow
def test_mott_lobes_table_flakes_continuum_clusters_infinite():
    table = mf.mott_lobes(7, 3, rings=(3, 5), clusters=("klein",))
    kinds = [r["kind"] for r in table.rows()]
    assert kinds == ["flake", "continuum", "flake", "continuum", "cluster", "infinite"]
    tips = {(r["kind"], r["rings"]): r["tip_t_over_U"] for r in table.rows()}
    # a larger lambda_max gives a smaller lobe: flakes > infinite lattice > q-regular cluster
    assert tips[("flake", 3)] > tips[("flake", 5)] > tips[("infinite", None)] > tips[("cluster", None)]
    # the continuum disk (paper dictionary) reproduces the flake's tip to 0.1 % at l = 5
    assert tips[("continuum", 5)] == pytest.approx(tips[("flake", 5)], rel=1e-3)
    ax = table.plot()
    assert ax.get_xlabel() == "t / U"
    import matplotlib.pyplot as plt

    plt.close("all")


def test_cli_meanfield_contract(capsys):
    assert main(["bosons", "meanfield", "--rings", "4", "-p", "7", "-q", "3", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    for key in ("lambda_max", "mu_over_U", "t_c_over_U"):
        assert key in out
    assert out["lambda_max"] == pytest.approx(2.84663309, abs=1e-8)
    mu = np.array(out["mu_over_U"])
    tc = np.array(out["t_c_over_U"])
    assert mu[0] == 0 and mu[-1] == 1 and tc[0] == 0 and tc[-1] == 0
    assert np.allclose(tc[1:-1], mf.lobe_boundary(out["lambda_max"], mu[1:-1]), rtol=1e-14)
    assert main(["bosons", "meanfield", "--cluster", "bolza", "-p", "8", "--filling", "2", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["lambda_max"] == 3.0 and out["mu_over_U"][0] == 1.0


@pytest.mark.parametrize("words", [["--rings", "0"], ["--rings", "4", "--filling", "0"],
                                   ["--cluster", "nonesuch"], ["--rings", "3", "--t", "0.1"],
                                   ["--cluster", "klein", "--continuum"]])
def test_cli_meanfield_bad_input_is_one_line(words, capsys):
    assert main(["bosons", "meanfield", *words]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "error" in err[0]


def test_selfconsistent_state_is_a_fixed_point_of_an_independent_local_solver():
    # the warm-started kernel's answer, checked by dense eigh on every site's local Hamiltonian
    lat = hl.ring_lattice(7, 3, 4)
    st = mf.gutzwiller(lat, 0.09, 0.6, 1.0, nmax=5)
    phi = 0.09 * (hl.adjacency(lat) @ st.psi)
    k = np.arange(6)
    for i in range(0, lat.sites, 7):
        h = np.diag(0.5 * k * (k - 1) - 0.6 * k) - phi[i] * (np.diag(np.sqrt(k[1:]), 1) + np.diag(np.sqrt(k[1:]), -1))
        v0 = np.linalg.eigh(h)[1][:, 0]
        # the iteration stops at a change of 1e-10 per sweep; the map contracts, so the fixed-point
        # error is of that order too
        assert abs(abs(np.sum(np.sqrt(k[1:]) * v0[:-1] * v0[1:])) - st.psi[i]) < 1e-8
        assert abs(np.sum(k * v0**2) - st.density[i]) < 1e-8


def test_mean_field_gap_closes_at_the_lobe_tip():
    from hyperlattice.compare.bosons import mean_field_gap

    lam = 3.0
    tip = mf.lobe_tip(lam, 1)[1]
    assert mean_field_gap(lam, 0.0) == 1.0
    assert mean_field_gap(lam, 0.999 * tip) > 0 and mean_field_gap(lam, 1.001 * tip) == 0.0
    # the gap is the distance between the two lobe boundaries at that t
    t = 0.5 * tip
    gap = mean_field_gap(lam, t)
    mu = np.linspace(1e-9, 1 - 1e-9, 400_001)
    inside = mu[mf.lobe_boundary(lam, mu) > t]
    assert gap == pytest.approx(inside[-1] - inside[0], abs=1e-5)   # grid spacing 2.5e-6


@pytest.mark.slow
def test_ed_charge_gap_against_mean_field_on_the_heptagon():
    from hyperlattice.compare.bosons import mott_gap_comparison

    cmp = mott_gap_comparison(hl.ring_lattice(7, 3, 1), (0.0, 0.02, 0.1))
    assert cmp.lambda_max == pytest.approx(2.0, abs=1e-12)   # the 7-cycle
    assert cmp.nmax == 8                                     # N + 1: no truncation
    assert cmp.gap_ed[0] == pytest.approx(1.0, abs=1e-10)   # atomic limit: U
    assert cmp.gap_mean_field[0] == 1.0
    # weak hopping: both close to the atomic gap; beyond the mean-field tip (t/U = 0.0858 for
    # lambda_max = 2) the finite system keeps a gap that mean field does not have
    assert abs(cmp.gap_ed[1] - cmp.gap_mean_field[1]) < 0.02
    assert cmp.gap_mean_field[2] == 0.0 and cmp.gap_ed[2] > 0.4


@pytest.mark.parametrize("kw, match", [
    (dict(t=0.1, mu=0.5, U=1e308), "t = 0.1 is less than 1e-150 U"),            # was ZeroDivisionError
    (dict(t=0.1, mu=1e308, U=1.0), "mean filling would be about 1e\\+308 bosons per site"),  # "nmax must be..."
    (dict(t=1e308, mu=0.5, U=1.0), "more than 1e\\+06 U: far in the weakly interacting regime"),
    (dict(t=0.1, mu=-1e308, U=1.0), "below -1e\\+06 U: the ground state there is the empty lattice"),
])
def test_gutzwiller_refuses_overflowing_scales_in_one_sentence(kw, match):
    # issue 28 item 6: gutzwiller(U=1e308) divided by zero; --mu 1e308 named the internal nmax
    import hyperlattice as hl
    from hyperlattice.bosons.meanfield import gutzwiller

    with pytest.raises(ValueError, match=match) as exc:
        gutzwiller(hl.ring_lattice(7, 3, 2), **kw)
    assert "nmax" not in str(exc.value) and "\n" not in str(exc.value)


def test_gutzwiller_depends_on_the_ratios_only():
    # solved in units of U: U = 1e300 with t, mu scaled along is the U = 1 state, energy times U
    import hyperlattice as hl
    from hyperlattice.bosons.meanfield import gutzwiller

    lat = hl.ring_lattice(7, 3, 2)
    one = gutzwiller(lat, 0.05, 0.4, 1.0)
    big = gutzwiller(lat, 0.05e300, 0.4e300, 1e300)
    assert np.allclose(big.psi, one.psi, rtol=1e-12, atol=1e-14) and big.U == 1e300 and big.t == 0.05e300
    assert big.energy == pytest.approx(one.energy * 1e300, rel=1e-12)


def test_cli_infinite_lattice_lobe_with_its_error(capsys):
    # issue 28 item 5: `bosons meanfield --infinite` (the report's lobe tip 0.058335 of the infinite {7,3})
    assert main(["bosons", "meanfield", "--infinite", "--points", "3", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["lambda_max"] == pytest.approx(2.94116, abs=2e-4) and out["sites"] is None
    assert out["tip"]["t_c_over_U"] == pytest.approx(0.058335, abs=5e-6)
    assert 0 < out["tip"]["t_c_over_U_error"] < 1e-4


def test_cli_plot_file_is_written(tmp_path, capsys):
    # issue 28 item 5: --plot's argparse type took two arguments, so the flag could never work
    target = tmp_path / "lobe.png"
    assert main(["bosons", "meanfield", "--rings", "2", "--points", "3", "--plot", str(target)]) == 0
    assert target.read_bytes()[:4] == b"\x89PNG"
    assert main(["bosons", "meanfield", "--rings", "2", "--plot", str(tmp_path / "lobe.txt")]) == 2
    assert "must end in one of .png" in capsys.readouterr().err
