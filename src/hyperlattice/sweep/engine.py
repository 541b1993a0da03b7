"""The sweep engine: a grid of independent tasks on dask.distributed, streamed into a resumable table.

* **Where it runs.** ``"local"`` starts a ``distributed.LocalCluster`` on this machine (one
  single-threaded worker process per core, no set-up, shut down at the end); ``scheduler=None``
  does the same only when the grid is worth it: the first task runs in this process, and when the
  rest would take less than :data:`LOCAL_CLUSTER_SECONDS` (the cluster's start-up) they run here
  too, and the report's ``scheduler`` says so;
  ``"threads"`` the same with worker threads in this process; an address such as
  ``"tcp://10.0.0.5:8786"`` connects to a running scheduler (a cluster started by hand or by
  dask-jobqueue on SLURM/PBS, see docs/sweeps.md); a ``distributed.Client`` is used as given;
  ``"serial"`` runs in this process without Dask (also the fallback when dask is not installed),
  writing the same table.
* **Idempotent keys.** A task's key is its task name and a hash of its parameters
  (:func:`task_key`): the same task always has the same key, so a rerun skips every key whose row
  is on disk (resumable), a grid that lists a value twice is refused, and a task that a dying
  worker leaves half-done is recomputed by the scheduler under the same key and written once.
* **Streaming.** Rows are collected as futures complete (``distributed.as_completed``) and written
  every ``flush_seconds`` as one atomically renamed part file; the table is consolidated at the
  end, also after an interruption.
* **Failures.** A task that raises is retried ``retries`` times (``Client.submit(retries=...)``); a
  task whose worker dies is rescheduled by the scheduler (up to ``distributed.scheduler.allowed-
  failures`` deaths). What still fails is reported in :class:`SweepReport` ``failed`` and in
  ``_failures.json`` with its error, and is retried by the next run; nothing is dropped silently.
* **Progress.** A tqdm bar on stderr (``progress=True``; the package's one mechanism, :mod:`hyperlattice._progress`).
* **Refusals before work, in one sentence.** A grid of more than :data:`MAX_TASKS` points, or
  more than the memory available allows (``_BYTES_PER_TASK`` each), before it is expanded; a
  ``tcp://`` address where no Dask scheduler answers its handshake within ``timeout`` (at most
  :data:`CONNECT_TIMEOUT` s: distributed's own handshake read waits without limit), before the
  sweep directory is created; ``tls://`` without certificates and unknown ``inproc://``
  addresses. ``workers`` beyond the machine's cores is capped with one warning, and
  distributed's loggers are silenced while a sweep runs (its failures are the sweep's report).
"""

from __future__ import annotations

import itertools
import json
import math
import os
import re
import time
from dataclasses import dataclass, field
from typing import Callable

from .. import __version__, _validate
from ..errors import HyperlatticeError
from ..results import Result
from .store import SweepStore
from .keys import _canonical, task_key
from .tasks import execute, get_task

__all__ = ["run_sweep", "SweepReport", "expand_grid", "have_dask"]

#: Documented maximum of tasks per sweep (split a bigger study into several sweeps into one
#: directory: the grids merge). A sweep holds every point's parameters, key and (on Dask) future
#: in the driver at once; ten million of them ended in std::bad_alloc.
MAX_TASKS = 1_000_000
#: Driver memory per task, with margin: 440 B for the expanded point and its key (tracemalloc,
#: 200,000 probe points), plus its row on consolidation and, on Dask, its future and the
#: scheduler's task state (a few kB).
_BYTES_PER_TASK = 8192


def _memory_budget() -> int:
    """Bytes this process may still allocate (the package's one probe: machine, RLIMIT_AS, cgroup)."""
    from .. import _validate

    return int(_validate.available_memory())


def max_tasks() -> int:
    """The most tasks one sweep may have here: :data:`MAX_TASKS`, or fewer if memory is short."""
    return int(max(1, min(MAX_TASKS, _memory_budget() // _BYTES_PER_TASK)))


def check_grid_size(total: int) -> None:
    """Refuse a grid of ``total`` points before anything is expanded (ValueError with the limit)."""
    total = _validate.integer("total", total, minimum=0)
    limit = max_tasks()
    if total > limit:
        why = "per sweep" if limit == MAX_TASKS else \
            f"for the {_memory_budget() / 2**30:.1f} GiB of memory available ({_BYTES_PER_TASK:,} bytes per task)"
        raise ValueError(f"the grid has {total:,} tasks; at most {limit:,} {why} "
                         "(split it into several sweeps into the same directory).")


_SCALAR = (int, float, str, bool, type(None))


def have_dask() -> bool:
    """True if dask.distributed can be imported.

    Returns
    -------
    bool
        Whether the Dask schedulers of :func:`run_sweep` are available (without them only
        ``scheduler="serial"`` runs).

    Examples
    --------
    >>> from hyperlattice.sweep.engine import have_dask
    >>> isinstance(have_dask(), bool)
    True
    """
    try:
        import distributed  # noqa: F401
    except ImportError:
        return False
    return True


def expand_grid(task: str, grid: dict) -> list[dict]:
    """The Cartesian product of ``grid`` (name -> list of values, or one value), over the task's defaults.

    Order: the first parameter varies slowest, as in nested loops in the grid's order. Every
    combination is checked (:class:`~hyperlattice.sweep.tasks.Task` ``check``) before anything runs.

    Parameters
    ----------
    task : str
        A registered task (:data:`hyperlattice.sweep.tasks.TASKS`).
    grid : dict
        Parameter name to a list of values (or one value). Values must be finite numbers,
        strings, booleans or None.

    Returns
    -------
    list of dict
        One complete parameter dict per grid point (the task's defaults filled in).

    Raises
    ------
    ValueError
        For an unknown task or parameter, an empty value list, a value listed twice, a value of
        the wrong kind, a point the task's check refuses, or more points than :func:`run_sweep` accepts
        (:data:`MAX_TASKS`, fewer when memory is short).

    Examples
    --------
    >>> from hyperlattice.sweep.engine import expand_grid
    >>> expand_grid("probe", {"x": [1, 2], "sleep": 0.0})
    [{'x': 1, 'sleep': 0.0}, {'x': 2, 'sleep': 0.0}]
    """
    spec = get_task(task)
    if not isinstance(grid, dict):
        raise ValueError(f"the grid must be a mapping of parameter names to lists of values, got {type(grid).__name__}.")
    defaults = spec.defaults
    names, values = [], []
    for name, vals in grid.items():
        if name not in defaults:
            raise ValueError(f"task {task!r} has no parameter {name!r} (it has {', '.join(defaults)}).")
        if not isinstance(vals, (list, tuple)):
            vals = [vals]
        if len(vals) == 0:
            raise ValueError(f"the grid gives no values for {name!r}.")
        names.append(name)
        values.append([_canonical(v) for v in vals])
    check_grid_size(math.prod(len(v) for v in values))
    for name, vals in zip(names, values):
        # a value listed twice was silently one task: the user's count of points was not the run's
        seen_values: set[str] = set()
        for v in vals:
            text = json.dumps(v)            # 1 and 1.0 stay apart, as in the task keys
            if text in seen_values:
                raise ValueError(f"the grid lists {name} = {v!r} twice; give each value once.")
            seen_values.add(text)
    out, seen = [], set()
    for combo in itertools.product(*values):
        params = dict(defaults)
        params.update(zip(names, combo))
        params = {k: _canonical(v) for k, v in params.items()}
        spec.check(params)
        key = task_key(task, params)
        if key not in seen:         # distinct values give distinct keys; kept as a guard
            seen.add(key)
            out.append(params)
    return out


@dataclass(frozen=True, eq=False, kw_only=True)
class SweepReport(Result):
    """What a sweep run did: counts, failures (key, parameters, error), where the table is.

    ``completed`` counts rows written by this run, ``skipped`` rows already on disk.

    Attributes
    ----------
    path : str
        The sweep directory.
    table : str
        The consolidated table file (Parquet, or JSON lines without pyarrow).
    task : str
        The task's name (:data:`hyperlattice.sweep.tasks.TASKS`).
    scheduler : str
        What ran the tasks: ``"serial"``, ``"local (n processes)"`` / ``"local (n threads)"`` (a
        local Dask cluster), ``"client <address>"`` or the scheduler's address, or
        ``"nothing to do"`` when every row was on disk and no Dask scheduler was needed (a serial
        run keeps ``"serial"``); with the default scheduler, ``"serial (about x s of tasks, less
        than ...)"`` when the grid was too small to be worth starting a local cluster.
    total : int
        Grid points of this run.
    skipped : int
        Points whose rows were already on disk.
    completed : int
        Rows written by this run.
    failed : list of dict
        One ``{"key", "params", "error"}`` per task that failed.
    seconds : float
        Wall-clock time of the run.
    version : str
        The hyperlattice version that ran.

    Examples
    --------
    >>> import os, tempfile
    >>> import hyperlattice as hl
    >>> where = os.path.join(tempfile.mkdtemp(), "probe")
    >>> report = hl.run_sweep("probe", {"x": [1.0, 2.0, 3.0]}, where, scheduler="serial", progress=False)
    >>> report.task, report.total, report.completed, report.skipped, report.ok
    ('probe', 3, 3, 0, True)
    >>> again = hl.run_sweep("probe", {"x": [1.0, 2.0, 3.0]}, where, scheduler="serial", progress=False)
    >>> again.completed, again.skipped                      # resumed: every row was on disk
    (0, 3)
    """

    path: str
    table: str
    task: str
    scheduler: str
    total: int
    skipped: int
    completed: int
    failed: list = field(default_factory=list)
    seconds: float = 0.0
    version: str = __version__

    @property
    def ok(self) -> bool:
        """True when every task of the grid has its row."""
        return not self.failed and self.skipped + self.completed == self.total

    def summary(self) -> dict:
        """The ``sweep`` command's JSON: path, table, task, scheduler, total, skipped, completed, failed, seconds."""
        return {"path": self.path, "table": self.table, "task": self.task, "scheduler": self.scheduler,
                "total": self.total, "skipped": self.skipped, "completed": self.completed,
                "failed": len(self.failed), "failures": list(self.failed), "seconds": self.seconds,
                "version": self.version}


def _bar(total: int, progress: bool | None, desc: str):
    # the package's one progress mechanism; entered, so the tasks run in this process stay quiet
    from .._progress import progress_bar

    return progress_bar(total, desc, unit="task", progress=progress).__enter__()


def _error_text(exc: BaseException) -> str:
    return " ".join(f"{type(exc).__name__}: {exc}".split())[:500]


def _run_serial(task, todo, keys, write, retries, failures, bar, on_row, deadline):
    for params, key in zip(todo, keys):
        if deadline is not None and time.monotonic() > deadline:
            failures.append({"key": key, "params": params, "error": "TimeoutError: the sweep's time limit passed"})
            continue
        if bar is not None:
            # a serial task may run for minutes: the bar names it before it ends
            bar.item(", ".join(f"{k}={v}" for k, v in params.items()) or key)
        err = None
        for _attempt in range(retries + 1):
            try:
                row = execute(task, params)
                err = None
                break
            except Exception as exc:    # any failure of the task is reported, as Dask would (Ctrl-C passes)
                err = exc
        if err is not None:
            failures.append({"key": key, "params": params, "error": _error_text(err), "attempts": retries + 1})
        else:
            write(key, params, row)
            if on_row is not None:
                on_row(key)
        if bar is not None:
            bar.update(1)


#: Seconds a default local cluster takes to start (measured 5-6 s on the project's 2-core machine,
#: 2026-11-26): with ``scheduler=None`` a grid whose tasks would take less runs serially.
LOCAL_CLUSTER_SECONDS = 5.0


#: Seconds to reach a scheduler at an address (distributed's own default is 30 s, each retry
#: included); a smaller sweep ``timeout`` bounds it further.
CONNECT_TIMEOUT = 10.0


def _connect_wait(timeout: float | None) -> float:
    return CONNECT_TIMEOUT if timeout is None else min(CONNECT_TIMEOUT, timeout)


def _split_tcp(address: str) -> tuple[str, int] | None:
    """(host, port) of a tcp:// or bare host:port address, else None."""
    rest = address[len("tcp://"):] if address.startswith("tcp://") else address
    if "://" in rest:
        return None
    host, sep, port = rest.rpartition(":")
    if not sep or not port.isdigit():
        return None
    return host.strip("[]") or "127.0.0.1", int(port)


def _probe_tcp(address: str, wait: float) -> None:
    """Refuse, within ``wait`` seconds, a tcp address where no Dask scheduler answers.

    A Dask server speaks first: on accepting a connection it sends its handshake, a frame whose
    first 8 bytes are the little-endian byte count of what follows (``distributed.comm.tcp``).
    distributed's own handshake read has no time limit, so a port where something else listens
    (an HTTP server waits for a request) would hang the client for minutes; this probe waits at
    most ``wait`` seconds for those 8 bytes and checks that they are plausible.
    """
    import socket
    import struct

    hp = _split_tcp(address)
    if hp is None:
        return
    deadline = time.monotonic() + wait
    try:
        with socket.create_connection(hp, timeout=max(0.1, wait)) as sock:
            head = b""
            while len(head) < 8:
                left = deadline - time.monotonic()
                if left <= 0:
                    raise socket.timeout
                sock.settimeout(left)
                chunk = sock.recv(8 - len(head))
                if not chunk:
                    raise HyperlatticeError(f"something listens at {address} but closed the connection without "
                                            "answering as a Dask scheduler.")
                head += chunk
    except HyperlatticeError:
        raise
    except socket.timeout:
        raise HyperlatticeError(f"something listens at {address} but did not answer as a Dask scheduler "
                                f"within {wait:g} s.") from None
    except OSError as exc:
        raise HyperlatticeError(f"cannot reach the Dask scheduler at {address}: "
                                f"{exc.strerror or type(exc).__name__}.") from None
    (nbytes,) = struct.unpack("<Q", head)
    if not 0 < nbytes < 2**24:      # a handshake is a few hundred bytes
        raise HyperlatticeError(f"something listens at {address} but does not speak Dask's protocol.")


def _quiet_distributed():
    """distributed's loggers at CRITICAL while a sweep runs: its own retries, worker restarts and
    closed comms are reported by the sweep (failures, one-line errors), not as tracebacks on stderr."""
    import contextlib
    import logging

    @contextlib.contextmanager
    def quiet():
        names = ("distributed", "distributed.nanny", "distributed.scheduler", "distributed.worker",
                 "distributed.core", "distributed.comm", "distributed.client", "tornado", "asyncio")
        saved = [(logging.getLogger(n), logging.getLogger(n).level) for n in names]
        for lg, _ in saved:
            lg.setLevel(logging.CRITICAL)
        try:
            yield
        finally:
            for lg, level in saved:
                lg.setLevel(level)

    return quiet()


def _local_workers(workers: int | None) -> int:
    """Workers of a local cluster: one per core by default; more than the cores are capped, with a warning."""
    import warnings

    cores = max(1, os.cpu_count() or 1)
    if workers is None:
        return cores
    if workers > cores:
        # each worker is a single-threaded process (or thread): more of them than cores only
        # compete for the same cores, and dozens of nannies on a small machine time out
        warnings.warn(f"{workers} workers requested on a machine with {cores} cores; using {cores}.",
                      UserWarning, stacklevel=4)
        return cores
    return workers


def _client_for(scheduler, workers: int | None, timeout: float | None = None):
    """(client, cluster or None, label, own) for the scheduler argument; the caller closes what it got."""
    import logging

    import dask
    from distributed import Client, LocalCluster

    if isinstance(scheduler, Client):
        return scheduler, None, f"client {scheduler.scheduler.address}", False
    if scheduler in (None, "local", "threads"):
        n = _local_workers(workers)
        processes = scheduler != "threads"
        # dashboard_address=":0": a free port. None still binds Dask's default 8787 and, when another
        # cluster (or another user's notebook) holds it, warns and moves; ":0" never collides.
        cluster = LocalCluster(n_workers=n, threads_per_worker=1, processes=processes, dashboard_address=":0",
                               silence_logs=logging.CRITICAL)
        try:
            client = Client(cluster)
        except BaseException:
            cluster.close()
            raise
        return client, cluster, f"local ({n} {'processes' if processes else 'threads'})", True
    wait = _connect_wait(timeout)
    if str(scheduler).startswith("inproc://"):
        # an in-process address is known to this process's registry or to nobody: asked for one that
        # is not there, distributed waits for it (it hung inside a pytest-xdist worker)
        from distributed.comm.inproc import global_manager

        try:
            listener = global_manager.get_listener_for(str(scheduler)[len("inproc://"):])
        except Exception:       # not even an address of this host and process
            listener = None
        if listener is None:
            raise HyperlatticeError(f"no Dask scheduler {scheduler} runs in this process (an inproc:// address "
                                    "is only valid inside the process that started it).")
    _probe_tcp(scheduler, wait)     # again: run_sweep's probe may be long past
    try:
        with dask.config.set({"distributed.comm.timeouts.connect": f"{wait}s"}):
            client = Client(scheduler, timeout=wait)
    except (OSError, TimeoutError) as exc:
        raise HyperlatticeError(f"cannot reach the Dask scheduler at {scheduler} within {wait:g} s "
                                f"({_error_text(exc)}).") from None
    except TypeError as exc:
        if str(scheduler).startswith(("tls://", "wss://")):
            raise HyperlatticeError(f"cannot connect to the Dask scheduler at {scheduler}: TLS needs certificates "
                                    "in the dask configuration (distributed.comm.tls) or a distributed.Client "
                                    "made with a Security object.") from None
        raise HyperlatticeError(f"cannot connect to the Dask scheduler at {scheduler}: {_error_text(exc)}."
                                ) from None
    except Exception as exc:        # any other backend error, in one sentence
        if str(scheduler).startswith("inproc://"):
            raise HyperlatticeError(f"no Dask scheduler {scheduler} runs in this process (an inproc:// address "
                                    "is only valid inside the process that started it).") from None
        raise HyperlatticeError(f"cannot connect to the Dask scheduler at {scheduler}: {_error_text(exc)}."
                                ) from None
    return client, None, str(scheduler), True


def _run_dask(task, todo, keys, write, retries, failures, bar, on_row, scheduler, workers, timeout):
    from distributed import as_completed

    client, cluster, label, own = _client_for(scheduler, workers, timeout)
    futures = {}
    try:
        for params, key in zip(todo, keys):
            fut = client.submit(execute, task, params, key=key, retries=retries, pure=False)
            futures[fut] = (params, key)
        pending = set(futures)
        try:
            # with_results: results come in batches with the completion events (no round trip per task);
            # raise_errors=False: a failed task's exception comes back as its result, to be reported
            for fut, result in as_completed(list(futures), timeout=timeout, with_results=True, raise_errors=False):
                params, key = futures[fut]
                pending.discard(fut)
                if fut.status == "finished":
                    write(key, params, result)
                    if on_row is not None:
                        on_row(key)
                else:
                    exc = result if isinstance(result, BaseException) else fut.exception()
                    failures.append({"key": key, "params": params, "error": _error_text(exc),
                                     "attempts": retries + 1})
                if bar is not None:
                    bar.update(1)
        except TimeoutError:
            for fut in pending:
                params, key = futures[fut]
                failures.append({"key": key, "params": params,
                                 "error": f"TimeoutError: not finished within the sweep's {timeout:g} s"})
    finally:
        if futures:
            client.cancel(list(futures), force=True)
        if own:
            client.close()
        if cluster is not None:
            cluster.close()
    return label


_ADDRESS = re.compile(r"^(?:(?:tcp|tls|ucx|ws|wss|inproc)://\S+|[A-Za-z0-9_.\-\[\]:]+:\d{1,5})$")


def _check_address(text: str) -> str:
    """A scheduler address like ``tcp://host:8786`` or ``host:8786`` (refused before any connection)."""
    if not _ADDRESS.match(text):
        raise ValueError(f"scheduler must be 'local', 'threads', 'serial' or an address such as "
                         f"tcp://host:8786, got {text!r}.")
    return text


def run_sweep(task: str, grid: dict, path, *, scheduler=None, workers: int | None = None, retries: int = 2,
              progress: bool | None = True, timeout: float | None = None,
              on_row: Callable[[str], None] | None = None, flush_seconds: float = 2.0,
              flush_rows: int = 1000) -> SweepReport:
    """Run every point of ``grid`` for ``task``, skipping points already in the table at ``path``.

    Parameters
    ----------
    task : str
        A registered task (:data:`hyperlattice.sweep.tasks.TASKS`: ``disorder``, ``levels``, ``probe``).
    grid : dict
        Parameter name -> list of values (or one value); missing parameters take the task's defaults.
    path : path
        The sweep directory (created; resumed if it exists).
    scheduler : None, "local", "threads", "serial", address or distributed.Client
        See the module docstring. Without dask installed only ``"serial"`` (and None, which then
        means serial) is available.
    workers : int, optional
        Workers of the local cluster (default: one per core).
    retries : int, optional
        Extra attempts of a task that raises. Default 2.
    progress : bool or None, optional
        tqdm progress bar on stderr; None: when stderr is a terminal (:mod:`hyperlattice._progress`).
        Default True.
    timeout : float, optional
        Seconds after which unfinished tasks are cancelled and reported as failed.
    on_row : callable, optional
        Called with each key as its result arrives (e.g. to log, or to stop the run: rows that
        arrived are written before the exception leaves).
    flush_seconds, flush_rows : float, int, optional
        Finished rows are written as one part when this many seconds passed since the last write
        or this many rows wait (one file per task would cost a file per row; a driver killed
        outright loses at most these rows, which the next run recomputes). Defaults 2.0 s and
        1000 rows.

    Returns
    -------
    SweepReport
        ``total`` tasks of the grid, ``completed`` (written by this run), ``skipped`` (already
        on disk), ``failed`` (key, parameters and error of each task that still failed),
        ``path`` and ``table`` of the sweep, ``scheduler`` used and ``seconds``; ``ok`` is True
        when every task has its row.

    Raises
    ------
    ValueError
        For an unknown task or parameter, a bad grid or scheduler argument, a grid larger than
        :data:`MAX_TASKS` (or than memory allows), a Dask scheduler asked for without dask
        installed, or an unusable sweep directory.
    hyperlattice.errors.HyperlatticeError
        If no Dask scheduler answers at the given address (within ``timeout``, at most
        :data:`CONNECT_TIMEOUT` s).

    See Also
    --------
    read_table : the rows written.
    expand_grid : the points of a grid.

    Examples
    --------
    The ``probe`` task (y = x², no physics) in this process:

    >>> import os, tempfile
    >>> import hyperlattice as hl
    >>> where = os.path.join(tempfile.mkdtemp(), "probe")
    >>> report = hl.run_sweep("probe", {"x": [1.0, 2.0, 3.0]}, where, scheduler="serial", progress=False)
    >>> report.total, report.completed, report.skipped, report.ok
    (3, 3, 0, True)
    >>> again = hl.run_sweep("probe", {"x": [1.0, 2.0, 3.0]}, where, scheduler="serial", progress=False)
    >>> again.completed, again.skipped
    (0, 3)
    """
    spec = get_task(task)
    retries = _validate.integer("retries", retries, minimum=0, maximum=100)
    if progress is not None:
        progress = _validate.flag("progress", progress)
    if workers is not None:
        workers = _validate.positive_int("workers", workers, maximum=4096)
    if timeout is not None:
        timeout = _validate.positive_real("timeout", timeout)
    if on_row is not None:
        on_row = _validate.function("on_row", on_row)
    flush_seconds = _validate.real("flush_seconds", flush_seconds, minimum=0.0, maximum=86400.0)
    flush_rows = _validate.positive_int("flush_rows", flush_rows, maximum=10**7)
    serial = scheduler == "serial" or (scheduler is None and not have_dask())
    if not serial and not have_dask():
        raise ValueError("this scheduler needs dask.distributed (pip install 'hyperlattice[sweep]'); "
                         "use scheduler='serial' to run in this process.")
    if not serial and not (scheduler in (None, "local", "threads") or isinstance(scheduler, str)):
        from distributed import Client

        if not isinstance(scheduler, Client):
            raise ValueError(f"scheduler must be None, 'local', 'threads', 'serial', an address or a "
                             f"distributed.Client, got {scheduler!r}.")
    if isinstance(scheduler, str) and scheduler not in ("local", "threads", "serial"):
        _check_address(scheduler)
        if not serial:
            # before the sweep directory is created: a wrong address leaves nothing behind
            _probe_tcp(scheduler, _connect_wait(timeout))
    points = expand_grid(spec.name, grid)
    store = SweepStore(path)
    meta = store.open(spec.name, {k: [_canonical(x) for x in (v if isinstance(v, (list, tuple)) else [v])]
                                  for k, v in grid.items()})
    keys_all = [task_key(spec.name, p) for p in points]
    done = store.done()
    todo = [(p, k) for p, k in zip(points, keys_all) if k not in done]
    part_meta = {"version": __version__, "task": spec.name, "parameters": meta["parameters"]}

    buffer: list[dict] = []
    last_flush = [time.monotonic()]

    def flush():
        store.write_rows(buffer, part_meta)
        buffer.clear()
        last_flush[0] = time.monotonic()

    written = [0]

    def write(key, params, outputs):
        # keyed by the parameters only; the grid position ("index") is the merged grid's, given on reading
        row = {"key": key, **params}
        for name, value in outputs.items():
            row[name if name not in row and name != "index" else f"out_{name}"] = value
        buffer.append(row)
        written[0] += 1
        if len(buffer) >= flush_rows or time.monotonic() - last_flush[0] >= flush_seconds:
            flush()

    failures: list[dict] = []
    t0 = time.perf_counter()
    bar = _bar(len(todo), progress, f"sweep {spec.name}")
    label = "serial"
    try:
        if todo:
            ps, ks = [p for p, _ in todo], [k for _, k in todo]
            deadline = None if timeout is None else time.monotonic() + timeout
            if scheduler is None and not serial:
                # the default local cluster costs ~LOCAL_CLUSTER_SECONDS to start (6 s for 6 tiny
                # tasks against 0.7 s serially): tasks run here one by one while the rest, at the
                # pace of those after the first (which pays the imports), would take less than
                # that; the cluster starts only for a rest that is worth it, else the run says why not
                t_start, t_first = time.perf_counter(), None
                while ps:
                    _run_serial(spec.name, ps[:1], ks[:1], write, retries, failures, bar, on_row, deadline)
                    ps, ks = ps[1:], ks[1:]
                    now = time.perf_counter()
                    ran = len(todo) - len(ps)
                    if t_first is None:
                        # the first alone decides only when it outlasts the start-up by itself
                        t_first = now
                        if ps and now - t_start > LOCAL_CLUSTER_SECONDS:
                            break
                        continue
                    if (now - t_first) / (ran - 1) * len(ps) > LOCAL_CLUSTER_SECONDS:
                        break
                if not ps:
                    serial = True
                    label = (f"serial ({time.perf_counter() - t_start:.2g} s of tasks, less than the "
                             f"~{LOCAL_CLUSTER_SECONDS:g} s a local cluster takes to start)")
            if not ps:
                pass
            elif serial:
                _run_serial(spec.name, ps, ks, write, retries, failures, bar, on_row, deadline)
            else:
                with _quiet_distributed():
                    label = _run_dask(spec.name, ps, ks, write, retries, failures, bar, on_row, scheduler,
                                      workers, timeout)
        elif not serial:
            label = "nothing to do"
    finally:
        flush()             # whatever finished is kept, also on KeyboardInterrupt
        bar.__exit__(None, None, None)
        store.write_failures(failures, tried={k for _, k in todo})
        table = store.consolidate()
    completed = written[0]
    return SweepReport(path=str(store.path), table=str(table), task=spec.name, scheduler=label,
                       total=len(points), skipped=len(keys_all) - len(todo), completed=completed,
                       failed=failures, seconds=time.perf_counter() - t0)


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
