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
import sys
from pathlib import Path
from typing import TYPE_CHECKING, Callable

import numpy as np

if TYPE_CHECKING:
    from .graph.lattice import Lattice

__all__ = [
    "integer",
    "positive_int",
    "int_list",
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
    "progress",
    "lattice",
    "is_matrix",
    "hermitian_matrix",
    "site_index",
    "site_indices",
    "pq",
    "output_path",
    "input_path",
    "directory",
    "available_memory",
    "require_memory",
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

#: the implicit upper bound of :func:`integer`
INT64_MAX = 2**63 - 1


def integer(name: str, value, *, minimum: int | None = None, maximum: int | None = None) -> int:
    """``value`` as a Python int in ``[minimum, maximum]`` (bounds optional).

    Accepts Python and numpy integers, floats with an integral value (``3.0``) and 0-d arrays of
    either; refuses ``bool``, None, NaN, inf, strings, complex numbers and fractions. Without a
    ``maximum``, the value must fit a 64-bit integer (what numpy and every size computation take;
    10**140 used to surface as OverflowError deep in the stack).
    """
    if maximum is None:
        maximum = INT64_MAX
    if minimum is None:
        minimum = -INT64_MAX - 1
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


def int_list(name: str, value, *, minimum: int | None = None, maximum: int | None = None) -> list[int]:
    """A non-empty list, tuple or 1-d array of integers, each as :func:`integer` checks it."""
    if isinstance(value, (str, bytes, dict)) or not isinstance(value, (list, tuple, range, np.ndarray)):
        raise ValueError(f"{name} must be a list of integers, got {_shown(value)}.")
    if isinstance(value, np.ndarray) and value.ndim != 1:
        raise ValueError(f"{name} must be a flat list of integers, got an array of shape {value.shape}.")
    if len(value) == 0:
        raise ValueError(f"{name} must hold at least one value.")
    try:
        return [integer(name, v, minimum=minimum, maximum=maximum) for v in value]
    except ValueError as exc:
        raise ValueError(f"{name} must be a list of integers: {exc}") from None


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


#: largest |t| the level solvers take: the levels scale with t exactly, and squares of entries
#: of ~1e300 overflow inside the residual checks (a ConvergenceError "residual inf" before)
MAX_HOPPING = 1e150
#: smallest residual tolerance a solver can be asked for, relative to the scale of the matrix
MIN_TOLERANCE = 1e-15


def hopping(name: str, value, *, positive: bool = False) -> float:
    """A hopping amplitude t: a finite real (> 0 with ``positive``) of magnitude at most
    :data:`MAX_HOPPING`; beyond it, one sentence saying that the levels simply scale with t."""
    t = positive_real(name, value) if positive else real(name, value)
    if abs(t) > MAX_HOPPING:
        raise ValueError(f"{name} = {t:g} is beyond {MAX_HOPPING:g}: the levels are t times those at t = 1, so "
                         "compute them at t = 1 and scale them.")
    return t


def solver_tolerance(name: str, value, *, floor: float = MIN_TOLERANCE) -> float:
    """A residual tolerance: positive and not below ``floor``, what float64 arithmetic can reach
    (tol = 1e-300 ended as a ConvergenceError after the work instead of a refusal before it)."""
    tol = positive_real(name, value)
    if tol < floor:
        raise ValueError(f"{name} = {tol:g} is below what float64 arithmetic can reach (about {floor:g} "
                         f"relative to the problem's scale); give {name} >= {floor:g}.")
    return tol


def damping(name: str, value, tol: float, max_allowed: int) -> float:
    """The mixing of a damped fixed-point iteration, 0 < damping <= 1, refused before work when no
    allowed number of iterations could reach ``tol``: each step moves at most ``damping`` of the way
    to the target, so a start off the fixed point by O(1) needs log(tol)/log(1 - damping) steps
    (damping = 1e-300 iterated to the cap and ended in a ConvergenceError). Call it only when the
    start is off the fixed point (a nonzero self-energy)."""
    d = real(name, value, minimum=0.0, maximum=1.0, open_min=True)
    fewest = math.log(tol) / math.log1p(-d) if d < 1.0 else 1.0
    if fewest > max_allowed:
        raise ValueError(f"{name} = {d:g} moves each iterate only that fraction of the way: reaching tol = {tol:g} "
                         f"takes at least {fewest:.3g} iterations, more than the {max_allowed:,} allowed; raise "
                         f"{name} (0 < {name} <= 1).")
    return d


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


def progress(name: str, value):
    """A ``progress`` argument: True, False, None (auto) or a function receiving one-line messages."""
    if value is None or callable(value):
        return value
    if isinstance(value, (bool, np.bool_)):
        return bool(value)
    raise ValueError(f"{name} must be True, False, None or a function, got {_shown(value)}.")


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


def is_matrix(value) -> bool:
    """Whether ``value`` is offered as a Hamiltonian matrix: any scipy.sparse matrix or array, or a
    2-d numpy array (what :func:`hermitian_matrix` then checks)."""
    if isinstance(value, np.ndarray):
        return value.ndim == 2
    sparse = sys.modules.get("scipy.sparse")      # a sparse matrix means scipy.sparse is loaded
    return sparse is not None and sparse.issparse(value)


#: relative tolerance of the Hermiticity check: max |H - H^+| <= HERMITIAN_RTOL * max |H_ij|
#: (rounding of a matrix built by arithmetic passes; a wrong sign or a missing entry does not)
HERMITIAN_RTOL = 1e-12


def hermitian_matrix(name: str, value, *, rtol: float = HERMITIAN_RTOL):
    """A real symmetric or complex Hermitian matrix as scipy CSR (float64, or complex128 when an
    entry has a nonzero imaginary part), symmetrised as (H + H^+)/2.

    Takes a scipy.sparse matrix of any format (csr, csc, coo, ...) or a 2-d array (nested lists
    too). Refused: a
    non-square or empty matrix, entries that are not finite numbers, and a matrix farther from
    Hermitian than ``rtol`` times its largest entry.
    """
    import scipy.sparse as sp

    if sp.issparse(value):
        if value.dtype.kind not in "biufc":
            raise ValueError(f"{name} must hold numbers, got a sparse matrix of dtype {value.dtype}.")
        h = sp.csr_matrix(value)
    else:
        arr = complex_array(name, value, ndim=2)      # also nested lists; NaN, strings, shapes refused
        h = sp.csr_matrix(arr if np.any(arr.imag) else arr.real)
    if h.shape[0] != h.shape[1] or h.shape[0] == 0:
        raise ValueError(f"{name} must be a non-empty square matrix, got shape {h.shape}.")
    if not np.all(np.isfinite(h.data)):
        raise ValueError(f"{name} contains NaN or infinite values.")
    if h.dtype.kind == "c" and not np.any(h.data.imag):
        h = h.real
    h = h.astype(np.complex128 if h.dtype.kind == "c" else np.float64)
    h.sum_duplicates()
    scale = float(abs(h).max()) if h.nnz else 0.0
    gap = float(abs(h - h.conj().T).max()) if h.nnz else 0.0
    if gap > rtol * scale:
        kind = "Hermitian" if h.dtype.kind == "c" else "symmetric"
        raise ValueError(f"{name} must be {kind}: max |H - H^+| = {gap:.3g} exceeds {rtol:g} times "
                         f"the largest entry {scale:.3g}.")
    return ((h + h.conj().T) * 0.5).tocsr()


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

#: the largest p or q accepted anywhere: far beyond any lattice that can be built, and small
#: enough that every {p,q} constant and dictionary map (products like pq, areas (p-2)π - 2πp/q,
#: fields 2πf/𝒜) stays finite and accurate in float64 (p = 1e308 would give inf and NaN)
PQ_MAX = 10**9


def pq(p, q, *, allow_infinite_p: bool = False) -> tuple:
    """A hyperbolic Schläfli symbol {p,q}: integers with (p-2)(q-2) > 4 (p = inf optionally).

    p and q are at most :data:`PQ_MAX` (10⁹), where float arithmetic on {p,q} constants holds.
    Builders that store per-site data in small integers bound p and q further themselves.
    """
    if allow_infinite_p and isinstance(p, float) and math.isinf(p) and p > 0:
        return math.inf, integer("q", q, minimum=3, maximum=PQ_MAX)
    p = integer("p", p, minimum=3, maximum=PQ_MAX)
    q = integer("q", q, minimum=3, maximum=PQ_MAX)
    if (p - 2) * (q - 2) <= 4:
        raise ValueError(f"{{{p},{q}}} is not a hyperbolic tessellation: need (p-2)(q-2) > 4, "
                         f"got {(p - 2) * (q - 2)}.")
    return p, q


def lattice(value, *, kind: str | None = None) -> Lattice:
    """A :class:`~hyperlattice.graph.lattice.Lattice` (``kind`` "sites" or "line_graph" if given).

    Recognised by the class marker ``__hyperlattice_lattice__`` that :class:`Lattice` (and any
    subclass) carries: this module is the bottom layer and does not import ``graph/``.
    """
    if getattr(type(value), "__hyperlattice_lattice__", False) is not True:
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


#: environment variable that hides CHOLMOD from the package (``superlu``; see hyperlattice.graph.factor)
FACTOR_BACKEND_ENV = "HYPERLATTICE_FACTOR_BACKEND"


def factor_backend_env() -> str:
    """The value of :data:`FACTOR_BACKEND_ENV`, lower case: ``""`` (unset, ``auto`` or ``cholmod``:
    the default choice) or ``"superlu"``; anything else is refused in one sentence (a typo such as
    ``=junk`` was silently taken as auto). Checked by the CLI before any command runs, and by
    every backend choice of the API."""
    raw = os.environ.get(FACTOR_BACKEND_ENV, "")
    chosen = raw.strip().lower()
    if chosen in ("superlu", "splu"):
        return "superlu"
    if chosen in ("", "auto", "cholmod"):
        return ""
    raise ValueError(f"the environment variable {FACTOR_BACKEND_ENV} = {_shown(raw)} is not one of auto, "
                     "cholmod, superlu; unset it or give one of them.")


def file_problem(exc: BaseException) -> str:
    """What is wrong with a file a loader could not read, in one clause for a physicist.

    numpy and Python phrase some refusals as advice to the programmer (``allow_pickle=True``,
    ``max_header_size``, ``sys.set_int_max_str_digits()``): loosening them would be wrong for a
    file hyperlattice did not write, so they become what they mean. Other messages pass as they are.
    """
    text = " ".join(str(exc).split()).rstrip(".")
    low = text.lower()
    if "allow_pickle" in low and "object arrays" in low:
        return "it holds Python objects (pickled data), which hyperlattice never writes and does not load"
    if "max_header_size" in low or "header info length" in low:
        return "it has an array header far larger than any hyperlattice writes (not loaded, for safety)"
    if "int_max_str_digits" in low or "integer string conversion" in low:
        return "it holds an integer of more than 4,300 digits, which no hyperlattice file has"
    return text or type(exc).__name__


def owned_directory(name: str, value, *, marker: str, ours=(), what: str = "the package's") -> Path:
    """A directory the package may write into without touching anything of the user's.

    It is created when missing; an existing one must hold ``marker`` (the file the package wrote
    when it first used the directory: a sweep's manifest, a report's ``_report.json``) or be empty
    apart from the names in ``ours`` (a directory among them must itself be empty). Anything else
    is refused with one sentence naming a file found, so a user's own files are never overwritten.
    Used by :class:`hyperlattice.sweep.store.SweepStore` and :func:`hyperlattice.report.reproduce`.
    """
    path = directory(name, value)
    if (path / marker).is_file():
        return path
    try:
        foreign = []
        for f in sorted(path.iterdir(), key=lambda f: f.name):
            if f.name not in ours:
                foreign.append(f.name + ("/" if f.is_dir() else ""))
            elif f.is_dir() and not f.is_symlink() and any(f.iterdir()):
                foreign.append(f.name + "/")
    except OSError as exc:
        raise ValueError(f"cannot read {name} {str(path)!r}: {exc.strerror or exc}.") from None
    if foreign:
        raise ValueError(f"{name} {str(path)!r} is not {what} directory (no {marker}, and it holds "
                         f"{foreign[0]!r}{' and more' if len(foreign) > 1 else ''}); "
                         "give a new or empty directory, so that nothing of yours is overwritten.")
    return path


# ----------------------------------------------------------------------------
# memory: what this process may still allocate
# ----------------------------------------------------------------------------

def _read_int(path: str) -> int | None:
    try:
        with open(path) as fh:
            text = fh.read().strip()
    except OSError:
        return None
    return int(text) if text.isdigit() else None  # "max" (no limit) and junk: None


def _proc_status_bytes(key: str) -> int | None:
    try:
        with open("/proc/self/status") as fh:
            for line in fh:
                if line.startswith(key + ":"):
                    return int(line.split()[1]) * 1024
    except (OSError, ValueError, IndexError):
        pass
    return None


def memory_limits() -> tuple[int, int | None]:
    """(resident bytes this process may still use, address space left under ``RLIMIT_AS`` or None).

    Resident: the least of the machine's ``MemAvailable`` (``/proc/meminfo``; sysconf as a
    fallback) and the cgroup's ``memory.max`` (v2) or ``memory.limit_in_bytes`` (v1) minus its
    current usage (containers, CI runners, batch jobs). Address space: the soft ``RLIMIT_AS``
    (``ulimit -v``) minus the address space already mapped (``VmSize``); None without a limit. The
    two are kept apart because some backends (SuperLU) reserve far more address space than they
    touch.
    """
    resident = []
    try:
        with open("/proc/meminfo") as fh:
            for line in fh:
                if line.startswith("MemAvailable:"):
                    resident.append(int(line.split()[1]) * 1024)
                    break
    except (OSError, ValueError, IndexError):
        pass
    if not resident:
        try:
            resident.append(os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_AVPHYS_PAGES"))
        except (ValueError, OSError, AttributeError):
            resident.append(8 * 1024**3)
    for limit_file, usage_file in (("/sys/fs/cgroup/memory.max", "/sys/fs/cgroup/memory.current"),
                                   ("/sys/fs/cgroup/memory/memory.limit_in_bytes",
                                    "/sys/fs/cgroup/memory/memory.usage_in_bytes")):
        limit = _read_int(limit_file)
        if limit is not None and limit < 2**60:  # v1 reports "no limit" as a huge number
            resident.append(limit - (_read_int(usage_file) or 0))
            break
    address = None
    try:
        import resource

        soft, _ = resource.getrlimit(resource.RLIMIT_AS)
        if soft != resource.RLIM_INFINITY and soft > 0:
            address = max(0, int(soft) - (_proc_status_bytes("VmSize") or 0))
    except (ImportError, OSError, ValueError):
        pass
    return max(0, int(min(resident))), address


def available_memory() -> int:
    """Bytes this process may still allocate: the least of the limits of :func:`memory_limits`.

    The one memory probe of the package: every refusal "needs X, Y available" asks it.
    """
    resident, address = memory_limits()
    return resident if address is None else min(resident, address)


def require_memory(what: str, needed: float) -> None:
    """Refuse (MemoryError with a sentence) when ``needed`` bytes exceed :func:`available_memory`."""
    have = available_memory()
    if needed > have:
        raise MemoryError(f"{what} needs about {_bytes(needed)}, more than the {_bytes(have)} this process "
                          "may still allocate.")


def _bytes(n: float) -> str:
    for unit, size in (("TiB", 2**40), ("GiB", 2**30), ("MiB", 2**20)):
        if n >= size:
            return f"{n / size:.3g} {unit}" if n / size < 1e6 else f"{n / size:.3g} {unit}"
    return f"{int(n):,} bytes"


# ----------------------------------------------------------------------------
# the generic guard: every public function checks its annotated parameter types
# ----------------------------------------------------------------------------
#
# Each module ends with ``_validate.guard_public(globals())``. Every public function defined in
# it is then wrapped so that an argument whose *type* contradicts the annotation (``True`` for
# ``resolvent: BelowBandResolvent | None``, ``None`` for ``q: int``, ``0`` for ``check: bool``,
# a complex number for ``t: float``) gives the door's ValueError naming the parameter, before
# the function body can fail with AttributeError or TypeError deep in the stack. Ranges and
# meanings stay with each function's own checks; the guard only knows types. Parameters whose
# annotation it does not understand (``np.ndarray`` accepts lists, type aliases) are left alone,
# and a function with nothing to check is not wrapped at all (no cost on hot paths).

_ATOM_WORDS = {
    "int": "an integer",
    "float": "a finite real number",
    "complex": "a finite (complex) number",
    "bool": "True or False",
    "str": "a string",
    "dict": "a dict",
    "list": "a list",
    "tuple": "a tuple or list",
    "Sequence": "a list or tuple",
    "Callable": "a function",
    "Path": "a path",
}


def _is_int(v) -> bool:
    v = _zero_d(v)
    if isinstance(v, (bool, np.bool_)):
        return False
    if isinstance(v, (int, np.integer)):
        return True
    return isinstance(v, (float, np.floating)) and math.isfinite(v) and float(v).is_integer()


def _is_real(v) -> bool:
    v = _zero_d(v)
    if isinstance(v, (bool, np.bool_)) or not isinstance(v, numbers.Real):
        return False
    try:
        return math.isfinite(float(v))
    except (OverflowError, TypeError, ValueError):
        return False


def _is_complex(v) -> bool:
    v = _zero_d(v)
    if isinstance(v, (bool, np.bool_)) or not isinstance(v, numbers.Number):
        return False
    try:
        c = complex(v)
    except (OverflowError, TypeError, ValueError):
        return False
    return math.isfinite(c.real) and math.isfinite(c.imag)


_PLAIN = (bool, np.bool_, numbers.Number, str, bytes, list, tuple, dict, set, frozenset, range)


def _is_object_like(v) -> bool:
    return not (v is None or isinstance(v, _PLAIN) or type(v) is object
                or (isinstance(v, np.ndarray) and v.ndim == 0))


def _is_sequence(v) -> bool:
    return not isinstance(v, (str, bytes, dict, bool, np.bool_)) and hasattr(v, "__iter__")


def _array_or(test):
    # scalar annotations on functions that broadcast: arrays are left to the function itself
    return lambda v: (isinstance(v, np.ndarray) and v.ndim > 0) or test(v)


_ATOM_TESTS = {
    "int": _array_or(_is_int),
    "float": _array_or(_is_real),
    "complex": _array_or(_is_complex),
    "bool": lambda v: isinstance(v, (bool, np.bool_)),
    "str": lambda v: isinstance(v, str),
    "dict": lambda v: isinstance(v, dict),
    "list": _is_sequence,
    "tuple": _is_sequence,
    "Sequence": _is_sequence,
    "Callable": callable,
    "Path": lambda v: isinstance(v, (str, os.PathLike)) and not isinstance(v, bool),
}


def _split_union(text: str) -> list[str]:
    parts, depth, start = [], 0, 0
    for i, ch in enumerate(text):
        if ch in "[(":
            depth += 1
        elif ch in "])":
            depth -= 1
        elif ch == "|" and depth == 0:
            parts.append(text[start:i].strip())
            start = i + 1
    parts.append(text[start:].strip())
    return parts


def _resolve_class(name: str, namespace: dict):
    """The class a string annotation names, from the function's module or any loaded hyperlattice
    module (result types are often imported only for type checking); None when unknown."""
    import importlib
    import sys

    head, _, rest = name.partition(".")
    obj = namespace.get(head)
    if obj is None and rest:
        try:
            obj = importlib.import_module(head)
        except ImportError:
            obj = None
    if obj is not None:
        for part in rest.split(".") if rest else ():
            obj = getattr(obj, part, None)
    if obj is None and not rest:
        for modname, module in list(sys.modules.items()):
            if modname.startswith("hyperlattice") and module is not None:
                cand = getattr(module, name, None)
                if isinstance(cand, type):
                    obj = cand
                    break
    return obj if isinstance(obj, type) else None


class _Check:
    """The type test of one annotated parameter (built on first use: classes load lazily)."""

    __slots__ = ("annotation", "namespace", "allow_none", "tests", "words", "ready", "usable")

    def __init__(self, annotation: str, namespace: dict, allow_none: bool) -> None:
        self.annotation, self.namespace, self.allow_none = annotation, namespace, allow_none
        self.ready, self.usable = False, True
        self.tests, self.words = [], []

    def _build(self) -> None:
        self.ready = True
        for part in _split_union(self.annotation):
            base = part.split("[", 1)[0].strip().strip("'\"")
            if base == "None":
                self.allow_none = True
            elif base in ("list", "Sequence") and "[" in part and part.endswith("]"):
                # list[dict], Sequence[DeltaCurve]: the elements are checked too
                inner = _Check(part[part.index("[") + 1:-1].strip(), self.namespace, False)
                inner._build()
                if not inner.usable:
                    self.tests.append(_ATOM_TESTS[base])
                    self.words.append(_ATOM_WORDS[base])
                else:
                    self.tests.append(lambda v, inner=inner: _is_sequence(v) and not isinstance(v, np.ndarray)
                                      and all(any(t(e) for t in inner.tests) for e in v))
                    self.words.append(f"a list of {' or '.join(w.split(' ', 1)[-1] for w in inner.words)} values")
            elif base in _ATOM_TESTS:
                self.tests.append(_ATOM_TESTS[base])
                self.words.append(_ATOM_WORDS[base])
            elif base.isidentifier() or all(w.isidentifier() for w in base.split(".")):
                cls = _resolve_class(base, self.namespace)
                head = base.split(".")[0]
                if cls is None and (head in self.namespace or base in ("np", "sp") or head in ("np", "sp")):
                    self.usable = False  # a type alias (OnSite = float | array | callable): no guess
                    return
                if cls is not None and (cls.__module__ in ("numpy", "builtins")
                                        or cls.__module__.startswith(("numpy.", "scipy"))):
                    self.usable = False  # np.ndarray, sparse matrices: arrays take lists too
                    return
                # duck-typed: an annotation ``Lattice`` also takes a Cluster, a SectorLattice, ...
                # (and a class known only to the type checker, e.g. matplotlib's Axes, is not
                # imported here); what such a parameter never takes is a plain value (None, True,
                # 3.5, "x", [1, 2], object())
                self.tests.append(lambda v, cls=cls: (cls is not None and isinstance(v, cls)) or _is_object_like(v))
                word = base.split(".")[-1]
                self.words.append(f"{'an' if word[0] in 'AEIOU' else 'a'} {word}")
            else:
                self.usable = False
                return
        if not self.tests:
            self.usable = False

    def __call__(self, name: str, value) -> None:
        if not self.ready:
            self._build()
        if not self.usable or (value is None and self.allow_none):
            return
        for test in self.tests:
            if test(value):
                return
        words = self.words + (["None"] if self.allow_none else [])
        what = ", ".join(words[:-1]) + " or " + words[-1] if len(words) > 1 else words[0]
        raise ValueError(f"{name} must be {what}, got {_shown(value)}.")


#: what a function body raises when an argument of the wrong type reaches it
_CRASHES = (TypeError, AttributeError, OverflowError, ZeroDivisionError, IndexError, KeyError,
            RecursionError)


def guard(func: Callable) -> Callable:
    """``func`` wrapped so that its annotated parameter types are checked at the door.

    Two kinds of check. A parameter annotated ``bool`` must be True or False *before* the call
    (``check=0`` would otherwise be taken silently as False). Every other annotated parameter is
    checked only if the body fails with a type-level crash (:data:`_CRASHES`): then the first
    argument that contradicts its annotation is named in a ValueError, and if none does, the
    original exception propagates (a bug of ours, not bad input). This keeps each function's own,
    more specific messages, costs nothing on the success path, and never refuses a value that a
    function handles although its annotation is narrower. Returns ``func`` itself when no
    parameter has an annotation the guard understands.
    """
    import functools
    import inspect

    if getattr(func, "__hyperlattice_guarded__", False):
        return func
    try:
        sig = inspect.signature(func)
    except (TypeError, ValueError):
        return func
    namespace = getattr(func, "__globals__", {})
    before, after, paths = [], [], []
    for index, par in enumerate(sig.parameters.values()):
        if par.kind in (par.VAR_POSITIONAL, par.VAR_KEYWORD) or par.annotation is par.empty:
            continue
        ann = par.annotation
        text = ann if isinstance(ann, str) else getattr(ann, "__name__", None) or str(ann)
        if not isinstance(text, str):
            continue
        position = index if par.kind in (par.POSITIONAL_ONLY, par.POSITIONAL_OR_KEYWORD) else 10**9
        entry = (position, par.name, par.default, _Check(text, namespace, par.default is None))
        # True or False and functions are never ambiguous: check them before the call (check=0
        # would be taken as False; a bad progress callback would fail only after the work)
        atoms = {p.split("[", 1)[0].strip() for p in _split_union(text)}
        if atoms <= {"Path", "None"} and "Path" in atoms:
            paths.append(entry)  # a ``Path`` parameter takes any path: str is converted first
        (before if atoms <= {"bool", "None", "Callable", "Path"} else after).append(entry)
    if not before and not after:
        return func
    before, after = tuple(before), tuple(before + after)
    paths = tuple((position, name) for position, name, _, _ in paths)

    def as_paths(args, kwargs):
        args = list(args)
        for position, name in paths:
            if position < len(args):
                if isinstance(args[position], (str, os.PathLike)):
                    args[position] = Path(args[position])
            elif isinstance(kwargs.get(name), (str, os.PathLike)):
                kwargs[name] = Path(kwargs[name])
        return args, kwargs

    def run(checks, args, kwargs):
        n = len(args)
        for position, name, default, check in checks:
            if position < n:
                value = args[position]
            elif name in kwargs:
                value = kwargs[name]
            else:
                continue
            if value is not default:
                check(name, value)

    @functools.wraps(func)
    def guarded(*args, **kwargs):
        if before:
            run(before, args, kwargs)
            if paths:
                args, kwargs = as_paths(args, kwargs)
        try:
            return func(*args, **kwargs)
        except _CRASHES:
            try:
                run(after, args, kwargs)
            except ValueError as bad:  # an argument is to blame: the door's sentence, not the crash
                raise bad from None
            raise

    guarded.__hyperlattice_guarded__ = True
    return guarded


def _all_finite(value) -> bool:
    if isinstance(value, (bool, np.bool_, str, bytes)) or value is None:
        return True
    if isinstance(value, numbers.Number):
        c = complex(value)
        return math.isfinite(c.real) and math.isfinite(c.imag)
    if isinstance(value, np.ndarray):
        return value.dtype.kind not in "fc" or bool(np.all(np.isfinite(value)))
    if isinstance(value, (tuple, list)):
        return all(_all_finite(v) for v in value)
    import dataclasses

    if dataclasses.is_dataclass(value) and not isinstance(value, type):  # e.g. ContinuumParameters
        return all(_all_finite(getattr(value, f.name)) for f in dataclasses.fields(value))
    return True


def finite_output(func: Callable) -> Callable:
    """``func`` wrapped so that a result that is not finite becomes a ValueError.

    For the maps of the dictionary and of geometry: an argument like ``f = 1e308`` used to give
    ``B = inf`` (or NaN) as if it were an answer. The true value lies beyond the float64 range,
    so the map refuses with a sentence instead (numpy's overflow warnings are silenced inside:
    the sentence says it).
    """
    import functools

    @functools.wraps(func)
    def checked(*args, **kwargs):
        with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
            out = func(*args, **kwargs)
        if not _all_finite(out):
            raise ValueError(f"{func.__name__}: the result for these arguments is not a finite number "
                             "(it lies beyond the float64 range, about 1.8e308); use smaller arguments.")
        return out

    checked.__hyperlattice_guarded__ = getattr(func, "__hyperlattice_guarded__", False)
    return checked


def guard_public(namespace: dict, *, finite=()) -> None:
    """Wrap every public function defined in the module ``namespace`` with :func:`guard`.

    Called as the last line of each module, ``_validate.guard_public(globals())``: a new public
    function is guarded the day it is written, and the bad-input harness (tests/badinput.py)
    walks them all. ``finite`` (True for all, or a tuple of names) adds :func:`finite_output`.
    """
    import inspect

    module = namespace.get("__name__")
    for name, obj in list(namespace.items()):
        if name.startswith("_") or not inspect.isfunction(obj) or obj.__module__ != module:
            continue
        if finite is True or name in finite:
            obj = finite_output(obj)
        namespace[name] = guard(obj)
