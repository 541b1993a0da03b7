"""The result protocol (results.py): exact round trips, read-only arrays, identity equality.

Every registered Result type is walked: the ones of this package that are cheap to compute are
built by their real functions, the others from their field annotations.
"""

from __future__ import annotations

import dataclasses
import importlib
import json
import math
import pkgutil
import sys
import typing
from pathlib import Path

import numpy as np
import pytest

import hyperlattice
from hyperlattice.results import Levels, Result, load_result, result_types, to_jsonable


def _import_everything() -> None:
    """Import every module so that every Result subclass is registered."""
    for info in pkgutil.walk_packages(hyperlattice.__path__, "hyperlattice."):
        if not info.name.endswith("__main__"):
            importlib.import_module(info.name)


_import_everything()


@dataclasses.dataclass(frozen=True, eq=False, kw_only=True)
class Everything(Result):
    """Every kind of value a field may hold (the defects of the first results.py)."""

    TYPE = "tests.Everything"

    ints: np.ndarray
    int32: np.ndarray
    empty: np.ndarray
    bools: np.ndarray
    floats: np.ndarray
    cplx: np.ndarray
    strings: np.ndarray
    none_array: np.ndarray | None
    scalar: complex
    nonfinite: float
    negzero: float
    label: str
    pair: tuple
    by_int: dict
    nested: Levels
    results: list
    path: Path
    big: int


def _levels() -> Levels:
    return Levels(energies=np.array([-2.9, -2.8, -2.8]), n=np.array([1, 1, 1]), m=np.array([0, 1, -1]),
                  errors=np.array([1e-13, 2e-13, np.nan]), error_kind="residual", method="dense",
                  description="dense eigensolver", p=7, q=3)


def _everything() -> Everything:
    return Everything(
        ints=np.arange(6, dtype=np.int64).reshape(2, 3), int32=np.array([[0, 1], [1, 2]], dtype=np.int32),
        empty=np.zeros((0, 2), dtype=np.int32), bools=np.array([True, False]),
        floats=np.array([0.1, -0.0, np.inf, -np.inf, np.nan, 1e-310]),
        cplx=np.array([1 + 2j, np.nan - 1j, complex(0, np.inf)]), strings=np.array(["a", "bc"]),
        none_array=None, scalar=0.1 - 2.5j, nonfinite=-math.inf, negzero=-0.0, label="nan",
        pair=(1, 2.5, "x", (3,)), by_int={2: np.arange(3.0), 3: {"inner": (1, 2)}, "type": "not a result"},
        nested=_levels(), results=[_levels(), None], path=Path("a/b.json"), big=2 ** 70)


def _device_transmission():
    from hyperlattice.device import resonator_device, transmission

    dev = resonator_device(ring_lattice_small(), line_graph=True, omega0=1.0, J=-0.1, kappa_int=0.01,
                           ports={"0-1": 0.05, "3-4": 0.05})
    return transmission(dev, [0.8, 1.0, 1.2])


def _device_voltages():
    from hyperlattice.device import node_voltages

    return node_voltages(ring_lattice_small(), 1.0, edge="C:1", ground="L:1,R:10", drive="0")


def ring_lattice_small():
    from hyperlattice.graph.lattice import ring_lattice

    return ring_lattice(7, 3, 1)


def _factories():
    """Real constructions of this package's results, by type tag (cheap: small lattices)."""
    from hyperlattice.compare import scaling, sums
    from hyperlattice.dictionary import continuum_parameters
    from hyperlattice.graph.lattice import line_graph, ring_lattice

    def spectrum():
        from hyperlattice.graph.spectrum import lowest_levels

        return lowest_levels(ring_lattice(7, 3, 2), levels=3)

    def matrix_spectrum():
        from hyperlattice.graph.operators import hamiltonian
        from hyperlattice.graph.spectrum import lowest_levels

        # complex Hermitian H: complex eigenvectors go through the stored form too
        return lowest_levels(hamiltonian(ring_lattice(7, 3, 2), flux=0.1), 3, eigenvectors=True)

    def green():
        from hyperlattice.compare.green import compare_green

        return compare_green(ring_lattice(7, 3, 2), complex(-2.5, 0.1), 3)

    def tiling():
        from hyperlattice.geometry import tiling_constants

        return tiling_constants(7, 3)

    return {
        Everything.TYPE: _everything,
        "Levels": _levels,
        "Lattice": lambda: ring_lattice(7, 3, 2),
        "tests.LineGraph": lambda: line_graph(ring_lattice(7, 3, 2)),
        "Transmission": _device_transmission,
        "NodeVoltages": _device_voltages,
        "Spectrum": spectrum,
        "MatrixSpectrum": matrix_spectrum,
        # tables and grids whose columns have lengths the annotations cannot say
        "DisorderEnsemble": lambda: __import__("hyperlattice.compare.disorder", fromlist=["x"]).disorder_ensemble(
            ring_lattice(7, 3, 2), 1.0, realizations=2, seed=1),
        "DirichletTable": lambda: __import__("hyperlattice.continuum.spectrum", fromlist=["x"]).dirichlet_levels(
            7, 3, rings=3, n_max=2, m_max=3),
        "Butterfly": lambda: __import__("hyperlattice.graph.butterfly", fromlist=["x"]).butterfly(
            ring_lattice(7, 3, 2), [0.0, 0.1, 0.25]),
        # Levels are checked when read back (integer n, ascending energies): real data, not samples
        "ContinuumSpectrum": lambda: __import__("hyperlattice.continuum.spectrum", fromlist=["x"]).continuum_levels(
            7, 3, rings=3, levels=3),
        "MagneticSpectrum": lambda: __import__("hyperlattice.continuum.magnetic", fromlist=["x"]).magnetic_levels(
            7, 3, rings=3, levels=2, flux=0.1),
        "LabelledSpectrum": lambda: __import__("hyperlattice.compare.levels", fromlist=["x"]).continuum_labels(
            __import__("hyperlattice.graph.spectrum", fromlist=["x"]).lowest_levels(ring_lattice(8, 3, 3), 10)),
        "GreenComparison": green,
        "TilingConstants": tiling,
        "ContinuumParameters": lambda: continuum_parameters(1.0, 0.5, 2.0),
        "FrameAngles": lambda: scaling.frame_angles(ring_lattice(7, 3, 2)),
        "RadialProfile": lambda: scaling.angle_profile(ring_lattice(7, 3, 2)),
        "OperatorProfile": lambda: scaling.operator_profile(ring_lattice(7, 3, 3), h=0.1),
        "ConvergenceStudy": lambda: scaling.convergence_study(ring_lattice(7, 3, 3), scaling.SmoothFunction.exp_x()),
        "CountingFit": lambda: sums.fit_counting(ring_lattice(7, 3, 4)),
        "MagneticComparison": _magnetic_comparison,
        # a table of lobes: its list holds MottLobe results, which annotations cannot say
        "MottLobeTable": lambda: __import__("hyperlattice.bosons.meanfield", fromlist=["x"]).mott_lobes(
            7, 3, rings=(3,), clusters=("klein",), points=5),
        **_beyond_factories(),
        "SumCheck": lambda: sums.SumCheck(p=7, q=3, rings=2, sites=77, radius=0.9, function="f",
                                          lattice_sum=1.5 + 1e-3j, integral=complex(1.49, 0.0)),
    }


def _beyond_factories():
    """Real constructions of the results beyond the paper (small and cheap)."""
    from hyperlattice.graph.lattice import ring_lattice

    def bolza():
        from hyperlattice.graph.clusters import pbc_cluster

        return pbc_cluster(8, 3, "bolza")

    def bands(kind):
        from hyperlattice.graph import bands as b

        return {"Windings": lambda: b.edge_windings(bolza()),
                "Bands": lambda: b.band_structure(bolza(), points=3),
                "AbelianDOS": lambda: b.abelian_dos(bolza(), samples=8, bins=10, batches=2)}[kind]()

    def limits(kind):
        from hyperlattice.compare import limits as lim

        return {"BandBottom": lambda: lim.band_bottom(7, 3, schur_window=None),
                "SchurBound": lambda: lim.schur_bound(7, 3, window=0, rings=7),
                "DictionaryComparison": lambda: lim.compare_dictionaries(),
                "BandBottomFit": lambda: lim.fit_band_bottom(*[a[-6:] for a in lim.reference_levels()[:2]])}[kind]()

    def dos():
        from hyperlattice.compare.dos import dos_comparison

        return dos_comparison(7, 3, clusters=("klein",), rings=(4,), moments=32, vectors=3, abelian=False,
                              walk_length=11, resolution=20)

    def spins():
        from hyperlattice.graph.qubits import spin_model

        return spin_model(ring_lattice(7, 3, 3), [0, 10, 30], -3.1, 0.05)

    def cluster():
        from hyperlattice.graph.clusters import pbc_cluster

        return pbc_cluster(7, 3, "klein")

    def tables():
        # the tabular results of issue 21, item 5, from small real computations
        from hyperlattice.bosons import ed
        from hyperlattice.graph.kpm import kpm_dos

        return {"KPMDos": lambda: kpm_dos(ring_lattice(7, 3, 2), 16, vectors=3, seed=1),
                "BoseHubbardLevels": lambda: ed.bose_hubbard(ring_lattice(7, 3, 1), 2, 2, 4.0, levels=3),
                "ChargeGap": lambda: ed.charge_gap(ring_lattice(7, 3, 1), 2, 2, 4.0)}

    def per_site():
        # results with one row per site (or grid point), found by the audit below
        from hyperlattice.bosons.gp import gp_ground_state
        from hyperlattice.bosons.meanfield import gutzwiller
        from hyperlattice.bosons.thermal import exact_thermal
        from hyperlattice.compare import boundary, qubits as cq
        from hyperlattice.continuum import gp as cgp
        from hyperlattice.graph.disorder import disorder
        from hyperlattice.graph.qubits import bound_state

        def disk_gp():
            return cgp.disk_gp(0.75, 0.057, 0.112, 20.0, cells=40)

        return {"GPState": lambda: gp_ground_state(ring_lattice(7, 3, 2), 10.0, 0.5),
                "GutzwillerState": lambda: gutzwiller(ring_lattice(7, 3, 2), 0.1, 0.5),
                "ThermalAverages": lambda: exact_thermal(ring_lattice(7, 3, 1), U=4.0, mu=1.0, beta=2.0, nmax=1),
                "BoundState": lambda: bound_state(ring_lattice(7, 3, 3), 0, -3.5, 0.2),
                "BoundaryCorrelator": lambda: boundary.boundary_correlator(ring_lattice(7, 3, 4), -3.5),
                "BulkToBoundary": lambda: boundary.bulk_to_boundary(ring_lattice(7, 3, 4), -3.5),
                "ExchangeComparison": lambda: cq.exchange_comparison(ring_lattice(7, 3, 4), -3.2, 0.1),
                "DiskGPState": disk_gp,
                "DiskBogoliubov": lambda: cgp.disk_bogoliubov(disk_gp(), 4),
                "Disorder": lambda: disorder(ring_lattice(7, 3, 2), "box", 2.0, seed=1, realization=3)}

    def comparisons():
        # tables that were built from annotation samples: now small real computations, so that the
        # round trip compares real rows
        from hyperlattice.bosons.meanfield import mott_lobe
        from hyperlattice.compare import boundary, disorder as cd, levels as lv, limits as lim
        from hyperlattice.compare.bosons import mott_gap_comparison
        from hyperlattice.compare.correlation import bin_by_distance
        from hyperlattice.compare.qubits import bound_state_sizes
        from hyperlattice.continuum.spectrum import continuum_levels

        lat3 = ring_lattice(7, 3, 3)

        def trend():
            rings, e0, _ = lim.reference_levels(7, 3)
            rings, e0 = rings[:4], e0[:4]
            return lv.relative_error_trend(rings, e0, [continuum_levels(7, 3, rings=int(x), levels=1).energies[0]
                                                       for x in rings])

        def side_by_side():
            from hyperlattice.graph.spectrum import lowest_levels

            return lv.levels_side_by_side(lowest_levels(ring_lattice(7, 3, 2), 3),
                                          continuum_levels(7, 3, rings=2, levels=3))

        return {
            "BinnedCorrelation": lambda: bin_by_distance([0.4, 0.6, 1.5, 2.2], [1.0, 3.0, 5.0, 2.0], width=1.0),
            "BoundStateSizes": lambda: bound_state_sizes(ring_lattice(7, 3, 4), [-3.0, -3.5], 0.1),
            "DeltaCurve": lambda: boundary.delta_curve(ring_lattice(7, 3, 5), [-3.5, -4.0]),
            "LatticeBFBound": lambda: boundary.lattice_bf_bound(7, 3, rings=(3, 4)),
            "DisorderGreen": lambda: cd.green_ensemble(lat3, -3.5 + 0.1j, 1.0, realizations=2, seed=1),
            "RScan": lambda: cd.r_scan(lat3, [0.5, 4.0], realizations=2, window=None),
            "SCBAComparison": lambda: cd.compare_scba(lat3, -3.5 + 0.1j, [0.5, 1.0], realizations=2, seed=1),
            "LevelComparison": side_by_side,
            "LevelCount": lambda: lv.graph_levels_below(ring_lattice(7, 3, 2)),
            "PartitionComparison": lambda: lv.partition_functions(lv.graph_levels_below(ring_lattice(7, 3, 2)),
                                                                  lv.continuum_levels_below(7, 3, rings=2),
                                                                  [0.5, 1.0, 2.0]),
            "RelativeErrorTrend": trend,
            "PlateauAnalysis": lambda: lim.plateau_analysis(_build("BandBottom")),
            "MottLobe": lambda: mott_lobe(3.0, points=21),
            "MottGapComparison": lambda: mott_gap_comparison(ring_lattice(7, 3, 1), [0.0, 0.05]),
        }

    out = {"Cluster": cluster, "DosComparison": dos, "SpinModel": spins, **tables(), **per_site(), **comparisons()}
    out["TemperingResult"] = _tempering
    out["ClassicalResult"] = _classical
    out["TwistMarker"] = _twist_marker
    out.update({k: (lambda k=k: bands(k)) for k in ("Windings", "Bands", "AbelianDOS")})
    out.update({k: (lambda k=k: limits(k)) for k in ("BandBottom", "SchurBound", "DictionaryComparison",
                                                     "BandBottomFit")})
    return out


def _twist_marker():
    from hyperlattice.graph.clusters import pbc_cluster
    from hyperlattice.topology.frames import qwz_frame_terms
    from hyperlattice.topology.twist_marker import twist_marker

    return twist_marker(qwz_frame_terms(pbc_cluster(8, 3, "bolza"), M=1.0), pairs=[(0, 1)])


def _classical():
    import warnings

    from hyperlattice.graph.lattice import ring_lattice
    from hyperlattice.spins import classical_mc

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")          # a short chain: its plateau warnings are not under test
        return classical_mc(ring_lattice(7, 3, 2), model="ising", J=-1.0, T=1.0, sweeps=64, seed=1,
                            progress=False)


def _tempering():
    import warnings

    from hyperlattice.graph.lattice import ring_lattice
    from hyperlattice.spins import tempering_mc

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")          # a short chain: its plateau warnings are not under test
        return tempering_mc(ring_lattice(7, 3, 2), model="ising", J=-1.0, T=[0.8, 1.2], sweeps=50, seed=1,
                            progress=False)


def _magnetic_comparison():
    from hyperlattice.compare.magnetic import magnetic_comparison

    return magnetic_comparison(7, 3, rings=[3], fluxes=[0.0, 0.1], levels=2)


_SAMPLES = {"int": 3, "float": 0.25, "str": "x", "bool": True, "complex": 1 - 2j, "dict": {2: np.arange(3.0)},
            "list": [1, 2.5], "tuple": (1, "a")}


def _sample(hint: str):
    """A value for a field annotated ``hint`` (a string such as ``'np.ndarray | None'``)."""
    first = hint.split("|")[0].strip()
    if "ndarray" in first:
        return np.array([0.5, -1.5, 2.0])
    if first in _SAMPLES:
        return _SAMPLES[first]
    cls = result_types().get(first)
    if cls is not None:
        return _generic(cls)
    raise LookupError(hint)


def _generic(cls):
    kwargs = {}
    for f in dataclasses.fields(cls):
        if f.init and f.default is dataclasses.MISSING and f.default_factory is dataclasses.MISSING:
            kwargs[f.name] = _sample(str(f.type))
    return cls(**kwargs)


_BUILT: dict = {}


def _build(tag: str):
    """One instance per tag (results are immutable, so tests may share them)."""
    if tag not in _BUILT:
        factory = _factories().get(tag)
        if factory is not None:
            _BUILT[tag] = factory()
        else:
            try:
                _BUILT[tag] = _generic(result_types()[tag])
            except (LookupError, ValueError, TypeError) as exc:  # fields that need real data
                pytest.skip(f"{tag} cannot be built from its annotations ({exc}); add a factory")
    return _BUILT[tag]


def _reading(tag: str, read):
    """``read()``; a type built from annotations may refuse that made-up data when it is read back."""
    try:
        return read()
    except ValueError as exc:
        if tag in _factories():
            raise
        pytest.skip(f"{tag} checks its data when read and the annotation sample fails ({exc}); add a factory")


def _norm(x):
    if isinstance(x, np.bool_):
        return bool(x)
    if isinstance(x, np.integer):
        return int(x)
    if isinstance(x, np.floating):
        return float(x)
    if isinstance(x, np.complexfloating):
        return complex(x)
    return x


def same(a, b, where="") -> None:
    """Exact equality of values, types, dtypes and shapes (NaN equals NaN, -0.0 is not 0.0)."""
    a, b = _norm(a), _norm(b)
    if isinstance(a, np.ndarray):
        assert isinstance(b, np.ndarray), where
        assert (a.dtype, a.shape) == (b.dtype, b.shape), where
        if a.dtype.kind in "fc":
            assert np.array_equal(a, b, equal_nan=True), where
            assert np.array_equal(np.signbit(a.real), np.signbit(b.real)), where
        else:
            assert np.array_equal(a, b), where
        return
    assert type(a) is type(b), f"{where}: {type(a).__name__} vs {type(b).__name__}"
    if isinstance(a, Result):
        for f in dataclasses.fields(a):
            if f.name not in a._TRANSIENT:
                same(getattr(a, f.name), getattr(b, f.name), f"{where}.{f.name}")
    elif isinstance(a, dict):
        assert list(a) == list(b) and [type(k) for k in a] == [type(k) for k in b], where
        for k in a:
            same(a[k], b[k], f"{where}[{k!r}]")
    elif isinstance(a, (list, tuple)):
        assert len(a) == len(b), where
        for i, (u, v) in enumerate(zip(a, b)):
            same(u, v, f"{where}[{i}]")
    elif isinstance(a, float):
        assert (a == b or (math.isnan(a) and math.isnan(b))) and math.copysign(1, a) == math.copysign(1, b), where
    elif isinstance(a, complex):
        same(a.real, b.real, where)
        same(a.imag, b.imag, where)
    else:
        assert a == b, where


def _arrays(value):
    if isinstance(value, np.ndarray):
        yield value
    elif isinstance(value, Result):
        for f in dataclasses.fields(value):
            yield from _arrays(getattr(value, f.name))
    elif isinstance(value, dict):
        for v in value.values():
            yield from _arrays(v)
    elif isinstance(value, (list, tuple)):
        for v in value:
            yield from _arrays(v)


TAGS = sorted(result_types()) + ["tests.LineGraph"]  # a Lattice of the other kind


@pytest.mark.parametrize("tag", TAGS)
def test_dict_round_trip_is_exact(tag):
    res = _build(tag)
    d = res.as_dict()
    text = json.dumps(d, allow_nan=False)  # strict JSON
    back = _reading(tag, lambda: type(res).from_dict(json.loads(text)))
    same(res, back, tag)
    assert json.dumps(back.as_dict(), allow_nan=False) == text
    same(Result.from_dict(json.loads(text)), res, tag)  # dispatch on "type" from the base


@pytest.mark.parametrize("suffix", [".json", ".npz"])
@pytest.mark.parametrize("tag", TAGS)
def test_file_round_trip_is_exact(tag, suffix, tmp_path):
    res = _build(tag)
    path = res.save(tmp_path / f"r{suffix}")
    same(res, _reading(tag, lambda: load_result(path)), tag)
    same(res, type(res).load(path), tag)


@pytest.mark.parametrize("tag", TAGS)
def test_arrays_read_only_and_eq_by_identity(tag):
    res = _build(tag)
    for a in _arrays(res):
        assert not a.flags.writeable
        if a.size:
            with pytest.raises(ValueError):
                a.flat[0] = a.flat[0]
    other = _reading(tag, lambda: type(res).from_dict(res.as_dict()))
    assert (res == res) is True and (res == other) is False and (res != other) is True
    json.dumps(to_jsonable(res.summary()), allow_nan=False)  # the CLI's view, as print_json writes it
    with pytest.raises(dataclasses.FrozenInstanceError):
        setattr(res, dataclasses.fields(res)[0].name, None)


# ---------------------------------------------------------------------------------------------
# defects of the first version, one regression test each
# ---------------------------------------------------------------------------------------------

def test_int_keys_survive():
    """ConvergenceStudy.errors is keyed by the order (int); keys came back as '2', '3', '4'."""
    from hyperlattice.compare.scaling import SmoothFunction, convergence_study
    from hyperlattice.graph.lattice import ring_lattice

    st = convergence_study(ring_lattice(7, 3, 3), SmoothFunction.exp_x())
    back = Result.from_dict(st.as_dict())
    assert list(back.errors) == [2, 3, 4] and back.exponents[2] == st.exponents[2]
    assert to_jsonable(back.summary()) == to_jsonable(st.summary())


def test_dtype_shape_and_strings_survive():
    e = _everything()
    back = Result.from_dict(json.loads(e.to_json()))
    assert back.int32.dtype == np.int32 and back.empty.shape == (0, 2) and back.empty.dtype == np.int32
    assert back.label == "nan" and isinstance(back.label, str)  # was turned into float('nan')
    assert back.pair == (1, 2.5, "x", (3,)) and back.by_int["type"] == "not a result"
    assert back.none_array is None and back.scalar == 0.1 - 2.5j and back.big == 2 ** 70


def test_nested_arrays_are_read_only():
    e = _everything()
    assert not e.by_int[2].flags.writeable and not e.nested.energies.flags.writeable


def test_summary_is_the_plain_view():
    lv = _levels()
    s = lv.summary()
    assert s["type"] == "Levels" and s["energies"] == [-2.9, -2.8, -2.8] and s["errors"][2] is None  # NaN is null in the display view (one convention)
    assert to_jsonable(lv) == s


@pytest.mark.parametrize("data, match", [
    ([1, 2], "dict"),
    ({"type": ["Levels"]}, "string"),
    ({"type": "NoSuchResult"}, "cannot be read"),
    ({"type": "Levels", "energies": [1.0]}, "lacks"),
    ({"type": "Levels", "bogus": 1}, "unknown fields"),
    ({**_levels().as_dict(), "energies": {"__ndarray__": "float64", "shape": [2], "data": [1.0]}}, "energies"),
    ({**_levels().as_dict(), "energies": {"__ndarray__": "nonsense", "shape": [1], "data": [1.0]}}, "energies"),
    ({**_levels().as_dict(), "p": {"__float__": "seven"}}, "p"),
    ({**_levels().as_dict(), "p": {"__complex__": 3}}, "p"),
])
def test_from_dict_bad_data_is_valueerror(data, match):
    with pytest.raises(ValueError, match=match):
        Result.from_dict(data)


def test_from_dict_of_other_class_refused():
    from hyperlattice.dictionary import ContinuumParameters

    with pytest.raises(ValueError, match="cannot be read as ContinuumParameters"):
        ContinuumParameters.from_dict(_levels().as_dict())


def test_load_bad_files_is_valueerror(tmp_path):
    cases = {"list.json": "[1, 2]", "text.json": "not json", "bad.npz": "not a zip file"}
    for name, text in cases.items():
        (tmp_path / name).write_text(text)
        with pytest.raises(ValueError):
            load_result(tmp_path / name)
    np.savez(tmp_path / "plain.npz", a=np.arange(3))
    with pytest.raises(ValueError, match="not a saved"):
        load_result(tmp_path / "plain.npz")
    meta = json.dumps({"type": "Levels", "p": 7})  # fields missing: was a TypeError
    np.savez(tmp_path / "short.npz", __meta__=np.array(meta), energies=np.zeros(2))
    with pytest.raises(ValueError, match="lacks"):
        load_result(tmp_path / "short.npz", require_checksum=False)
    np.savez(tmp_path / "meta.npz", __meta__=np.array("[1]"))
    with pytest.raises(ValueError):
        load_result(tmp_path / "meta.npz")
    with pytest.raises(ValueError):
        load_result(tmp_path / "missing.json")


def test_load_as_wrong_class(tmp_path):
    from hyperlattice.dictionary import ContinuumParameters

    path = _levels().save(tmp_path / "l.json")
    with pytest.raises(ValueError, match="not a ContinuumParameters"):
        ContinuumParameters.load(path)


@pytest.mark.parametrize("where", ["directory", "suffix", "missing-folder"])
def test_save_to_bad_path_is_valueerror(where, tmp_path):
    path = {"directory": tmp_path, "suffix": tmp_path / "r.txt", "missing-folder": tmp_path / "no" / "r.json"}[where]
    with pytest.raises(ValueError):
        _levels().save(path)


def test_unstorable_value_is_valueerror():
    @dataclasses.dataclass(frozen=True, eq=False, kw_only=True)
    class Holder(Result):
        TYPE = "tests.Holder"
        value: typing.Any

    with pytest.raises(ValueError, match="cannot be stored"):
        Holder(value=object()).as_dict()
    with pytest.raises(ValueError, match="cannot be stored"):
        Holder(value=np.array([object()])).as_dict()


def test_duplicate_type_tag_refused():
    with pytest.raises(TypeError, match="already used"):
        @dataclasses.dataclass(frozen=True, eq=False, kw_only=True)
        class Levels(Result):  # noqa: F811 - the point of the test
            x: int


def test_a_result_reads_back_in_a_fresh_interpreter(tmp_path):
    """Regression: load_result in a new process did not know types whose module was not imported
    yet (a saved MagneticComparison gave 'unknown result type')."""
    import subprocess
    import sys

    from hyperlattice.compare.magnetic import magnetic_comparison

    path = tmp_path / "cmp.npz"
    magnetic_comparison(7, 3, rings=(2,), fluxes=[0.0, 0.1], levels=1).save(path)
    code = ("import sys, hyperlattice as hl; r = hl.load_result(sys.argv[1]); "
            "print(type(r).__name__, r.rings.tolist())")
    out = subprocess.run([sys.executable, "-c", code, str(path)], capture_output=True, text=True, check=True)
    assert out.stdout.split() == ["MagneticComparison", "[2]"]


def test_one_json_display_convention_for_api_and_cli():
    """The CLI's encoder is the package's: NaN -> null, +-inf -> "inf"/"-inf", in both."""
    from hyperlattice.cli._common import to_jsonable as cli_encode

    data = {"a": np.array([1.0, np.nan, np.inf, -np.inf]), "b": complex(np.nan, 1.0)}
    want = {"a": [1.0, None, "inf", "-inf"], "b": {"re": None, "im": 1.0}}
    assert to_jsonable(data) == cli_encode(data) == want
    json.dumps(want, allow_nan=False)  # strict JSON


# ----------------------------------------------------------------------------
# tables (pandas) and grids (xarray), declared on the class (issue 21)
# ----------------------------------------------------------------------------

TABLES = [tag for tag in TAGS if tag in result_types() and result_types()[tag].COLUMNS]
GRIDS = [tag for tag in TAGS if tag in result_types() and result_types()[tag].GRID is not None]


def test_the_tabular_results_are_declared():
    """The tables issue 21 asks for (levels, comparisons, disorder, Mott lobes, ...) declare a schema."""
    assert {"Levels", "Spectrum", "ContinuumSpectrum", "MagneticSpectrum", "MatrixSpectrum", "LevelCount",
            "DisorderEnsemble", "RScan", "SCBAComparison", "MottLobe", "MottGapComparison",
            "DictionaryComparison", "AbelianDOS", "LevelComparison", "DosComparison",
            "KPMDos", "CountingFit", "BoseHubbardLevels", "ChargeGap", "BoundaryCorrelator", "GreenComparison",
            "ExchangeComparison", "BandBottomFit", "FrameAngles", "GPState", "GutzwillerState"} <= set(TABLES)
    assert {"Butterfly", "MagneticComparison", "DirichletTable", "DosComparison", "SpinModel", "Bands"} <= set(GRIDS)
    for tag in TABLES:
        names = [c.name for c in result_types()[tag].COLUMNS]
        assert len(names) == len(set(names)) and all(c.unit for c in result_types()[tag].COLUMNS), tag


@pytest.mark.parametrize("tag", TABLES)
def test_to_dataframe_holds_the_arrays_and_their_units(tag):
    pd = pytest.importorskip("pandas")
    res = _build(tag)
    df = res.to_dataframe()
    assert isinstance(df, pd.DataFrame)
    declared = [c for c in res.COLUMNS if getattr(res, c.source) is not None]
    assert list(df.columns) == [c.name for c in declared]
    for c in declared:
        a = np.asarray(getattr(res, c.source))
        if a.dtype.kind == "U":       # text: pandas keeps its own string dtype
            assert df[c.name].tolist() == a.tolist(), (tag, c.name)
            continue
        assert df[c.name].to_numpy().dtype == a.dtype, (tag, c.name)
        np.testing.assert_array_equal(df[c.name].to_numpy(), a, err_msg=f"{tag}.{c.name}")
    assert df.attrs == {"type": res.TYPE, "units": {c.name: c.unit for c in declared}}
    df.iloc[0, 0] = df.iloc[0, 0]         # a copy: writing to the frame leaves the result alone


@pytest.mark.parametrize("tag", GRIDS)
def test_to_xarray_holds_the_grid_and_its_units(tag):
    pytest.importorskip("xarray")
    res = _build(tag)
    ds = res.to_xarray()
    assert ds.attrs["type"] == res.TYPE
    for v in res.GRID.variables:
        assert ds[v.name].dims == v.dims and ds[v.name].attrs["units"] == v.unit
        np.testing.assert_array_equal(ds[v.name].to_numpy(), np.asarray(getattr(res, v.source)))
    for c in res.GRID.coords:
        assert ds[c.name].attrs["units"] == c.unit
        if c.source:
            assert ds[c.name].to_numpy().tolist() == np.asarray(getattr(res, c.source)).tolist()
        else:
            np.testing.assert_array_equal(ds[c.name].to_numpy(), np.arange(ds.sizes[c.name]))


def test_new_tables_hold_the_physics():
    """The tables of issue 21, item 5: rows mean what the result says (not only the same arrays)."""
    pytest.importorskip("pandas")
    kpm = _build("KPMDos").to_dataframe()
    assert kpm["order"].tolist() == list(range(16)) and kpm["mu"][0] == 1.0      # T_0 = 1: mu_0 = 1 exactly
    gap = _build("ChargeGap")
    df = gap.to_dataframe()
    assert df["particles"].tolist() == [1, 2, 3]
    e = df.set_index("particles")["ground_energy"]
    assert math.isclose(e[1], -2.0, abs_tol=1e-12)    # one boson: the band bottom -2t of the 7-ring
    assert math.isclose(e[3] + e[1] - 2 * e[2], gap.gap, rel_tol=1e-12)
    bh = _build("BoseHubbardLevels")
    levels = bh.to_dataframe()
    assert math.isclose(levels["energy"][0], e[2], abs_tol=bh.tolerance[0])   # N = 2, U = 4 by two routes
    assert levels["m"].tolist()[:3] == [0, 1, -1] and (levels["residual"] <= levels["tolerance"]).all()
    fit = _build("CountingFit")
    df = fit.to_dataframe()
    np.testing.assert_allclose(df["rho"], (1 + df["r"] ** 2) / (1 - df["r"] ** 2), rtol=1e-14)
    from hyperlattice.graph.lattice import ring_lattice

    # N(r) counts the sites within radius r: rising, and all of them at the last radius
    assert df["count"].is_monotonic_increasing and df["count"].iloc[-1] == ring_lattice(7, 3, 4).z.size


def _row_arrays(res) -> dict[str, tuple[int, ...]]:
    """The 1-d numeric arrays of a result, fields and properties, by name: what could be table columns."""
    found = {}
    names = [f.name for f in dataclasses.fields(res)]
    names += [n for n in dir(type(res)) if isinstance(getattr(type(res), n, None), property)]
    for name in names:
        try:
            v = getattr(res, name)
        except Exception:  # noqa: BLE001 - a property that needs data this instance lacks
            continue
        if isinstance(v, np.ndarray) and v.ndim == 1 and v.dtype.kind in "biufc":
            found[name] = v.shape[0]
    return found


def _untabled_rows(res) -> list[str] | None:
    """The names of two or more equal-length 1-d numeric arrays of a result type that declares neither
    COLUMNS nor GRID nor NOT_TABULAR (a table that slipped through), else None."""
    if res.COLUMNS or res.GRID is not None or res.NOT_TABULAR:
        return None
    by_length: dict[int, list[str]] = {}
    for name, n in _row_arrays(res).items():
        by_length.setdefault(n, []).append(name)
    rows = max(by_length.values(), key=len, default=[])
    return sorted(rows) if len(rows) >= 2 else None


@pytest.mark.parametrize("tag", TAGS)
def test_every_tabular_result_declares_its_table(tag):
    """The audit of issue 21, item 5: a result with two or more 1-d numeric arrays of one length
    (rows) declares COLUMNS, GRID or, with a reason, NOT_TABULAR; a new result cannot slip."""
    res = _build(tag)
    assert _untabled_rows(res) is None, (
        f"{tag} has rows {_untabled_rows(res)} but declares no COLUMNS, GRID or NOT_TABULAR")
    assert not (res.NOT_TABULAR and (res.COLUMNS or res.GRID is not None)), tag
    if res.NOT_TABULAR:            # the opt-out only where the audit would otherwise fire
        assert isinstance(res.NOT_TABULAR, str) and res.NOT_TABULAR.strip(), tag
        assert any(list(_row_arrays(res).values()).count(n) >= 2 for n in _row_arrays(res).values()), tag


def test_the_tables_page_lists_every_table_and_grid():
    """docs/tables.md has one row per declared table, grid and NOT_TABULAR reason, as the code says."""
    import re

    text = (Path(__file__).resolve().parents[1] / "docs" / "tables.md").read_text()
    listed = set(re.findall(r"^\| `([\w.]+)` \| `[\w.]+` \| (table|grid|neither) \|", text, re.M))
    declared = set()
    for tag, cls in result_types().items():
        if tag.startswith("tests."):
            continue
        declared |= {(tag, kind) for kind, on in (("table", cls.COLUMNS), ("grid", cls.GRID is not None),
                                                   ("neither", cls.NOT_TABULAR)) if on}
    assert listed == declared, (sorted(declared - listed), sorted(listed - declared))
    for tag, kind in declared:        # and the columns with their units, as declared
        cls = result_types()[tag]
        if kind == "table":
            assert ", ".join(f"`{c.name}` ({c.unit})" for c in cls.COLUMNS) in text, tag


def test_the_audit_catches_an_undeclared_table():
    @dataclasses.dataclass(frozen=True, eq=False, kw_only=True)
    class Untabled(Result):
        TYPE = "tests.Untabled"
        x: np.ndarray
        y: np.ndarray
        label: str

    @dataclasses.dataclass(frozen=True, eq=False, kw_only=True)
    class Derived(Result):       # a property counts as much as a field
        TYPE = "tests.Derived"
        x: np.ndarray

        @property
        def x2(self) -> np.ndarray:
            return self.x**2

    assert _untabled_rows(Untabled(x=np.arange(4.0), y=np.ones(4), label="a")) == ["x", "y"]
    assert _untabled_rows(Untabled(x=np.arange(4.0), y=np.ones(5), label="a")) is None   # two lengths
    assert _untabled_rows(Untabled(x=np.arange(4.0), y=np.array(["a"] * 4), label="a")) is None  # text
    assert _untabled_rows(Derived(x=np.arange(3.0))) == ["x", "x2"]


def test_levels_without_m_leave_the_column_out():
    pytest.importorskip("pandas")
    lev = dataclasses.replace(_levels(), m=None)
    assert list(lev.to_dataframe().columns) == ["energy", "n", "degeneracy", "error"]


def test_a_result_that_is_no_table_says_so():
    res = _build("TilingConstants")
    with pytest.raises(NotImplementedError, match="^TilingConstants is not a table"):
        res.to_dataframe()
    with pytest.raises(NotImplementedError, match="^TilingConstants is not a grid"):
        res.to_xarray()


@pytest.mark.parametrize("module, extra, call", [("pandas", "pandas", "to_dataframe"),
                                                  ("xarray", "xarray", "to_xarray")])
def test_missing_pandas_or_xarray_names_the_extra(monkeypatch, module, extra, call):
    import builtins

    real_import = builtins.__import__

    def no_module(name, *args, **kwargs):
        if name == module or name.startswith(module + "."):
            raise ImportError(f"No module named {name!r}")
        return real_import(name, *args, **kwargs)

    monkeypatch.delitem(sys.modules, module, raising=False)
    monkeypatch.setattr(builtins, "__import__", no_module)
    monkeypatch.setattr(importlib, "import_module", lambda name, *a: no_module(name))
    res = _build("Butterfly" if call == "to_xarray" else "Spectrum")
    with pytest.raises(ImportError) as info:
        getattr(res, call)()
    assert str(info.value) == (f"this export needs {module}, which is not installed: "
                               f'pip install "hyperlattice[{extra}]".')
