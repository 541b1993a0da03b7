"""Bad input to the disorder, SCBA and sweep API and to the ``disorder`` and ``sweep`` commands
(harness: tests/badinput.py)."""

from __future__ import annotations

import pytest

from badinput import api_cases, check_api, check_cli, cli_cases
from hyperlattice.compare import disorder as cdis
from hyperlattice.continuum import scba as kscba
from hyperlattice.graph import disorder as gdis
from hyperlattice.graph.lattice import ring_lattice
from hyperlattice import sweep

LAT = ring_lattice(7, 3, 2)
DIS = gdis.disorder(LAT, "box", 1.0)


def _sweep(**kw):
    return sweep.run_sweep(**kw)


CASES = [
    ("disorder", gdis.disorder, dict(lattice=LAT, model="box", strength=1.0, seed=0, realization=0), {}),
    ("disorder_resonator", gdis.disorder, dict(lattice=LAT, model="box", strength=1.0, omega0=None),
     {"omega0": {"none"}}),
    ("disordered_hamiltonian", gdis.disordered_hamiltonian, dict(lattice=LAT, dis=DIS, t=1.0), {}),
    ("onsite_variance", gdis.onsite_variance, dict(model="box", strength=1.0), {}),
    ("realization_rng", gdis.realization_rng, dict(seed=0, realization=1), {}),
    ("spacing_ratios", cdis.spacing_ratios, dict(energies=[0.0, 1.0, 3.0], window=(0.0, 2.0)), {"window": {"none"}}),
    ("realization_observables", cdis.realization_observables,
     dict(lattice=LAT, model="box", strength=1.0, seed=0, realization=0, windows=None, dos_bins=10, ipr=False),
     {"windows": {"none"}, "ipr": {"bool"}}),
    ("disorder_ensemble", cdis.disorder_ensemble,
     dict(lattice=LAT, strength=1.0, realizations=2, seed=0, model="box", dos_bins=10), {}),
    ("r_scan", cdis.r_scan, dict(lattice=LAT, strengths=[1.0], realizations=2, seed=0, window=(-1.0, 1.0)),
     {"window": {"none"}}),
    ("green_ensemble", cdis.green_ensemble,
     dict(lattice=LAT, omega=-2.9 + 0.2j, strength=0.5, realizations=2, seed=0, source=0), {"omega": {"complex"}}),
    ("graph_scba", cdis.graph_scba, dict(lattice=LAT, omega=-2.9 + 0.2j, variance=0.01), {"omega": {"complex"}}),
    ("compare_scba", cdis.compare_scba,
     dict(lattice=LAT, omega=-2.9 + 0.2j, strengths=[0.5], realizations=2, seed=0, source=0),
     {"omega": {"complex"}}),
    ("continuum_local_green", kscba.continuum_local_green, dict(omega=-2.9 + 0.1j, p=7, q=3), {"omega": {"complex"}}),
    ("scba", kscba.scba, dict(omega=-2.9 + 0.1j, variance=0.01, p=7, q=3, max_iter=100), {"omega": {"complex"}}),
    ("band_cutoff", kscba.band_cutoff, dict(p=7, q=3), {}),
    ("expand_grid", sweep.expand_grid, dict(task="probe", grid={"x": [1.0]}), {}),
    ("run_sweep", _sweep, dict(task="probe", grid={"x": [1.0]}, path="/nonexistent-dir/\0x", scheduler="serial",
                               retries=0, progress=False),
     {"path": set()}),
    ("read_table", sweep.read_table, dict(path="/nonexistent/sweep"), {}),
]


@pytest.mark.parametrize("func,good,arg,value", list(api_cases(CASES)))
def test_api_bad_value_gives_valueerror(func, good, arg, value):
    check_api(func, good, arg, value)


def test_more_bad_values():
    with pytest.raises(ValueError, match="omega must have a positive imaginary part"):
        cdis.green_ensemble(LAT, -2.9, 1.0)
    with pytest.raises(ValueError, match="drawn for another lattice"):
        gdis.disordered_hamiltonian(ring_lattice(7, 3, 3), DIS)
    with pytest.raises(ValueError, match="no parameter 'y'"):
        sweep.expand_grid("probe", {"y": [1]})
    with pytest.raises(ValueError, match="task"):
        sweep.expand_grid("nope", {})
    with pytest.raises(ValueError, match="dense computation"):
        sweep.expand_grid("disorder", {"rings": [9]})
    with pytest.raises(ValueError, match="address"):
        sweep.run_sweep("probe", {"x": 1.0}, "/tmp", scheduler="not an address", progress=False)
    with pytest.raises(ValueError, match="hopping disorder has no on-site variance"):
        gdis.onsite_variance("hopping", 1.0)


RUN = ["sweep", "--task", "probe", "--grid", "x=1", "--out", "sw", "--scheduler", "serial", "--no-progress"]
CLI_FLAGS = [
    (["disorder", "--rings", "2", "--realizations", "1"], "--W", {"0", "3.5", "1e22"}),
    (["disorder"], "--rings", set()),
    (["disorder", "--rings", "2"], "--realizations", set()),
    (["disorder", "--rings", "2", "--realizations", "1"], "--seed", {"0"}),
    (["disorder", "--rings", "2", "--line-graph", "--model", "resonator", "--W", "1e-3", "--realizations", "1"],
     "--omega0", {"3.5", "1e22"}),
    (["disorder", "--rings", "2"], "-p", set()),
    (["sweep", "--task", "probe", "--out", "sw", "--scheduler", "serial"], "--grid", set()),
    (RUN, "--workers", set()),
    (RUN, "--retries", {"0"}),
    (RUN, "--timeout", {"3.5", "1e22"}),
    (["sweep", "--task", "probe", "--grid", "x=1", "--out", "sw"], "--scheduler", set()),
    (["sweep", "--grid", "x=1", "--out", "sw", "--scheduler", "serial"], "--task", set()),
]


@pytest.mark.parametrize("words,flag,value", list(cli_cases(CLI_FLAGS)))
def test_cli_bad_value_exits_2_with_one_line(words, flag, value, capsys, tmp_path, monkeypatch):
    check_cli(words, flag, value, capsys, tmp_path, monkeypatch)
