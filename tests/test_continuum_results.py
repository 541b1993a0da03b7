"""The continuum results follow the result protocol (issue 10, item 1): ContinuumSpectrum is a
Levels, DirichletTable and GreenInfo are Results; exact JSON/npz round trips, read-only arrays,
identity equality that does not raise, and the CLI's summary keys."""

from __future__ import annotations

import dataclasses
import json

import matplotlib
import numpy as np
import pytest

from hyperlattice.continuum.green import GreenInfo, continuum_green
from hyperlattice.continuum.spectrum import ContinuumSpectrum, DirichletTable, continuum_levels, dirichlet_levels
from hyperlattice.results import Levels, Result, compare_levels, load_result

matplotlib.use("Agg")

CLI_KEYS = {"p", "q", "rings", "radius", "h", "energies", "n", "m", "k", "asymptotic"}


def _results():
    _, info = continuum_green(0.3, 0.1j, 2.0 + 0.5j, 0.9, return_info=True)
    return {
        "spectrum(rings)": continuum_levels(7, 3, rings=4, levels=5),
        "spectrum(radius)": continuum_levels(8, 3, radius=0.8, levels=3),
        "table": dirichlet_levels(7, 3, radius=0.9, n_max=3, m_max=4),
        "green_info": info,
    }


RESULTS = _results()


def _same(a, b) -> bool:
    """Field-by-field exact equality (arrays: same dtype, shape and values)."""
    if type(a) is not type(b):
        return False
    for f in dataclasses.fields(a):
        x, y = getattr(a, f.name), getattr(b, f.name)
        if isinstance(x, np.ndarray):
            if not (isinstance(y, np.ndarray) and x.dtype == y.dtype and x.shape == y.shape
                    and np.array_equal(x, y)):
                return False
        elif x != y or type(x) is not type(y):
            return False
    return True


def test_types():
    assert isinstance(RESULTS["spectrum(rings)"], ContinuumSpectrum)
    assert isinstance(RESULTS["spectrum(rings)"], Levels)
    assert isinstance(RESULTS["table"], DirichletTable) and isinstance(RESULTS["table"], Result)
    assert isinstance(RESULTS["green_info"], GreenInfo) and isinstance(RESULTS["green_info"], Result)


@pytest.mark.parametrize("name", sorted(RESULTS))
def test_equality_is_identity_and_does_not_raise(name):
    """``continuum_levels(...) == continuum_levels(...)`` raised (dataclass eq on arrays)."""
    a = RESULTS[name]
    b = _results()[name]
    assert (a == a) is True
    assert (a == b) is False
    assert (a != b) is True


@pytest.mark.parametrize("name", sorted(RESULTS))
def test_dict_and_json_round_trip_exactly(name):
    a = RESULTS[name]
    d = json.loads(json.dumps(a.as_dict()))
    assert d["type"] == type(a).__name__
    assert _same(a, type(a).from_dict(d))
    assert _same(a, Result.from_dict(d))


@pytest.mark.parametrize("suffix", [".json", ".npz"])
@pytest.mark.parametrize("name", sorted(RESULTS))
def test_save_and_load_round_trip_exactly(name, suffix, tmp_path):
    a = RESULTS[name]
    path = a.save(tmp_path / f"r{suffix}")
    assert _same(a, load_result(path))
    assert _same(a, type(a).load(path))


@pytest.mark.parametrize("name", sorted(RESULTS))
def test_arrays_are_read_only_and_fields_frozen(name):
    a = RESULTS[name]
    arrays = [getattr(a, f.name) for f in dataclasses.fields(a) if isinstance(getattr(a, f.name), np.ndarray)]
    for arr in arrays:
        with pytest.raises(ValueError):
            arr[...] = 0
    with pytest.raises(dataclasses.FrozenInstanceError):
        a.p = 5  # type: ignore[misc]


def test_spectrum_fields_and_cli_summary():
    spec = RESULTS["spectrum(rings)"]
    assert set(spec.summary()) == CLI_KEYS
    assert spec.method == "dirichlet-roots" and spec.error_kind == "energy error bound"
    assert "Chandrupatla" in spec.description
    assert spec.errors.shape == spec.energies.shape and np.all(spec.errors > 0)
    assert list(spec.degeneracy) == [1, 2, 2, 2, 2]
    assert spec.table()[0]["m"] == 0
    # a graph and a continuum spectrum compare field by field
    cmp = compare_levels(spec, spec)
    assert cmp["labels_agree"] and np.all(cmp["relative_difference"] == 0)


def test_table_errors_and_shape():
    tab = RESULTS["table"]
    assert tab.k.shape == tab.energies.shape == tab.errors.shape == (3, 5)
    assert np.all(tab.errors > 0) and np.all(tab.errors < 1e-12)


@pytest.mark.parametrize("name", ["spectrum(rings)", "table"])
def test_plot_returns_the_axes(name):
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots()
    assert RESULTS[name].plot(ax=ax) is ax
    assert RESULTS[name].plot() is not None
    plt.close("all")


def test_green_info_fields():
    info = RESULTS["green_info"]
    assert info.method == "series" and info.converged and isinstance(info.nu, complex)
    assert info.rounding_estimate == 0.0
