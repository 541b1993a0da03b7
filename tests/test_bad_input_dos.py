"""Bad input for the densities of states (issue 12, part 3): KPM, closed walks, the comparison, the dos CLI."""

from __future__ import annotations

import numpy as np
import pytest

from badinput import api_cases, check_api, check_cli, cli_cases
from hyperlattice.compare import dos as cdos
from hyperlattice.graph import kpm, walks
from hyperlattice.graph.lattice import ring_lattice

LAT = ring_lattice(7, 3, 3)
RES = kpm.kpm_dos(LAT, 8, vectors=3)

# (id, function, working keyword arguments, {argument: tags it legitimately accepts})
CASES = [
    ("kpm_dos", kpm.kpm_dos, dict(graph=LAT, moments=8, vectors=2, seed=0, kind="rademacher", deflate=False,
                                  parallel=False), {"deflate": {"bool"}, "parallel": {"bool"}}),
    ("local_dos", kpm.local_dos, dict(graph=LAT, site=0, moments=8), {}),
    ("bulk_dos", kpm.bulk_dos, dict(lattice=LAT, moments=8, exclude=1, vectors=2, seed=0, kind="phase"),
     {"moments": {"none"}, "exclude": {"none"}}),
    ("jackson_kernel", kpm.jackson_kernel, dict(moments=8), {}),
    ("graph_operator", kpm.graph_operator, dict(graph=LAT), {}),
    ("spectral_bound", kpm.spectral_bound, dict(graph=LAT), {}),
    ("KPMDos.density", RES.density, dict(energies=[0.0, 1.0]), {"energies": {"none"}}),
    ("KPMDos.integrated", RES.integrated, dict(energies=[0.0, 1.0]), {"energies": {"none"}}),
    ("KPMDos.kernel_width", RES.kernel_width, dict(energy=0.5), {}),
    ("KPMDos.energy_grid", RES.energy_grid, dict(points=5), {"points": {"none"}}),
    ("closed_walks", walks.closed_walks, dict(p=7, q=3, n_max=6), {}),
    ("exact_depth", walks.exact_depth, dict(rings=3, ring=1), {}),
    ("exact_depths", walks.exact_depths, dict(lattice=LAT), {}),
    ("boundary_distance", walks.boundary_distance, dict(lattice=LAT, site=0), {"site": {"none"}}),
    ("rings_for_walks", walks.rings_for_walks, dict(p=7, q=3, n_max=6), {}),
    ("chebyshev_from_walks", walks.chebyshev_from_walks, dict(walks=[1, 0, 3], scale=3.0, sign=-1), {}),
    ("spectral_radius_bounds", walks.spectral_radius_bounds, dict(walks=[1, 0, 3, 0, 15]), {}),
    ("spectral_radius", walks.spectral_radius, dict(p=7, q=3, n_max=8), {}),
    ("isoperimetric_upper_bound", walks.isoperimetric_upper_bound, dict(p=7, q=3), {"p": {"inf"}}),
    ("continuum_dos", cdos.continuum_dos, dict(energies=[-2.9], p=7, q=3, dictionary_name="paper"), {}),
    ("continuum_integrated_dos", cdos.continuum_integrated_dos,
     dict(energies=[-2.9], p=7, q=3, dictionary_name="improved"), {}),
    ("jackson_density", cdos.jackson_density, dict(mu=[1.0, 0.0], scale=3.0, energies=[0.0]), {}),
    ("quantile_energy", cdos.quantile_energy, dict(energies=[0.0, 1.0], integrated=[0.0, 1.0], quantile=0.5), {}),
    ("dos_comparison", cdos.dos_comparison,
     dict(p=7, q=3, clusters=["klein"], rings=[3], moments=16, resolution=8, vectors=3, seed=0, quantile=1e-3,
          abelian=False, abelian_samples=8, quantile_moments=16, walk_length=8),
     {"clusters": {"none"}, "rings": {"none"}, "quantile_moments": {"none"}, "abelian": {"bool"}}),
]


@pytest.mark.parametrize("func,good,arg,value", list(api_cases(CASES)))
def test_api(func, good, arg, value):
    check_api(func, good, arg, value)


BASE = ["dos", "--moments", "8", "--vectors", "2"]
CLI_FLAGS = [
    (BASE, "-p", set()),
    (BASE, "-q", set()),
    (BASE, "--rings", set()),
    (["dos", "--vectors", "2", "--rings", "3"], "--moments", set()),
    (["dos", "--moments", "8", "--rings", "3"], "--vectors", set()),
    (BASE + ["--rings", "3"], "--seed", {"0"}),
    (BASE + ["--rings", "3"], "--exclude", set()),
    (BASE + ["--rings", "3"], "--site", {"0"}),
    (BASE + ["--rings", "3"], "--points", set()),
    (BASE, "--cluster", set()),
    (BASE + ["--rings", "3"], "--out", {"0", "-1", "1e22", "3.5", "nan", "inf", "abc", "1e400"}),
    (BASE + ["--rings", "3"], "--plot", set()),
]


@pytest.mark.parametrize("words,flag,value", list(cli_cases(CLI_FLAGS)))
def test_cli(words, flag, value, capsys, tmp_path, monkeypatch):
    check_cli(words, flag, value, capsys, tmp_path, monkeypatch)


def test_bad_graphs_and_sizes(monkeypatch):
    with pytest.raises(ValueError):
        kpm.kpm_dos(np.zeros((3, 0), dtype=int))
    with pytest.raises(ValueError):
        kpm.bulk_dos(LAT, exclude=3)  # nothing left to trace
    with pytest.raises(ValueError):
        walks.chebyshev_from_walks([1, -2], 3.0)
    with pytest.raises(ValueError):
        walks.chebyshev_from_walks([1, 2], 3.0, sign=0)
    with pytest.raises(ValueError):
        cdos.dos_comparison(7, 3, clusters="klein")
