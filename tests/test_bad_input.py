"""Every public entry point and every CLI subcommand, walked with bad values.

The contract (README, "Conventions"): bad input gives a ``ValueError`` with a plain sentence from
the API, and one line on stderr with exit code 2 from the CLI, never a traceback or another
exception type. Each public function is listed below with a call that would work and the
arguments to spoil; every argument is then replaced, one at a time, by each value of ``BAD``
that the argument does not legitimately accept.
"""

from __future__ import annotations


import numpy as np
import pytest

import hyperlattice as hl
from hyperlattice import dictionary, geometry
from hyperlattice.cli import main
from hyperlattice.compare import correlation, scaling, sums
from hyperlattice.compare import green as cgreen
from hyperlattice.continuum import green as kgreen
from hyperlattice.continuum import magnetic, special, spectrum as kspec
from hyperlattice.graph import green as ggreen
from hyperlattice.graph import lattice as glat
from hyperlattice.graph import operators, symmetry
from hyperlattice.graph import spectrum as gspec

LAT = glat.ring_lattice(7, 3, 2)
F = scaling.SmoothFunction.cos_distance()

from badinput import api_cases, check_api, check_cli, cli_cases  # noqa: E402

# (id, function, working keyword arguments, {argument: tags it legitimately accepts})
# Arguments not listed in the working call are not spoiled.
CASES = [
    # geometry
    ("distance", geometry.distance, dict(z1=0.1, z2=0.2j), {"z1": {"complex"}, "z2": {"complex"}}),
    ("tiling_constants", geometry.tiling_constants, dict(p=7, q=3), {"p": {"inf"}}),
    ("lattice_h", geometry.lattice_h, dict(p=7, q=3), {"p": {"inf"}}),
    ("d0", geometry.d0, dict(p=7, q=3), {"p": {"inf"}}),
    ("r0", geometry.r0, dict(p=7, q=3), {"p": {"inf"}}),
    ("site_area", geometry.site_area, dict(p=7, q=3), {"p": {"inf"}}),
    ("effective_radius", geometry.effective_radius, dict(sites=112, p=7, q=3), {"p": {"inf"}}),
    ("mobius", geometry.mobius, dict(z=0.1, a=0.2j), {"z": {"complex"}, "a": {"complex"}}),
    ("geodesic_point", geometry.geodesic_point, dict(z1=0.1, z2=0.2j, t=0.5), {"z1": {"complex"}, "z2": {"complex"}}),
    ("rho", geometry.rho, dict(r=0.5), {}),
    # graph: lattices and operators
    ("ring_lattice", glat.ring_lattice, dict(p=7, q=3, rings=2, max_sites=1000), {"max_sites": {"none"}}),
    ("ring_sizes", glat.ring_sizes, dict(p=7, q=3, rings=3), {}),
    ("site_count", glat.site_count, dict(p=7, q=3, rings=3), {}),
    ("line_graph", glat.line_graph, dict(lattice=LAT), {}),
    ("load_lattice", glat.load_lattice, dict(path="/nonexistent/lattice.npz"), {}),
    ("adjacency", operators.adjacency, dict(lattice=LAT), {}),
    ("incidence", operators.incidence, dict(lattice=LAT), {}),
    ("hamiltonian", operators.hamiltonian, dict(lattice=LAT, t=1.0, onsite=0.0),
     {"onsite": {"none", "complex"}}),  # a complex potential (absorbing sites) is a valid, non-Hermitian H
    ("sector_hamiltonian", symmetry.sector_hamiltonian, dict(lattice=LAT, m=1, t=1.0), {}),
    ("signed_sector", symmetry.signed_sector, dict(m=1, p=7), {}),
    ("rotation_orbits", symmetry.rotation_orbits, dict(lattice=LAT), {}),
    # graph: spectra and Green functions
    ("lowest_levels", gspec.lowest_levels,
     dict(lattice=LAT, levels=2, t=1.0, method="auto", sector=0, eigenvectors=False, tol=1e-10),
     {"sector": {"none"}, "eigenvectors": {"bool"}}),
    ("full_spectrum", gspec.full_spectrum, dict(lattice=LAT, t=1.0, max_sites=1000), {}),
    ("partition_function", gspec.partition_function, dict(system=LAT, beta=1.0), {}),
    ("graph_green", ggreen.graph_green, dict(lattice=LAT, omega=-2.95, source=1, t=1.0),
     {"omega": {"complex"}, "source": {"none"}}),
    ("GraphResolvent", ggreen.GraphResolvent, dict(system=LAT, t=1.0, method="auto"), {}),
    # continuum: special functions
    ("legendre_p", special.legendre_p, dict(nu=0.5, m=1, x=2.0), {"nu": {"complex"}}),
    ("legendre_q", special.legendre_q, dict(nu=0.5, m=1, x=2.0), {"nu": {"complex"}}),
    ("legendre_log_p", special.legendre_log_p, dict(nu=0.5, m=1, x=2.0), {"nu": {"complex"}}),
    ("legendre_log_q", special.legendre_log_q, dict(nu=0.5, m=1, x=2.0), {"nu": {"complex"}}),
    ("legendre_q_over_p", special.legendre_q_over_p, dict(nu=0.5, m=1, x=2.0), {"nu": {"complex"}}),
    ("legendre_wronskian", special.legendre_wronskian, dict(nu=0.5, m=1, x=2.0), {"nu": {"complex"}}),
    ("legendre_cm", special.legendre_cm, dict(nu=0.5, m=1), {"nu": {"complex"}}),
    ("nu_from_lambda", special.nu_from_lambda, dict(lam=0.5), {"lam": {"complex"}}),
    ("conical_p", special.conical_p, dict(k=1.0, m=1, x=2.0), {}),
    # continuum: levels and Green functions
    ("disk_argument", kspec.disk_argument, dict(radius=0.9, p=7, q=3), {}),
    ("level_energy", kspec.level_energy, dict(k=1.0, p=7, q=3), {}),
    ("energy_infinity", kspec.energy_infinity, dict(p=7, q=3), {}),
    ("asymptotic_energies", kspec.asymptotic_energies, dict(p=7, q=3, radius=0.9, form="radius"), {}),
    ("dirichlet_roots", kspec.dirichlet_roots, dict(m=1, radius=0.9, n_roots=2), {}),
    ("dirichlet_levels", kspec.dirichlet_levels, dict(p=7, q=3, radius=0.9, n_max=2, m_max=2), {}),
    ("continuum_levels", kspec.continuum_levels, dict(p=7, q=3, radius=0.9, levels=2), {}),
    ("continuum_levels(rings)", kspec.continuum_levels, dict(p=7, q=3, rings=3, levels=2), {}),
    ("psi_K", kspec.psi_K, dict(z=0.1, k=1.0, beta=0.0), {"z": {"complex"}}),
    ("radial_g", kspec.radial_g, dict(k=1.0, m=1, r=0.5), {}),
    ("continuum_green", kgreen.continuum_green, dict(z=0.1, zp=0.2j, lam=0.5, radius=0.9, tol=1e-12, max_terms=100),
     {"z": {"complex"}, "zp": {"complex"}, "lam": {"complex"}}),
    ("green_laplace", kgreen.green_laplace, dict(z=0.1, zp=0.2j, radius=0.9), {"z": {"complex"}, "zp": {"complex"}}),
    ("green_infinite_disk", kgreen.green_infinite_disk, dict(z=0.1, zp=0.2j, lam=0.5),
     {"z": {"complex"}, "zp": {"complex"}, "lam": {"complex"}}),
    ("fundamental_solution", kgreen.fundamental_solution, dict(z=0.1, zp=0.2j, lam=0.5),
     {"z": {"complex"}, "zp": {"complex"}, "lam": {"complex"}}),
    ("coefficient_cm", kgreen.coefficient_cm, dict(nu=0.5, m=1), {"nu": {"complex"}}),
    ("boundary_constant", kgreen.boundary_constant, dict(lam=0.5), {"lam": {"complex"}}),
    ("magnetic_levels", magnetic.magnetic_levels, dict(p=7, q=3, radius=0.9, levels=2, flux=0.1), {}),
    ("magnetic_roots", magnetic.magnetic_roots, dict(m=1, B=10.0, radius=0.9, n_roots=1), {}),
    ("landau_levels", magnetic.landau_levels, dict(B=10.0), {}),
    ("radial_function", magnetic.radial_function, dict(r=0.5, m=1, B=10.0, kappa=5.0), {}),
    # the dictionary
    ("field_from_flux", dictionary.field_from_flux, dict(f=0.1, p=7, q=3), {}),
    ("flux_from_field", dictionary.flux_from_field, dict(B=1.0, p=7, q=3), {}),
    ("hopping_scale", dictionary.hopping_scale, dict(p=7, q=3), {"p": {"inf"}}),
    ("lambda_from_energy", dictionary.lambda_from_energy, dict(omega=-2.9, p=7, q=3), {"omega": {"complex"}, "p": {"inf"}}),
    ("energy_from_lambda", dictionary.energy_from_lambda, dict(lam=0.5, p=7, q=3), {"lam": {"complex"}, "p": {"inf"}}),
    ("energy_from_k", dictionary.energy_from_k, dict(k=1.0, p=7, q=3), {"k": {"complex"}, "p": {"inf"}}),
    ("green_prefactor", dictionary.green_prefactor, dict(p=7, q=3), {"p": {"inf"}}),
    ("dictionary_parameters", dictionary.dictionary_parameters, dict(omega=-2.9, p=7, q=3), {"omega": {"complex"}}),
    ("disk_radius", dictionary.disk_radius, dict(sites=112, p=7, q=3), {}),
    ("continuum_parameters", dictionary.continuum_parameters, dict(t=1.0, mu=0.5, U=2.0, p=7, q=3), {}),
    ("lattice_parameters", dictionary.lattice_parameters, dict(t_prime=1.0, mu_prime=0.5, U_prime=2.0, p=7, q=3), {}),
    # comparisons
    ("compare_green", cgreen.compare_green, dict(lattice=LAT, omega=-2.95, source=1, tol=1e-12), {"omega": {"complex"}}),
    ("continuum_column", cgreen.continuum_column, dict(lattice=LAT, omega=-2.95, source=1, tol=1e-12),
     {"omega": {"complex"}}),
    ("relative_l2", cgreen.relative_l2, dict(graph=np.ones(3), continuum=np.ones(3), exclude=0), {"exclude": {"none"}}),
    ("correlation_pairs", correlation.correlation_pairs, dict(lattice=LAT, source=1, values=np.ones(LAT.sites)), {}),
    ("bin_by_distance", correlation.bin_by_distance, dict(dist=np.linspace(0, 1, 5), values=np.ones(5), width=0.2),
     {"width": {"none"}}),
    ("collapse_measure", correlation.collapse_measure, dict(dist=np.linspace(0, 1, 5), values=np.ones(5), width=0.2),
     {"width": {"none"}}),
    ("counting_function", sums.counting_function, dict(lattice=LAT, rtol=1e-9), {}),
    ("fit_counting", sums.fit_counting, dict(lattice=glat.ring_lattice(7, 3, 4), slope=14.0, window="all"),
     {"slope": {"none"}}),
    ("disk_integral", sums.disk_integral, dict(f=F, radius=0.5, angular_points=16, rtol=1e-6), {}),
    ("sum_check", sums.sum_check, dict(lattice=LAT, f=F), {}),
    ("frame_angles", scaling.frame_angles, dict(lattice=LAT), {}),
    ("formal_operator", scaling.formal_operator, dict(lattice=LAT, f=F, h=0.1), {"h": {"none"}}),
    ("expansion", scaling.expansion, dict(lattice=LAT, f=F, h=0.1, order=2), {"h": {"none"}}),
    ("expected_error_order", scaling.expected_error_order, dict(q=3, order=2), {}),
    ("convergence_study", scaling.convergence_study, dict(lattice=LAT, f=F, hs=[0.02, 0.04, 0.08]), {"hs": {"none"}}),
    ("radial_profile", scaling.radial_profile, dict(z=LAT.z, values=np.ones(LAT.sites)), {"z": {"complex"}}),
]


@pytest.mark.parametrize("func,good,arg,value", list(api_cases(CASES)))
def test_api_bad_value_gives_valueerror(func, good, arg, value):
    check_api(func, good, arg, value)


def test_every_public_name_is_reachable():
    for name in hl.__all__:
        assert getattr(hl, name) is not None


# ---------------------------------------------------------------------------------------------
# the CLI: one line on stderr and exit code 2 for every bad flag value
# ---------------------------------------------------------------------------------------------

# (subcommand words, flag, values among BAD_CLI that are legitimate for it)
CLI_FLAGS = [
    (["geometry"], "-p", {"inf"}),
    (["geometry"], "-q", set()),
    (["lattice"], "-p", set()),
    (["lattice"], "-q", set()),
    (["lattice"], "--rings", set()),
    (["spectrum", "--rings", "2"], "--levels", set()),
    (["spectrum"], "--rings", set()),
    (["spectrum", "--rings", "2"], "--sector", {"-1", "0"}),
    (["spectrum", "--rings", "2"], "--tol", {"1e22", "3.5"}),
    (["continuum"], "--rings", set()),
    (["continuum"], "--radius", set()),
    (["continuum", "--rings", "3"], "--levels", set()),
    (["green", "--rings", "2"], "--omega", {"-1", "0", "3.5"}),
    (["green", "--rings", "2"], "--site", {"0"}),
    (["green", "--rings", "2"], "--tol", {"1e22"}),
    (["green"], "--rings", set()),
    (["scaling", "angles"], "--rings", set()),
    (["scaling", "operator", "--rings", "2"], "--h", set()),
    (["scaling", "convergence", "--rings", "2"], "--points", set()),
    (["scaling", "convergence", "--rings", "2"], "--h-min", set()),
    (["scaling", "convergence", "--rings", "2"], "--h-max", set()),
    (["scaling", "counting", "--rings", "3"], "--slope", {"-1", "0", "3.5"}),
    (["scaling", "sums"], "--rings", set()),
    (["dictionary"], "--t", {"-1", "0", "3.5", "1e22"}),
    (["dictionary"], "--mu", {"-1", "0", "3.5", "1e22"}),
    (["dictionary"], "--U", {"-1", "0", "3.5", "1e22"}),
    (["reproduce"], "--max-rings", set()),
]


@pytest.mark.parametrize("words,flag,value", list(cli_cases(CLI_FLAGS)))
def test_cli_bad_value_exits_2_with_one_line(words, flag, value, capsys, tmp_path, monkeypatch):
    check_cli(words, flag, value, capsys, tmp_path, monkeypatch)


@pytest.mark.parametrize("words", [
    ["lattice", "--rings", "2", "--out"],
    ["green", "--rings", "2", "--out"],
    ["scaling", "angles", "--rings", "2", "--plot"],
    ["scaling", "counting", "--rings", "3", "--plot"],
    ["reproduce", "--max-rings", "2", "--cache-dir"],
    ["reproduce", "--max-rings", "2", "--out"],
])
@pytest.mark.parametrize("where", ["missing-folder", "directory", "read-only"])
def test_cli_unwritable_paths_exit_2(words, where, capsys, tmp_path, monkeypatch):
    monkeypatch.setenv("HYPERLATTICE_CACHE", str(tmp_path / "cache"))
    locked = tmp_path / "locked"
    locked.mkdir()
    locked.chmod(0o500)
    target = {"missing-folder": tmp_path / "no" / "such" / "file.png",
              "directory": tmp_path,
              "read-only": locked / "file.png"}[where]
    if words[0] == "reproduce" and where == "directory":
        target = tmp_path / "afile"
        target.write_text("not a directory")
    if words[0] == "reproduce" and where == "missing-folder":
        pytest.skip("a missing output folder is created by reproduce")
    if words[0] == "lattice" or words[0] == "green":
        target = target.with_suffix(".csv" if words[0] == "green" else ".npz") if where != "directory" else target
    import os
    if where == "read-only" and os.geteuid() == 0:
        pytest.skip("root can write into read-only folders")
    code = main(words + [str(target)])
    err = capsys.readouterr().err
    assert code == 2, err
    assert len([line for line in err.splitlines() if line.strip()]) == 1, err
