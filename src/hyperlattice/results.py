r"""The result protocol: one shape for everything a computation hands back.

Every result of hyperlattice (a graph spectrum, continuum levels, a Green-function comparison,
a fit) is a :class:`Result`:

* a frozen dataclass with ``eq=False``: results hold arrays, and ``==`` between arrays has no
  single truth value, so results compare by identity (compare fields explicitly instead);
* its numpy arrays are read-only (``result.energies[0] = 1`` raises), also inside dict, list
  and tuple fields, so a result cannot be changed behind the back of a cache or a figure that
  already used it;
* :meth:`Result.as_dict` / :meth:`Result.from_dict` round-trip it *exactly* through strict JSON
  (see "Stored form" below), and :meth:`Result.save` / :func:`load_result` through ``.json`` or
  ``.npz`` files;
* :meth:`Result.summary` is the short JSON view the CLI prints (a stable contract; by default
  the plain view of :func:`to_jsonable`);
* :meth:`Result.plot` draws it on a matplotlib ``ax`` and returns the axes, where a plot makes
  sense (see "Figures" below).

:class:`Levels` is the shared shape of a list of energy levels, on the graph and in the
continuum alike: ``energies``, ``n``, ``m``, ``degeneracy``, ``errors`` (a residual or an error
estimate, see ``error_kind``), a short ``method`` label and a ``description``, so that a graph
spectrum and a continuum spectrum can be compared field by field (:func:`compare_levels`).

Stored form
-----------
:meth:`Result.as_dict` gives ``{"type": tag, field: value, ...}`` in strict JSON types. Values
that JSON cannot hold exactly are written as one-key objects whose key starts with ``__``:

* an array: ``{"__ndarray__": "int32", "shape": [2, 3], "data": [...]}`` (``data`` flat, in C
  order; complex arrays have ``"real"`` and ``"imag"`` instead; non-finite floats are the
  strings ``"nan"``, ``"inf"``, ``"-inf"``), so dtype and shape survive, empty arrays included;
* a non-finite float ``{"__float__": "inf"}``, a complex number ``{"__complex__": [re, im]}``,
  a tuple ``{"__tuple__": [...]}``, a dict whose keys are not plain strings (``{2: ...}``)
  ``{"__dict__": [[key, value], ...]}``, a path ``{"__path__": "..."}``;
* a nested result: its own ``as_dict()`` (recognised by its ``"type"``).

Figures
-------
Result types do not import the plotting layer, and :mod:`hyperlattice.plots` does not hand
drawings back through methods: ``plots`` registers one function per result type with
:func:`register_plotter` (a decorator next to each drawing), and :meth:`Result.plot` looks the
function up by the result's ``TYPE`` (nearest base class first). When ``plots`` was never
imported, the look-up imports it by name (:func:`importlib.import_module`), once: imports run
one way, from ``plots`` down to the results, and ``import hyperlattice.graph.lattice`` never
loads matplotlib. See ``docs/architecture.md`` for the layer rule.

This module imports only numpy: every layer may use it.
"""

from __future__ import annotations

import dataclasses
import functools
import hashlib
import importlib
import json
import math
import sys
import typing
import zipfile
from pathlib import Path
from typing import TYPE_CHECKING, Any, Callable, ClassVar

import numpy as np

if TYPE_CHECKING:
    from matplotlib.axes import Axes

__all__ = ["Result", "Levels", "load_result", "to_jsonable", "from_jsonable", "result_types",
           "register_plotter", "plotter", "Column", "Grid", "INDEX"]

_REGISTRY: dict[str, type] = {}


def result_types() -> dict[str, type]:
    """Every registered result class by its ``type`` tag (for :func:`load_result`).

    A class registers itself when its module is imported, so the table grows as more of the
    package is used.

    Returns
    -------
    dict of str to type
        A copy of the registry: ``type`` tag (the class name) to :class:`Result` subclass.

    See Also
    --------
    load_result : uses the tag stored in a file to pick the class.

    Examples
    --------
    >>> from hyperlattice.results import Levels, result_types
    >>> result_types()["Levels"] is Levels
    True
    """
    return dict(_REGISTRY)


# ----------------------------------------------------------------------------
# figures: plots/ registers a drawing per result type; Result.plot asks here
# ----------------------------------------------------------------------------

#: drawing function of each result type tag, filled by hyperlattice.plots when it is imported
_PLOTTERS: dict[str, Callable] = {}
_PLOTS_PACKAGE = "hyperlattice.plots"


def register_plotter(kind) -> Callable:
    """Decorator: the function draws results of ``kind`` (a result class or its ``TYPE`` tag).

    The function is called as ``func(result, ax=ax, **kwargs)`` by :meth:`Result.plot` and
    returns the axes. Only :mod:`hyperlattice.plots` registers; a subclass without a drawing of
    its own uses the one of its nearest registered base class.

    Parameters
    ----------
    kind : type or str
        A :class:`Result` subclass or its ``TYPE`` tag.

    Returns
    -------
    callable
        The decorator; it stores the function and returns it unchanged.

    Raises
    ------
    ValueError
        If ``kind`` is neither a Result class nor a non-empty tag.

    See Also
    --------
    plotter : the look-up used by :meth:`Result.plot`.

    Examples
    --------
    >>> from hyperlattice.results import register_plotter
    >>> register_plotter(42)
    Traceback (most recent call last):
    ...
    ValueError: a plotter is registered for a result class or its type tag, got 42.
    """
    tag = kind.TYPE if isinstance(kind, type) and issubclass(kind, Result) else kind
    if not isinstance(tag, str) or not tag:
        raise ValueError(f"a plotter is registered for a result class or its type tag, got {kind!r}.")

    def register(func: Callable) -> Callable:
        _PLOTTERS[tag] = func
        return func

    return register


def plotter(kind: type) -> Callable | None:
    """The drawing registered for result class ``kind`` (or its nearest base), or None.

    The first look-up imports :mod:`hyperlattice.plots` by name (:func:`importlib.import_module`),
    which registers every drawing: result modules never import the plotting layer themselves.

    Parameters
    ----------
    kind : type
        A :class:`Result` subclass.

    Returns
    -------
    callable or None
        ``func(result, ax=None, **kwargs) -> Axes``, or None when no drawing is registered for
        the class or any of its bases.

    See Also
    --------
    register_plotter

    Examples
    --------
    >>> from hyperlattice.results import plotter
    >>> from hyperlattice.graph.spectrum import Spectrum
    >>> plotter(Spectrum).__name__
    'plot_levels'
    """
    if sys.modules.get(_PLOTS_PACKAGE) is None:
        importlib.import_module(_PLOTS_PACKAGE)
    for klass in kind.__mro__:
        if klass is not Result and issubclass(klass, Result) and klass.TYPE in _PLOTTERS:
            return _PLOTTERS[klass.TYPE]
    return None


# ----------------------------------------------------------------------------
# tables and grids: declared on the class, exported to pandas / xarray
# ----------------------------------------------------------------------------

#: the ``source`` of a grid coordinate that is just the position 0, 1, 2, ... along its axis
INDEX = ""


@dataclasses.dataclass(frozen=True)
class Column:
    """One column of a result's table (or one variable or coordinate of its grid).

    ``name`` is the column's name in the table, ``source`` the attribute of the result that holds
    its values (a field or a property; :data:`INDEX` for a grid coordinate 0, 1, 2, ...), ``unit``
    its unit in words (``"t"``: the hopping, the energy unit of every Hamiltonian here; ``"1"``:
    a pure number). ``dims`` names the grid axes of a grid variable (empty in a table).

    Attributes
    ----------
    name : str
        The column's name in the table (or the variable's or axis's name in the grid).
    source : str
        The attribute of the result holding the values, or :data:`INDEX`.
    unit : str
        The unit in words (``"t"``, ``"1"``, ``"flux quanta per p-gon"``, ...).
    dims : tuple of str
        The grid axes of a grid variable; empty in a table.

    Examples
    --------
    >>> from hyperlattice import Spectrum
    >>> Spectrum.COLUMNS[0]
    Column(name='energy', source='energies', unit='t', dims=())
    """

    name: str
    source: str
    unit: str
    dims: tuple[str, ...] = ()


@dataclasses.dataclass(frozen=True)
class Grid:
    """The grid of a result: ``coords`` (one :class:`Column` per axis, in order) and ``variables``
    (each :class:`Column` names its axes in ``dims``).

    Attributes
    ----------
    coords : tuple of Column
        One per axis, in order.
    variables : tuple of Column
        The gridded quantities; each names its axes in ``dims``.

    Examples
    --------
    >>> from hyperlattice import Butterfly
    >>> [c.name for c in Butterfly.GRID.coords], [(v.name, v.dims) for v in Butterfly.GRID.variables]
    (['flux', 'state'], [('energy', ('flux', 'state')), ('m', ('flux', 'state'))])
    """

    coords: tuple[Column, ...]
    variables: tuple[Column, ...]


def _optional(module: str, extra: str):
    """Import an optional dependency, or say in one sentence which extra installs it."""
    try:
        return importlib.import_module(module)
    except ImportError:
        raise ImportError(f"this export needs {module}, which is not installed: "
                          f'pip install "hyperlattice[{extra}]".') from None


# ----------------------------------------------------------------------------
# the plain (display) JSON view: lossy, for summaries and the CLI
# ----------------------------------------------------------------------------

def _float(x: float):
    x = float(x)
    if math.isnan(x):
        return "nan"
    if math.isinf(x):
        return "inf" if x > 0 else "-inf"
    return x


def _display_float(x: float):
    """The display view's one convention: NaN ("no value") is null, as pandas and most JSON
    readers take it; an infinity, which JSON has no number for, is the string "inf" / "-inf"."""
    x = float(x)
    if math.isnan(x):
        return None
    if math.isinf(x):
        return "inf" if x > 0 else "-inf"
    return x


def to_jsonable(obj) -> Any:
    """Plain JSON types for numbers, arrays, tuples, dicts and results (a display view).

    The package's one JSON encoder for what it prints (the CLI's ``--json``, summaries).
    Complex numbers become ``{"re": x, "im": y}``; NaN becomes ``null`` and an infinity the
    string ``"inf"`` or ``"-inf"`` (strict JSON has no such numbers); arrays become nested
    lists (complex arrays ``{"re": [...], "im": [...]}``); a result becomes its
    :meth:`Result.summary`. Not exactly invertible (dtypes, tuples and int keys are lost): the
    exact form is :meth:`Result.as_dict`, which keeps NaN as ``{"__float__": "nan"}``.

    Parameters
    ----------
    obj : object
        A number, numpy scalar or array, list, tuple, dict, :class:`~pathlib.Path`,
        :class:`Result` or any JSON-ready value (returned as it is).

    Returns
    -------
    object
        The same data in plain JSON types (dict, list, str, int, float, bool, None).

    See Also
    --------
    from_jsonable : back to numbers.
    Result.as_dict : the exact, invertible form.

    Examples
    --------
    >>> import numpy as np
    >>> from hyperlattice.results import to_jsonable
    >>> to_jsonable({"E": np.array([1.0, np.nan]), "z": 1 + 2j, "x": float("inf")})
    {'E': [1.0, None], 'z': {'re': 1.0, 'im': 2.0}, 'x': 'inf'}
    """
    if isinstance(obj, Result):
        return obj.summary()
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
        return _display_float(obj)
    if isinstance(obj, (complex, np.complexfloating)):
        return {"re": _display_float(obj.real), "im": _display_float(obj.imag)}
    if isinstance(obj, Path):
        return str(obj)
    return obj


def _number(x):
    if x is None:
        return math.nan
    if isinstance(x, str) and x in ("nan", "inf", "-inf"):
        return float(x)
    return x


def from_jsonable(obj) -> Any:
    """Inverse of :func:`to_jsonable` for scalars: ``null`` (NaN), ``"inf"`` and ``{"re", "im"}`` back to numbers.

    Parameters
    ----------
    obj : object
        Plain JSON data (as from :func:`to_jsonable` or :func:`json.loads`); lists and dicts are
        walked recursively.

    Returns
    -------
    object
        The same structure with ``None`` as NaN, ``"inf"``/``"-inf"``/``"nan"`` as floats and
        ``{"re": x, "im": y}`` (scalars) as complex numbers. Arrays stay lists.

    See Also
    --------
    to_jsonable

    Examples
    --------
    >>> from hyperlattice.results import from_jsonable
    >>> from_jsonable(["inf", None, 2])
    [inf, nan, 2]
    >>> from_jsonable({"re": 1.0, "im": 0.5})
    (1+0.5j)
    """
    if isinstance(obj, dict):
        if set(obj) == {"re", "im"} and not isinstance(obj["re"], list):
            return complex(_number(obj["re"]), _number(obj["im"]))
        return {k: from_jsonable(v) for k, v in obj.items()}
    if isinstance(obj, list):
        return [from_jsonable(v) for v in obj]
    return _number(obj)


# ----------------------------------------------------------------------------
# the exact stored form (see "Stored form" in the module docstring)
# ----------------------------------------------------------------------------

#: array dtypes stored exactly (bool, signed/unsigned integers, floats, complex, unicode)
_ARRAY_KINDS = "biufcU"


def _plain_key(k) -> bool:
    # "type" marks a nested result and "__..." our tagged values: such keys go the long way
    return isinstance(k, str) and k != "type" and not k.startswith("__")


def _encode_floats(values: list) -> list:
    return [v if math.isfinite(v) else _float(v) for v in values]


def _encode_array(a: np.ndarray) -> dict:
    if a.dtype.kind not in _ARRAY_KINDS:
        raise ValueError(f"an array of dtype {a.dtype} cannot be stored in a result.")
    if a.dtype.kind == "f" and a.dtype.itemsize > 8:
        raise ValueError(f"an array of dtype {a.dtype} cannot be stored exactly; use float64.")
    flat = a.ravel()
    out: dict[str, Any] = {"__ndarray__": a.dtype.str if a.dtype.kind == "U" else a.dtype.name,
                           "shape": list(a.shape)}
    if a.dtype.kind == "c":
        out["real"] = _encode_floats(flat.real.tolist())
        out["imag"] = _encode_floats(flat.imag.tolist())
    elif a.dtype.kind == "f":
        out["data"] = _encode_floats(flat.tolist())
    else:
        out["data"] = flat.tolist()
    return out


def _encode(obj):
    """``obj`` in the exact stored form (strict JSON types only)."""
    if isinstance(obj, Result):
        return obj.as_dict()
    if obj is None or isinstance(obj, (bool, str)):
        return obj
    if isinstance(obj, np.bool_):
        return bool(obj)
    if isinstance(obj, (int, np.integer)):
        return int(obj)
    if isinstance(obj, (float, np.floating)):
        x = float(obj)
        return x if math.isfinite(x) else {"__float__": _float(x)}
    if isinstance(obj, (complex, np.complexfloating)):
        return {"__complex__": [_encode(float(obj.real)), _encode(float(obj.imag))]}
    if isinstance(obj, np.ndarray):
        return _encode_array(obj)
    if isinstance(obj, tuple):
        return {"__tuple__": [_encode(v) for v in obj]}
    if isinstance(obj, list):
        return [_encode(v) for v in obj]
    if isinstance(obj, dict):
        if all(_plain_key(k) for k in obj):
            return {k: _encode(v) for k, v in obj.items()}
        return {"__dict__": [[_encode(k), _encode(v)] for k, v in obj.items()]}
    if isinstance(obj, Path):
        return {"__path__": str(obj)}
    raise ValueError(f"a value of type {type(obj).__name__} cannot be stored in a result.")


def _decode_floats(values) -> list:
    return [_number(v) for v in values]


def _decode_array(obj: dict) -> np.ndarray:
    dtype = np.dtype(obj["__ndarray__"])
    shape = tuple(int(n) for n in obj["shape"])
    if dtype.kind == "c":
        re = np.asarray(_decode_floats(obj["real"]), dtype=float)
        im = np.asarray(_decode_floats(obj["imag"]), dtype=float)
        flat = np.empty(re.shape, dtype=dtype)
        flat.real, flat.imag = re, im
    elif dtype.kind == "f":
        flat = np.asarray(_decode_floats(obj["data"]), dtype=dtype)
    else:
        flat = np.asarray(obj["data"], dtype=dtype)
    return flat.reshape(shape)


def _decode(obj):
    """Inverse of :func:`_encode`."""
    if isinstance(obj, list):
        return [_decode(v) for v in obj]
    if not isinstance(obj, dict):
        return obj
    if "type" in obj:
        return Result.from_dict(obj)
    if "__ndarray__" in obj:
        return _decode_array(obj)
    if len(obj) == 1:
        (key, value), = obj.items()
        if key == "__float__":
            return float(_number(value)) if value in ("nan", "inf", "-inf") else _bad(obj)
        if key == "__complex__":
            re, im = (_decode(v) for v in value)
            return complex(float(re), float(im))
        if key == "__tuple__":
            return tuple(_decode(v) for v in value)
        if key == "__dict__":
            return {_decode(k): _decode(v) for k, v in value}
        if key == "__path__":
            return Path(value)
    if any(isinstance(k, str) and k.startswith("__") for k in obj):
        _bad(obj)
    return {k: _decode(v) for k, v in obj.items()}


def _digest(meta: dict, arrays: dict | None = None) -> str:
    """sha256 of a stored result: the canonical JSON of ``meta`` (without its ``"sha256"``) and,
    for ``.npz`` files, each array's name, dtype, shape and bytes in name order."""
    h = hashlib.sha256()
    body = {k: v for k, v in meta.items() if k != "sha256"}
    h.update(json.dumps(body, sort_keys=True, separators=(",", ":"), allow_nan=False).encode())
    for name in sorted(arrays or {}):
        a = np.ascontiguousarray(arrays[name])
        h.update(f"\0{name}\0{a.dtype.str}\0{a.shape}\0".encode())
        h.update(a.tobytes())
    return h.hexdigest()


def _verify_digest(where: str, meta: dict, arrays: dict | None = None, *, required: bool = False) -> None:
    """Pop ``meta["sha256"]`` and check it; a file without one (hand-written, or its checksum
    deleted) is refused when ``required``, else not checked."""
    stored = meta.pop("sha256", None)
    if stored is None:
        if required:
            raise ValueError(f"{where} carries no checksum, so an edit of it could not be detected; "
                             "load_result(path, require_checksum=False) reads a file written by hand "
                             "(its types and invariants are still checked).")
        return
    try:
        ok = isinstance(stored, str) and stored == _digest(meta, arrays)
    except (ValueError, TypeError):     # a NaN or a non-JSON value typed into the file
        ok = False
    if not ok:
        raise ValueError(f"{where} fails its checksum: it was changed after hyperlattice wrote it, or is damaged.")


def _bad(obj):
    text = json.dumps(obj)
    raise ValueError(f"unreadable stored value {text[:60]}{'...' if len(text) > 60 else ''}.")


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


def _freeze_nested(v):
    """Read-only arrays inside dict/list/tuple fields too (containers rebuilt, same type)."""
    if isinstance(v, np.ndarray):
        return _freeze(v)
    if isinstance(v, dict):
        return {k: _freeze_nested(u) for k, u in v.items()}
    if isinstance(v, (list, tuple)):
        return type(v)(_freeze_nested(u) for u in v)
    return v


class Result:
    """Base of all result objects (see the module docstring).

    Subclasses are ``@dataclass(frozen=True, eq=False, kw_only=True)``; fields annotated as
    ``np.ndarray`` are converted with :func:`numpy.asarray` and made read-only at birth, and
    arrays inside dict, list or tuple fields are made read-only too.
    ``TYPE`` is the tag written by :meth:`as_dict` (default: the class name); two classes may
    not share a tag. The base has no fields of its own: each subclass documents its fields
    (with their units) under Attributes.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> import hyperlattice as hl
    >>> from hyperlattice.results import Result
    >>> spec = hl.lowest_levels(hl.ring_lattice(7, 3, 2), 2)
    >>> data = spec.as_dict()
    >>> data["type"], type(Result.from_dict(data)).__name__
    ('Spectrum', 'Spectrum')
    >>> with tempfile.TemporaryDirectory() as d:
    ...     back = Result.load(spec.save(pathlib.Path(d) / "spectrum.json"))
    >>> [round(float(e), 4) for e in back.energies]
    [-2.6364, -2.2833]
    """

    TYPE: ClassVar[str] = ""
    #: fields left out of as_dict() (e.g. derived caches); eigenvectors are kept
    _TRANSIENT: ClassVar[tuple[str, ...]] = ()
    #: the table of this result type (:meth:`to_dataframe`): 1-d columns of equal length;
    #: empty for a result that is not a table
    COLUMNS: ClassVar[tuple[Column, ...]] = ()
    #: the grid of this result type (:meth:`to_xarray`), or None
    GRID: ClassVar[Grid | None] = None
    #: why a result type that holds equal-length 1-d arrays is nevertheless neither a table nor a
    #: grid (one sentence); empty for every other type. The tests hold every result type with two
    #: or more 1-d numeric arrays of one length to COLUMNS, GRID or this reason.
    NOT_TABULAR: ClassVar[str] = ""

    def __init_subclass__(cls, **kwargs):
        super().__init_subclass__(**kwargs)
        tag = cls.__dict__.get("TYPE") or cls.__name__
        old = _REGISTRY.get(tag)
        if old is not None and (old.__module__, old.__qualname__) != (cls.__module__, cls.__qualname__):
            # two results with one tag could not be told apart when loading: a programming error
            raise TypeError(f"result type tag {tag!r} of {cls.__module__}.{cls.__qualname__} is "
                            f"already used by {old.__module__}.{old.__qualname__}; set TYPE.")
        cls.TYPE = tag
        _REGISTRY[tag] = cls

    # dataclasses call __post_init__ if it exists
    def __post_init__(self) -> None:
        hints = _hints(type(self))
        for f in dataclasses.fields(self):
            v = getattr(self, f.name)
            if v is not None and not isinstance(v, np.ndarray) and _is_array_field(f, hints):
                object.__setattr__(self, f.name, _freeze(np.asarray(v)))
            elif isinstance(v, (np.ndarray, dict, list, tuple)):
                object.__setattr__(self, f.name, _freeze_nested(v))

    # -- dict / JSON -----------------------------------------------------------------
    def as_dict(self) -> dict:
        """Every field in the exact stored form plus ``"type"``; :meth:`from_dict` inverts it exactly."""
        out: dict[str, Any] = {"type": self.TYPE}
        for f in dataclasses.fields(self):
            if f.name in self._TRANSIENT:
                continue
            try:
                out[f.name] = _encode(getattr(self, f.name))
            except ValueError as exc:
                raise ValueError(f"{self.TYPE}.{f.name}: {exc}") from None
        return out

    @classmethod
    def from_dict(cls, data: dict) -> "Result":
        """Rebuild a result from :meth:`as_dict` output (dispatching on ``"type"`` from the base).

        Parameters
        ----------
        data : dict
            The output of :meth:`as_dict` (or its JSON round trip).

        Returns
        -------
        Result
            A result of the type named by ``data["type"]``.

        Raises
        ------
        ValueError
            If ``data`` is not the stored form of a result of this class.
        """
        if not isinstance(data, dict):
            raise ValueError(f"a result is stored as a dict, got {type(data).__name__}.")
        tag = data.get("type", cls.TYPE)
        if not isinstance(tag, str):
            raise ValueError(f"the type tag of a stored result must be a string, got {tag!r}.")
        target = _registered(tag) if cls is Result else cls
        if target is None or (cls is not Result and tag != cls.TYPE):
            raise ValueError(f"stored result of type {tag!r} cannot be read as {cls.__name__}.")
        fields = {f.name: f for f in dataclasses.fields(target)}
        unknown = set(data) - set(fields) - {"type"}
        if unknown:
            raise ValueError(f"stored {tag} has unknown fields {sorted(map(str, unknown))}.")
        kwargs = {}
        for name in fields:
            if name in data:
                try:
                    kwargs[name] = _decode(data[name])
                except ValueError as exc:
                    raise ValueError(f"stored {tag}.{name}: {exc}") from None
                except (TypeError, KeyError, IndexError, AttributeError):
                    raise ValueError(f"stored {tag}.{name} is malformed.") from None
        return _build(target, kwargs)

    def to_json(self) -> str:
        """:meth:`as_dict` as a (strict) JSON string."""
        return json.dumps(self.as_dict(), allow_nan=False)

    def summary(self) -> dict:
        """The short JSON view printed by the CLI (default: every field in the plain view of
        :func:`to_jsonable`, plus ``"type"``)."""
        out: dict[str, Any] = {"type": self.TYPE}
        for f in dataclasses.fields(self):
            if f.name not in self._TRANSIENT:
                out[f.name] = to_jsonable(getattr(self, f.name))
        return out

    # -- files -------------------------------------------------------------------------
    def save(self, path) -> Path:
        """Write the result to ``path`` (``.json`` or ``.npz``, by suffix) and return the path.

        Parameters
        ----------
        path : str or pathlib.Path
            Output file ending in ``.json`` or ``.npz``.

        Returns
        -------
        pathlib.Path
            The path written.

        Raises
        ------
        ValueError
            If the path is not writable (checked before anything is written).
        """
        from . import _validate

        path = _validate.output_path("path", path, suffixes=(".json", ".npz"))
        try:
            if path.suffix == ".json":
                data = self.as_dict()
                data["sha256"] = _digest(data)      # checked by load_result: edits are refused
                path.write_text(json.dumps(data, allow_nan=False))
                return path
            arrays = {}
            meta = {"type": self.TYPE}
            for f in dataclasses.fields(self):
                if f.name in self._TRANSIENT:
                    continue
                v = getattr(self, f.name)
                if isinstance(v, np.ndarray) and v.dtype.kind in _ARRAY_KINDS:
                    arrays[f.name] = v
                else:
                    meta[f.name] = _encode(v)
            meta["sha256"] = _digest(meta, arrays)
            np.savez(path, __meta__=np.array(json.dumps(meta, allow_nan=False)), **arrays)
        except OSError as exc:
            raise ValueError(f"cannot write {str(path)!r}: {exc.strerror or exc}.") from None
        return path

    @classmethod
    def load(cls, path) -> "Result":
        """Read a result written by :meth:`save`.

        Parameters
        ----------
        path : str or pathlib.Path
            A ``.json`` or ``.npz`` file written by :meth:`save`.

        Returns
        -------
        Result
            The result (of this class, when called on a subclass).

        Raises
        ------
        ValueError
            If the file is not a result, was edited, or holds another result type.
        """
        res = load_result(path)
        if cls is not Result and not isinstance(res, cls):
            raise ValueError(f"{path} holds a {type(res).__name__}, not a {cls.__name__}.")
        return res

    # -- checks of what is read back -----------------------------------------------------
    def _check_loaded(self) -> str | None:
        """Why this result, read from a file, cannot be what hyperlattice computed (one clause), or None.

        The base checks every field against its type hint (an ``int`` field holds an integer, not
        a float or a bool; an array field a numeric array; ...) and that counts are not negative
        (``p, q >= 3``; ``sites, rings, edges, levels`` >= 0). Subclasses add their invariants.
        """
        hints = _hints(type(self))
        for f in dataclasses.fields(self):
            why = _type_error(f.name, getattr(self, f.name), hints.get(f.name, f.type))
            if why is not None:
                return why
            v = getattr(self, f.name)
            if isinstance(v, (int, np.integer)) and not isinstance(v, bool):
                low = _MINIMUM.get(f.name)
                if low is not None and v < low:
                    return f"{f.name} = {v} (it must be at least {low})"
        return None

    # -- tables and grids ----------------------------------------------------------------
    def table_columns(self) -> dict[str, np.ndarray]:
        """The declared table (:attr:`COLUMNS`) as ``{name: 1-d array}``; a column whose attribute is
        None (e.g. ``m`` when the rotation is broken) is left out.

        Raises
        ------
        NotImplementedError
            If this result type declares no table.
        ValueError
            If the columns differ in length (a result built by hand with inconsistent arrays).
        """
        if not self.COLUMNS:
            raise NotImplementedError(f"{type(self).__name__} is not a table (it declares no COLUMNS).")
        out = {}
        for col in self.COLUMNS:
            v = getattr(self, col.source)
            if v is not None:
                out[col.name] = np.asarray(v)
        lengths = {name: a.shape for name, a in out.items()}
        if any(len(shape) != 1 for shape in lengths.values()) or len({sh[0] for sh in lengths.values()}) > 1:
            raise ValueError(f"the columns of this {type(self).__name__} are not 1-d arrays of one length: {lengths}.")
        return out

    def to_dataframe(self):
        """The declared table as a :class:`pandas.DataFrame` (pandas: ``pip install "hyperlattice[pandas]"``).

        One column per entry of :attr:`COLUMNS` (:meth:`table_columns`), values copied; ``df.attrs``
        holds ``"type"`` (the result's tag) and ``"units"`` (``{column: unit}``).

        Raises
        ------
        NotImplementedError
            If this result type declares no table.
        ImportError
            If pandas is not installed (the message names the extra).
        """
        columns = self.table_columns()
        pd = _optional("pandas", "pandas")
        df = pd.DataFrame({name: np.array(a) for name, a in columns.items()})
        df.attrs["type"] = self.TYPE
        df.attrs["units"] = {c.name: c.unit for c in self.COLUMNS if c.name in columns}
        return df

    def grid_arrays(self) -> tuple[dict[str, np.ndarray], dict[str, tuple[tuple[str, ...], np.ndarray]]]:
        """The declared grid (:attr:`GRID`): ``({axis: coordinates}, {variable: (axes, values)})``.

        Raises
        ------
        NotImplementedError
            If this result type declares no grid.
        ValueError
            If a variable's shape does not match its axes.
        """
        if self.GRID is None:
            raise NotImplementedError(f"{type(self).__name__} is not a grid (it declares no GRID).")
        variables = {v.name: (v.dims, np.asarray(getattr(self, v.source))) for v in self.GRID.variables}
        sizes: dict[str, int] = {}
        for name, (dims, a) in variables.items():
            if a.ndim != len(dims):
                raise ValueError(f"{type(self).__name__}.{name} has {a.ndim} axes, the grid says {dims}.")
            for d, n in zip(dims, a.shape):
                if sizes.setdefault(d, n) != n:
                    raise ValueError(f"the axis {d!r} of this {type(self).__name__} has lengths {sizes[d]} and {n}.")
        coords = {}
        for c in self.GRID.coords:
            values = np.arange(sizes[c.name]) if c.source == INDEX else np.asarray(getattr(self, c.source))
            if values.shape != (sizes.get(c.name, values.shape[0]),):
                raise ValueError(f"the coordinates {c.name!r} of this {type(self).__name__} do not match the grid.")
            coords[c.name] = values
        return coords, variables

    def to_xarray(self):
        """The declared grid as an :class:`xarray.Dataset` (``pip install "hyperlattice[xarray]"``).

        Coordinates and variables carry their unit in ``.attrs["units"]``; the dataset's
        ``attrs["type"]`` is the result's tag.

        Raises
        ------
        NotImplementedError
            If this result type declares no grid.
        ImportError
            If xarray is not installed (the message names the extra).
        """
        coords, variables = self.grid_arrays()
        xr = _optional("xarray", "xarray")
        units = {c.name: c.unit for c in self.GRID.coords + self.GRID.variables}
        ds = xr.Dataset({name: (dims, np.array(a), {"units": units[name]}) for name, (dims, a) in variables.items()},
                        coords={name: (name, np.array(a), {"units": units[name]}) for name, a in coords.items()})
        ds.attrs["type"] = self.TYPE
        return ds

    # -- figures -----------------------------------------------------------------------
    def plot(self, ax=None, **kwargs) -> Axes:
        """Draw the result on ``ax`` (a new figure if None) and return the axes.

        The drawing is the function :mod:`hyperlattice.plots` registered for this result type
        (:func:`register_plotter`); ``kwargs`` go to it. See "Figures" in the module docstring.

        Parameters
        ----------
        ax : matplotlib.axes.Axes, optional
            Where to draw; a new figure when None.
        **kwargs
            Passed to the registered drawing function.

        Returns
        -------
        matplotlib.axes.Axes
            The axes drawn on.

        Raises
        ------
        NotImplementedError
            If no figure is registered for this result type.
        """
        func = plotter(type(self))
        if func is None:
            raise NotImplementedError(f"{type(self).__name__} has no standard plot.")
        return func(self, ax=ax, **kwargs)


#: Smallest valid value of integer fields of these names, wherever they occur.
_MINIMUM = {"p": 3, "q": 3, "sites": 0, "rings": 0, "edges": 0, "levels": 0, "realizations": 0}


def _type_error(name: str, v, hint) -> str | None:
    """Why ``v`` does not fit the type hint of field ``name`` (for plain hints), or None."""
    text = str(hint).replace("typing.", "")
    options = [t.strip() for t in text.replace("Optional[", "").rstrip("]").split("|")]
    if v is None:       # some fields are None by construction although their hint omits it
        return None
    plain = {"<class 'int'>": "int", "int": "int", "<class 'float'>": "float", "float": "float",
             "<class 'str'>": "str", "str": "str", "<class 'bool'>": "bool", "bool": "bool"}
    kinds = {plain.get(o, o) for o in options} - {"None", "NoneType"}
    if any("ndarray" in k for k in kinds) and len(kinds) == 1:
        if not isinstance(v, np.ndarray) or v.dtype.kind not in "biufcUS":
            return f"{name} must be an array of numbers or strings, got {type(v).__name__}" + \
                (f" of dtype {v.dtype}" if isinstance(v, np.ndarray) else "")
        return None
    if kinds == {"int"}:
        if isinstance(v, bool) or not isinstance(v, (int, np.integer)):
            return f"{name} must be an integer, got {v!r}"
    elif kinds == {"float"}:
        if isinstance(v, bool) or not isinstance(v, (int, float, np.integer, np.floating)):
            return f"{name} must be a number, got {v!r}"
    elif kinds == {"str"}:
        if not isinstance(v, str):
            return f"{name} must be a string, got {v!r}"
    elif kinds == {"bool"}:
        if not isinstance(v, (bool, np.bool_)):
            return f"{name} must be true or false, got {v!r}"
    return None


@functools.lru_cache(maxsize=None)
def _hints(cls) -> dict:
    # once per class: get_type_hints evaluates every annotation (about 1 ms for a result type),
    # and results are made in loops (one per mass, per source, per omega)
    try:
        return typing.get_type_hints(cls)
    except Exception:  # pragma: no cover - forward references that cannot be resolved
        return {f.name: f.type for f in dataclasses.fields(cls)}


def _build(cls, kwargs: dict) -> Result:
    """``cls(**kwargs)`` with missing fields and bad values reported as ValueError."""
    missing = [f.name for f in dataclasses.fields(cls)
               if f.init and f.name not in kwargs
               and f.default is dataclasses.MISSING and f.default_factory is dataclasses.MISSING]
    if missing:
        raise ValueError(f"stored {cls.TYPE} lacks the field(s) {', '.join(map(repr, missing))}.")
    try:
        return cls(**kwargs)
    except (TypeError, AttributeError, KeyError, IndexError) as exc:
        raise ValueError(f"stored {cls.TYPE} is malformed: {exc}.") from None


def _registered(tag: str):
    """The result class of a type tag. Result types register when their module is imported; a tag
    not yet known (a file read in a fresh interpreter) imports every module of the package once
    (not ``cli``), so any result saved by hyperlattice can be read back."""
    cls = _REGISTRY.get(tag)
    if cls is None and not _ALL_IMPORTED:
        import importlib
        import pkgutil

        import hyperlattice

        for info in pkgutil.walk_packages(hyperlattice.__path__, "hyperlattice."):
            if info.name.startswith("hyperlattice.cli") or info.name.endswith("__main__"):
                continue
            importlib.import_module(info.name)
        _ALL_IMPORTED.append(True)
        cls = _REGISTRY.get(tag)
    return cls


_ALL_IMPORTED: list = []


def load_result(path, *, require_checksum: bool = True) -> Result:
    """Read any result written by :meth:`Result.save` (``.json`` or ``.npz``), checked.

    A file written by this version carries the sha256 of its contents: a mismatch (an edited
    number, a damaged file) is refused, and so is a file without a checksum (deleting the
    ``sha256`` key would otherwise let any edit through) unless ``require_checksum=False`` says
    that the file was written by hand. Every file is then checked for what the result must satisfy: field types (an integer is not a float or a bool, arrays
    are numeric), counts not negative, and the result's own invariants (:class:`Levels`: finite,
    ascending energies with one ``n``, ``m`` and error per level; a lattice: its structure).

    Parameters
    ----------
    path : str or path-like
        A ``.json`` or ``.npz`` file written by :meth:`Result.save`.
    require_checksum : bool, optional
        Refuse a file that carries no checksum (default True); False reads a hand-written file,
        whose field types and invariants are still checked.

    Returns
    -------
    Result
        The stored result, of the class named by its ``type`` tag (:func:`result_types`), with
        read-only arrays.

    Raises
    ------
    ValueError
        If the file is missing, unreadable, fails its checksum (or has none, with
        ``require_checksum``) or does not hold a valid saved result; the message (one sentence)
        names the file.

    See Also
    --------
    Result.save, result_types

    Examples
    --------
    >>> import os, tempfile
    >>> import hyperlattice as hl
    >>> levels = hl.lowest_levels(hl.ring_lattice(7, 3, 2), 2)
    >>> path = levels.save(os.path.join(tempfile.mkdtemp(), "levels.npz"))
    >>> back = hl.load_result(path)
    >>> type(back).__name__, back.m.tolist()
    ('Spectrum', [0, 1])
    >>> [round(float(e), 6) for e in back.energies]
    [-2.636405, -2.283335]
    """
    from . import _validate

    require_checksum = _validate.flag("require_checksum", require_checksum)
    path = _validate.input_path("path", path, suffixes=(".json", ".npz"))
    where = repr(str(path))
    arrays = None
    try:
        if path.suffix == ".json":
            meta = json.loads(path.read_text())
        else:
            with np.load(path, allow_pickle=False) as data:
                if "__meta__" not in data:
                    raise ValueError(f"{where} is not a saved hyperlattice result.")
                meta = json.loads(str(data["__meta__"]))
                arrays = {k: data[k] for k in data.files if k != "__meta__"}
    except (OSError, EOFError, zipfile.BadZipFile, json.JSONDecodeError, UnicodeDecodeError) as exc:
        raise ValueError(f"cannot read a result from {where}: {_validate.file_problem(exc)}.") from None
    except RecursionError:
        raise ValueError(f"cannot read a result from {where}: it is nested too deeply.") from None
    except ValueError as exc:
        # numpy's object-array and header refusals, Python's 4300-digit integer limit: no file name
        # and programmer's advice (allow_pickle=True, ...) before; one sentence naming the file now
        if str(exc).startswith(where):
            raise
        raise ValueError(f"cannot read a result from {where}: {_validate.file_problem(exc)}.") from None
    if not isinstance(meta, dict):
        raise ValueError(f"{where} is not a saved hyperlattice result.")
    _verify_digest(where, meta, arrays, required=require_checksum)
    tag = meta.get("type")
    cls = _registered(tag) if isinstance(tag, str) else None
    if cls is None:
        raise ValueError(f"{where} holds an unknown result type {tag!r}.")
    try:
        if arrays is None:
            res = Result.from_dict(meta)
        else:
            res = _from_npz(cls, tag, meta, arrays)
    except ValueError as exc:
        raise ValueError(f"{where}: {str(exc).rstrip('.')}.") from None
    except RecursionError:
        raise ValueError(f"cannot read a result from {where}: it is nested too deeply.") from None
    why = res._check_loaded()
    if why is not None:
        raise ValueError(f"{where} does not hold a valid {tag}: {why}.")
    return res


def _from_npz(cls, tag: str, meta: dict, arrays: dict) -> Result:
    names = {f.name for f in dataclasses.fields(cls)}
    unknown = (set(meta) | set(arrays)) - names - {"type"}
    if unknown:
        raise ValueError(f"stored {tag} has unknown fields {sorted(unknown)}.")
    kwargs = dict(arrays)
    for name, v in meta.items():
        if name != "type":
            try:
                kwargs[name] = _decode(v)
            except ValueError as exc:
                raise ValueError(f"stored {tag}.{name}: {exc}") from None
            except (TypeError, KeyError, IndexError, AttributeError):
                raise ValueError(f"stored {tag}.{name} is malformed.") from None
    return _build(cls, kwargs)


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
        Signed angular momentum in :math:`\mathbb Z` (continuum), or for a graph spectrum its
        signed rotation sector in :math:`(-p/2, p/2]`, which is the angular momentum only modulo p
        (:func:`hyperlattice.compare.levels.continuum_labels` gives the continuum (n, m) a graph
        level continues); a pair is listed +m first. None when the rotation is broken.
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

    Examples
    --------
    >>> import hyperlattice as hl
    >>> levels = hl.lowest_levels(hl.ring_lattice(7, 3, 2), 3)     # a Levels subclass
    >>> len(levels), levels.n.tolist(), levels.m.tolist(), levels.degeneracy.tolist()
    (3, [1, 1, 1], [0, 1, -1], [1, 2, 2])
    """

    COLUMNS = (Column("energy", "energies", "t"), Column("n", "n", "1"), Column("m", "m", "1"),
               Column("degeneracy", "degeneracy", "1"), Column("error", "errors", "t"))

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

    def _check_loaded(self) -> str | None:
        why = super()._check_loaded()
        if why is not None:
            return why
        e, n, m, err = self.energies, self.n, self.m, self.errors
        if e.ndim != 1 or e.dtype.kind != "f":
            return f"energies must be a 1-d float array, got {e.dtype} of shape {e.shape}"
        k = e.shape[0]
        for name, a, kinds in (("n", n, "iu"), ("m", m, "iu"), ("errors", err, "f")):
            if a is None:
                continue
            if a.dtype.kind not in kinds:
                return f"{name} has the wrong dtype {a.dtype}"
            if a.shape != (k,):
                return f"{name} has {a.shape[0] if a.ndim else 0} entries for {k} energies"
        if not np.all(np.isfinite(e)):
            return "some energies are not finite"
        if np.any(n < 1):
            return "the radial index n starts at 1"
        if np.any(err < 0):      # NaN stands for an unknown error and is kept
            return "errors must be non-negative"
        if m is not None and self._m_is_sector() and np.any((2 * m <= -self.p) | (2 * m > self.p)):
            return f"m must lie in (-p/2, p/2] = (-{self.p / 2:g}, {self.p / 2:g}]"
        if k > 1:
            # ascending up to each level's own error and the rounding of the largest energy
            known = np.nan_to_num(err, nan=0.0, posinf=0.0)
            slack = known[:-1] + known[1:] + 16 * np.finfo(float).eps * max(1.0, float(np.max(np.abs(e))))
            if np.any(np.diff(e) < -slack):
                i = int(np.argmax(np.diff(e) < -slack))
                return f"the energies are not ascending (E[{i}] = {e[i]:.17g} > E[{i + 1}] = {e[i + 1]:.17g})"
        return None

    def _m_is_sector(self) -> bool:
        # a graph spectrum's m is its signed rotation sector in (-p/2, p/2]; a continuum m is any
        # integer (and so is the continuum label a graph level carries once matched)
        return self.error_kind == "residual"

    @property
    def degeneracy(self) -> np.ndarray:
        """Symmetry degeneracy of each level: 2 for a :math:`\\pm m` pair, else 1."""
        if self.m is None or getattr(self, "flux", 0.0):  # a field splits m from -m
            return np.ones(len(self), dtype=int)
        if self.error_kind == "residual":  # lattice: m and -m = p - m coincide for m = p/2
            return np.where((2 * self.m) % self.p == 0, 1, 2)
        return np.where(self.m == 0, 1, 2)

    def table(self) -> list[dict]:
        """One dict per level: ``energy, n, m, degeneracy, error``."""
        m = [None] * len(self) if self.m is None else self.m.tolist()
        return [{"energy": float(e), "n": int(n), "m": mm, "degeneracy": int(g), "error": float(r)}
                for e, n, mm, g, r in zip(self.energies, self.n, m, self.degeneracy, self.errors)]


def compare_levels(graph: Levels, continuum: Levels) -> dict:
    r"""Field-by-field comparison of two level lists of equal length.

    Returns the relative differences :math:`(E_g - E_c)/|E_g|`, whether the (n, m) labels agree
    level by level, and both error columns. The labels are compared as given: a graph spectrum's
    m is its sector (m mod p); :func:`hyperlattice.compare.levels.levels_side_by_side` compares the
    continuum labels of the graph levels instead.

    Parameters
    ----------
    graph : Levels
        Graph levels (e.g. from ``lowest_levels``), units of t.
    continuum : Levels
        Continuum levels (e.g. from ``continuum_levels``), units of t. Only the first
        ``min(len(graph), len(continuum))`` levels of each are compared.

    Returns
    -------
    dict
        ``"levels"`` (the number K compared), ``"relative_difference"`` (ndarray (K,),
        :math:`(E_g - E_c)/|E_g|`), ``"labels_agree"`` (bool, or None when either side has no
        m labels), ``"graph_errors"`` and ``"continuum_errors"`` (ndarray (K,)).

    Raises
    ------
    ValueError
        If either argument is not a :class:`Levels`.

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.results import compare_levels
    >>> graph = hl.lowest_levels(hl.ring_lattice(7, 3, 2), 2)
    >>> cont = hl.continuum_levels(7, 3, rings=2, levels=2)
    >>> out = compare_levels(graph, cont)
    >>> out["levels"], out["labels_agree"]
    (2, True)
    >>> [round(float(x), 4) for x in out["relative_difference"]]
    [-0.0251, -0.0871]
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


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
