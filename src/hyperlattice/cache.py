"""A small on-disk cache for expensive, deterministic results.

Entries are keyed on a name, the inputs and the package version, so a new version never
reads an old result. The directory is ``$HYPERLATTICE_CACHE`` or ``~/.cache/hyperlattice``
(``$XDG_CACHE_HOME/hyperlattice``); its entries can be deleted at any time
(``hyperlattice reproduce --clear-cache``).

An entry is one JSON file, ``<dir>/<version>/<name>-<digest>.json``::

    {"schema": "hyperlattice-cache/1", "name": ..., "inputs": ..., "version": ...,
     "type": "dict" or a result type tag, "sha256": ..., "value": ...}

``sha256`` is the digest of the canonical JSON of ``value`` (sorted keys, no spaces). A value is
a plain JSON dict, or any :class:`hyperlattice.results.Result` stored through its exact
``as_dict`` / ``from_dict`` round trip.

Trust, but check: an entry that cannot be parsed, lacks the schema, belongs to other inputs,
fails its checksum (a hand-edited number), cannot be rebuilt into its result type, or is a
directory, is **discarded and recomputed**, with a :class:`CacheWarning`. Writes go to a unique
temporary file in the same directory (:func:`tempfile.mkstemp`) that replaces the entry with
:func:`os.replace`, which is atomic on POSIX and Windows: concurrent runs never see half an entry
and never collide on a temporary name; the last writer wins. A failure to *store* (disk full,
permissions changed) only warns: the value was computed and is returned.

Only what the package wrote is ever deleted. The cache directory may be shared with the user's
own files (``--cache-dir ~/thesis``, or the same directory as ``--out``): :meth:`Cache.clear`
removes only entry files (``<name>-<24 hex digits>.json`` whose content starts with this
module's schema) and the package's own temporary files inside version subdirectories marked by
``.hyperlattice-cache``, then the marker and the subdirectory if it is left empty. Anything else
there -- a user's ``thesis/c.tex``, a file renamed by hand -- stays.

Why hand-written and not ``diskcache`` (the obvious library): the entries stay plain JSON files a
person can open, diff and delete one by one (the reproduction's numbers can be traced to them);
``diskcache`` keeps values in SQLite, pickled by default (unpickling a shared cache directory runs
code), and checks no value against a checksum; and this file is the whole feature, without a new
dependency.
"""

from __future__ import annotations

import contextlib
import hashlib
import json
import os
import re
import shutil
import tempfile
import warnings
from pathlib import Path
from typing import Callable

from . import __version__, _validate
from .results import Result

__all__ = ["Cache", "CacheWarning", "default_cache_dir", "checkpoint_cache"]

#: Written into every entry; an entry with another schema is recomputed.
SCHEMA = "hyperlattice-cache/1"
#: Marks a version subdirectory as written by this module (clear() looks only into marked ones).
MARKER = ".hyperlattice-cache"
_ENTRY = re.compile(r"^[A-Za-z0-9_-]+-[0-9a-f]{24}\.json$")
_TEMP = re.compile(r"^\.[A-Za-z0-9_-]+-[0-9a-f]{24}\..+\.tmp$")


class CacheWarning(UserWarning):
    """A cache entry was bad and has been recomputed, or a value could not be stored."""


def default_cache_dir() -> Path:
    """``$HYPERLATTICE_CACHE``, else ``$XDG_CACHE_HOME/hyperlattice``, else ``~/.cache/hyperlattice``.

    Returns
    -------
    pathlib.Path
        The directory a :class:`Cache` uses when none is given (not created here).

    Examples
    --------
    >>> import os
    >>> from unittest import mock
    >>> from hyperlattice.cache import default_cache_dir
    >>> with mock.patch.dict(os.environ, {"HYPERLATTICE_CACHE": "/tmp/hl-cache"}):
    ...     print(default_cache_dir())
    /tmp/hl-cache
    """
    env = os.environ.get("HYPERLATTICE_CACHE")
    if env:
        return Path(env)
    base = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
    return Path(base) / "hyperlattice"


def _canonical(value) -> str:
    # allow_nan: plain dict values may hold inf/nan (Python's JSON writes Infinity/NaN and reads
    # them back); results are encoded without them
    return json.dumps(value, sort_keys=True, separators=(",", ":"))


def _checksum(value) -> str:
    return hashlib.sha256(_canonical(value).encode()).hexdigest()


class Cache:
    """JSON cache keyed on (name, inputs, package version). ``enabled=False`` computes always.

    Parameters
    ----------
    directory : str or Path, optional
        Cache directory (created if missing); default :func:`default_cache_dir`.
    enabled : bool
        False: never read or write, every :meth:`get` computes.

    Raises
    ------
    ValueError
        If the cache is enabled and the directory cannot be created or written to.

    Attributes
    ----------
    hits, misses, reused : int
        Entries read that an earlier run (or another Cache object) wrote, values computed
        (including recomputed bad entries), and entries read again that this object wrote itself.

    Examples
    --------
    >>> import tempfile
    >>> from hyperlattice.cache import Cache
    >>> with tempfile.TemporaryDirectory() as d:
    ...     cache = Cache(d)
    ...     first = cache.get("square", {"x": 3}, lambda: {"value": 9})
    ...     again = Cache(d).get("square", {"x": 3}, lambda: {"value": -1})   # read, not computed
    ...     removed = cache.clear()
    >>> first, again, cache.misses, removed
    ({'value': 9}, {'value': 9}, 1, 1)
    """

    def __init__(self, directory: str | Path | None = None, *, enabled: bool = True) -> None:
        self.enabled = _validate.flag("enabled", enabled)
        if directory is None:
            directory = default_cache_dir()
        if self.enabled:
            # refuse an unusable directory now, not after the first hour of computing
            self.directory = _validate.directory("cache directory", directory)
        else:
            self.directory = _validate._as_path("cache directory", directory)
        self.hits = 0
        self.misses = 0
        self.reused = 0
        self._written: set[Path] = set()  # entries this object stored: reading them again is no hit

    def _path(self, name: str, inputs: dict) -> Path:
        blob = json.dumps({"name": name, "inputs": inputs, "version": __version__}, sort_keys=True)
        digest = hashlib.sha256(blob.encode()).hexdigest()[:24]
        return self.directory / __version__ / f"{name}-{digest}.json"

    @staticmethod
    def _key(name, inputs) -> tuple[str, dict]:
        if not isinstance(name, str) or not name or not name.replace("_", "").replace("-", "").isalnum():
            raise ValueError(f"a cache entry name must be letters, digits, '-' and '_', got {name!r}.")
        if not isinstance(inputs, dict):
            raise ValueError(f"cache inputs must be a dict of JSON values, got {type(inputs).__name__}.")
        try:
            # the round trip normalises tuples to lists, so the stored inputs compare equal
            inputs = json.loads(json.dumps(inputs, sort_keys=True, allow_nan=False))
        except (TypeError, ValueError):
            raise ValueError("cache inputs must be JSON values (numbers, strings, lists, dicts).") from None
        return name, inputs

    # -- reading ----------------------------------------------------------------------
    def _discard(self, path: Path, why: str) -> None:
        warnings.warn(f"cache entry {path.name} {why}; it is discarded and recomputed.", CacheWarning,
                      stacklevel=4)
        with contextlib.suppress(OSError):
            if path.is_dir() and not path.is_symlink():
                shutil.rmtree(path)
            else:
                path.unlink()

    def _read(self, path: Path, name: str, inputs: dict, expect):
        """The stored value, or None (after a warning and removal) if the entry is bad."""
        if path.is_dir():
            self._discard(path, "is a directory")
            return None
        try:
            with open(path, encoding="utf-8") as fh:
                entry = json.load(fh)
        except FileNotFoundError:
            return None
        except (OSError, ValueError) as exc:  # JSONDecodeError and UnicodeDecodeError are ValueErrors
            self._discard(path, f"cannot be read ({type(exc).__name__})")
            return None
        if not isinstance(entry, dict) or entry.get("schema") != SCHEMA \
                or not {"name", "inputs", "version", "type", "sha256", "value"} <= set(entry):
            self._discard(path, f"is not a {SCHEMA} entry")
            return None
        if (entry["name"], entry["inputs"], entry["version"]) != (name, inputs, __version__):
            self._discard(path, "belongs to other inputs")
            return None
        value = entry["value"]
        if entry["sha256"] != _checksum(value):
            self._discard(path, "fails its checksum (edited or damaged)")
            return None
        kind = entry["type"]
        wanted = None if expect is None else ("dict" if expect is dict else expect.TYPE)
        if wanted is not None and kind != wanted:
            self._discard(path, f"holds a {kind}, not the expected {wanted}")
            return None
        if kind == "dict":
            if not isinstance(value, dict):
                self._discard(path, "holds a value of the wrong type")
                return None
            return value
        if not isinstance(value, dict) or value.get("type") != kind:
            self._discard(path, "has a type tag that does not match its value")
            return None
        try:
            return Result.from_dict(value)
        except ValueError as exc:
            self._discard(path, f"cannot be rebuilt ({exc})")
            return None

    # -- writing ----------------------------------------------------------------------
    def _write(self, path: Path, name: str, inputs: dict, value) -> None:
        if isinstance(value, Result):
            kind, stored = value.TYPE, value.as_dict()
        else:
            kind, stored = "dict", value
        entry = {"schema": SCHEMA, "name": name, "inputs": inputs, "version": __version__,
                 "type": kind, "sha256": _checksum(stored), "value": stored}
        text = json.dumps(entry)
        tmp = None
        try:
            path.parent.mkdir(parents=True, exist_ok=True)
            marker = path.parent / MARKER
            if not marker.exists():
                marker.write_text("hyperlattice cache entries (hyperlattice reproduce --clear-cache deletes "
                                  "only files named <name>-<digest>.json holding a cache entry)\n")
            if path.is_dir() and not path.is_symlink():
                shutil.rmtree(path)  # os.replace cannot put a file over a directory
            fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.stem}.", suffix=".tmp")
            with os.fdopen(fd, "w", encoding="utf-8") as fh:
                fh.write(text)
            os.replace(tmp, path)
            tmp = None
        except OSError as exc:
            warnings.warn(f"could not store cache entry {path.name}: {exc.strerror or exc}.", CacheWarning,
                          stacklevel=3)
        finally:
            if tmp is not None:
                with contextlib.suppress(OSError):
                    os.unlink(tmp)

    # -- public -----------------------------------------------------------------------
    def get(self, name: str, inputs: dict, compute: Callable[[], dict | Result], *,
            expect: type | None = None) -> dict | Result:
        """Return the cached value for ``(name, inputs)`` or compute, store and return it.

        Parameters
        ----------
        name : str
            Kind of entry (letters, digits, ``-``, ``_``), e.g. ``"graph_levels"``.
        inputs : dict
            JSON values that determine the result.
        compute : callable
            Returns a dict of JSON values or a :class:`~hyperlattice.results.Result`.
        expect : type, optional
            ``dict`` or a Result class: a stored value of another type counts as a bad entry.

        Returns
        -------
        dict or Result
            The stored value when a good entry exists, else the value ``compute()`` returned.

        Warns
        -----
        CacheWarning
            When a bad entry was discarded, or the value could not be stored.
        """
        name, inputs = self._key(name, inputs)
        if expect is not None and not (expect is dict or (isinstance(expect, type) and issubclass(expect, Result))):
            raise ValueError(f"expect must be dict or a Result class, got {expect!r}.")
        path = self._path(name, inputs)
        if self.enabled and (path.exists() or path.is_symlink()):
            value = self._read(path, name, inputs, expect)
            if value is not None:
                if path in self._written:
                    self.reused += 1
                else:
                    self.hits += 1
                return value
        value = compute()
        if not isinstance(value, (dict, Result)):
            raise ValueError(f"a cached computation must return a dict or a Result, got {type(value).__name__}.")
        if self.enabled:
            self.put(name, inputs, value)
            self._written.add(path)
        # counted once stored: a run stopped (Ctrl-C) during the write reports only what is on disk
        self.misses += 1
        return value

    def put(self, name: str, inputs: dict, value: dict | Result) -> None:
        """Store ``value`` for ``(name, inputs)`` atomically (a no-op when disabled).

        Parameters
        ----------
        name : str
            Kind of entry (letters, digits, ``-``, ``_``).
        inputs : dict
            JSON values that determine the value.
        value : dict or Result
            A dict of JSON values or a :class:`~hyperlattice.results.Result`.

        Raises
        ------
        ValueError
            If the value is neither, or a dict holds values that are not JSON.
        """
        name, inputs = self._key(name, inputs)
        if not isinstance(value, (dict, Result)):
            raise ValueError(f"the cache stores dicts and Results, got {type(value).__name__}.")
        if isinstance(value, dict):
            try:
                value = json.loads(json.dumps(value))  # what a later read returns, checked now
            except (TypeError, ValueError):
                raise ValueError("a cached dict must hold JSON values only.") from None
        if self.enabled:
            self._write(self._path(name, inputs), name, inputs, value)

    def clear(self) -> int:
        """Delete the cache entries this package wrote, and nothing else; return how many.

        Only version subdirectories marked by ``.hyperlattice-cache`` are looked into, and in
        them only entry files (``<name>-<digest>.json`` starting with the schema), the package's
        temporary files and the marker are removed; the subdirectory goes when nothing else is
        left in it. Other files and directories, also the user's own in the same directory,
        are never touched.

        Raises
        ------
        ValueError
            If an entry cannot be deleted.
        """
        removed = 0
        if not self.directory.is_dir():
            return 0
        head = '{"schema": "%s"' % SCHEMA
        for sub in sorted(self.directory.iterdir()):
            if sub.is_symlink() or not sub.is_dir() or not (sub / MARKER).is_file():
                continue
            for f in sorted(sub.iterdir()):
                if f.is_symlink() or not f.is_file():
                    continue
                ours = bool(_TEMP.match(f.name))
                if not ours and _ENTRY.match(f.name):
                    try:
                        with open(f, encoding="utf-8", errors="replace") as fh:
                            ours = fh.read(len(head)) == head
                    except OSError:
                        ours = False
                if ours:
                    try:
                        f.unlink()
                    except FileNotFoundError:
                        continue
                    except OSError as exc:
                        raise ValueError(f"cannot clear the cache entry {str(f)!r}: "
                                         f"{exc.strerror or exc}.") from None
                    removed += 1
            # the marker is ours too; the subdirectory goes only when nothing else is in it
            with contextlib.suppress(OSError):
                (sub / MARKER).unlink()
                sub.rmdir()
        return removed


def checkpoint_cache(checkpoint) -> Cache | None:
    """The cache that keeps the finished points of a long multi-point run (``checkpoint=`` of
    :func:`~hyperlattice.compare.magnetic.magnetic_comparison` and
    :func:`~hyperlattice.graph.butterfly.butterfly`): ``checkpoint`` itself if it is a :class:`Cache`,
    a new one in the directory it names, or None (nothing kept).

    Parameters
    ----------
    checkpoint : Cache, str, path-like or None
        A cache, a directory (created if missing), or None.

    Returns
    -------
    Cache or None
        The cache to keep the points in, or None when ``checkpoint`` is None.

    Raises
    ------
    ValueError
        If ``checkpoint`` is of another type or names an unusable directory.

    Examples
    --------
    >>> import tempfile
    >>> from hyperlattice.cache import Cache, checkpoint_cache
    >>> cache = checkpoint_cache(tempfile.mkdtemp())
    >>> isinstance(cache, Cache), checkpoint_cache(cache) is cache, checkpoint_cache(None)
    (True, True, None)
    """
    if checkpoint is None or isinstance(checkpoint, Cache):
        return checkpoint
    if isinstance(checkpoint, (str, os.PathLike)) and not isinstance(checkpoint, bool):
        return Cache(checkpoint)
    raise ValueError(f"checkpoint must be a directory or a Cache, got {_validate._shown(checkpoint)}.")


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
