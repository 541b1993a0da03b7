"""A level request flows down once (issue 28, item 9), followed as data with a profiler.

``trace_modules`` (benchmarks/level_flow.py, the script whose table docs/architecture.md quotes)
runs a call under :func:`sys.setprofile` and counts, for every module of the package, how often the
running code *enters* it: a call whose callee lies in the module and whose nearest calling frame
of the package lies outside it (a maximal run of frames of one module on the stack counts once;
the ``_validate`` guard wrapper of every public function is transparent, and frames without a
caller, the profiler's view of numba-compiled kernels, are skipped).

The design gives: the route (``graph/spectrum.py``) enters ``graph/sectors.py`` once (the
sector-only flake route: build, block builder, solve and assembly behind one call) and
``graph/symmetry.py`` at most twice (once to ask whether V is rotation invariant, which chooses
the route, and once to build every sector block of a built lattice); no lower module calls back
up into the route or the sector modules.
"""

from __future__ import annotations

import importlib.util
from pathlib import Path

import pytest

import hyperlattice as hl

_spec = importlib.util.spec_from_file_location(
    "level_flow", Path(__file__).resolve().parents[1] / "benchmarks" / "level_flow.py")
level_flow = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(level_flow)
trace_modules = level_flow.trace_modules
SECTORS, SYMMETRY = level_flow.SECTORS, level_flow.SYMMETRY


def _counts(func, *args, **kwargs):
    func(*args, **kwargs)          # compile and import first: the traced call is the request alone
    out, entries, runs, _ = trace_modules(func, *args, **kwargs)
    return out, entries.get(SECTORS, 0), entries.get(SYMMETRY, 0), runs


def test_the_tracer_counts_entries_not_internal_calls():
    from hyperlattice.graph import symmetry

    lat = hl.ring_lattice(7, 3, 2)
    _, entries, runs, _ = trace_modules(symmetry.rotation_orbits, lat)
    assert entries.get(SYMMETRY) == 1
    assert runs[0] == SYMMETRY


def test_flake_route_enters_sectors_once():
    """{7,3} with 7 rings (841 orbits) takes the sector-only route: one call into sectors.py, symmetry only
    for the route's question (docs/architecture.md follows the {8,3} flake with 8 rings the same way)."""
    lat = hl.ring_lattice(7, 3, 7)
    spec, n_sectors, n_symmetry, runs = _counts(hl.lowest_levels, lat, 5)
    assert spec.method == "sector-shift-invert"
    assert n_sectors == 1, runs
    assert n_symmetry <= 1, runs


@pytest.mark.parametrize("onsite", [None, 0.25])
def test_sector_route_enters_symmetry_twice_at_most(onsite):
    """The {7,3} flake with 4 rings takes the sector route: all blocks from one call into symmetry.py."""
    lat = hl.ring_lattice(7, 3, 4)
    spec, n_sectors, n_symmetry, runs = _counts(hl.lowest_levels, lat, 6, onsite=onsite)
    assert spec.method == "sector-dense"
    assert n_sectors == 0
    assert n_symmetry <= 2, runs


def test_sector_route_with_eigenvectors_and_flux():
    lat = hl.ring_lattice(7, 3, 3)
    spec, n_sectors, n_symmetry, runs = _counts(hl.lowest_levels, lat, 4, eigenvectors=True, flux=0.1)
    assert spec.eigenvectors is not None
    assert n_sectors == 0
    assert n_symmetry <= 3, runs     # the route's question, the blocks, the lift of the states


def test_cli_spectrum_enters_sectors_once(capsys):
    from hyperlattice.cli import main

    _, n_sectors, n_symmetry, runs = _counts(main, ["spectrum", "-p", "7", "--rings", "7", "--levels", "5"])
    capsys.readouterr()
    assert n_sectors == 1, runs
    assert n_symmetry <= 1, runs


@pytest.mark.slow
def test_mott_gap_comparison_flows_down():
    from hyperlattice.compare.bosons import mott_gap_comparison

    _, n_sectors, n_symmetry, runs = _counts(mott_gap_comparison, hl.ring_lattice(7, 3, 1), [0.0, 0.05])
    assert n_sectors == 0
    assert n_symmetry <= 2, runs


@pytest.mark.parametrize("request_", ["flake", "sector", "flux-vectors", "sparse", "onsite-dense"])
def test_every_call_of_a_level_request_points_down(request_):
    """At run time too, inside graph/ every call goes to an earlier module of INNER_ORDER (no callback up)."""
    from test_layers import INNER_ORDER

    calls = {
        "flake": lambda: hl.lowest_levels(hl.ring_lattice(7, 3, 7), 5),
        "sector": lambda: hl.lowest_levels(hl.ring_lattice(7, 3, 4), 6, onsite=lambda z, ring: 0.1 * ring),
        "flux-vectors": lambda: hl.lowest_levels(hl.ring_lattice(7, 3, 3), 4, eigenvectors=True, flux=0.1),
        "sparse": lambda: hl.lowest_levels(hl.ring_lattice(7, 3, 4), 4, method="sparse"),
        "onsite-dense": lambda: hl.lowest_levels(hl.ring_lattice(7, 3, 3), 4, onsite=lambda z, ring: z.real),
    }
    calls[request_]()
    _, _, _, arrows = trace_modules(calls[request_])
    rank = {f"hyperlattice.graph.{m}": k for k, m in enumerate(INNER_ORDER["graph"])}
    up = sorted(f"{a} -> {b}" for a, b in arrows if a in rank and b in rank and rank[b] > rank[a])
    assert not up, "calls pointing up inside graph/:\n" + "\n".join(up)


# ----------------------------------------------------------------------------
# the route and the plan are pure functions of the request
# ----------------------------------------------------------------------------

def _route(method="auto", *, p=7, sites=5887, kind="sites", levels=5, t=1.0, onsite=None, flux=0.0, sector=None,
           eigenvectors=False, symmetric=True):
    from hyperlattice.graph.spectrum import _choose_route

    return _choose_route(method, p=p, sites=sites, kind=kind, levels=levels, t=t, onsite=onsite, flux=flux,
                         sector=sector, eigenvectors=eigenvectors, symmetric=symmetric)


def test_the_route_is_chosen_from_the_request_alone():
    assert _route() == _route()     # a frozen value: the same request, the same route
    big = _route()
    assert big.flake and big.method == "sector"
    assert not _route(sites=2240).flake                      # 320 orbits: the dense blocks are as fast
    assert _route("shift-invert", sites=2240).flake          # asked for: whenever it applies
    assert not _route(levels=5887 // 2 + 1).flake            # more than half the states
    for plain_breaker in ({"onsite": 0.5}, {"flux": 0.1}, {"sector": 1}, {"eigenvectors": True},
                          {"kind": "line"}, {"t": -1.0}):
        assert not _route(**plain_breaker).flake, plain_breaker
    assert _route(symmetric=False, onsite=1.0, sites=100).method == "dense"
    assert _route(symmetric=False, onsite=1.0, sites=10**5).method == "sparse"
    assert _route("dense").method == "dense" and not _route("dense").flake
    with pytest.raises(ValueError, match="a single sector needs method='sector'"):
        _route("dense", sector=1)
    with pytest.raises(ValueError, match="not invariant under the p-fold rotation"):
        _route("sector", symmetric=False, onsite=1.0)


def test_the_command_line_asks_the_same_rule():
    from hyperlattice.graph.spectrum import _flake_route_applies

    # before any lattice exists, --method shift-invert takes the sector-only route for any number of levels
    assert _flake_route_applies(7, 112, 100, "shift-invert", plain=True, built=False)
    assert not _flake_route_applies(7, 112, 100, "shift-invert", plain=True)
    assert not _flake_route_applies(7, 5887, 5, "sector", plain=True, built=False)
    assert _flake_route_applies(7, 5887, 5, "auto", plain=True, built=False) == \
        _flake_route_applies(7, 5887, 5, "auto", plain=True)


def test_the_sector_only_plan_is_pure():
    from hyperlattice.graph.sectors import _plan_solve

    dims = {"even": 9, "odd": 7, "real": 16}
    plan = _plan_solve(7, 3, 16, 2, dims)
    assert plan.specs == ((0, "even"), (0, "odd"), (1, "real"), (2, "real"), (3, "real"))
    assert plan.start == "pair" and plan.floor_tol > 0
    assert _plan_solve(7, 3, 16, 5, dims).start == "estimate"
    assert [plan.states(s) for s in plan.specs] == [1, 1, 2, 2, 2]
    assert _plan_solve(8, 3, 16, 5, dims).states((4, "real")) == 1      # m = p/2 is its own partner
    assert (0, "odd") not in _plan_solve(7, 3, 16, 5, {**dims, "odd": 0}).specs
    assert plan.dense(400, 1) and not plan.dense(401, 1) and plan.dense(1000, 499)
