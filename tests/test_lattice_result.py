"""Lattice as a Result: dict/JSON and file round trips, the old .npz layout, bad files, plot."""

import json

import numpy as np
import pytest

from hyperlattice.graph.lattice import Lattice, line_graph, load_lattice, ring_lattice
from hyperlattice.results import Result, load_result

ARRAYS = ("z", "ring", "edges", "rotation")


def _same(a: Lattice, b: Lattice) -> None:
    assert (a.p, a.q, a.rings, a.kind) == (b.p, b.q, b.rings, b.kind)
    for name in ARRAYS + ("parent_edges",):
        x, y = getattr(a, name), getattr(b, name)
        if x is None:
            assert y is None
            continue
        assert x.dtype == y.dtype and np.array_equal(x, y), name
        assert not y.flags.writeable


@pytest.fixture(scope="module", params=["sites", "line_graph"])
def lat(request):
    base = ring_lattice(8, 3, 3)
    return base if request.param == "sites" else line_graph(base)


def test_is_a_frozen_result(lat):
    assert isinstance(lat, Result)
    with pytest.raises(AttributeError):
        lat.rings = 4
    with pytest.raises(ValueError):
        lat.edges[0, 0] = 5
    assert lat != ring_lattice(8, 3, 3)  # eq=False: identity, never element-wise


def test_dict_round_trip(lat):
    data = json.loads(json.dumps(lat.as_dict()))  # through real JSON
    assert data["type"] == "Lattice"
    _same(lat, Lattice.from_dict(data))
    _same(lat, Result.from_dict(data))


@pytest.mark.parametrize("suffix", [".npz", ".json"])
def test_file_round_trip(lat, suffix, tmp_path):
    path = lat.save(tmp_path / f"lat{suffix}")
    _same(lat, load_lattice(path))
    _same(lat, Lattice.load(path))
    _same(lat, load_result(path))


def test_npz_keeps_the_old_layout(lat, tmp_path):
    path = lat.save(tmp_path / "lat.npz")
    with np.load(path) as f:
        assert {"z", "ring", "edges", "rotation", "p", "q", "rings", "kind"} <= set(f.files)
        assert int(f["p"]) == lat.p and str(f["kind"]) == lat.kind
        assert np.array_equal(f["z"], lat.z)


def test_reads_files_of_the_previous_version(lat, tmp_path):
    # exactly what Lattice.save wrote before it became a Result (no "__meta__" entry)
    path = tmp_path / "old.npz"
    extra = {} if lat.parent_edges is None else {"parent_edges": lat.parent_edges}
    np.savez_compressed(path, z=lat.z, ring=lat.ring, edges=lat.edges, p=lat.p, q=lat.q, rings=lat.rings,
                        kind=lat.kind, rotation=lat.rotation, **extra)
    _same(lat, load_lattice(path))
    _same(lat, Lattice.load(path))


def test_summary_is_the_cli_view():
    s = ring_lattice(7, 3, 6).summary()
    assert s["sites"] == 2240 and s["edges"] == 2856 and s["kind"] == "sites"
    assert set(s) == {"p", "q", "rings", "kind", "sites", "edges", "sites_per_ring", "d0", "h", "radius"}
    json.dumps(s)


@pytest.mark.parametrize("name", ["lat.txt", "lat"])
def test_save_unknown_format(name, tmp_path):
    with pytest.raises(ValueError, match="format"):
        ring_lattice(7, 3, 2).save(tmp_path / name)


def test_save_to_a_directory_or_missing_folder(tmp_path):
    lat = ring_lattice(7, 3, 2)
    (tmp_path / "d.npz").mkdir()
    with pytest.raises(ValueError, match="directory"):
        lat.save(tmp_path / "d.npz")
    with pytest.raises(ValueError, match="does not exist"):
        lat.save(tmp_path / "no" / "x.npz")


# ----------------------------------------------------------------------------
# load_lattice: every bad file is a ValueError with a sentence
# ----------------------------------------------------------------------------

def _bad_file(kind: str, tmp_path):
    lat = ring_lattice(7, 3, 2)
    path = tmp_path / "bad.npz"
    if kind == "missing":
        return tmp_path / "missing.npz"
    if kind == "directory":
        path.mkdir()
    elif kind == "text":
        path.write_text("not a zip file")
    elif kind == "empty":
        path.write_bytes(b"")
    elif kind == "other arrays":
        np.savez(path, a=np.arange(3))
    elif kind == "edge out of range":
        np.savez(path, z=lat.z, ring=lat.ring, edges=lat.edges + lat.sites, p=7, q=3, rings=2, kind="sites",
                 rotation=lat.rotation)
    elif kind == "not a permutation":
        np.savez(path, z=lat.z, ring=lat.ring, edges=lat.edges, p=7, q=3, rings=2, kind="sites",
                 rotation=np.zeros(lat.sites, dtype=np.int32))
    elif kind == "outside the disk":
        np.savez(path, z=lat.z * 10, ring=lat.ring, edges=lat.edges, p=7, q=3, rings=2, kind="sites",
                 rotation=lat.rotation)
    elif kind == "bad p":
        np.savez(path, z=lat.z, ring=lat.ring, edges=lat.edges, p="seven", q=3, rings=2, kind="sites",
                 rotation=lat.rotation)
    elif kind == "not hyperbolic":
        np.savez(path, z=lat.z, ring=lat.ring, edges=lat.edges, p=6, q=3, rings=2, kind="sites",
                 rotation=lat.rotation)
    elif kind == "bad kind":
        np.savez(path, z=lat.z, ring=lat.ring, edges=lat.edges, p=7, q=3, rings=2, kind="hexagons",
                 rotation=lat.rotation)
    elif kind == "bad json":
        path = tmp_path / "bad.json"
        path.write_text("{")
    elif kind == "wrong json":
        path = tmp_path / "bad.json"
        path.write_text(json.dumps({"type": "Lattice", "p": 7}))
    return path


@pytest.mark.parametrize("kind", ["missing", "directory", "text", "empty", "other arrays", "edge out of range",
                                  "not a permutation", "outside the disk", "bad p", "not hyperbolic", "bad kind",
                                  "bad json", "wrong json"])
def test_load_bad_files(kind, tmp_path):
    # regression: a missing file raised FileNotFoundError, others raw numpy/zip errors
    path = _bad_file(kind, tmp_path)
    with pytest.raises(ValueError) as exc:
        load_lattice(path)
    msg = str(exc.value)
    assert msg.endswith(".") and "\n" not in msg


@pytest.mark.parametrize("bad", [None, 3, ""])
def test_load_bad_path_argument(bad):
    with pytest.raises(ValueError, match="path"):
        load_lattice(bad)


# ----------------------------------------------------------------------------
# plot
# ----------------------------------------------------------------------------

@pytest.mark.parametrize("geodesic", [True, False])
def test_plot_returns_axes(lat, geodesic):
    import matplotlib.pyplot as plt

    ax = lat.plot(geodesic=geodesic)
    try:
        assert ax.get_aspect() == 1.0
        segments = ax.collections[0].get_segments()
        assert len(segments) == lat.edges.shape[0]
        # segment ends are the edge's sites; geodesic arcs stay in the disk
        ends = np.array([[s[0, 0] + 1j * s[0, 1], s[-1, 0] + 1j * s[-1, 1]] for s in segments])
        assert np.allclose(ends, lat.z[lat.edges], atol=1e-12)
        assert max(np.abs(s[:, 0] + 1j * s[:, 1]).max() for s in segments) < 1
        fig, ax2 = plt.subplots()
        assert lat.plot(ax2) is ax2
        plt.close(fig)
    finally:
        plt.close(ax.figure)


def test_plot_bad_options():
    with pytest.raises(ValueError):
        ring_lattice(7, 3, 2).plot(samples=1)
    with pytest.raises(ValueError):
        ring_lattice(7, 3, 2).plot(geodesic="yes")


def test_package_ships_license_and_py_typed():
    """PEP 561 marker (annotations visible to type checkers) and the MIT licence in the sdist/wheel."""
    from importlib.resources import files
    from pathlib import Path

    assert files("hyperlattice").joinpath("py.typed").is_file()
    root = Path(__file__).resolve().parents[1]
    assert "MIT License" in (root / "LICENSE").read_text()
