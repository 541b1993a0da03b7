"""The on-disk table of a sweep: one Parquet file, written from per-task parts that make it resumable.

Layout of a sweep directory::

    _sweep.json            manifest: format, task, package version, the parameter grid, backend
    parts/part-<hash>.*    finished tasks, a batch per file, written atomically as results arrive
    table.parquet          every row, sorted by grid position (``index``), rebuilt at the end of a run
    _failures.json         the tasks that failed in the last run, with their errors (absent if none)

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

from .. import __version__, _validate

__all__ = ["SweepStore", "SweepTable", "read_table", "have_pyarrow", "FORMAT"]

FORMAT = "hyperlattice-sweep/1"
_MANIFEST = "_sweep.json"
_FAILURES = "_failures.json"


def have_pyarrow() -> bool:
    """True if pyarrow (the Parquet backend) can be imported."""
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
    """A sweep's rows as columns (numpy arrays for numeric columns, lists otherwise) and its metadata."""

    columns: dict = field(default_factory=dict)
    metadata: dict = field(default_factory=dict)

    def __len__(self) -> int:
        return len(next(iter(self.columns.values()))) if self.columns else 0

    def rows(self) -> list[dict]:
        """One dict per row."""
        names = list(self.columns)
        return [{k: (self.columns[k][i].item() if isinstance(self.columns[k], np.ndarray)
                     else self.columns[k][i]) for k in names} for i in range(len(self))]

    def to_pandas(self):
        """A ``pandas.DataFrame`` (pandas is not a dependency; install it to use this)."""
        import pandas as pd

        df = pd.DataFrame({k: list(v) if not isinstance(v, np.ndarray) else v for k, v in self.columns.items()})
        df.attrs["hyperlattice"] = self.metadata
        return df


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


class SweepStore:
    """A sweep directory (see the module docstring). ``backend`` is ``"parquet"`` or ``"json"``."""

    def __init__(self, path, *, backend: str | None = None) -> None:
        self.path = _validate.directory("the sweep directory", path)
        self.parts = self.path / "parts"
        self.parts.mkdir(exist_ok=True)
        if backend is None:
            backend = self._manifest().get("backend") or ("parquet" if have_pyarrow() else "json")
        self.backend = _validate.choice("backend", backend, ("parquet", "json"))
        if self.backend == "parquet" and not have_pyarrow():
            raise ValueError("this sweep directory holds Parquet parts, which need pyarrow "
                             "(pip install 'hyperlattice[sweep]').")
        self.suffix = ".parquet" if self.backend == "parquet" else ".json"

    # -- manifest --------------------------------------------------------------
    def _manifest(self) -> dict:
        f = self.path / _MANIFEST
        if not f.exists():
            return {}
        try:
            data = json.loads(f.read_text())
        except (OSError, ValueError):
            raise ValueError(f"{str(f)!r} is not a sweep manifest (unreadable JSON).") from None
        if not isinstance(data, dict) or data.get("format") != FORMAT:
            raise ValueError(f"{str(f)!r} is not a manifest of format {FORMAT}.")
        return data

    def open(self, task: str, parameters: dict) -> dict:
        """Start (or resume) a sweep of ``task``: write the manifest, refusing another task's directory."""
        old = self._manifest()
        if old and old.get("task") != task:
            raise ValueError(f"{str(self.path)!r} holds a sweep of task {old.get('task')!r}, not {task!r}; "
                             "use another directory.")
        if old and old.get("backend") != self.backend:
            raise ValueError(f"{str(self.path)!r} holds {old.get('backend')} parts; this run would write "
                             f"{self.backend}.")
        meta = {"format": FORMAT, "task": task, "version": __version__, "backend": self.backend,
                "parameters": parameters}
        tmp = self.path / f".{_MANIFEST}.{os.getpid()}"
        tmp.write_text(json.dumps(meta, indent=1, sort_keys=True))
        os.replace(tmp, self.path / _MANIFEST)
        return meta

    # -- parts -----------------------------------------------------------------
    def _part_files(self) -> list[Path]:
        return sorted(self.parts.glob(f"part-*{self.suffix}"))

    def done(self) -> set[str]:
        """Keys of the finished tasks (rows present in some part)."""
        keys: set[str] = set()
        for f in self._part_files():
            if self.backend == "parquet":
                import pyarrow.parquet as pq

                keys.update(pq.read_table(f, columns=["key"]).column("key").to_pylist())
            else:
                keys.update(r["key"] for r in json.loads(f.read_text()))
        return keys

    def write_rows(self, rows: list[dict], meta: dict) -> Path | None:
        """Write finished tasks as one part, atomically (a temporary file renamed into place).

        The part's name is a hash of its keys, so the same batch written twice is one file.
        """
        if not rows:
            return None
        rows = [{k: _plain(v) for k, v in row.items()} for row in rows]
        digest = hashlib.sha256("\n".join(r["key"] for r in rows).encode()).hexdigest()[:24]
        final = self.parts / f"part-{digest}{self.suffix}"
        tmp = self.parts / f".tmp-{digest}-{os.getpid()}{self.suffix}"
        if self.backend == "parquet":
            import pyarrow as pa
            import pyarrow.parquet as pq

            table = pa.Table.from_pylist(rows).replace_schema_metadata({"hyperlattice": json.dumps(meta)})
            pq.write_table(table, tmp)
        else:
            tmp.write_text(json.dumps(rows))
        os.replace(tmp, final)
        return final

    def _read_parts(self) -> list[dict]:
        if self.backend == "parquet":
            return self._parquet_parts().to_pylist()
        rows = [r for f in self._part_files() for r in json.loads(f.read_text())]
        rows.sort(key=lambda r: (r.get("index", 0), r.get("key", "")))
        return _unique(rows)

    def _parquet_parts(self):
        """All Parquet parts as one pyarrow table sorted by (index, key), one row per key."""
        import pyarrow as pa
        import pyarrow.parquet as pq

        files = self._part_files()
        if not files:
            return pa.table({})
        tables = [pq.read_table(f).replace_schema_metadata(None) for f in files]
        table = pa.concat_tables(tables, promote_options="permissive")
        table = table.sort_by([("index", "ascending"), ("key", "ascending")])
        keys = table.column("key").to_pylist()
        if len(set(keys)) != len(keys):
            # two runs raced on one directory: the rows of one key are identical (deterministic tasks)
            first = [i for i, k in enumerate(keys) if i == 0 or k != keys[i - 1]]
            table = table.take(first)
        return table

    # -- the table ----------------------------------------------------------------
    @property
    def table_path(self) -> Path:
        return self.path / ("table.parquet" if self.backend == "parquet" else "table.jsonl")

    def consolidate(self) -> Path:
        """Rebuild the table from all parts, sorted by grid position, metadata in the schema."""
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

    def write_failures(self, failures: list[dict]) -> None:
        f = self.path / _FAILURES
        if failures:
            f.write_text(json.dumps(failures, indent=1))
        elif f.exists():
            f.unlink()

    def failures(self) -> list[dict]:
        f = self.path / _FAILURES
        return json.loads(f.read_text()) if f.exists() else []


def read_table(path) -> SweepTable:
    """Read a sweep directory's table (all finished rows, sorted by grid position) and its metadata.

    Reads the parts, so it also works on a sweep that is still running or was interrupted.
    """
    p = _validate.directory("the sweep directory", path, create=False)
    if not (p / _MANIFEST).exists():
        raise ValueError(f"{str(p)!r} is not a sweep directory (no {_MANIFEST}).")
    store = SweepStore(p)
    rows = store._read_parts()
    return SweepTable(columns=_columns(rows), metadata=store._manifest())



# every public function above checks its annotated argument types at the door (issue 19)
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
