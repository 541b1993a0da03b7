"""Files read back are checked, never trusted (issue 19, item 5): ``load_lattice`` and ``load_result``
refuse tampered files in one sentence that names the file.

Each case takes a file the package wrote and changes one thing. With the checksum kept, any edit
is a checksum mismatch; with the checksum dropped (a file that could be hand-written), the
structure and invariants must catch it. Before the fix all of these loaded without an error, and
``lowest_levels`` on a rewired lattice returned wrong energies with tiny residuals.
"""

from __future__ import annotations

import copy
import json

import numpy as np
import pytest

from hyperlattice.graph.lattice import load_lattice, ring_lattice
from hyperlattice.graph.spectrum import lowest_levels
from hyperlattice.results import load_result

LAT = ring_lattice(7, 3, 3)


def _one_sentence(exc, path) -> str:
    text = str(exc.value)
    assert str(path) in text and "\n" not in text and text.endswith("."), text
    return text


# -- lattices ------------------------------------------------------------------------------------

def _arrays(lat=LAT) -> dict:
    return {"z": lat.z.copy(), "ring": lat.ring.copy(), "edges": lat.edges.copy(), "rotation": lat.rotation.copy(),
            "p": np.asarray(lat.p), "q": np.asarray(lat.q), "rings": np.asarray(lat.rings),
            "kind": np.asarray(lat.kind)}


def _duplicate(a):
    a["edges"][5] = a["edges"][4]


def _rewire(a):
    e = a["edges"]
    e[7, 1] = (e[7, 1] + 3) % len(a["z"])        # one endpoint moved to another site


def _self_loop(a):
    a["edges"][3, 1] = a["edges"][3, 0]


def _move(a):
    a["z"][10] *= 1.0 + 1e-6                      # a site moved by a micro-unit


def _rotation(a):
    r = a["rotation"]
    r[[8, 9]] = r[[9, 8]]                        # still a permutation, no longer the rotation


def _float_edges(a):
    a["edges"] = a["edges"].astype(float)


def _order(a):
    z = a["z"]
    z[[7, 8]] = z[[8, 7]]                         # two sites of ring 2 swapped (and their edges with them)
    e = a["edges"]
    swap = {7: 8, 8: 7}
    a["edges"] = np.sort(np.vectorize(lambda i: swap.get(int(i), int(i)))(e), axis=1).astype(np.int32)


@pytest.mark.parametrize("tamper, match", [
    (_duplicate, "appears twice|neighbours"),
    (_rewire, "length|neighbours|skips a ring|rotation table"),
    (_self_loop, "edge to itself"),
    (_move, "has length"),
    (_rotation, "rotation table"),
    (_float_edges, "wrong dtype"),
])
def test_load_lattice_refuses_a_tampered_file_without_checksum(tamper, match, tmp_path):
    a = _arrays()
    tamper(a)
    path = tmp_path / "lat.npz"
    np.savez_compressed(path, **a)           # the layout of earlier versions: no checksum to help
    with pytest.raises(ValueError, match=match) as exc:
        load_lattice(path)
    _one_sentence(exc, path)


def test_a_swap_of_two_sites_keeps_the_graph_but_is_refused(tmp_path):
    # relabelling two sites keeps every edge length: the ring order and the rotation table catch it
    a = _arrays()
    _order(a)
    path = tmp_path / "lat.npz"
    np.savez_compressed(path, **a)
    with pytest.raises(ValueError, match="counterclockwise|rotation") as exc:
        load_lattice(path)
    _one_sentence(exc, path)


@pytest.mark.parametrize("suffix", [".npz", ".json"])
def test_load_lattice_checks_its_checksum(suffix, tmp_path):
    path = LAT.save(tmp_path / f"lat{suffix}")
    back = load_lattice(path)
    assert np.array_equal(back.z, LAT.z) and np.array_equal(back.edges, LAT.edges)   # intact files load
    if suffix == ".npz":
        with np.load(path) as f:
            a = {k: f[k] for k in f.files}
        a["z"] = a["z"].copy()
        a["z"][0] += 1e-15                                     # below any structural tolerance
        np.savez_compressed(path, **a)
    else:
        data = json.loads(path.read_text())
        data["z"]["real"][0] += 1e-15
        path.write_text(json.dumps(data))
    with pytest.raises(ValueError, match="fails its checksum") as exc:
        load_lattice(path)
    _one_sentence(exc, path)
    with pytest.raises(ValueError, match="fails its checksum"):
        load_result(path)                                      # the same file through the other door


def test_a_rewired_lattice_no_longer_reaches_the_solver(tmp_path):
    a = _arrays()
    _rewire(a)
    path = tmp_path / "lat.npz"
    np.savez_compressed(path, **a)
    with pytest.raises(ValueError):
        lowest_levels(load_lattice(path), 2)


def test_every_saved_lattice_kind_loads(tmp_path):
    from hyperlattice.graph.lattice import line_graph

    for lat in (ring_lattice(3, 7, 3), ring_lattice(4, 5, 3), line_graph(ring_lattice(7, 3, 3)),
                ring_lattice(7, 3, 1)):
        for suffix in (".npz", ".json"):
            back = load_lattice(lat.save(tmp_path / f"l{suffix}"))
            assert back.kind == lat.kind and np.array_equal(back.rotation, lat.rotation)


# -- results -------------------------------------------------------------------------------------

SPEC = lowest_levels(ring_lattice(7, 3, 2), 3)


def _json_case(edit):
    def apply(d):
        edit(d)
        return d
    return apply


def _set_array(name, values, dtype=None):
    def edit(d):
        arr = d[name]
        arr["data"] = list(values)
        arr["shape"] = [len(values)]
        if dtype is not None:
            arr["__ndarray__"] = dtype
    return edit


def _energy(i, value):
    def edit(d):
        d["energies"]["data"][i] = value
    return edit


# (what changes, keep the checksum?, expected clause): twelve kinds of tampered file
CASES = [
    ("edited energy", _energy(0, -2.0), True, "fails its checksum"),
    ("garbled checksum", lambda d: None, "garbled", "fails its checksum"),
    ("NaN energy", _energy(1, "nan"), False, "not finite"),
    ("infinite energy", _energy(2, "inf"), False, "not finite"),
    ("energies shorter than n", lambda d: _set_array("energies", d["energies"]["data"][:2])(d), False,
     "entries for 2 energies"),
    ("unsorted", lambda d: d["energies"].__setitem__("data", d["energies"]["data"][::-1]), False, "not ascending"),
    ("sites=-5", lambda d: d.__setitem__("sites", -5), False, "sites = -5"),
    ("sites a float", lambda d: d.__setitem__("sites", 22.0), False, "sites must be an integer"),
    ("p a string", lambda d: d.__setitem__("p", "7"), False, "p must be an integer"),
    ("energies as integers", lambda d: _set_array("energies", [-3, -2, -2], "int64")(d), False,
     "energies must be a 1-d float array"),
    ("n as floats", lambda d: _set_array("n", [1.0, 1.0, 1.0], "float64")(d), False, "n has the wrong dtype"),
    ("n = 0", lambda d: _set_array("n", [0, 1, 1])(d), False, "n starts at 1"),
    ("negative residual", lambda d: _set_array("errors", [1e-14, -1e-3, 1e-14])(d), False, "non-negative"),
    ("m out of range", lambda d: _set_array("m", [0, 9, -9])(d), False, "m must lie"),
]


@pytest.mark.parametrize("what, edit, keep, match", CASES, ids=[c[0] for c in CASES])
def test_load_result_refuses_a_tampered_json_file(what, edit, keep, match, tmp_path):
    path = SPEC.save(tmp_path / "spec.json")
    assert load_result(path).energies.tolist() == SPEC.energies.tolist()        # the intact file loads
    data = json.loads(path.read_text())
    data = copy.deepcopy(data)
    edit(data)
    if keep == "garbled":
        data["sha256"] = "0" * 64
    elif not keep:
        data.pop("sha256")
    path.write_text(json.dumps(data))
    if not keep:
        # without its checksum the file is refused as such, and read as hand-written it is checked
        with pytest.raises(ValueError, match="carries no checksum") as exc:
            load_result(path)
        _one_sentence(exc, path)
    with pytest.raises(ValueError, match=match) as exc:
        load_result(path, require_checksum=keep is not False)
    _one_sentence(exc, path)


@pytest.mark.parametrize("keep", [True, False])
def test_load_result_refuses_a_tampered_npz_file(keep, tmp_path):
    path = SPEC.save(tmp_path / "spec.npz")
    with np.load(path) as f:
        a = {k: f[k] for k in f.files}
    e = a["energies"].copy()
    if keep:
        e[0] -= 1e-3                                           # an edited energy, still ascending
    else:
        e = e[::-1].copy()                                     # unsorted, checksum dropped
        meta = json.loads(str(a["__meta__"]))
        meta.pop("sha256")
        a["__meta__"] = np.array(json.dumps(meta))
    a["energies"] = e
    np.savez(path, **a)
    with pytest.raises(ValueError, match="fails its checksum" if keep else "not ascending") as exc:
        load_result(path, require_checksum=keep)
    _one_sentence(exc, path)


@pytest.mark.parametrize("suffix", [".json", ".npz"])
def test_load_result_refuses_a_file_whose_checksum_was_deleted(suffix, tmp_path):
    # issue 28 item 6: an edited number passed once the sha256 key was deleted (still ascending)
    path = SPEC.save(tmp_path / f"spec{suffix}")
    if suffix == ".json":
        data = json.loads(path.read_text())
        data.pop("sha256")
        data["energies"]["data"][0] -= 1e-3
        path.write_text(json.dumps(data))
    else:
        with np.load(path) as f:
            a = {k: f[k] for k in f.files}
        meta = json.loads(str(a["__meta__"]))
        meta.pop("sha256")
        a["__meta__"] = np.array(json.dumps(meta))
        a["energies"] = a["energies"] - np.r_[1e-3, np.zeros(len(a["energies"]) - 1)]
        np.savez(path, **a)
    with pytest.raises(ValueError, match="carries no checksum.*require_checksum=False") as exc:
        load_result(path)
    _one_sentence(exc, path)
    back = load_result(path, require_checksum=False)     # read as hand-written: it is consistent
    assert back.energies[0] == pytest.approx(SPEC.energies[0] - 1e-3)


def test_a_deeply_nested_result_file_is_one_sentence(tmp_path):
    path = tmp_path / "deep.json"
    path.write_text("[" * 100_000 + "]" * 100_000)
    with pytest.raises(ValueError, match="nested too deeply") as exc:
        load_result(path)
    _one_sentence(exc, path)


def _object_npz(path, meta):
    np.savez(path, __meta__=np.array(json.dumps(meta)), energies=np.array([1, "a", None], dtype=object))


def _header_npz(path, meta):
    np.savez(path, __meta__=np.array(json.dumps(meta)),
             energies=np.zeros(1, dtype=[(f"f{i}", "f8") for i in range(3000)]))


def _digits_json(path, meta):
    path.write_text('{"type": "Spectrum", "p": ' + "9" * 5000 + "}")


@pytest.mark.parametrize("write, suffix, match", [
    (_object_npz, ".npz", "it holds Python objects"),
    (_header_npz, ".npz", "array header far larger"),
    (_digits_json, ".json", "integer of more than 4,300 digits"),
])
@pytest.mark.parametrize("loader", ["load_result", "load_lattice"])
def test_loader_refusals_are_physicist_sentences(write, suffix, match, loader, tmp_path):
    # issue 28 item 6: numpy's "allow_pickle", "max_header_size" and Python's
    # "set_int_max_str_digits" advice reached the user, load_result's without the file's name
    path = tmp_path / f"f{suffix}"
    meta = {"type": "Spectrum"}
    write(path, meta)
    if loader == "load_lattice" and write is not _digits_json:
        # a lattice archive needs its arrays before any is read: the object array stands for z
        arrays = {k: v for k, v in _arrays().items() if k != "z"}
        z = np.array([1, "a"], dtype=object) if write is _object_npz else \
            np.zeros(1, dtype=[(f"f{i}", "f8") for i in range(3000)])
        np.savez(path, z=z, **arrays)
    with pytest.raises(ValueError, match=match) as exc:
        (load_result if loader == "load_result" else load_lattice)(path)
    text = _one_sentence(exc, path)
    for advice in ("allow_pickle", "max_header_size", "set_int_max_str_digits"):
        assert advice not in text
