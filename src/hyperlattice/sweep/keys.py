r"""Task keys: one task, one key, in every process and on every machine.

The bottom of the sweep package: the engine (which runs grids) and the store (which orders a
table's rows by the grids that wrote them) both derive keys here, so neither imports the other.
"""

from __future__ import annotations

import json
import hashlib
import itertools
import math

from .tasks import get_task

__all__ = ["task_key"]


def _canonical(value):
    """Parameter values as JSON scalars; floats that are integers stay floats (1.0 != 1 in a key)."""
    if isinstance(value, bool) or value is None or isinstance(value, str):
        return value
    if isinstance(value, int):
        return int(value)
    if isinstance(value, float):
        if not math.isfinite(value):
            raise ValueError(f"parameter values must be finite, got {value!r}.")
        return float(value)
    try:
        import numpy as np

        if isinstance(value, np.integer):
            return int(value)
        if isinstance(value, np.floating):
            return _canonical(float(value))
        if isinstance(value, np.bool_):
            return bool(value)
    except ImportError:  # pragma: no cover
        pass
    raise ValueError(f"parameter values must be numbers, strings, booleans or null, got {value!r}.")


def task_key(task: str, params: dict) -> str:
    """``<task>-<sha256 of the sorted parameters, 24 hex digits>``: equal tasks, equal keys.

    Parameters
    ----------
    task : str
        Task name.
    params : dict
        Parameter name (str) to value (numbers, strings, booleans, None or lists of them).
        ``1`` and ``1.0`` give different keys; :func:`expand_grid` makes values canonical.

    Returns
    -------
    str
        The key, the same in every process and on every machine.

    Raises
    ------
    ValueError
        If ``task`` is not a string, ``params`` not a dict with string keys, or a value cannot
        be written as JSON.

    Examples
    --------
    >>> from hyperlattice.sweep.keys import task_key
    >>> task_key("probe", {"x": 1.0, "sleep": 0.0})
    'probe-6e621f423fe33c172460a69e'
    """
    if not isinstance(task, str):
        raise ValueError(f"task must be a task name (a string), got {type(task).__name__}.")
    if not isinstance(params, dict) or not all(isinstance(k, str) for k in params):
        raise ValueError("params must be a dict from parameter names (strings) to values.")
    try:
        text = json.dumps({"task": task, "params": params}, sort_keys=True, separators=(",", ":"))
    except (TypeError, ValueError) as exc:  # a complex number, an object: not a table value
        raise ValueError(f"task parameters must be numbers, strings, True/False or lists of them ({exc}).") from None
    return f"{task}-{hashlib.sha256(text.encode()).hexdigest()[:24]}"


def _grid_keys(task: str, grid: dict):
    """The keys of ``grid``'s points in grid order (no checks: the grid was checked when it ran)."""
    spec = get_task(task)
    names = [n for n in grid if n in spec.defaults]
    values = [[_canonical(v) for v in (grid[n] if isinstance(grid[n], (list, tuple)) else [grid[n]])]
              for n in names]
    for combo in itertools.product(*values):
        params = dict(spec.defaults)
        params.update(zip(names, combo))
        yield task_key(task, {k: _canonical(v) for k, v in params.items()})
