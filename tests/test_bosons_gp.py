"""Gross–Pitaevskii and Bogoliubov, graph and continuum (issue 22, item 3)."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

import hyperlattice as hl
from hyperlattice.bosons.gp import bogoliubov, gp_ground_state
from hyperlattice.cli import main
from hyperlattice.continuum.gp import disk_bogoliubov, disk_gp, disk_gp_shooting, healing_length
from hyperlattice.dictionary import continuum_parameters, disk_radius_for_rings

LAT = hl.ring_lattice(7, 3, 4)


def test_graph_u_to_zero_gives_the_single_particle_ground_state():
    e0 = hl.lowest_levels(LAT, 1).energies[0]
    free = gp_ground_state(LAT, 50.0, 0.0)
    assert free.mu == pytest.approx(e0, abs=1e-12)
    # a weak interaction shifts mu by about U * sum(psi^4) / N (first-order perturbation)
    weak = gp_ground_state(LAT, 50.0, 1e-6)
    shift = 1e-6 * np.sum(free.psi**4) / 50.0
    assert weak.mu - e0 == pytest.approx(shift, rel=1e-3)


def test_graph_gp_equation_residual_and_mu_is_dE_dN():
    s = gp_ground_state(LAT, 315.0, 0.5)
    h = -hl.adjacency(LAT)
    r = h @ s.psi + 0.5 * s.psi**3 - s.mu * s.psi
    assert np.linalg.norm(r) / (abs(s.mu) * math.sqrt(315.0)) < 1e-10
    assert np.sum(s.psi**2) == pytest.approx(315.0, rel=1e-12)
    # mu = dE/dN (central difference, step 0.5: error ~ E''' h^2 ~ 1e-6)
    up = gp_ground_state(LAT, 315.5, 0.5).energy
    down = gp_ground_state(LAT, 314.5, 0.5).energy
    assert (up - down) == pytest.approx(s.mu, rel=1e-5)


@pytest.mark.slow
def test_bogoliubov_real_positive_with_goldstone_mode_dense_and_sparse_agree():
    s = gp_ground_state(LAT, 315.0, 0.5)
    dense = bogoliubov(s, LAT, 6)
    assert dense.method == "dense"
    assert dense.zero_mode < dense.tolerance           # the broken U(1) symmetry's zero mode
    assert np.all(dense.frequencies[1:] > 10 * dense.tolerance)
    from hyperlattice.bosons import gp as G

    old = G._DENSE_SITES
    G._DENSE_SITES = 10
    try:
        sparse = bogoliubov(s, LAT, 6)
    finally:
        G._DENSE_SITES = old
    assert sparse.method == "shift-invert"
    # both to ~1e-10 (dense eigvalsh and ARPACK at tol 1e-12 on omega^2; omega ~ 0.1)
    assert np.allclose(sparse.frequencies[1:], dense.frequencies[1:], atol=1e-9, rtol=0)


def test_continuum_u_to_zero_gives_the_dirichlet_level():
    L, _ = disk_radius_for_rings(5)
    cp = continuum_parameters(1.0, 0.0, 0.0)
    s = disk_gp(L, cp.t_prime, 0.0, 10.0, cells=1600)
    e0 = hl.continuum_levels(7, 3, rings=5, levels=1).energies[0]
    # mu_c - q t is the continuum E0; second-order finite volumes at 1600 cells: ~1e-7
    assert s.mu_c - 3.0 == pytest.approx(e0, abs=2e-7)


@pytest.mark.parametrize("winding", [0, 1])
@pytest.mark.slow
def test_continuum_two_discretisations_agree(winding):
    L, _ = disk_radius_for_rings(4)
    cp = continuum_parameters(1.0, 0.0, 0.5)
    coarse = disk_gp(L, cp.t_prime, cp.U_prime, 315.0, winding=winding, cells=400)
    fine = disk_gp(L, cp.t_prime, cp.U_prime, 315.0, winding=winding, cells=800)
    shoot = disk_gp_shooting(L, cp.t_prime, cp.U_prime, 315.0, winding=winding, guess=fine)
    assert coarse.residual < 1e-10 and fine.residual < 1e-10 and shoot.residual < 1e-9
    # finite volumes are second order: Richardson from 400 and 800 cells matches the shooting
    # solution (DOP853 at rtol 1e-12) to 1e-7 relative, and the fine grid alone to ~1e-5
    rich = (4 * fine.mu_c - coarse.mu_c) / 3
    assert rich == pytest.approx(shoot.mu_c, rel=1e-7)
    assert fine.mu_c == pytest.approx(shoot.mu_c, rel=1e-5)


@pytest.mark.slow
def test_continuum_bogoliubov_goldstone_and_degenerate_pairs():
    L, _ = disk_radius_for_rings(4)
    cp = continuum_parameters(1.0, 0.0, 0.5)
    s = disk_gp(L, cp.t_prime, cp.U_prime, 315.0, cells=400)
    b = disk_bogoliubov(s, 5)
    assert b.zero_mode < 1e-4 and b.angular_momenta[0] == 0
    assert np.all(b.frequencies[1:] > 1e-2)
    assert b.angular_momenta.tolist() == [0, 1, 1, 2, 2]
    assert b.frequencies[1] == b.frequencies[2]
    assert healing_length(s) == pytest.approx(math.sqrt(cp.t_prime / (cp.U_prime * np.max(s.f**2))))


@pytest.mark.slow
def test_vortex_costs_energy():
    L, _ = disk_radius_for_rings(4)
    cp = continuum_parameters(1.0, 0.0, 0.5)
    ground = disk_gp(L, cp.t_prime, cp.U_prime, 315.0, cells=400)
    vortex = disk_gp(L, cp.t_prime, cp.U_prime, 315.0, winding=1, cells=400)
    assert vortex.energy > ground.energy and vortex.f[0] < 1e-2 * ground.f[0]


@pytest.mark.slow
def test_comparison_weak_interaction_agrees_better_than_strong():
    from hyperlattice.compare.bosons import gp_comparison

    weak = gp_comparison(rings=(4,), U=0.05, cells=400, modes=3).rows[0]
    strong = gp_comparison(rings=(4,), U=5.0, cells=400, modes=3).rows[0]
    # the dictionary is a gradient expansion: it needs xi >> d0
    assert weak["xi_over_d0"] > strong["xi_over_d0"]
    assert abs(weak["mu_rel_diff"]) < abs(strong["mu_rel_diff"])


def test_cli_gp_json(capsys):
    assert main(["bosons", "gp", "--rings", "3", "--U", "0.5", "--modes", "3", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    for key in ("graph", "continuum", "mu_rel_diff", "xi_over_d0", "profile", "sites", "particles"):
        assert key in out
    assert out["sites"] == 112 and out["particles"] == 112
    assert len(out["graph"]["bogoliubov"]) == 3
    assert main(["bosons", "gp", "--rings", "3", "--U", "0.5", "--particles", "56"]) == 0
    assert "N = 56 bosons" in capsys.readouterr().out


@pytest.mark.parametrize("words", [["--rings", "3", "--U", "-1"], ["--rings", "0", "--U", "1"],
                                   ["--rings", "3", "--U", "1", "--filling", "0"],
                                   ["--rings", "3", "--U", "1", "--modes", "1"]])
def test_cli_gp_bad_input_is_one_line(words, capsys):
    assert main(["bosons", "gp", *words]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "error" in err[0]


def test_tiny_U_is_the_noninteracting_limit_not_a_refusal(capsys):
    # issue 28 item 6: `bosons gp --U 1e-14` was refused ("Bogoliubov matrix not positive definite"):
    # the lowest eigenvalue of B, ~2U psi^2, lies below the error of the computed B there
    import warnings

    from hyperlattice.bosons.gp import bogoliubov, gp_ground_state
    from hyperlattice.cli import main
    from hyperlattice.graph.lattice import ring_lattice
    from hyperlattice.graph.spectrum import lowest_levels

    lat = ring_lattice(7, 3, 2)
    e = lowest_levels(lat, 2).energies
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        state = gp_ground_state(lat, 10.0, 1e-14)
        spec = bogoliubov(state, lat, modes=3)
    assert state.residual <= 1e-10 and abs(state.mu - e[0]) < 1e-12
    assert spec.frequencies[0] < spec.tolerance and abs(spec.frequencies[1] - (e[1] - e[0])) < 1e-6
    assert main(["bosons", "gp", "--rings", "2", "--U", "1e-14"]) == 0
    assert capsys.readouterr().err == ""


@pytest.mark.parametrize("particles, U", [(1e308, 1.0), (1e302, 0.0), (1e160, 1e-3)])
def test_energies_beyond_float64_are_refused_before_work(particles, U):
    # issue 28 item 6: 1e308 bosons came back as NaN and -inf
    from hyperlattice.bosons.gp import gp_ground_state
    from hyperlattice.graph.lattice import ring_lattice

    with pytest.raises(ValueError, match=r"^particles = .* lies beyond the range of float64 numbers .*\.$"):
        gp_ground_state(ring_lattice(7, 3, 2), particles, U)


def test_a_vanishing_condensate_is_computed():
    # 1e-300 bosons: the uniform start stopped at once (gradients below the optimiser's tolerance)
    from hyperlattice.bosons.gp import gp_ground_state
    from hyperlattice.graph.lattice import ring_lattice

    s = gp_ground_state(ring_lattice(7, 3, 2), 1e-300, 1.0)
    assert s.residual <= 1e-10 and s.mu == pytest.approx(-2.636404937210, abs=1e-10)


def test_cli_filling_beside_particles_is_refused(capsys):
    # issue 28 item 6: --filling was silently ignored when --particles was given
    from hyperlattice.cli import main

    with pytest.raises(SystemExit) as exc:                  # argparse's refusal: one line, exit 2
        main(["bosons", "gp", "--rings", "2", "--U", "0.5", "--filling", "2", "--particles", "35"])
    assert exc.value.code == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--particles: not allowed with argument --filling" in err
