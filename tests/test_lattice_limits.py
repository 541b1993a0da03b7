"""Sizes, bounds and bad input of the lattice builder: refused at once, before allocating."""

import json
import os
import time
import tracemalloc
from pathlib import Path

import numpy as np
import pytest

from hyperlattice.cli import main
from hyperlattice.graph import lattice as L
from hyperlattice.graph.lattice import edge_count, line_graph, ring_lattice, ring_sizes, site_count


def _refused_cost(fn, *args, match: str = "sites", **kwargs):
    """(seconds, peak traced bytes) of a call that must raise ValueError."""
    tracemalloc.start()
    t = time.perf_counter()
    try:
        with pytest.raises(ValueError, match=match):
            fn(*args, **kwargs)
        return time.perf_counter() - t, tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()


# ----------------------------------------------------------------------------
# counting
# ----------------------------------------------------------------------------

@pytest.mark.parametrize("p, q, rings", [(7, 3, 9), (8, 3, 8), (9, 3, 7), (4, 5, 7), (5, 4, 7), (3, 7, 9),
                                         (3, 8, 7), (3, 12, 5), (4, 6, 5), (6, 4, 5), (5, 5, 5), (3, 130, 3)])
def test_counts_match_explicit_construction(p, q, rings):
    # the type recursion (now also for p = 3, which used to be counted explicitly and then
    # extrapolated) against the array construction of every ring
    explicit = L._ring_counts(p, q, rings, max_spokes=10**7)
    assert len(explicit) == rings
    assert ring_sizes(p, q, rings).tolist() == explicit


@pytest.mark.parametrize("p, q, rings", [(7, 3, 8), (3, 7, 6), (4, 5, 5), (8, 3, 6), (5, 4, 5), (3, 9, 4)])
def test_edge_count_matches_built_lattice(p, q, rings):
    assert edge_count(p, q, rings) == ring_lattice(p, q, rings).edges.shape[0]


def test_counts_beyond_int64_are_refused():
    assert site_count(7, 3, 43) == 6577109941848143887  # the largest {7,3} that fits in int64
    t, peak = _refused_cost(ring_sizes, 7, 3, 44, match="2\\*\\*63")
    assert t < 0.5 and peak < 1e6
    # used to run an O(rings^2) big-integer loop (and then overflow); now stops at once
    t, peak = _refused_cost(site_count, 3, 7, 10**9, match="2\\*\\*63")
    assert t < 0.5 and peak < 1e6
    with pytest.raises(ValueError, match="edges"):
        edge_count(7, 3, 10**6)


# ----------------------------------------------------------------------------
# ring_lattice: refused before allocating
# ----------------------------------------------------------------------------

@pytest.mark.parametrize("rings", [41, 44, 1000, 10**5, 10**6, 1e22, 1e308])
def test_huge_lattices_refused_at_once(rings):
    # regression: 44 .. 1e5 rings raised OverflowError; 1e6, 1e22 and 1e308 rings counted
    # sites with ever larger integers before the size check (10 GB after 35 s)
    # beyond int64 the door refuses the count itself (issue 19: every integer fits int64 unless
    # a function says otherwise); below, the size estimate refuses the number of sites
    match = "sites" if rings < 2**63 else "rings must be at most"
    t, peak = _refused_cost(ring_lattice, 7, 3, rings, match=match)
    assert t < 0.5 and peak < 1e6


@pytest.mark.parametrize("p, q, rings", [(3, 7, 10**6), (3, 10**6, 3), (4, 5, 10**4), (10**5, 3, 4),
                                         (2**20, 2**20, 2)])
def test_other_families_refused_at_once(p, q, rings):
    t, peak = _refused_cost(ring_lattice, p, q, rings)
    assert t < 0.5 and peak < 1e6


def test_refusal_message_states_the_limit():
    with pytest.raises(ValueError, match=r"more than max_sites allows \(limit 1,000 sites\)"):
        ring_lattice(7, 3, 6, max_sites=1000)
    with pytest.raises(ValueError, match=r"has more than .* sites"):
        ring_lattice(7, 3, 10**6, max_sites=1000)
    with pytest.raises(ValueError, match="32-bit"):
        ring_lattice(7, 3, 30, max_sites=10**12)


@pytest.mark.parametrize("q", [130, 1000])
def test_large_q_builds(q):
    # regression: q > 127 overflowed the int8 polygon counter (OverflowError)
    lat = ring_lattice(3, q, 2)
    assert lat.sites == 3 + 3 * (q - 3)
    assert lat.degree.max() == q
    lat = ring_lattice(7, q, 1)
    assert lat.sites == 7


@pytest.mark.parametrize("p, q", [(3, 2**31), (2**31, 3), (3, 10**30)])
def test_p_q_beyond_32_bits_refused(p, q):
    # p, q <= 10**9 (_validate.PQ_MAX, issue 19) is tighter than the builder's 32-bit bound
    with pytest.raises(ValueError, match="at most 1,000,000,000"):
        ring_lattice(p, q, 1)
    with pytest.raises(ValueError, match="at most"):
        ring_sizes(p, q, 2)


@pytest.mark.parametrize("bad", [float("nan"), float("inf"), 0, -5, 2.5, "100", True, None, 1j])
def test_bad_max_sites(bad):
    # regression: max_sites=nan was accepted
    if bad is None:
        ring_lattice(7, 3, 2, max_sites=bad)
        return
    with pytest.raises(ValueError, match="max_sites"):
        ring_lattice(7, 3, 2, max_sites=bad)


# ----------------------------------------------------------------------------
# line graphs
# ----------------------------------------------------------------------------

@pytest.mark.parametrize("bad", [None, "lattice", 3, np.zeros(3)])
def test_line_graph_of_a_non_lattice(bad):
    # regression: line_graph(None) raised AttributeError
    with pytest.raises(ValueError, match="Lattice"):
        line_graph(bad)


def test_line_graph_of_a_line_graph():
    with pytest.raises(ValueError, match="site lattice"):
        line_graph(line_graph(ring_lattice(7, 3, 2)))


def test_line_graph_size_is_checked_before_allocating():
    lat = ring_lattice(7, 3, 6)
    t, peak = _refused_cost(line_graph, lat, max_sites=1000, match="limit 1,000 sites")
    assert t < 0.5 and peak < 1e5
    assert line_graph(lat, max_sites=lat.edges.shape[0]).sites == lat.edges.shape[0]
    with pytest.raises(ValueError, match="max_sites"):
        line_graph(lat, max_sites=float("nan"))


def test_line_graph_refused_by_memory(monkeypatch):
    lat = ring_lattice(7, 3, 6)
    monkeypatch.setattr(L, "_available_memory", lambda: 10**6)
    with pytest.raises(ValueError, match="more than this process may allocate"):
        line_graph(lat)
    # the CLI refuses before it builds the parent lattice
    with pytest.raises(ValueError, match="line graph"):
        L._check_line_graph_fits(7, 3, 6)


def test_line_graph_fits_precheck_matches_size():
    assert L._check_line_graph_fits(7, 3, 6) == ring_lattice(7, 3, 6).edges.shape[0]


# ----------------------------------------------------------------------------
# the CLI: one line, exit 2, no traceback, at once
# ----------------------------------------------------------------------------

@pytest.mark.parametrize("argv", [
    ["lattice", "--rings", "44"],
    ["lattice", "--rings", "100000"],
    ["lattice", "--rings", "1000000"],
    ["lattice", "--rings", "1e22"],
    ["lattice", "-p", "3", "-q", "1000000"],
    ["lattice", "-p", "3", "-q", "3000000000", "--rings", "1"],
    ["lattice", "--rings", "17", "--line-graph"],
])
def test_cli_refuses_huge_sizes_at_once(argv, capsys):
    main(["lattice", "--rings", "1", "--json"])  # imports every subcommand: not part of the timing
    capsys.readouterr()
    t = time.perf_counter()
    try:
        code = main(argv)
    except SystemExit as exc:  # argparse's own errors (e.g. "1e22" is not an int)
        code = exc.code
    elapsed = time.perf_counter() - t
    err = capsys.readouterr().err
    assert elapsed < 1.0, elapsed
    assert code == 2 and err.count("\n") == 1 and "Traceback" not in err


def test_cli_large_q_works(capsys):
    assert main(["lattice", "-p", "3", "-q", "130", "--rings", "2", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["sites"] == 3 + 3 * 127


@pytest.mark.parametrize("kind", ["directory", "missing_folder", "unwritable"])
def test_cli_bad_out_path_refused_before_building(kind, tmp_path, capsys, monkeypatch):
    if kind == "directory":
        out = tmp_path / "a.npz"
        out.mkdir()
    elif kind == "missing_folder":
        out = tmp_path / "nope" / "a.npz"
    else:
        ro = tmp_path / "ro"
        ro.mkdir()
        ro.chmod(0o500)
        out = ro / "a.npz"
        if os.access(ro, os.W_OK):  # root ignores permissions: make the check see them
            real_access = os.access
            monkeypatch.setattr(os, "access", lambda path, mode, *a, **k:
                                False if Path(path) == ro and mode & os.W_OK else real_access(path, mode, *a, **k))
    built = []
    monkeypatch.setattr("hyperlattice.cli.cmd_lattice.ring_lattice", lambda *a, **k: built.append(a))
    code = main(["lattice", "--rings", "3", "--out", str(out)])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1 and "Traceback" not in err
    assert built == []  # refused before any work
