r"""The result protocol: one shape for everything a computation hands back.

Every result of hyperlattice (a graph spectrum, continuum levels, a Green-function comparison,
a fit) is a :class:`Result`:

* a frozen dataclass with ``eq=False``: results hold arrays, and ``==`` between arrays has no
  single truth value, so results compare by identity (compare fields explicitly instead);
* its numpy arrays are read-only (``result.energies[0] = 1`` raises), so a result cannot be
  changed behind the back of a cache or a figure that already used it;
* :meth:`Result.as_dict` / :meth:`Result.from_dict` round-trip it exactly through plain JSON
  types (arrays become lists, complex numbers ``{"re", "im"}``, with a ``"type"`` tag), and
  :meth:`Result.save` / :func:`load_result` through ``.json`` or ``.npz`` files;
* :meth:`Result.summary` is the short JSON view the CLI prints (a stable contract);
* :meth:`Result.plot` draws it on a matplotlib ``ax`` and returns the axes, where a plot makes
  sense.

:class:`Levels` is the shared shape of a list of energy levels, on the graph and in the
continuum alike: ``energies``, ``n``, ``m``, ``degeneracy``, ``errors`` (a residual or an error
estimate, see ``error_kind``), a short ``method`` label and a ``description``, so that a graph
spectrum and a continuum spectrum can be compared field by field (:func:`compare_levels`).

This module imports only numpy (matplotlib only inside ``plot``): every layer may use it.
"""

from __future__ import annotations

import dataclasses
import json
import math
import typing
from pathlib import Path
from typing import Any, ClassVar

import numpy as np

__all__ = ["Result", "Levels", "load_result", "to_jsonable", "from_jsonable", "result_types"]

_REGISTRY: dict[str, type] = {}


def result_types() -> dict[str, type]:
    """Every registered result class by its ``type`` tag (for :func:`load_result`)."""
    return dict(_REGISTRY)


# ----------------------------------------------------------------------------
# JSON encoding of numbers and arrays
# ----------------------------------------------------------------------------

def _float(x: float):
    x = float(x)
    if math.isnan(x):
        return "nan"
    if math.isinf(x):
        return "inf" if x > 0 else "-inf"
    return x


def to_jsonable(obj):
    """Plain JSON types for numbers, arrays, tuples, dicts and results.

    Complex numbers become ``{"re": x, "im": y}``, non-finite floats the strings
    ``"inf"``, ``"-inf"``, ``"nan"`` (strict JSON has no such numbers); arrays become nested
    lists (complex arrays ``{"re": [...], "im": [...]}``).
    """
    if isinstance(obj, Result):
        return obj.as_dict()
    if isinstance(obj, dict):
        return {str(k): to_jsonable(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [to_jsonable(v) for v in obj]
    if isinstance(obj, np.ndarray):
        if np.iscomplexobj(obj):
            return {"re": to_jsonable(obj.real), "im": to_jsonable(obj.imag)}
        return to_jsonable(obj.tolist())
    if isinstance(obj, (bool, np.bool_)):
        return bool(obj)
    if isinstance(obj, np.integer):
        return int(obj)
    if isinstance(obj, (float, np.floating)):
        return _float(obj)
    if isinstance(obj, (complex, np.complexfloating)):
        return {"re": _float(obj.real), "im": _float(obj.imag)}
    if isinstance(obj, Path):
        return str(obj)
    return obj


def _number(x):
    if isinstance(x, str) and x in ("nan", "inf", "-inf"):
        return float(x)
    return x


def from_jsonable(obj):
    """Inverse of :func:`to_jsonable` for scalars: ``"inf"`` and ``{"re", "im"}`` back to numbers."""
    if isinstance(obj, dict):
        if set(obj) == {"re", "im"} and not isinstance(obj["re"], list):
            return complex(_number(obj["re"]), _number(obj["im"]))
        return {k: from_jsonable(v) for k, v in obj.items()}
    if isinstance(obj, list):
        return [from_jsonable(v) for v in obj]
    return _number(obj)


def _array_from(value, dtype=None) -> np.ndarray:
    if isinstance(value, dict) and set(value) == {"re", "im"}:
        return _array_from(value["re"], float) + 1j * _array_from(value["im"], float)

    def conv(v):
        if isinstance(v, list):
            return [conv(u) for u in v]
        return _number(v)

    return np.asarray(conv(value), dtype=dtype)


# ----------------------------------------------------------------------------
# the base class
# ----------------------------------------------------------------------------

def _is_array_field(f: dataclasses.Field, hints: dict) -> bool:
    hint = hints.get(f.name, f.type)
    return "ndarray" in str(hint)


def _freeze(a: np.ndarray) -> np.ndarray:
    if a.flags.writeable:
        if not a.flags.owndata and a.base is not None:
            a = a.copy()  # do not flip the flag on somebody else's buffer
        a.setflags(write=False)
    return a


class Result:
    """Base of all result objects (see the module docstring).

    Subclasses are ``@dataclass(frozen=True, eq=False, kw_only=True)``; fields annotated as
    ``np.ndarray`` are converted with :func:`numpy.asarray` and made read-only at birth.
    ``TYPE`` is the tag written by :meth:`as_dict` (default: the class name).
    """

    TYPE: ClassVar[str] = ""
    #: fields left out of as_dict() (e.g. derived caches); eigenvectors are kept
    _TRANSIENT: ClassVar[tuple[str, ...]] = ()

    def __init_subclass__(cls, **kwargs):
        super().__init_subclass__(**kwargs)
        tag = cls.__dict__.get("TYPE") or cls.__name__
        cls.TYPE = tag
        _REGISTRY[tag] = cls

    # dataclasses call __post_init__ if it exists
    def __post_init__(self) -> None:
        hints = _hints(type(self))
        for f in dataclasses.fields(self):
            v = getattr(self, f.name)
            if isinstance(v, np.ndarray) or (v is not None and _is_array_field(f, hints)):
                object.__setattr__(self, f.name, _freeze(np.asarray(v)))

    # -- dict / JSON -----------------------------------------------------------------
    def as_dict(self) -> dict:
        """Every field as plain JSON types plus ``"type"``; :meth:`from_dict` inverts it exactly."""
        out: dict[str, Any] = {"type": self.TYPE}
        for f in dataclasses.fields(self):
            if f.name in self._TRANSIENT:
                continue
            out[f.name] = to_jsonable(getattr(self, f.name))
        return out

    @classmethod
    def from_dict(cls, data: dict):
        """Rebuild a result from :meth:`as_dict` output (dispatching on ``"type"`` from the base)."""
        if not isinstance(data, dict):
            raise ValueError(f"a result is stored as a dict, got {type(data).__name__}.")
        tag = data.get("type", cls.TYPE)
        target = _REGISTRY.get(tag) if cls is Result else cls
        if target is None or (cls is not Result and tag != cls.TYPE):
            raise ValueError(f"stored result of type {tag!r} cannot be read as {cls.__name__}.")
        hints = _hints(target)
        kwargs = {}
        names = {f.name for f in dataclasses.fields(target)}
        unknown = set(data) - names - {"type"}
        if unknown:
            raise ValueError(f"stored {tag} has unknown fields {sorted(unknown)}.")
        for f in dataclasses.fields(target):
            if f.name not in data:
                if f.default is dataclasses.MISSING and f.default_factory is dataclasses.MISSING:
                    raise ValueError(f"stored {tag} lacks the field {f.name!r}.")
                continue
            v = data[f.name]
            if v is not None and _is_array_field(f, hints):
                kwargs[f.name] = _array_from(v)
            else:
                kwargs[f.name] = _field_value(v, hints.get(f.name))
        return target(**kwargs)

    def to_json(self) -> str:
        """:meth:`as_dict` as a JSON string."""
        return json.dumps(self.as_dict())

    def summary(self) -> dict:
        """The short JSON view printed by the CLI (default: :meth:`as_dict`)."""
        return self.as_dict()

    # -- files -------------------------------------------------------------------------
    def save(self, path) -> Path:
        """Write the result to ``path`` (``.json`` or ``.npz``, by suffix) and return the path."""
        from . import _validate

        path = _validate.output_path("path", path, suffixes=(".json", ".npz"))
        if path.suffix == ".json":
            path.write_text(self.to_json())
            return path
        arrays = {}
        meta = {"type": self.TYPE}
        hints = _hints(type(self))
        for f in dataclasses.fields(self):
            if f.name in self._TRANSIENT:
                continue
            v = getattr(self, f.name)
            if isinstance(v, np.ndarray) and _is_array_field(f, hints):
                arrays[f.name] = v
            else:
                meta[f.name] = to_jsonable(v)
        np.savez(path, __meta__=np.array(json.dumps(meta)), **arrays)
        return path

    @classmethod
    def load(cls, path):
        """Read a result written by :meth:`save`."""
        res = load_result(path)
        if cls is not Result and not isinstance(res, cls):
            raise ValueError(f"{path} holds a {type(res).__name__}, not a {cls.__name__}.")
        return res

    # -- figures -----------------------------------------------------------------------
    def plot(self, ax=None):
        """Draw the result on ``ax`` (a new figure if None) and return the axes."""
        raise NotImplementedError(f"{type(self).__name__} has no standard plot.")


def _hints(cls) -> dict:
    try:
        return typing.get_type_hints(cls)
    except Exception:  # pragma: no cover - forward references that cannot be resolved
        return {f.name: f.type for f in dataclasses.fields(cls)}


def _field_value(v, hint):
    if isinstance(v, dict) and v.get("type") in _REGISTRY and "Result" not in str(hint or ""):
        return Result.from_dict(v)
    if isinstance(v, dict) and "type" in v and v["type"] in _REGISTRY:
        return Result.from_dict(v)
    return from_jsonable(v)


def load_result(path) -> Result:
    """Read any result written by :meth:`Result.save` (``.json`` or ``.npz``)."""
    from . import _validate

    path = _validate.input_path("path", path, suffixes=(".json", ".npz"))
    try:
        if path.suffix == ".json":
            return Result.from_dict(json.loads(path.read_text()))
        with np.load(path, allow_pickle=False) as data:
            if "__meta__" not in data:
                raise ValueError(f"{path} is not a saved hyperlattice result.")
            meta = json.loads(str(data["__meta__"]))
            arrays = {k: data[k] for k in data.files if k != "__meta__"}
    except (OSError, json.JSONDecodeError, UnicodeDecodeError) as exc:
        raise ValueError(f"cannot read a result from {path}: {exc}.") from None
    tag = meta.get("type")
    cls = _REGISTRY.get(tag)
    if cls is None:
        raise ValueError(f"{path} holds an unknown result type {tag!r}.")
    kwargs = {}
    hints = _hints(cls)
    for f in dataclasses.fields(cls):
        if f.name in arrays:
            kwargs[f.name] = arrays[f.name]
        elif f.name in meta:
            kwargs[f.name] = _field_value(meta[f.name], hints.get(f.name))
    return cls(**kwargs)


# ----------------------------------------------------------------------------
# levels: the shared shape of graph and continuum spectra
# ----------------------------------------------------------------------------

@dataclasses.dataclass(frozen=True, eq=False, kw_only=True)
class Levels(Result):
    r"""Energy levels with their labels, the same on the graph and in the continuum.

    Attributes
    ----------
    energies : ndarray, shape (K,)
        Ascending, in units of the hopping t (:math:`H = -tA`); a degenerate :math:`\pm m`
        pair appears twice (once per state).
    n : ndarray of int, shape (K,)
        Radial index 1, 2, ... within sector m.
    m : ndarray of int, shape (K,), or None
        Signed angular momentum in :math:`(-p/2, p/2]` (graph) or :math:`\mathbb Z`
        (continuum); a pair is listed +m first. None when the rotation is broken.
    errors : ndarray, shape (K,)
        Per level: the residual :math:`\|H\psi - E\psi\|` (graph) or a bound on the energy
        error (continuum); ``error_kind`` says which.
    error_kind : str
        ``"residual"`` or ``"energy error bound"``.
    method : str
        Short label of what ran (``"sector-sparse"``, ``"dirichlet-roots"``, ...).
    description : str
        One sentence on the method.
    p, q : int
        Schläfli symbol.
    """

    energies: np.ndarray
    n: np.ndarray
    m: np.ndarray | None
    errors: np.ndarray
    error_kind: str
    method: str
    description: str
    p: int
    q: int

    def __len__(self) -> int:
        return int(self.energies.shape[0])

    @property
    def degeneracy(self) -> np.ndarray:
        """Symmetry degeneracy of each level: 2 for a :math:`\\pm m` pair, else 1."""
        if self.m is None:
            return np.ones(len(self), dtype=int)
        if self.error_kind == "residual":  # lattice: m and -m = p - m coincide for m = p/2
            return np.where((2 * self.m) % self.p == 0, 1, 2)
        return np.where(self.m == 0, 1, 2)

    def table(self) -> list[dict]:
        """One dict per level: ``energy, n, m, degeneracy, error``."""
        m = [None] * len(self) if self.m is None else self.m.tolist()
        return [{"energy": float(e), "n": int(n), "m": mm, "degeneracy": int(g), "error": float(r)}
                for e, n, mm, g, r in zip(self.energies, self.n, m, self.degeneracy, self.errors)]

    def plot(self, ax=None, *, label: str | None = None, marker: str = "_", **kwargs):
        """Levels against m (the angular momentum), one marker per state; returns the axes."""
        from .plots import new_axes

        ax = new_axes(ax)
        x = np.zeros(len(self)) if self.m is None else self.m
        ax.plot(x, self.energies, linestyle="none", marker=marker, markersize=14,
                label=label or self.method, **kwargs)
        ax.set_xlabel("angular momentum m")
        ax.set_ylabel("energy E / t")
        return ax


def compare_levels(graph: Levels, continuum: Levels) -> dict:
    """Field-by-field comparison of two level lists of equal length.

    Returns the relative differences :math:`(E_g - E_c)/|E_g|`, whether the (n, m) labels agree
    level by level, and both error columns.
    """
    if not isinstance(graph, Levels) or not isinstance(continuum, Levels):
        raise ValueError("compare_levels takes two Levels results (a graph and a continuum spectrum).")
    k = min(len(graph), len(continuum))
    eg, ec = graph.energies[:k], continuum.energies[:k]
    same_m = None if graph.m is None or continuum.m is None else bool(np.all(graph.m[:k] == continuum.m[:k]))
    return {"levels": k, "relative_difference": (eg - ec) / np.abs(eg),
            "labels_agree": same_m and bool(np.all(graph.n[:k] == continuum.n[:k])),
            "graph_errors": graph.errors[:k], "continuum_errors": continuum.errors[:k]}


__all__.append("compare_levels")
