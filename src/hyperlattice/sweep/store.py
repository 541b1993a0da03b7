"""The on-disk table of a sweep: one Parquet file, written from per-task parts that make it resumable.

Layout of a sweep directory::

    _sweep.json            manifest: format, task, package version, every grid run into it, backend
    parts/part-<hash>.*    finished tasks, a batch per file, written atomically as results arrive,
                           each with the sha256 of its rows
    table.parquet          every row once, sorted by grid position (``index``), rebuilt at the end of a run
    _failures.json         the tasks that failed and have no row yet, with their errors (absent if none)
    .sweep.lock            the write lock (:mod:`filelock`)

Integrity, whatever runs write to one directory (at once or one after another):

* A row is keyed by its task and parameters only (:func:`~hyperlattice.sweep.keys.task_key`),
  never by a run's grid position, so the table holds each key exactly once (the rows of one key
  are identical: tasks are deterministic).
* ``index`` is not stored in the parts: it is the row's position in the *merged* grid, computed
  when the table is read -- the grids of all runs in the order they were first run, each in its
  own nested-loop order, a point already listed earlier keeping its place -- so it is 0..n-1 without
  collisions however the runs overlapped.
* The manifest keeps every grid (``grids``, in order) and, under ``parameters``, every value
  any grid gave each parameter; a later run adds its grid and never drops an earlier one.
* Every change of the manifest, the table and ``_failures.json`` happens under an exclusive lock
  on ``.sweep.lock`` (:class:`filelock.FileLock`: ``flock``/``LockFileEx``, released by the OS if
  a process dies), each as read-merge-write; parts need none (atomic renames, named by the hash of
  their keys).
* A part is checked against its sha256 when read: an edited or damaged part is refused with its
  file name, never copied into the table.
* A directory that holds anything but a sweep's files is refused: nothing of the user's is
  overwritten or deleted.

Why Parquet: a sweep's result is a flat table of numbers with a few list-valued columns (a DOS
histogram), which is exactly what Parquet stores, column-typed and compressed; pandas
(``pandas.read_parquet``), polars, DuckDB and xarray (through pandas) read it directly, and its
schema carries key-value metadata, where the parameters and the package version go (key
``hyperlattice``). Parts written while running give durability and resumption: a part is renamed
into place only when complete, so the rows in parts are finished tasks; the engine flushes a
batch every couple of seconds (and on any interruption), so a driver killed outright loses at
most the tasks of the last seconds, and they rerun. The table holds one row per key however
often a part was written. Zarr/NetCDF would suit dense
N-dimensional arrays on a full grid; a sweep with failures, partial reruns and ragged outputs is a
table.

Fallback without pyarrow: the same rows as JSON (``part-<hash>.json``, ``table.jsonl``, one JSON
object per line, readable by ``pandas.read_json(lines=True)``). Python's ``json`` writes floats
with ``repr``, which round-trips every float64 exactly, so the fallback table holds the same bits;
it is larger and slower, which matters little next to the computation of each row.
"""

from __future__ import annotations

import hashlib
import json
import os
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from filelock import FileLock, Timeout

from .. import __version__, _validate
from .keys import _grid_keys

__all__ = ["SweepStore", "SweepTable", "read_table", "have_pyarrow", "FORMAT"]

FORMAT = "hyperlattice-sweep/1"
_MANIFEST = "_sweep.json"
_FAILURES = "_failures.json"
_LOCK = ".sweep.lock"
#: Seconds to wait for another run's write (a part, the manifest or the table) before giving up.
LOCK_TIMEOUT = 120.0
#: What a new sweep directory may already hold (an empty parts/ and the lock of a run that stopped
#: before writing its manifest).
_OURS_BEFORE_MANIFEST = {"parts", _LOCK}


def have_pyarrow() -> bool:
    """True if pyarrow (the Parquet backend) can be imported.

    Returns
    -------
    bool
        Whether sweep tables can be written and read as Parquet (otherwise the JSON form is
        used).

    Examples
    --------
    >>> from hyperlattice.sweep.store import have_pyarrow
    >>> isinstance(have_pyarrow(), bool)
    True
    """
    try:
        import pyarrow  # noqa: F401
        import pyarrow.parquet  # noqa: F401
    except ImportError:
        return False
    return True


def _plain(v):
    """A JSON/Parquet-friendly value: Python scalars, lists for 1-d arrays."""
    if isinstance(v, np.ndarray):
        return [_plain(x) for x in v.tolist()]
    if isinstance(v, (list, tuple)):
        return [_plain(x) for x in v]
    if isinstance(v, np.generic):
        return v.item()
    return v


@dataclass
class SweepTable:
    """A sweep's rows as columns (numpy arrays for numeric columns, lists otherwise) and its metadata.

    Attributes
    ----------
    columns : dict of str to ndarray or list
        One entry per column: ``key`` (the point's digest), ``index`` (its position in the merged
        grid), the parameters and the task's outputs (energies in units of t for the physics tasks).
    metadata : dict
        The manifest: ``task``, ``version``, ``backend``, ``grids``, ``parameters``, ``format``.

    Examples
    --------
    >>> import os, tempfile
    >>> import hyperlattice as hl
    >>> where = os.path.join(tempfile.mkdtemp(), "probe")
    >>> _ = hl.run_sweep("probe", {"x": [1.0, 2.0]}, where, scheduler="serial", progress=False)
    >>> table = hl.read_table(where)
    >>> len(table), table.metadata["task"], table.rows()[1]["y"]
    (2, 'probe', 4.0)
    """

    columns: dict = field(default_factory=dict)
    metadata: dict = field(default_factory=dict)

    def __len__(self) -> int:
        return len(next(iter(self.columns.values()))) if self.columns else 0

    def rows(self) -> list[dict]:
        """One dict per row."""
        names = list(self.columns)
        return [{k: (self.columns[k][i].item() if isinstance(self.columns[k], np.ndarray)
                     else self.columns[k][i]) for k in names} for i in range(len(self))]

    def to_dataframe(self):
        """A ``pandas.DataFrame`` of the rows, the metadata in ``df.attrs["hyperlattice"]``
        (pandas is optional: ``pip install "hyperlattice[pandas]"``)."""
        from ..results import _optional

        pd = _optional("pandas", "pandas")
        df = pd.DataFrame({k: list(v) if not isinstance(v, np.ndarray) else v for k, v in self.columns.items()})
        df.attrs["hyperlattice"] = self.metadata
        return df

    #: the earlier name of :meth:`to_dataframe`
    to_pandas = to_dataframe


def _unique(rows: list[dict]) -> list[dict]:
    seen, out = set(), []
    for r in rows:
        if r.get("key") not in seen:
            seen.add(r.get("key"))
            out.append(r)
    return out


def _columns(rows: list[dict]) -> dict:
    names: list[str] = []
    for r in rows:
        for k in r:
            if k not in names:
                names.append(k)
    cols = {}
    for k in names:
        vals = [r.get(k) for r in rows]
        if vals and all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in vals):
            cols[k] = np.array(vals, dtype=float if any(isinstance(v, float) for v in vals) else np.int64)
        elif vals and all(isinstance(v, bool) for v in vals):
            cols[k] = np.array(vals, dtype=bool)
        else:
            cols[k] = vals
    return cols


def _rows_digest(rows: list[dict]) -> str:
    return hashlib.sha256(json.dumps(rows, sort_keys=True, separators=(",", ":"),
                                     allow_nan=True).encode()).hexdigest()


class SweepStore:
    """A sweep directory (see the module docstring). ``backend`` is ``"parquet"`` or ``"json"``.

    Parameters
    ----------
    path : str or pathlib.Path
        The directory (created if missing): new, empty, or a sweep's.
    backend : {"parquet", "json"}, optional
        Format of the parts; default: the directory's, else Parquet when pyarrow is installed.

    Raises
    ------
    ValueError
        If ``path`` exists and holds anything that is not a sweep's (its files are never touched).

    Examples
    --------
    >>> import tempfile
    >>> from hyperlattice.sweep.store import SweepStore
    >>> with tempfile.TemporaryDirectory() as d:
    ...     store = SweepStore(d, backend="json")
    ...     meta = store.open("probe", {"x": [1.0, 2.0]})
    ...     _ = store.write_rows([{"key": "a", "x": 1.0, "y": 1.0}], {"task": "probe"})
    ...     print(meta["task"], meta["parameters"], sorted(store.done()))
    probe {'x': [1.0, 2.0]} ['a']
    """

    def __init__(self, path, *, backend: str | None = None) -> None:
        self.path = _validate.owned_directory("the sweep directory", path, marker=_MANIFEST,
                                              ours=_OURS_BEFORE_MANIFEST, what="a sweep")
        self.lock = FileLock(str(self.path / _LOCK), timeout=LOCK_TIMEOUT)
        self.parts = self.path / "parts"
        self.parts.mkdir(exist_ok=True)
        if backend is None:
            backend = self._manifest().get("backend") or ("parquet" if have_pyarrow() else "json")
        self.backend = _validate.choice("backend", backend, ("parquet", "json"))
        if self.backend == "parquet" and not have_pyarrow():
            raise ValueError("this sweep directory holds Parquet parts, which need pyarrow "
                             "(pip install 'hyperlattice[sweep]').")
        self.suffix = ".parquet" if self.backend == "parquet" else ".json"

    # -- the lock ----------------------------------------------------------------
    def locked(self):
        """The directory's exclusive write lock, as a context manager (reentrant in one process)."""
        store = self

        class _Held:
            def __enter__(self_inner):
                try:
                    store.lock.acquire()
                except Timeout:
                    raise ValueError(f"the sweep directory {str(store.path)!r} stayed locked by another run "
                                     f"for {LOCK_TIMEOUT:g} s ({_LOCK}); try again when it has finished."
                                     ) from None
                return store

            def __exit__(self_inner, *exc):
                store.lock.release()
                return False

        return _Held()

    # -- manifest --------------------------------------------------------------
    def _manifest(self) -> dict:
        f = self.path / _MANIFEST
        if not f.exists():
            return {}
        try:
            data = json.loads(f.read_text())
        except (OSError, ValueError, RecursionError):
            raise ValueError(f"{str(f)!r} is not a sweep manifest (unreadable JSON).") from None
        if not isinstance(data, dict) or data.get("format") != FORMAT:
            raise ValueError(f"{str(f)!r} is not a manifest of format {FORMAT}.")
        grids = data.get("grids", [data.get("parameters", {})])
        if not isinstance(grids, list) or not all(isinstance(g, dict) for g in grids):
            raise ValueError(f"{str(f)!r} is not a sweep manifest (its grids are not a list of objects).")
        data["grids"] = grids
        return data

    def open(self, task: str, parameters: dict) -> dict:
        """Start (or resume) a sweep of ``task`` with grid ``parameters``; refuse another task's directory.

        The grid is added to the manifest's ``grids`` (once) and its values to ``parameters``,
        under the lock: a run never drops the grid of an earlier or concurrent one.

        Parameters
        ----------
        task : str
            The task's name.
        parameters : dict of str to list
            The grid: the values of each parameter.

        Returns
        -------
        dict
            The manifest written (``format``, ``task``, ``version``, ``backend``, ``grids``,
            ``parameters``).

        Raises
        ------
        ValueError
            If the directory holds a sweep of another task or backend.
        """
        grid = {str(k): list(v) for k, v in parameters.items()}
        with self.locked():
            old = self._manifest()
            if old and old.get("task") != task:
                raise ValueError(f"{str(self.path)!r} holds a sweep of task {old.get('task')!r}, not {task!r}; "
                                 "use another directory.")
            if old and old.get("backend") != self.backend:
                raise ValueError(f"{str(self.path)!r} holds {old.get('backend')} parts; this run would write "
                                 f"{self.backend}.")
            grids = [g for g in old.get("grids", []) if g] if old else []
            if grid not in grids:
                grids.append(grid)
            merged: dict = {}
            for g in grids:
                for name, values in g.items():
                    have = merged.setdefault(name, [])
                    for v in values:
                        if not any(type(v) is type(u) and v == u for u in have):
                            have.append(v)
            meta = {"format": FORMAT, "task": task, "version": __version__, "backend": self.backend,
                    "grids": grids, "parameters": merged}
            tmp = self.path / f".{_MANIFEST}.{os.getpid()}"
            tmp.write_text(json.dumps(meta, indent=1, sort_keys=True))
            os.replace(tmp, self.path / _MANIFEST)
        return meta

    # -- parts -----------------------------------------------------------------
    def _part_files(self) -> list[Path]:
        return sorted(self.parts.glob(f"part-*{self.suffix}"))

    def _bad_part(self, f: Path, why: str) -> ValueError:
        return ValueError(f"sweep part {str(f)!r} {why}; delete it to recompute its tasks.")

    def _read_part(self, f: Path):
        """The rows of one part (a list of dicts, or a pyarrow table), checked against its sha256."""
        if self.backend == "parquet":
            import pyarrow.parquet as pq

            try:
                table = pq.read_table(f)
            except (OSError, ValueError) as exc:
                raise self._bad_part(f, f"cannot be read ({type(exc).__name__})") from None
            meta = table.schema.metadata or {}
            try:
                stored = json.loads(meta.get(b"hyperlattice", b"{}")).get("sha256")
            except (ValueError, AttributeError):
                stored = None
            if stored is None:
                raise self._bad_part(f, "carries no checksum (it was not written by this version)")
            if stored != _rows_digest(table.to_pylist()):
                raise self._bad_part(f, "fails its checksum (edited or damaged)")
            return table.replace_schema_metadata(None)
        try:
            data = json.loads(f.read_text())
        except (OSError, ValueError, RecursionError) as exc:
            raise self._bad_part(f, f"cannot be read ({type(exc).__name__})") from None
        if not isinstance(data, dict) or data.get("format") != FORMAT or not isinstance(data.get("rows"), list) \
                or not all(isinstance(r, dict) and isinstance(r.get("key"), str) for r in data["rows"]):
            raise self._bad_part(f, f"is not a {FORMAT} part")
        if data.get("sha256") != _rows_digest(data["rows"]):
            raise self._bad_part(f, "fails its checksum (edited or damaged)")
        return data["rows"]

    def done(self) -> set[str]:
        """Keys of the finished tasks (rows present in some part)."""
        keys: set[str] = set()
        for f in self._part_files():
            part = self._read_part(f)
            if self.backend == "parquet":
                if "key" not in part.column_names:
                    raise self._bad_part(f, "has no key column")
                keys.update(part.column("key").to_pylist())
            else:
                keys.update(r["key"] for r in part)
        return keys

    def write_rows(self, rows: list[dict], meta: dict) -> Path | None:
        """Write finished tasks as one part, atomically (a temporary file renamed into place).

        The part's name is a hash of its keys, so the same batch written twice is one file; the
        part holds the sha256 of its rows. An ``index`` in the rows is dropped (it is the merged
        grid's, assigned on reading).

        Parameters
        ----------
        rows : list of dict
            Finished points, each with its ``key``.
        meta : dict
            Metadata stored with the part (beside the rows' sha256).

        Returns
        -------
        pathlib.Path or None
            The part written, or None for no rows.
        """
        if not rows:
            return None
        rows = [{k: _plain(v) for k, v in row.items() if k != "index"} for row in rows]
        digest = hashlib.sha256("\n".join(r["key"] for r in rows).encode()).hexdigest()[:24]
        final = self.parts / f"part-{digest}{self.suffix}"
        tmp = self.parts / f".tmp-{digest}-{os.getpid()}{self.suffix}"
        if self.backend == "parquet":
            import pyarrow as pa
            import pyarrow.parquet as pq

            table = pa.Table.from_pylist(rows)
            info = {**meta, "sha256": _rows_digest(table.to_pylist())}
            table = table.replace_schema_metadata({"hyperlattice": json.dumps(info)})
            pq.write_table(table, tmp)
        else:
            tmp.write_text(json.dumps({"format": FORMAT, "sha256": _rows_digest(rows), "rows": rows}))
        os.replace(tmp, final)
        return final

    def _positions(self, keys: list[str]) -> list[int]:
        """Each key's position in the merged grid (see the module docstring); unknown keys last."""
        meta = self._manifest()
        wanted = set(keys)
        pos: dict[str, int] = {}
        if meta:
            for grid in meta["grids"]:
                for k in _grid_keys(meta["task"], grid):
                    if k in wanted and k not in pos:
                        pos[k] = len(pos)
                if len(pos) == len(wanted):
                    break
        rest = sorted(wanted - set(pos))
        for k in rest:
            pos[k] = len(pos)
        return [pos[k] for k in keys]

    def _read_parts(self) -> list[dict]:
        if self.backend == "parquet":
            return self._parquet_parts().to_pylist()
        rows = [r for f in self._part_files() for r in self._read_part(f)]
        rows = _unique(rows)        # one row per key: the rows of one key are identical
        order = self._positions([r["key"] for r in rows])
        out = []
        for i, (_, r) in enumerate(sorted(zip(order, rows), key=lambda t: t[0])):
            r = {k: v for k, v in r.items() if k != "index"}
            out.append({"key": r.pop("key"), "index": i, **r})
        return out

    def _parquet_parts(self):
        """All Parquet parts as one pyarrow table in merged-grid order, one row per key, ``index`` 0..n-1."""
        import pyarrow as pa

        files = self._part_files()
        if not files:
            return pa.table({})
        tables = [self._read_part(f) for f in files]
        table = pa.concat_tables(tables, promote_options="permissive")
        if "index" in table.column_names:       # parts of earlier versions stored their run's position
            table = table.drop_columns(["index"])
        keys = table.column("key").to_pylist()
        first: dict[str, int] = {}
        for i, k in enumerate(keys):
            first.setdefault(k, i)          # one row per key, wherever the runs overlapped
        rows = list(first.values())
        order = self._positions(list(first))
        take = [r for _, r in sorted(zip(order, rows))]
        table = table.take(take)
        names = table.column_names
        table = table.add_column(1 if names and names[0] == "key" else 0, "index",
                                 pa.array(np.arange(len(take), dtype=np.int64)))
        if table.column_names[0] != "key":
            table = table.select(["key", "index"] + [n for n in table.column_names if n not in ("key", "index")])
        return table

    # -- the table ----------------------------------------------------------------
    @property
    def table_path(self) -> Path:
        return self.path / ("table.parquet" if self.backend == "parquet" else "table.jsonl")

    def consolidate(self) -> Path:
        """Rebuild the table from all parts, in merged-grid order, metadata in the schema (under the lock)."""
        with self.locked():
            meta = self._manifest()
            tmp = self.path / f".table-{os.getpid()}"
            if self.backend == "parquet":
                import pyarrow.parquet as pq

                table = self._parquet_parts()
                table = table.replace_schema_metadata({"hyperlattice": json.dumps(meta, sort_keys=True)})
                pq.write_table(table, tmp)
            else:
                rows = self._read_parts()
                with open(tmp, "w") as fh:
                    for r in rows:
                        fh.write(json.dumps(r) + "\n")
            os.replace(tmp, self.table_path)
        return self.table_path

    def write_failures(self, failures: list[dict], tried: set[str] | None = None) -> None:
        """Record this run's failures, merged with the earlier ones (under the lock).

        An earlier failure is dropped when its key now has a row or was tried again by this run
        (``tried``); the others stay, so a concurrent run's failures are not lost.

        Parameters
        ----------
        failures : list of dict
            This run's failures, each with its ``key``.
        tried : set of str, optional
            Keys this run tried (their earlier failures are replaced).
        """
        f = self.path / _FAILURES
        with self.locked():
            done = self.done()
            keep = [x for x in self.failures() if x.get("key") not in done
                    and x.get("key") not in (tried or set())]
            new_keys = {x["key"] for x in failures}
            merged = [x for x in keep if x.get("key") not in new_keys] + list(failures)
            if merged:
                tmp = self.path / f".{_FAILURES}.{os.getpid()}"
                tmp.write_text(json.dumps(merged, indent=1))
                os.replace(tmp, f)
            elif f.exists():
                f.unlink()

    def failures(self) -> list[dict]:
        f = self.path / _FAILURES
        if not f.exists():
            return []
        try:
            data = json.loads(f.read_text())
        except (OSError, ValueError, RecursionError):
            raise ValueError(f"{str(f)!r} is not a sweep's failure list (unreadable JSON).") from None
        if not isinstance(data, list) or not all(isinstance(x, dict) for x in data):
            raise ValueError(f"{str(f)!r} is not a sweep's failure list.")
        return data


def read_table(path) -> SweepTable:
    """Read a sweep directory's table (all finished rows, sorted by grid position) and its metadata.

    Reads the parts, so it also works on a sweep that is still running or was interrupted.

    Parameters
    ----------
    path : str or path-like
        The sweep directory given to :func:`~hyperlattice.sweep.engine.run_sweep`.

    Returns
    -------
    SweepTable
        ``columns`` (name to numpy array for numeric columns, list otherwise; one entry per
        finished row, with the task's parameters, its results, ``key`` and ``index``) and
        ``metadata`` (the sweep's manifest); ``rows()`` and ``to_pandas()`` give other views.

    Raises
    ------
    ValueError
        If ``path`` is not an existing sweep directory, its manifest is unreadable, or its
        Parquet parts need pyarrow, which is not installed.

    See Also
    --------
    hyperlattice.sweep.engine.run_sweep

    Examples
    --------
    >>> import os, tempfile
    >>> import hyperlattice as hl
    >>> where = os.path.join(tempfile.mkdtemp(), "probe")
    >>> _ = hl.run_sweep("probe", {"x": [1.0, 2.0, 3.0]}, where, scheduler="serial", progress=False)
    >>> table = hl.read_table(where)
    >>> len(table), table.columns["y"].tolist()
    (3, [1.0, 4.0, 9.0])
    """
    p = _validate.directory("the sweep directory", path, create=False)
    if not (p / _MANIFEST).exists():
        raise ValueError(f"{str(p)!r} is not a sweep directory (no {_MANIFEST}).")
    store = SweepStore(p)
    rows = store._read_parts()       # under no lock: a running sweep's parts are complete files
    return SweepTable(columns=_columns(rows), metadata=store._manifest())



# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
