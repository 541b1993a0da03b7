"""Bad input to the infinite-lattice analysis (issue 13): the improved dictionary, the
``dictionary=`` keyword, compare.limits and ``continuum --dictionary`` (harness: tests/badinput.py)."""

from __future__ import annotations

import pytest

from badinput import api_cases, check_api, check_cli, cli_cases
from hyperlattice import dictionary
from hyperlattice.compare import limits
from hyperlattice.continuum import spectrum as kspec

E0 = [-2.8466330868164005, -2.876770661107686, -2.894196944768138, -2.9052530439235205, -2.9127439314844312]
E1 = [-2.762158410466457, -2.827091460001197, -2.862642575029471, -2.8840139114531094, -2.8977878752036372]

CASES = [
    ("spherical_function", dictionary.spherical_function, dict(lam=1.5, d=0.3), {}),
    ("spherical_mean_energy", dictionary.spherical_mean_energy, dict(lam=1.5, q=3, h=0.2), {}),
    ("improved_energy_from_lambda", dictionary.improved_energy_from_lambda, dict(lam=1.5, p=7, q=3), {"p": {"inf"}}),
    ("improved_energy_from_k", dictionary.improved_energy_from_k, dict(k=0.5, p=7, q=3), {"p": {"inf"}}),
    ("improved_lambda_from_energy", dictionary.improved_lambda_from_energy, dict(energy=-2.9, p=7, q=3), {"p": {"inf"}}),
    ("improved_lambda_of_frequency", dictionary.improved_lambda_of_frequency, dict(omega=-3.5, p=7, q=3), {"p": {"inf"}}),
    ("improved_band_bottom", dictionary.improved_band_bottom, dict(p=7, q=3), {"p": {"inf"}}),
    ("dirichlet_radius_shift", dictionary.dirichlet_radius_shift, dict(p=7, q=3), {}),
    ("improved_disk_for_rings", dictionary.improved_disk_for_rings, dict(rings=4, p=7, q=3), {}),
    ("map_energy_from_k", dictionary.map_energy_from_k, dict(k=0.5, p=7, q=3, dictionary="improved"), {"p": {"inf"}}),
    ("continuum_levels(dictionary)", kspec.continuum_levels,
     dict(p=7, q=3, rings=3, levels=2, dictionary="improved"), {}),
    ("level_energy(dictionary)", kspec.level_energy, dict(k=0.5, p=7, q=3, dictionary="improved"), {}),
    ("energy_infinity(dictionary)", kspec.energy_infinity, dict(p=7, q=3, dictionary="improved"), {}),
    ("dirichlet_levels(dictionary)", kspec.dirichlet_levels,
     dict(p=7, q=3, rings=3, n_max=1, m_max=1, dictionary="improved"), {}),
    ("reference_levels", limits.reference_levels, dict(p=7, q=3), {}),
    ("flake_levels", limits.flake_levels, dict(p=7, q=3, rings=[2, 3], cache=None), {"cache": {"none"}}),
    ("fit_band_bottom", limits.fit_band_bottom,
     dict(rings=[4, 5, 6, 7, 8], energies=E0, p=7, q=3, level=0, model="rational"), {}),
    ("band_bottom", limits.band_bottom,
     dict(p=7, q=3, rings=[4, 5, 6, 7, 8], E0=E0, E1=E1, schur_window=None, max_rings=None),
     {"schur_window": {"none"}, "max_rings": {"none"}, "rings": {"none"}, "E0": {"none"}, "E1": {"none"}}),
    ("schur_bound", limits.schur_bound, dict(p=7, q=3, window=0, rings=6), {"rings": {"none"}}),
    ("compare_dictionaries", limits.compare_dictionaries,
     dict(rings=[4, 5], E0=E0[:2], E1=E1[:2], p=7, q=3, band=None), {"band": {"none"}}),
]

CLI_FLAGS = [
    (["continuum", "--rings", "3"], "--dictionary", set()),
]




@pytest.mark.parametrize("func,good,arg,value", list(api_cases(CASES)))
def test_api(func, good, arg, value):
    check_api(func, good, arg, value)


@pytest.mark.parametrize("words,flag,value", list(cli_cases(CLI_FLAGS)))
def test_cli(words, flag, value, capsys, tmp_path, monkeypatch):
    check_cli(words, flag, value, capsys, tmp_path, monkeypatch)


def test_band_bottom_needs_six_flakes():
    with pytest.raises(ValueError, match="at least 6 flakes"):
        limits.band_bottom(7, 3, [4, 5, 6, 7, 8], E0, E1, schur_window=None)


def test_improved_energy_outside_branch():
    with pytest.raises(ValueError, match="outside the range"):
        dictionary.improved_lambda_from_energy(-3.5)


def test_improved_flux_refused(capsys):
    from hyperlattice.cli import main

    assert main(["continuum", "--rings", "3", "--flux", "0.1", "--dictionary", "improved"]) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and "zero field" in err


def test_schur_window_memory_refused_before_allocating():
    with pytest.raises(ValueError, match="GB of ring words"):
        limits.schur_bound(7, 3, window=256, rings=13)


def test_plateau_needs_band():
    with pytest.raises(ValueError, match="BandBottom"):
        limits.plateau_analysis(object())
