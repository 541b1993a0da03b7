"""The one door for input checks.

Every public function of hyperlattice passes its arguments through these helpers, so that
``None``, NaN, ``bool``, strings, complex numbers where reals are expected and arrays of the
wrong shape give the same :class:`ValueError` with a plain sentence everywhere (the CLI turns it
into one line and exit code 2). Nothing here imports the rest of the package at module level.

Conventions
-----------
* Integers: Python/numpy integers, or floats with an integral value (``3.0``); never ``bool``.
* Reals: anything :func:`float` accepts that is finite, except ``bool``, strings and complex.
* The names passed in are the argument names a user typed, e.g. ``"rings"``, ``"radius L"``.
"""

from __future__ import annotations

import math
import numbers
import os
from pathlib import Path
from typing import TYPE_CHECKING, Callable

import numpy as np

if TYPE_CHECKING:
    from .graph.lattice import Lattice

__all__ = [
    "integer",
    "positive_int",
    "real",
    "positive_real",
    "complex_number",
    "radius",
    "real_array",
    "complex_array",
    "disk_points",
    "choice",
    "flag",
    "function",
    "lattice",
    "site_index",
    "site_indices",
    "pq",
    "output_path",
    "input_path",
    "directory",
]


def _shown(value) -> str:
    text = f"{value:,}" if isinstance(value, int) and not isinstance(value, bool) else repr(value)
    return text if len(text) <= 60 else text[:57] + "..."


def _zero_d(value):
    """A 0-d numeric numpy array as its Python scalar (``np.array(3)`` is a number too)."""
    if isinstance(value, np.ndarray) and value.ndim == 0 and value.dtype.kind in "biufc":
        return value.item()
    return value


# ----------------------------------------------------------------------------
# scalars
# ----------------------------------------------------------------------------

def integer(name: str, value, *, minimum: int | None = None, maximum: int | None = None) -> int:
    """``value`` as a Python int in ``[minimum, maximum]`` (bounds optional).

    Accepts Python and numpy integers, floats with an integral value (``3.0``) and 0-d arrays of
    either; refuses ``bool``, None, NaN, inf, strings, complex numbers and fractions.
    """
    value = _zero_d(value)
    if isinstance(value, (bool, np.bool_)) or value is None:
        raise ValueError(f"{name} must be an integer, got {_shown(value)}.")
    if isinstance(value, (int, np.integer)):
        v = int(value)
    elif isinstance(value, (float, np.floating)) and math.isfinite(value) and float(value).is_integer():
        # refuse before building a huge int (1e308 has 309 digits)
        if maximum is not None and value > maximum:
            raise ValueError(f"{name} must be at most {maximum:,}, got {_shown(value)}.")
        if minimum is not None and value < minimum:
            raise ValueError(f"{name} must be at least {minimum:,}, got {_shown(value)}.")
        v = int(value)
    else:
        raise ValueError(f"{name} must be an integer, got {_shown(value)}.")
    if minimum is not None and v < minimum:
        raise ValueError(f"{name} must be at least {minimum:,}, got {_shown(v)}.")
    if maximum is not None and v > maximum:
        raise ValueError(f"{name} must be at most {maximum:,}, got {_shown(v)}.")
    return v


def positive_int(name: str, value, *, maximum: int | None = None) -> int:
    """An integer >= 1."""
    return integer(name, value, minimum=1, maximum=maximum)


def real(name: str, value, *, minimum: float | None = None, maximum: float | None = None,
         open_min: bool = False, open_max: bool = False) -> float:
    """``value`` as a finite float, optionally inside a (half-)open interval."""
    if isinstance(value, (bool, np.bool_, str, bytes)) or value is None \
            or isinstance(value, (complex, np.complexfloating)) or not isinstance(value, numbers.Real):
        if isinstance(value, np.ndarray) and value.ndim == 0 and value.dtype.kind in "iuf":
            value = value.item()
        else:
            raise ValueError(f"{name} must be a real number, got {_shown(value)}.")
    try:
        v = float(value)
    except OverflowError:  # an int beyond 1.8e308
        raise ValueError(f"{name} must be finite, got {_shown(value)}.") from None
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a real number, got {_shown(value)}.") from None
    if not math.isfinite(v):
        raise ValueError(f"{name} must be finite, got {_shown(value)}.")
    if minimum is not None and (v < minimum or (open_min and v == minimum)):
        word = "greater than" if open_min else "at least"
        raise ValueError(f"{name} must be {word} {minimum:g}, got {v:g}.")
    if maximum is not None and (v > maximum or (open_max and v == maximum)):
        word = "less than" if open_max else "at most"
        raise ValueError(f"{name} must be {word} {maximum:g}, got {v:g}.")
    return v


def positive_real(name: str, value) -> float:
    """A finite float > 0."""
    return real(name, value, minimum=0.0, open_min=True)


def complex_number(name: str, value) -> complex:
    """``value`` as a finite Python complex (reals accepted)."""
    if isinstance(value, (bool, np.bool_, str, bytes)) or value is None or not isinstance(value, numbers.Number):
        if isinstance(value, np.ndarray) and value.ndim == 0 and value.dtype.kind in "iufc":
            value = value.item()
        else:
            raise ValueError(f"{name} must be a (complex) number, got {_shown(value)}.")
    try:
        v = complex(value)
    except (TypeError, ValueError, OverflowError):
        raise ValueError(f"{name} must be a (complex) number, got {_shown(value)}.") from None
    if not (math.isfinite(v.real) and math.isfinite(v.imag)):
        raise ValueError(f"{name} must be finite, got {_shown(value)}.")
    return v


def radius(name: str, value, *, allow_one: bool = False) -> float:
    """A disk radius L in the Poincaré disk: ``0 < L < 1``, or ``0 < L <= 1`` with ``allow_one``.

    L = 1 is the whole hyperbolic plane (only Green functions have that limit); the Dirichlet
    spectrum needs a finite disk.
    """
    return real(name, value, minimum=0.0, open_min=True, maximum=1.0, open_max=not allow_one)


def choice(name: str, value, options) -> str:
    """One of a fixed set of strings."""
    options = tuple(options)
    if not isinstance(value, str) or value not in options:
        raise ValueError(f"{name} must be one of {', '.join(map(repr, options))}, got {_shown(value)}.")
    return value


def flag(name: str, value) -> bool:
    """A bool (or numpy bool)."""
    if not isinstance(value, (bool, np.bool_)):
        raise ValueError(f"{name} must be True or False, got {_shown(value)}.")
    return bool(value)


def function(name: str, value) -> Callable:
    """A callable."""
    if not callable(value):
        raise ValueError(f"{name} must be a function, got {_shown(value)}.")
    return value


# ----------------------------------------------------------------------------
# arrays
# ----------------------------------------------------------------------------

def _array(name: str, value, kind: str, ndim, shape) -> np.ndarray:
    if value is None or isinstance(value, (str, bytes)):
        raise ValueError(f"{name} must be {'a real' if kind == 'f' else 'a complex'} array, got {_shown(value)}.")
    try:
        a = np.asarray(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a numeric array (a ragged or mixed list is not).") from None
    allowed = "iuf" if kind == "f" else "iufc"
    if a.dtype.kind not in allowed:
        what = "real numbers" if kind == "f" else "numbers"
        raise ValueError(f"{name} must contain {what}, got values of type {a.dtype}.")
    a = a.astype(np.float64 if kind == "f" else np.complex128, copy=False)
    if ndim is not None and a.ndim not in (ndim if isinstance(ndim, tuple) else (ndim,)):
        raise ValueError(f"{name} must have {ndim} dimension(s), got shape {a.shape}.")
    if shape is not None and a.shape != tuple(shape):
        raise ValueError(f"{name} must have shape {tuple(shape)}, got {a.shape}.")
    if not np.all(np.isfinite(a)):
        raise ValueError(f"{name} contains NaN or infinite values.")
    return a


def real_array(name: str, value, *, ndim=None, shape=None) -> np.ndarray:
    """A finite float64 array (scalars allowed unless ``ndim`` forbids them)."""
    return _array(name, value, "f", ndim, shape)


def complex_array(name: str, value, *, ndim=None, shape=None) -> np.ndarray:
    """A finite complex128 array."""
    return _array(name, value, "c", ndim, shape)


def disk_points(name: str, value, *, limit: float = 1.0, closed: bool = False) -> np.ndarray:
    """Points of the Poincaré disk as complex128: ``|z| < limit`` (``<=`` when ``closed``)."""
    z = complex_array(name, value)
    r = np.abs(z)
    bad = r > limit if closed else r >= limit
    if np.any(bad):
        rel = "<=" if closed else "<"
        raise ValueError(f"{name} must lie in the disk |z| {rel} {limit:g}; the largest |z| is {float(r.max()):.6g}.")
    return z


# ----------------------------------------------------------------------------
# lattice objects
# ----------------------------------------------------------------------------

def pq(p, q, *, allow_infinite_p: bool = False) -> tuple:
    """A hyperbolic Schläfli symbol {p,q}: integers with (p-2)(q-2) > 4 (p = inf optionally).

    Builders that store per-site data in small integers bound p and q further themselves.
    """
    if allow_infinite_p and isinstance(p, float) and math.isinf(p) and p > 0:
        return math.inf, integer("q", q, minimum=3)
    p = integer("p", p, minimum=3)
    q = integer("q", q, minimum=3)
    if (p - 2) * (q - 2) <= 4:
        raise ValueError(f"{{{p},{q}}} is not a hyperbolic tessellation: need (p-2)(q-2) > 4, "
                         f"got {(p - 2) * (q - 2)}.")
    return p, q


def lattice(value, *, kind: str | None = None) -> Lattice:
    """A :class:`~hyperlattice.graph.lattice.Lattice` (``kind`` "sites" or "line_graph" if given)."""
    from .graph.lattice import Lattice

    if not isinstance(value, Lattice):
        raise ValueError(f"expected a Lattice (from ring_lattice or line_graph), got {type(value).__name__}.")
    if kind is not None and value.kind != kind:
        hint = (" (the continuum dictionary is derived for the {p,q} lattice itself, not its line graph)"
                if kind == "sites" else "")
        raise ValueError(f"this computation needs a lattice of kind {kind!r}, got {value.kind!r}{hint}.")
    return value


def site_index(name: str, value, n: int) -> int:
    """A site index in ``range(n)`` (0-based, the paper's order); integral floats as in :func:`integer`."""
    try:
        v = integer(name, value)
    except ValueError:
        raise ValueError(f"{name} must be an integer site index, got {_shown(value)}.") from None
    if not 0 <= v < n:
        raise ValueError(f"{name} = {_shown(v)} is not a site of this lattice (valid: 0..{n - 1}).")
    return v


def site_indices(name: str, value, n: int) -> np.ndarray:
    """A 1-d int64 array of site indices in ``range(n)``."""
    if value is None or isinstance(value, (str, bytes, bool)):
        raise ValueError(f"{name} must be site indices, got {_shown(value)}.")
    if isinstance(value, (list, tuple)) and any(isinstance(v, (bool, np.bool_)) for v in value):
        raise ValueError(f"{name} must be site indices, not True/False values.")
    try:
        a = np.atleast_1d(np.asarray(value))
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a flat list of site indices (a ragged or mixed list is not).") from None
    if a.dtype.kind == "b" or a.dtype.kind not in "iuf" or a.ndim != 1:
        raise ValueError(f"{name} must be a 1-d list of site indices, got {_shown(value)}.")
    if a.dtype.kind == "f":
        if not np.all(np.isfinite(a)) or np.any(a != np.round(a)):
            raise ValueError(f"{name} must be integer site indices.")
    # range check before the cast: 1e308 or 2**64 would wrap around in int64
    if a.size and (a.min() < 0 or a.max() >= n):
        raise ValueError(f"{name} contains indices outside 0..{n - 1} (the sites of this lattice).")
    return a.astype(np.int64)


# ----------------------------------------------------------------------------
# files
# ----------------------------------------------------------------------------

def _as_path(name: str, value) -> Path:
    if isinstance(value, bool) or not isinstance(value, (str, os.PathLike)):
        raise ValueError(f"{name} must be a path, got {_shown(value)}.")
    text = os.fspath(value)
    if not isinstance(text, str) or text == "" or "\0" in text:
        raise ValueError(f"{name} must be a path, got {_shown(value)}.")
    return Path(text)


def _os_error(name: str, path: Path, exc: OSError) -> ValueError:
    # e.g. a name too long for the file system: the question "is it a directory?" itself fails
    return ValueError(f"{name} {str(path)!r} cannot be used: {exc.strerror or exc}.")


def output_path(name: str, value, *, suffixes: tuple[str, ...] | None = None) -> Path:
    """A file we may write: not a directory, its folder exists and is writable.

    Checked before any work is done, so a long computation never fails at its last step.
    """
    path = _as_path(name, value)
    if suffixes is not None and path.suffix not in suffixes:
        raise ValueError(f"{name} must end in {' or '.join(suffixes)}, got {str(path)!r}.")
    parent = path.parent if str(path.parent) else Path(".")
    try:
        if path.is_dir():
            raise ValueError(f"{name} {str(path)!r} is a directory; give a file name.")
        if not parent.is_dir():
            what = "is not a folder" if parent.exists() else "does not exist"
            raise ValueError(f"cannot write {str(path)!r}: the folder {str(parent)!r} {what}.")
        if not os.access(parent, os.W_OK) or (path.exists() and not os.access(path, os.W_OK)):
            raise ValueError(f"cannot write {str(path)!r}: permission denied.")
    except OSError as exc:
        raise _os_error(name, path, exc) from None
    return path


def input_path(name: str, value, *, suffixes: tuple[str, ...] | None = None) -> Path:
    """An existing, readable file."""
    path = _as_path(name, value)
    if suffixes is not None and path.suffix not in suffixes:
        raise ValueError(f"{name} must end in {' or '.join(suffixes)}, got {str(path)!r}.")
    try:
        if not path.is_file():
            raise ValueError(f"{name} {str(path)!r} does not exist or is not a file.")
        if not os.access(path, os.R_OK):
            raise ValueError(f"cannot read {str(path)!r}: permission denied.")
    except OSError as exc:
        raise _os_error(name, path, exc) from None
    return path


def directory(name: str, value, *, create: bool = True) -> Path:
    """A directory we may write into (created with its parents when ``create``)."""
    path = _as_path(name, value)
    try:
        if path.exists() and not path.is_dir():
            raise ValueError(f"{name} {str(path)!r} exists and is not a directory.")
        if not path.exists():
            if not create:
                raise ValueError(f"{name} {str(path)!r} does not exist.")
            try:
                path.mkdir(parents=True, exist_ok=True)
            except OSError as exc:
                raise ValueError(f"{name} {str(path)!r} cannot be created: {exc.strerror or exc}.") from None
        if not os.access(path, os.W_OK | os.X_OK):
            raise ValueError(f"{name} {str(path)!r} is not writable (permission denied).")
    except OSError as exc:
        raise _os_error(name, path, exc) from None
    return path
