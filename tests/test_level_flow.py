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
    """{8,3} with 8 rings takes the sector-only route: one call into sectors.py, symmetry only for the route."""
    lat = hl.ring_lattice(8, 3, 8)
    spec, n_sectors, n_symmetry, runs = _counts(hl.lowest_levels, lat, 10)
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

    _, n_sectors, n_symmetry, runs = _counts(main, ["spectrum", "-p", "8", "--rings", "8", "--levels", "10"])
    capsys.readouterr()
    assert n_sectors == 1, runs
    assert n_symmetry <= 1, runs


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
        "flake": lambda: hl.lowest_levels(hl.ring_lattice(8, 3, 8), 6),
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
