"""The one door for input checks (_validate): every helper with good and bad values."""

from __future__ import annotations

import math
import os
from fractions import Fraction
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from hyperlattice import _validate as v

# values nobody means as a number; each helper below says which of them it accepts
JUNK = {
    "none": None,
    "nan": math.nan,
    "inf": math.inf,
    "-inf": -math.inf,
    "np-nan": np.float64("nan"),
    "bool": True,
    "np-bool": np.bool_(False),
    "str": "3",
    "bytes": b"3",
    "complex": 1 + 2j,
    "list": [1.0],
    "ragged": [[1, 2], [3]],
    "object": object(),
    "dict": {"a": 1},
}


def _bad(accepted=()):
    return [pytest.param(val, id=tag) for tag, val in JUNK.items() if tag not in accepted]


def _one_sentence(exc: pytest.ExceptionInfo, name: str) -> None:
    msg = str(exc.value)
    assert msg.startswith(name) or name in msg, msg
    assert "\n" not in msg and msg.endswith("."), msg


# ----------------------------------------------------------------------------
# scalars
# ----------------------------------------------------------------------------

@pytest.mark.parametrize("value", _bad())
def test_integer_refuses_junk(value):
    with pytest.raises(ValueError) as exc:
        v.integer("rings", value)
    _one_sentence(exc, "rings")


@pytest.mark.parametrize("value, expected", [(3, 3), (np.int8(3), 3), (np.uint64(2 ** 63 - 1), 2 ** 63 - 1), (3.0, 3),
                                             (np.float32(-4.0), -4), (np.array(5), 5), (np.array(6.0), 6),
                                             (-(2 ** 63), -(2 ** 63))])
def test_integer_accepts(value, expected):
    out = v.integer("n", value)
    assert out == expected and type(out) is int


@pytest.mark.parametrize("value", [np.uint64(2 ** 63), 10 ** 30, -(10 ** 30), 10 ** 400])
def test_integer_beyond_int64_needs_an_explicit_maximum(value):
    # issue 19: 10**140 used to pass the door and end as OverflowError inside numpy
    with pytest.raises(ValueError, match="n must be at"):
        v.integer("n", value)
    assert v.integer("n", 10 ** 30, maximum=10 ** 40) == 10 ** 30


@pytest.mark.parametrize("value", [3.5, Fraction(7, 2), np.array([3]), np.array(True), 1e-300])
def test_integer_refuses_non_integers(value):
    with pytest.raises(ValueError, match="must be an integer"):
        v.integer("n", value)


@pytest.mark.parametrize("value", [1e308, 1e22, 10 ** 400, np.float64(1e300)])
def test_integer_huge_refused_by_maximum_quickly(value):
    """ring_lattice(7, 3, 1e308) built a 309-digit int before its size check."""
    with pytest.raises(ValueError, match="at most 1,000") as exc:
        v.integer("rings", value, maximum=1000)
    assert len(str(exc.value)) < 120


def test_integer_bounds():
    assert v.integer("n", 0, minimum=0) == 0
    with pytest.raises(ValueError, match="at least 1"):
        v.positive_int("n", 0)
    with pytest.raises(ValueError, match="at least 0"):
        v.integer("n", -1e308, minimum=0)
    assert v.positive_int("n", 7, maximum=7) == 7


@given(st.integers(min_value=-10 ** 6, max_value=10 ** 6))
def test_integer_property_ints_and_integral_floats(n):
    assert v.integer("n", n) == n and v.integer("n", float(n)) == n and v.integer("n", np.int64(n)) == n


@given(st.floats(allow_nan=False, allow_infinity=False).filter(lambda x: not x.is_integer()))
def test_integer_property_fractional_floats_refused(x):
    with pytest.raises(ValueError):
        v.integer("n", x)


@pytest.mark.parametrize("value", _bad())
def test_real_refuses_junk(value):
    with pytest.raises(ValueError) as exc:
        v.real("t", value)
    _one_sentence(exc, "t")


@pytest.mark.parametrize("value, expected", [(2, 2.0), (np.float32(0.5), 0.5), (Fraction(1, 4), 0.25),
                                             (np.array(1.5), 1.5), (np.array(2), 2.0), (1e308, 1e308),
                                             (np.int64(-3), -3.0)])
def test_real_accepts(value, expected):
    out = v.real("x", value)
    assert out == expected and type(out) is float


@pytest.mark.parametrize("value", [np.array(1 + 1j), np.array([1.0]), np.complex128(1.0), 10 ** 400])
def test_real_refuses_complex_arrays_and_overflow(value):
    with pytest.raises(ValueError):
        v.real("x", value)


def test_real_intervals():
    assert v.real("x", 0.0, minimum=0.0) == 0.0
    with pytest.raises(ValueError, match="greater than 0"):
        v.real("x", 0.0, minimum=0.0, open_min=True)
    with pytest.raises(ValueError, match="less than 1"):
        v.real("x", 1.0, maximum=1.0, open_max=True)
    with pytest.raises(ValueError, match="at most 2"):
        v.real("x", 2.5, maximum=2.0)
    with pytest.raises(ValueError, match="greater than 0"):
        v.positive_real("x", -1e-300)
    assert v.positive_real("x", 5e-324) == 5e-324


@given(st.floats(allow_nan=False, allow_infinity=False))
def test_real_property_identity_on_finite_floats(x):
    assert v.real("x", x) == x and v.real("x", np.float64(x)) == x


@pytest.mark.parametrize("value", _bad(accepted={"complex"}))
def test_complex_number_refuses_junk(value):
    with pytest.raises(ValueError) as exc:
        v.complex_number("omega", value)
    _one_sentence(exc, "omega")


@pytest.mark.parametrize("value", [complex(math.nan, 0), complex(0, math.inf), np.complex64(complex(1, math.inf))])
def test_complex_number_refuses_non_finite(value):
    with pytest.raises(ValueError, match="finite"):
        v.complex_number("omega", value)


@given(st.complex_numbers(allow_nan=False, allow_infinity=False))
def test_complex_number_property(z):
    out = v.complex_number("z", z)
    assert out == z and type(out) is complex
    assert v.complex_number("z", np.array(z)) == z


def test_complex_number_accepts_reals():
    assert v.complex_number("z", 2) == 2 + 0j and v.complex_number("z", np.float32(0.5)) == 0.5


@pytest.mark.parametrize("value", _bad())
def test_radius_refuses_junk(value):
    with pytest.raises(ValueError):
        v.radius("radius L", value)


@pytest.mark.parametrize("value, allow_one, ok", [(0.5, False, True), (1.0, False, False), (1.0, True, True),
                                                  (0.0, True, False), (-0.1, False, False), (float(np.nextafter(1.0, 2.0)), True, False)])
def test_radius_domain(value, allow_one, ok):
    """Two _check_radius functions disagreed on (0,1) vs (0,1]; there is one now, with a switch."""
    if ok:
        assert v.radius("L", value, allow_one=allow_one) == value
    else:
        with pytest.raises(ValueError):
            v.radius("L", value, allow_one=allow_one)


@given(st.floats(min_value=0.0, max_value=1.0, exclude_min=True, exclude_max=True))
def test_radius_property_open_unit_interval(x):
    assert v.radius("L", x) == x


def test_choice_and_flag():
    assert v.choice("window", "all", ("all", "complete")) == "all"
    for bad in (None, "ALL", 1, ["all"]):
        with pytest.raises(ValueError, match="window must be one of 'all', 'complete'"):
            v.choice("window", bad, ("all", "complete"))
    assert v.flag("f", True) is True and v.flag("f", np.bool_(False)) is False
    for bad in (None, 1, 0, "True", math.nan):
        with pytest.raises(ValueError, match="True or False"):
            v.flag("f", bad)


def test_function():
    assert v.function("f", abs) is abs
    for bad in (None, 3, "abs"):
        with pytest.raises(ValueError, match="must be a function"):
            v.function("f", bad)


# ----------------------------------------------------------------------------
# arrays
# ----------------------------------------------------------------------------

@pytest.mark.parametrize("value", _bad(accepted={"list", "nan", "inf", "-inf", "np-nan", "complex", "bool", "np-bool"}))
def test_real_array_refuses_junk(value):
    with pytest.raises(ValueError) as exc:
        v.real_array("values", value)
    _one_sentence(exc, "values")


@pytest.mark.parametrize("value, match", [
    ([1.0, math.nan], "NaN or infinite"), ([1.0, math.inf], "NaN or infinite"), ([1 + 1j], "real numbers"),
    ([True, False], "real numbers"), (np.array(["1"]), "real numbers"), ([10 ** 400], "real numbers"),
    (np.array([1.0, 2.0], dtype=object), "real numbers"), (math.nan, "NaN"),
])
def test_real_array_bad_contents(value, match):
    with pytest.raises(ValueError, match=match):
        v.real_array("values", value)


def test_real_array_shapes():
    a = v.real_array("a", [[1, 2], [3, 4]], ndim=2, shape=(2, 2))
    assert a.dtype == np.float64 and a.shape == (2, 2)
    assert v.real_array("a", 3.0).shape == ()  # scalars unless ndim forbids them
    with pytest.raises(ValueError, match="dimension"):
        v.real_array("a", 3.0, ndim=1)
    with pytest.raises(ValueError, match="dimension"):
        v.real_array("a", np.zeros((2, 2)), ndim=(1, 3))
    with pytest.raises(ValueError, match="shape"):
        v.real_array("a", np.zeros(3), shape=(2,))


@given(st.lists(st.floats(allow_nan=False, allow_infinity=False), max_size=20))
def test_real_array_property(xs):
    assert np.array_equal(v.real_array("a", xs), np.asarray(xs, dtype=float))


def test_complex_array():
    z = v.complex_array("z", [1, 2j, 3.5])
    assert z.dtype == np.complex128 and z[1] == 2j
    for bad, match in (([complex(0, math.nan)], "NaN"), (["a"], "numbers"), ([[1], [1, 2]], "ragged"), (None, "array")):
        with pytest.raises(ValueError, match=match):
            v.complex_array("z", bad)


def test_disk_points():
    assert v.disk_points("z", [0.5, 0.5j]).dtype == np.complex128
    with pytest.raises(ValueError, match=r"\|z\| < 1"):
        v.disk_points("z", [0.5, 1.0])
    assert v.disk_points("z", 0.3, limit=0.3, closed=True) == 0.3
    with pytest.raises(ValueError, match=r"\|z\| < 0.3"):
        v.disk_points("z", 0.3, limit=0.3)
    with pytest.raises(ValueError):
        v.disk_points("z", [1e308 + 1e308j])


# ----------------------------------------------------------------------------
# lattice objects
# ----------------------------------------------------------------------------

@pytest.mark.parametrize("p, q", [(7, 3), (3, 7), (5, 4), (4, 5), (8, 3), (7.0, 3.0), (np.int64(7), 3)])
def test_pq_accepts_hyperbolic(p, q):
    assert v.pq(p, q) == (int(p), int(q))


@pytest.mark.parametrize("p, q", [(6, 3), (4, 4), (3, 6), (2, 9), (7, 2), (math.inf, 3), (None, 3), (7, True),
                                  (7.5, 3), ("7", 3), (7, math.nan), (7, 1 + 2j)])
def test_pq_refuses(p, q):
    with pytest.raises(ValueError):
        v.pq(p, q)


def test_pq_infinite_p():
    assert v.pq(math.inf, 3, allow_infinite_p=True) == (math.inf, 3)
    with pytest.raises(ValueError):
        v.pq(-math.inf, 3, allow_infinite_p=True)


def test_lattice_kind():
    from hyperlattice.graph.lattice import line_graph, ring_lattice

    lat = ring_lattice(7, 3, 2)
    assert v.lattice(lat) is lat and v.lattice(lat, kind="sites") is lat
    for bad in (None, "lattice", np.zeros(3)):
        with pytest.raises(ValueError, match="expected a Lattice"):
            v.lattice(bad)
    with pytest.raises(ValueError, match="line graph"):
        v.lattice(line_graph(lat), kind="sites")


def test_site_index():
    assert v.site_index("source", 3, 10) == 3 and v.site_index("source", np.int32(9), 10) == 9
    assert v.site_index("source", 4.0, 10) == 4  # integral floats, as for every integer
    for bad in (-1, 10, 1e308, 3.5, None, True, "3", [3], math.nan):
        with pytest.raises(ValueError, match="source"):
            v.site_index("source", bad, 10)


def test_site_indices():
    out = v.site_indices("sites", [0, 3, 9.0], 10)
    assert out.dtype == np.int64 and out.tolist() == [0, 3, 9]
    assert v.site_indices("sites", 4, 10).tolist() == [4] and v.site_indices("sites", [], 10).size == 0
    # 1e308 and 2**64 used to wrap around in the int64 cast (and warn) before the range check
    for bad in ([1e308], [2 ** 64], np.array([2 ** 63], dtype=np.uint64), [-1], [10], [0.5], [math.nan],
                [[1, 2]], [True], None, "3", True):
        with pytest.raises(ValueError, match="sites"):
            v.site_indices("sites", bad, 10)


@given(st.lists(st.integers(min_value=0, max_value=99), max_size=30))
def test_site_indices_property(idx):
    assert v.site_indices("s", idx, 100).tolist() == idx


# ----------------------------------------------------------------------------
# files
# ----------------------------------------------------------------------------

@pytest.mark.parametrize("value", [None, 3, True, "", b"out.png", "a\0b", ["a"]])
def test_paths_refuse_non_paths(value, tmp_path):
    for fn in (v.output_path, v.input_path, v.directory):
        with pytest.raises(ValueError, match="must be a path"):
            fn("--out", value)


def test_output_path(tmp_path):
    assert v.output_path("--out", tmp_path / "f.csv") == tmp_path / "f.csv"
    assert v.output_path("--out", "relative.csv") == Path("relative.csv")  # the working folder
    assert v.output_path("--out", str(tmp_path / "f.npz"), suffixes=(".npz",)).suffix == ".npz"
    afile = tmp_path / "afile"
    afile.write_text("x")
    cases = {tmp_path: "is a directory", tmp_path / "no" / "f.csv": "does not exist",
             afile / "f.csv": "is not a folder", tmp_path / ("x" * 5000): "cannot be used",
             tmp_path / "f.txt": "must end in .npz"}
    for path, match in cases.items():
        with pytest.raises(ValueError, match=match):
            v.output_path("--out", path, suffixes=(".npz",) if path.suffix == ".txt" else None)


@pytest.mark.skipif(os.geteuid() == 0, reason="root may write into read-only folders")
def test_output_path_read_only(tmp_path):  # pragma: no cover - CI does not run as root
    locked = tmp_path / "locked"
    locked.mkdir()
    locked.chmod(0o500)
    with pytest.raises(ValueError, match="permission denied"):
        v.output_path("--out", locked / "f.csv")
    with pytest.raises(ValueError, match="not writable"):
        v.directory("--out", locked)


def test_input_path(tmp_path):
    f = tmp_path / "lat.npz"
    f.write_bytes(b"x")
    assert v.input_path("path", f, suffixes=(".npz",)) == f
    for path, match in ((tmp_path, "not a file"), (tmp_path / "missing.npz", "does not exist"),
                        (tmp_path / ("y" * 5000), "cannot be used")):
        with pytest.raises(ValueError, match=match):
            v.input_path("path", path)
    with pytest.raises(ValueError, match="must end in .json"):
        v.input_path("path", f, suffixes=(".json",))


def test_directory(tmp_path):
    new = tmp_path / "a" / "b"
    assert v.directory("--cache-dir", new) == new and new.is_dir()
    assert v.directory("--cache-dir", new, create=False) == new
    afile = tmp_path / "afile"
    afile.write_text("x")
    for path, kwargs, match in ((afile, {}, "not a directory"), (afile / "sub", {}, "cannot be created"),
                                (tmp_path / "missing", {"create": False}, "does not exist"),
                                (tmp_path / ("z" * 5000), {}, "cannot")):
        with pytest.raises(ValueError, match=match):
            v.directory("--cache-dir", path, **kwargs)


@settings(max_examples=50)
@given(st.text(min_size=1, max_size=40))
def test_output_path_never_raises_other_errors(name):
    """Whatever text a user types as a file name, the answer is a path or a ValueError."""
    try:
        v.output_path("--out", os.path.join("/nonexistent-hyperlattice-dir", name))
    except ValueError:
        pass
