"""Sweeps: grids of independent tasks on Dask (or serially), streamed into a resumable Parquet table.

:func:`run_sweep` is the one entry point (the ``hyperlattice sweep`` command calls it);
:func:`read_table` reads the result. See :mod:`.engine` for scheduling, keys, retries and
failures, :mod:`.store` for the on-disk table, :mod:`.tasks` for what can be swept.
"""

from __future__ import annotations

from .engine import SweepReport, expand_grid, have_dask, run_sweep
from .keys import task_key
from .store import SweepStore, SweepTable, have_pyarrow, read_table
from .tasks import TASKS, Task, get_task

__all__ = ["run_sweep", "SweepReport", "expand_grid", "task_key", "have_dask", "read_table", "SweepTable",
           "SweepStore", "have_pyarrow", "TASKS", "Task", "get_task"]
