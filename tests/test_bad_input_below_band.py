"""Bad input to the massive-scalar, boundary and qubit API and to the ``boundary`` and ``qubits``
commands (harness: tests/badinput.py)."""

from __future__ import annotations

import pytest

from badinput import api_cases, check_api, check_cli, cli_cases
from hyperlattice.compare import boundary as cb
from hyperlattice.compare import qubits as cq
from hyperlattice.continuum import massive as mv
from hyperlattice.graph import qubits as gq
from hyperlattice.graph.lattice import ring_lattice

LAT = ring_lattice(7, 3, 4)
SRC = int(cb.outer_ring(LAT)[0])

# p = inf is the {inf,q} limit the dictionary accepts (dictionary.lambda_from_energy)
CASES = [
    ("mass2_from_lambda", mv.mass2_from_lambda, dict(lam=0.5), {}),
    ("lambda_from_mass2", mv.lambda_from_mass2, dict(m2=0.5), {}),
    ("delta_from_mass2", mv.delta_from_mass2, dict(m2=0.5, branch="plus"), {}),
    ("mass2_from_delta", mv.mass2_from_delta, dict(delta=1.5), {}),
    ("mass2_from_omega", mv.mass2_from_omega, dict(omega=-3.2, p=7, q=3), {"p": {"inf"}}),
    ("omega_from_mass2", mv.omega_from_mass2, dict(m2=1.0, p=7, q=3), {"p": {"inf"}}),
    ("delta_from_omega", mv.delta_from_omega, dict(omega=-3.2, p=7, q=3), {"p": {"inf"}}),
    ("omega_from_delta", mv.omega_from_delta, dict(delta=1.5, p=7, q=3), {"p": {"inf"}}),
    ("bf_bound", mv.bf_bound, dict(p=7, q=3), {}),
    ("conformal_prefactor", mv.conformal_prefactor, dict(delta=1.5), {}),
    ("conformal_two_point", mv.conformal_two_point, dict(z=0.9, zp=-0.9, delta=1.5), {"z": {"complex"},
                                                                                        "zp": {"complex"}}),
    ("boundary_two_point", mv.boundary_two_point, dict(theta=1.0, delta=1.5, eps=0.1, eps_prime=0.1),
     {"eps_prime": {"none"}}),
    ("bulk_to_boundary_kernel", mv.bulk_to_boundary_kernel, dict(z=0.1j, theta=1.0, delta=1.5), {"z": {"complex"}}),
    ("outer_ring", cb.outer_ring, dict(lattice=LAT), {}),
    ("fit_window", cb.fit_window, dict(lattice=LAT, depth=2), {}),
    ("fit_delta", cb.fit_delta, dict(theta=[0.5 + 0.1 * k for k in range(12)], values=[1.0] * 12,
                                     eps=[0.1] * 12, theta_min=0.1), {}),
    ("boundary_correlator", cb.boundary_correlator, dict(lattice=LAT, omega=-3.2, source=SRC, depth=2,
                                                                continuum_disk="whole"),
     {"source": {"none"}}),
    ("boundary_correlator (mass2)", cb.boundary_correlator, dict(lattice=LAT, mass2=1.0, ads_radius=1, source=SRC,
                                                                 systematic=False),
     {"source": {"none"}, "systematic": {"bool"}}),
    ("mass2_in_paper_metric", mv.mass2_in_paper_metric, dict(m2=1.0, ads_radius=1), {}),
    ("delta_formulas", mv.delta_formulas, dict(m2=1.0), {}),
    ("continuum_boundary_column", cb.continuum_boundary_column,
     dict(lattice=LAT, omega=-3.2, source=SRC, targets=[SRC + 1], disk="whole"), {}),
    ("delta_curve", cb.delta_curve, dict(lattice=LAT, omegas=[-3.2], source=SRC, depth=2), {"source": {"none"}}),
    ("lattice_bf_bound", cb.lattice_bf_bound, dict(p=7, q=3, rings=[3]), {}),
    ("bulk_to_boundary", cb.bulk_to_boundary, dict(lattice=LAT, omega=-3.2, source=SRC), {"source": {"none"}}),
    ("qubit_hamiltonian", gq.qubit_hamiltonian, dict(lattice=LAT, sites=[0], omega_q=-3.2, g=0.1, t=1.0), {}),
    ("bound_state", gq.bound_state, dict(lattice=LAT, site=0, omega_q=-3.2, g=0.1, t=1.0, tol=1e-13), {}),
    ("spin_model", gq.spin_model, dict(lattice=LAT, sites=[0, 5], omega_q=-3.2, g=0.1, t=1.0), {}),
    ("exchange_comparison", cq.exchange_comparison, dict(lattice=LAT, omega_q=-3.2, g=0.1, site=0), {}),
    ("bound_state_sizes", cq.bound_state_sizes, dict(lattice=LAT, omegas_q=[-3.2], g=0.1, site=0), {}),
]

CLI_FLAGS = [
    (["boundary", "--rings", "4"], "--rings", set()),
    (["boundary", "--rings", "4"], "--omega", set()),   # -1, 0, 3.5 lie in or above the band
    (["boundary", "--rings", "4"], "--site", set()),
    (["boundary", "--rings", "4"], "--depth", set()),
    (["boundary", "--rings", "4"], "--continuum-disk", set()),
    (["boundary", "--rings", "4", "--ads-radius", "1"], "--mass2", {"0", "3.5"}),   # masses below the band
    (["boundary", "--rings", "4", "--mass2", "1"], "--ads-radius", set()),
    (["qubits", "--rings", "4"], "--rings", set()),
    (["qubits", "--rings", "4"], "--omega-q", set()),
    (["qubits", "--rings", "4"], "--g", {"-1", "3.5"}),    # the sign of g is irrelevant; 3.5 is strong coupling
    (["qubits", "--rings", "4"], "--site", {"0"}),
    (["qubits", "--rings", "4"], "--threshold", {"0"}),
]


@pytest.mark.parametrize("func,good,arg,value", list(api_cases(CASES)))
def test_api_bad_value_gives_valueerror(func, good, arg, value):
    check_api(func, good, arg, value)


@pytest.mark.parametrize("words,flag,value", list(cli_cases(CLI_FLAGS)))
def test_cli_bad_value_exits_2(words, flag, value, capsys, tmp_path, monkeypatch):
    check_cli(words, flag, value, capsys, tmp_path, monkeypatch)


def test_working_calls():
    # the good arguments above do work (so that every failure above is the spoiled argument's)
    for _, func, good, _ in CASES:
        func(**good)
