"""Every public function of every module, probed with bad values (issue 19, item 4).

:func:`badinput.public_functions` walks the package, so a new public function is probed the day
it is written. Each parameter is replaced in turn by each value of :data:`badinput.PROBES`
(None, True, a complex number, NaN, inf, 10**140, -1, a string, a ragged list, an object): the
call must either work or raise a ``ValueError`` (the package's errors are ValueError or
``HyperlatticeError`` subclasses; ``MemoryError`` for a refused size) with a one-line sentence,
never AttributeError, TypeError, OverflowError, ZeroDivisionError, RecursionError, ...

The other arguments come from a working call: the topic files' ``CASES`` where they list the
function, else :data:`GOOD` below by parameter name, else :data:`CALLS` for a function whose
working call needs something specific. Sizes are kept small so that a bad value that is
legitimately accepted (10**140 as a ``max_sites`` cap, say) still runs in milliseconds.
"""

from __future__ import annotations

import inspect

import numpy as np
import pytest

from badinput import probe, public_functions

pytestmark = pytest.mark.filterwarnings("ignore")


def _lat():
    from hyperlattice.graph.lattice import ring_lattice

    return ring_lattice(7, 3, 2)


LAT = _lat()


def _h_and_factor():
    from hyperlattice.graph.factor import factorize

    from hyperlattice import adjacency

    h = -adjacency(LAT).tocsc().astype(float)
    return h, factorize(h, -3.5, positive=True)


H, FACTOR = _h_and_factor()

#: a working value for a required parameter, by its name
GOOD = {
    "B": 10.0, "U": 2.0, "U_prime": 2.0, "a": 0.2j, "angle": 0.3, "b": 0.1 + 0.1j, "beta": 1.0, "center": 0.1,
    "d": 0.3, "delta": 1.5, "e0": -2.9, "energies": [-2.9, -2.8], "energy": -2.9, "eps": 0.1, "flux": 0.1,
    "fluxes": [0.0, 0.1], "g": 0.1, "genus": 2, "h": 0.1, "k": 1.0, "kappa": 5.0, "lam": 0.5, "lattice": LAT,
    "graph": LAT, "system": LAT, "m": 1, "m2": 0.5, "mu": 0.5, "mu_prime": 0.5, "n": 2, "n_max": 6, "nu": 0.5,
    "omega": -2.95, "omega_q": -3.2, "omegas": [-3.2], "omegas_q": [-3.2], "p": 7, "q": 3, "r": 0.5,
    "radius": 0.9, "rings": 2, "ring": 1, "site": 0, "sites": [0, 5], "source": 1, "strength": 1.0,
    "strengths": [1.0], "t": 1.0, "t_prime": 1.0, "theta": 1.0, "variance": 0.01, "x": 2.0, "z": 0.1,
    "zp": 0.2j, "z1": 0.1, "z2": 0.2j, "w": 0.1, "text": "x y X", "task": "probe", "grid": {"x": [1.0]},
    "params": {"x": 1.0}, "walks": [1, 0, 3, 0, 15], "moments": 8, "quantile": 0.5, "scale": 3.0,
    "theta_min": 0.1, "values": np.ones(LAT.sites), "dist": np.linspace(0, 1, LAT.sites), "u": 0.5,
    "key": "fig2", "printed": "1.5", "model": "box", "seed": 0, "realization": 0, "max_rings": 2,
    "n_generators": 2, "relators": ["x^2", "y^3", "(x y)^3"], "generators": [[1, 0, 2], [1, 2, 0]],
    "vectors": [[1.0, 0.0], [0.0, 1.0]], "integrated": [0.0, 1.0], "mirror": "real", "order": 2,
    # report and plot building blocks: a result object they need is left as None (refused: the
    # probes then check that nothing crashes, the topic tests check the working calls)
    # progress=None is refused before the call (a required callback): the report sections take
    # seconds to minutes, and a probe must not run one to its end
    "progress": None, "out": "out", "out_dir": "out", "timings": {}, "records": [],
    "trends": [], "sections": [], "header": [], "name": "x", "caption": "a caption", "func": None,
    "flag": "--out", "obj": 1.0,
}


def _bosons():
    from hyperlattice.bosons.basis import boson_basis
    from hyperlattice.bosons.ed import fock_sectors
    from hyperlattice.graph.lattice import ring_lattice

    hept = ring_lattice(7, 3, 1)
    basis = boson_basis(7, 2, 2)
    psi = np.full(basis.dim, basis.dim ** -0.5)
    return hept, basis, fock_sectors(basis, hept), psi


HEPT, BB, BSEC, BPSI = _bosons()
OCT = __import__("hyperlattice.graph.lattice", fromlist=["x"]).ring_lattice(8, 3, 1)
_BB = dict(sites=7, particles=2, nmax=2)
_BED = "hyperlattice.bosons.ed."

#: working calls that must stay cheap (small sizes), by qualified name, and probes they skip
#: because the bad value is a legitimate one there (a string is a path)
CALLS = {
    "hyperlattice.sweep.engine.run_sweep": (
        dict(task="probe", grid={"x": [1.0]}, path="sw", scheduler="serial", retries=0, progress=False),
        {("path", "str")}),
    "hyperlattice.report.reproduce": (dict(out_dir="out", max_rings=2), {("out_dir", "str")}),
    # a 7-qubit XY check: 300 sweeps are enough to exercise it (the default 4000 is the docs' run)
    "hyperlattice.compare.qmc_lobe.xy_qubit_check": (dict(sweeps=300), set()),
    "hyperlattice.report.below_band.delta_scaling": (
        dict(out=None, rings=[2], omegas=[-3.2], bf_rings=[3]), {("out", "str")}),
    "hyperlattice.compare.magnetic.magnetic_comparison": (dict(p=7, q=3, rings=[2], fluxes=[0.1], levels=1), set()),
    "hyperlattice.compare.levels.continuum_labels": (
        dict(spectrum=__import__("hyperlattice.graph.spectrum", fromlist=["x"]).lowest_levels(LAT, 3),
             radius=0.8, dictionary="paper"), set()),
    # every argument has a default, but the defaults are the report's sizes (rings 3-7, 800 cells:
    # seconds per call, and tens of seconds under load for an accepted filling=10**140)
    "hyperlattice.compare.bosons.gp_comparison": (dict(rings=(2,), modes=3, cells=200), set()),
    "hyperlattice.bosons.meanfield.mott_lobes": (dict(rings=(2,), points=21), set()),  # default: 7 flakes to l = 12
    "hyperlattice.graph.factor.analyze": (dict(mat=H), set()),
    "hyperlattice.graph.factor.factorize": (dict(mat=H, sigma=-3.5), set()),
    "hyperlattice.graph.factor.lowest_eigenpairs": (dict(mat=H, k=2), set()),
    "hyperlattice.graph.factor.shift_invert_lowest": (dict(mat=H, k=2, factor=FACTOR, tol=1e-10, label="H"), set()),
    "hyperlattice.cli.main": (dict(argv=["geometry"]), {("argv", "none")}),  # None: the process's own argv
    # issue 22, Bose-Hubbard ED: a 7-site heptagon with 2 bosons (28 states)
    "hyperlattice.bosons.basis.basis_dimension": (_BB, set()),
    "hyperlattice.bosons.basis.basis_memory": (_BB, set()),
    "hyperlattice.bosons.basis.boson_basis": (_BB, set()),
    "hyperlattice.bosons.basis.rank_states": (dict(basis=BB, occupations=[1, 1, 0, 0, 0, 0, 0]), set()),
    "hyperlattice.bosons.basis.unrank_states": (dict(basis=BB, indices=[0, 3]), set()),
    _BED + "bose_hubbard_graph": (dict(lattice=HEPT), set()),
    _BED + "hamiltonian": (dict(basis=BB, lattice=HEPT, U=2.0), set()),
    _BED + "hamiltonian_operator": (dict(basis=BB, lattice=HEPT, U=2.0), set()),
    _BED + "fock_sectors": (dict(basis=BB, lattice=HEPT), set()),
    _BED + "sector_block": (dict(basis=BB, lattice=HEPT, sectors=BSEC, m=1, U=2.0), set()),
    _BED + "lift_sector_vector": (dict(sectors=BSEC, m=1, phi=np.ones(BSEC.dim(1))), set()),
    _BED + "bose_hubbard": (dict(lattice=HEPT, particles=2, nmax=2, U=2.0, levels=2), set()),
    _BED + "charge_gap": (dict(lattice=HEPT, particles=2, nmax=2, U=2.0), set()),
    _BED + "density_profile": (dict(basis=BB, psi=BPSI), set()),
    _BED + "one_body_density_matrix": (dict(basis=BB, psi=BPSI), set()),
    _BED + "condensate_fraction": (dict(rho=np.eye(7) * 2 / 7, particles=2), set()),
    _BED + "correlation_vs_distance": (dict(rho=np.eye(7), distance=np.ones((7, 7)), width=0.5), set()),
    # issue 27: the exact thermal reference (hard-core heptagon, 128 states) and the QMC memory estimate
    "hyperlattice.bosons.thermal.exact_thermal": (dict(system=HEPT, U=2.0, mu=0.5, beta=1.0, nmax=1), set()),
    "hyperlattice.bosons.thermal.sector_dimensions": (dict(rotation=[1, 2, 3, 0], nmax=1), set()),
    "hyperlattice.bosons.sse.qmc_memory": (dict(system=HEPT, U=2.0, mu=0.5, beta=1.0, nmax=1), set()),
    # classical spins: a short chain on the 35-site flake (the default 10000 sweeps is a real run)
    "hyperlattice.spins.classical.classical_mc": (dict(system=LAT, model="ising", beta=1.0, sweeps=200), set()),
    "hyperlattice.spins.classical.classical_mc_memory": (dict(system=LAT, model="ising"), set()),
    "hyperlattice.bosons.sse.qmc_seconds": (dict(system=HEPT, U=2.0, mu=0.5, beta=1.0, nmax=1), set()),
    # the spin-1/2 XXZ model: the octagon (8 spins, bipartite), short chains
    "hyperlattice.spins.quantum.xxz_qmc": (dict(system=OCT, J=1.0, Delta=1.0, beta=1.0, sweeps=200), set()),
    "hyperlattice.spins.quantum.xxz_exact": (dict(system=OCT, J=1.0, Delta=1.0, beta=1.0), set()),
    # the SCBA of the topological Anderson insulator on the 35-site flake
    "hyperlattice.topology.anderson.scba": (dict(graph=LAT, M=1.6, disorder=[1.0]), set()),
    "hyperlattice.topology.anderson.scba_boundary": (dict(graph=LAT, masses=[1.6], critical_mass=1.42), set()),
}


def _collect_cases():
    """The working calls the topic files already list: {function: kwargs}."""
    import importlib

    calls = {}
    for name in ["test_bad_input", "test_bad_input_below_band", "test_bad_input_bigflakes",
                 "test_bad_input_clusters", "test_bad_input_disorder", "test_bad_input_dos",
                 "test_bad_input_limits", "test_bad_input_topology", "test_bad_input_topology_closed"]:
        for _, func, good, _ in importlib.import_module(name).CASES:
            calls.setdefault(inspect.unwrap(func), good)
    return calls


CASES = _collect_cases()
FUNCTIONS = public_functions()


#: modules whose accepted calls run the SSE kernels: on a fresh clone (empty numba cache) the
#: first call compiles them, seconds of CPU that the probe's limit must not charge to a bad value
JIT_MODULES = ("hyperlattice.bosons.sse.", "hyperlattice.compare.qmc_lobe.", "hyperlattice.bosons.strong_coupling.",
               "hyperlattice.spins.quantum.")


def _compile_sse_kernels():
    import warnings

    from hyperlattice.bosons import qmc
    from hyperlattice.graph.lattice import ring_lattice

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        qmc(ring_lattice(7, 3, 1), U=4.0, mu=1.0, beta=1.0, nmax=2, sweeps=20, seed=1, progress=False)
        from hyperlattice.spins.quantum import xxz_qmc

        xxz_qmc(ring_lattice(8, 3, 1), J=1.0, Delta=1.0, beta=1.0, sweeps=20, seed=1, progress=False)


def good_call(func) -> dict:
    target = inspect.unwrap(func)
    qual = f"{target.__module__}.{target.__qualname__}"
    if qual in CALLS:
        return dict(CALLS[qual][0])
    if target in CASES:
        return dict(CASES[target])
    good = {}
    for par in inspect.signature(func).parameters.values():
        if par.default is par.empty and par.kind not in (par.VAR_POSITIONAL, par.VAR_KEYWORD):
            good[par.name] = GOOD.get(par.name)
    return good


@pytest.mark.parametrize("name", list(FUNCTIONS))
def test_public_function_refuses_bad_values_with_a_sentence(name, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv("HYPERLATTICE_CACHE", str(tmp_path / "cache"))
    func = FUNCTIONS[name]
    skip = CALLS.get(name, ({}, set()))[1]
    if name.startswith(JIT_MODULES):
        _compile_sse_kernels()  # numba's first compile (~10 s of CPU on a fresh clone) is not the call's work
    failures = probe(func, good_call(func), skip=skip)
    import sys

    if "matplotlib.pyplot" in sys.modules:  # the plot probes that work leave figures open
        sys.modules["matplotlib.pyplot"].close("all")
    assert not failures, f"{name}:\n  " + "\n  ".join(failures)


def test_the_probe_sees_a_crash_and_the_guard_turns_it_into_a_sentence():
    from hyperlattice import _validate

    def unguarded(x: int, flag: bool = False) -> int:
        return x + 1

    failures = probe(unguarded, {"x": 1})
    assert any("x=none: TypeError" in f for f in failures)
    assert any("flag" in f for f in failures) is False  # flag is ignored by the body: no crash to see
    guarded = _validate.guard(unguarded)
    assert probe(guarded, {"x": 1}) == []
    with pytest.raises(ValueError, match="flag must be True or False"):
        guarded(1, flag=0)


def test_the_probe_limit_counts_cpu_time_not_waiting():
    """The probe's time limit is this process's CPU time (issue 28, item 7): a call that waits
    (here it sleeps; on a loaded machine it waits for a core) is not cut off however long the
    wait, a call that computes is. With a wall-clock limit the gp_comparison probe failed in a
    full run on the shared 2-core machine and passed when run alone later."""
    import time

    from badinput import PROBES

    only_negative = {("x", tag) for tag in PROBES if tag != "negative"}

    def waits(x: int) -> int:
        time.sleep(0.5)
        return x

    def computes(x: int) -> int:
        while True:
            x += 1

    assert probe(waits, {"x": 1}, seconds=0.1, skip=only_negative) == []
    assert probe(computes, {"x": 1}, seconds=0.1, skip=only_negative) == [
        "x=negative: still running after 0.1 s of CPU time"]


def test_the_walk_finds_every_public_module():
    # the harness walked ~80 functions before issue 19; every module's public functions now
    mods = {name.rsplit(".", 1)[0] for name in FUNCTIONS}
    for expected in ("hyperlattice.geometry", "hyperlattice.graph.flux", "hyperlattice.plots.paper",
                     "hyperlattice.report.writers", "hyperlattice.sweep.engine", "hyperlattice.cli"):
        assert expected in mods
    assert len(FUNCTIONS) > 300
