r"""What every Markov chain of the package shares: its checkpoint file on disk, the directory lock,
a clean stop on SIGINT/SIGTERM, the checks a stored chain passes before it is resumed, and the
checks before independent chains are merged.

Used by the bosons' SSE (:mod:`hyperlattice.bosons.sse`, through ``bosons._checkpoint``) and the
spin chains (:mod:`hyperlattice.spins.classical`, :mod:`hyperlattice.spins.quantum`).

A checkpoint is one ``.npz`` file whose every array and whose metadata (a JSON text) are covered
by one SHA-256 digest stored inside it: the digest runs over the metadata's bytes and, for each
array in name order, its name, dtype, shape and C-order bytes. :func:`read` recomputes it before
any array is handed on, so a truncated, edited or foreign file is refused in one sentence instead
of reaching a compiled kernel (the caller then checks shapes and ranges, which protects against
a file whose digest was recomputed after an edit). :func:`write` writes a temporary file in the
same directory, flushes it to the disk (``fsync``) and renames it over the old one
(``os.replace``, atomic on POSIX and Windows), so an interrupted write leaves the previous
checkpoint intact. :func:`locked` holds a :class:`filelock.FileLock` on the directory for the
whole run: a second run into the same directory is refused, not interleaved.

:class:`StopSignals` replaces the SIGINT and SIGTERM handlers by one that only records the
signal; the driver checks :attr:`StopSignals.signum` between kernel calls (a signal handler that
raises while a numba kernel runs surfaces as ``SystemError`` from the dispatcher), saves, and
calls :meth:`StopSignals.reraise`, which hands the signal to the handler that was installed
before (the command line's, or Python's ``KeyboardInterrupt``).
"""

from __future__ import annotations

import contextlib
import hashlib
import json
import math
import os
import signal
import tempfile
import threading
from pathlib import Path

import numpy as np

__all__ = ["FORMAT", "digest", "write", "read", "locked", "StopSignals", "Stopped", "load_chain",
           "chains_to_merge", "merged_scalars", "weighted_arrays", "merged_run", "load_kernels"]

#: the format of the file (part of its metadata; another number is refused)
FORMAT = 2
_TAG = b"hyperlattice qmc checkpoint\0"


def digest(meta_text: str, arrays: dict) -> str:
    """SHA-256 over the metadata text and every array (name, dtype, shape, bytes), in name order."""
    h = hashlib.sha256(_TAG)
    raw = meta_text.encode()
    h.update(len(raw).to_bytes(8, "little") + raw)
    for name in sorted(arrays):
        a = np.ascontiguousarray(arrays[name])
        head = json.dumps([name, a.dtype.str, list(a.shape)]).encode()
        h.update(len(head).to_bytes(8, "little") + head)
        h.update(a.tobytes())
    return h.hexdigest()


def write(path: Path, meta: dict, arrays: dict) -> None:
    """Write ``arrays`` and ``meta`` to ``path`` atomically (temporary file, fsync, rename)."""
    path = Path(path)
    text = json.dumps({**meta, "format": FORMAT}, sort_keys=True)
    check = digest(text, arrays)
    fd, tmp = tempfile.mkstemp(prefix=path.name + ".", suffix=".tmp", dir=path.parent)
    try:
        with os.fdopen(fd, "wb") as fh:
            np.savez(fh, __meta__=np.array(text), __sha256__=np.array(check), **arrays)
            fh.flush()
            os.fsync(fh.fileno())
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        raise
    with contextlib.suppress(OSError, AttributeError):     # the rename itself reaches the disk
        dfd = os.open(path.parent, os.O_RDONLY)
        try:
            os.fsync(dfd)
        finally:
            os.close(dfd)


def read(path: Path) -> tuple[dict, dict]:
    """``(meta, arrays)`` of a checkpoint whose digest matches; ValueError (one sentence) otherwise."""
    path = Path(path)
    shown = repr(str(path))
    try:
        with open(path, "rb") as fh, np.load(fh, allow_pickle=False) as data:
            arrays = {k: np.array(data[k]) for k in data.files}
    except Exception as exc:  # zipfile, zlib, numpy's format checks: a truncated or foreign file
        raise ValueError(f"the checkpoint {shown} is damaged or truncated and cannot be read "
                         f"({type(exc).__name__}); delete it to start the chain afresh.") from None
    text = arrays.pop("__meta__", None)
    check = arrays.pop("__sha256__", None)
    if (text is None or check is None or text.dtype.kind != "U" or check.dtype.kind != "U"
            or text.shape != () or check.shape != ()):
        raise ValueError(f"the checkpoint {shown} carries no checksum (written by another program or by "
                         "hyperlattice 0.5.0 or earlier); delete it to start the chain afresh.")
    text = str(text)
    if digest(text, arrays) != str(check):
        raise ValueError(f"the checkpoint {shown} is damaged: its contents do not match its SHA-256 checksum; "
                         "delete it to start the chain afresh.")
    try:
        meta = json.loads(text)
    except ValueError:
        meta = None
    if not isinstance(meta, dict) or meta.get("format") != FORMAT:
        raise ValueError(f"the checkpoint {shown} has an unknown format; delete it to start the chain afresh.")
    return meta, arrays


@contextlib.contextmanager
def locked(directory: Path, name: str):
    """Hold the lock file ``directory/name`` for the block; ValueError when another run holds it."""
    from filelock import FileLock, Timeout

    lock = FileLock(str(Path(directory) / name), timeout=0)
    try:
        lock.acquire()
    except Timeout:
        raise ValueError(f"the checkpoint directory {str(directory)!r} is in use by another run (it holds "
                         f"{name}); wait for it to finish or use another directory.") from None
    except OSError as exc:
        raise ValueError(f"the checkpoint directory {str(directory)!r} cannot be locked: "
                         f"{exc.strerror or exc}.") from None
    try:
        yield
    finally:
        lock.release()


class StopSignals:
    """Record SIGINT/SIGTERM instead of raising, for the duration of a ``with`` block.

    Installed only in the main thread (Python delivers signals there alone) and only over a
    handler that is not ``SIG_IGN``. Outside the block the previous handlers are back.
    """

    def __init__(self) -> None:
        self.signum: int | None = None
        self._old: dict = {}

    def _record(self, signum, frame) -> None:
        if self.signum is None:
            self.signum = signum

    def __enter__(self) -> "StopSignals":
        if threading.current_thread() is threading.main_thread():
            for sig in (signal.SIGINT, signal.SIGTERM):
                old = signal.getsignal(sig)
                if old in (signal.SIG_IGN, None):
                    continue
                self._old[sig] = old
                signal.signal(sig, self._record)
        return self

    def _restore(self) -> None:
        for sig, old in self._old.items():
            signal.signal(sig, old)
        self._old = {}

    def __exit__(self, *exc) -> None:
        self._restore()

    def reraise(self, message: str) -> None:
        """Hand the recorded signal to the previous handler; raise ``Stopped(message)`` (a
        KeyboardInterrupt) in its place when that handler raised KeyboardInterrupt or returned."""
        signum = self.signum
        old = self._old.get(signum, signal.SIG_DFL)
        self._restore()
        try:
            if callable(old):
                old(signum, None)
            elif signum == signal.SIGTERM and old == signal.SIG_DFL:
                # the default action of SIGTERM: end the process (the checkpoint is saved)
                signal.signal(signum, signal.SIG_DFL)
                os.kill(os.getpid(), signum)
        except KeyboardInterrupt:
            pass
        raise Stopped(message, signum)


class Stopped(KeyboardInterrupt):
    """A run stopped by SIGINT or SIGTERM between kernel calls; ``signum`` says which, the message
    what was kept."""

    def __init__(self, message: str, signum=None) -> None:
        super().__init__(message)
        self.signum = signum


def load_chain(path: Path, fingerprint: str, template: dict, other: str, grow: tuple = ()) -> dict:
    """The arrays of the checkpoint ``path`` after the checks every chain needs: the checksum
    (:func:`read`), the run's fingerprint (``other`` names what it covers) and, for every array
    of ``template``, its dtype and shape (the names in ``grow`` may change length, not rank).
    ValueError in one sentence otherwise; the caller then checks ranges and consistency."""
    meta, data = read(path)       # truncated, edited or foreign: one sentence
    shown = repr(str(path))
    if meta.get("fingerprint") != fingerprint:
        raise ValueError(f"the checkpoint {shown} belongs to a run with other parameters ({other}); "
                         "use another directory.")
    for k, want in template.items():
        got = data.get(k)
        if (got is None or got.dtype != want.dtype or got.ndim != want.ndim
                or (k not in grow and got.shape != want.shape)):
            raise ValueError(f"the checkpoint {shown} is damaged (field {k}); delete it to start the chain afresh.")
    return data


def chains_to_merge(results, cls: type, merger: str, keys: tuple, *, single: bool = True):
    """``(chains, seeds, weights)`` of independent chains to merge: a non-empty list of ``cls``
    (one result alone too when ``single``) of one model (``keys`` equal), no seed twice; the
    weights are the measured sweeps. ValueError in one sentence otherwise."""
    name = cls.__name__
    if single and isinstance(results, cls):
        res = [results]
    elif isinstance(results, (list, tuple)):
        res = list(results)
    elif single:
        raise ValueError(f"results must be a list of {name} (independent chains of one model).")
    else:
        res = []
    if not res or not all(isinstance(r, cls) for r in res):
        raise ValueError(f"{merger} takes a non-empty list of {name}"
                         + ("." if single else " (independent chains of one model)."))
    ref = res[0]
    for r in res[1:]:
        for k in keys:
            if getattr(r, k) != getattr(ref, k):
                raise ValueError(f"{merger} needs chains of one model; {k} differs ({getattr(ref, k)!r} vs "
                                 f"{getattr(r, k)!r}).")
    seeds = tuple(s for r in res for s in r.seeds)
    if len(set(seeds)) != len(seeds):
        raise ValueError(f"{merger} needs independent chains, but a seed occurs twice.")
    return res, seeds, np.array([r.sweeps for r in res], dtype=float)


def merged_scalars(res: list, weights: np.ndarray, names) -> dict:
    """``name`` and ``name_err`` of independent chains combined (:func:`hyperlattice.mcstats.combine_independent`);
    nan where a chain did not measure it (a staggered observable off a bipartite graph)."""
    from . import mcstats

    out = {}
    for name in names:
        v = [getattr(r, name) for r in res]
        if all(np.isfinite(v)):
            out[name], out[name + "_err"] = mcstats.combine_independent(
                v, [getattr(r, name + "_err") for r in res], weights)
        else:
            out[name] = out[name + "_err"] = math.nan
    return out


def weighted_arrays(res: list, weights: np.ndarray, name: str):
    """``(mean, error)`` of the array ``name`` (and ``name_err``) over independent chains, weighted by
    their sweeps; ``(None, None)`` when a chain lacks it."""
    if any(getattr(r, name) is None or getattr(r, name + "_err") is None for r in res):
        return None, None
    tot = float(weights.sum())
    v = sum(wc * getattr(r, name) for wc, r in zip(weights, res)) / tot
    err = np.sqrt(sum((wc * getattr(r, name + "_err")) ** 2 for wc, r in zip(weights, res))) / tot
    return v, err


def merged_run(res: list, weights: np.ndarray, seeds: tuple) -> dict:
    """The bookkeeping fields of merged chains: sweeps, thermalisation sweeps and seconds summed,
    ``seed`` None and every seed in ``seeds``, ``tau_int`` the sweep-weighted mean, the bins summed
    (their size the largest), ``converged`` only if every chain was, each chain's notes."""
    tot = float(weights.sum())
    return dict(
        sweeps=int(tot), thermalization=int(sum(r.thermalization for r in res)), seed=None, seeds=seeds,
        chains=int(sum(r.chains for r in res)),
        tau_int={k: float(sum(wc * r.tau_int.get(k, math.nan) for wc, r in zip(weights, res)) / tot)
                 for k in res[0].tau_int},
        bins=int(sum(r.bins for r in res)), bin_size=int(max(r.bin_size for r in res)),
        converged=all(r.converged for r in res), notes=tuple(f"chain {r.seed}: {x}" for r in res for x in r.notes),
        seconds=float(sum(r.seconds for r in res)))


def load_kernels(load, what: str):
    """``load()`` (the import of a numba kernel module), its failure for want of address space
    turned into a MemoryError saying so (``what``: whose kernels)."""
    from . import _validate

    try:
        return load()
    except (OSError, MemoryError, ImportError) as exc:
        _, address = _validate.memory_limits()
        if address is None and not isinstance(exc, MemoryError):
            raise
        raise MemoryError(f"loading the {what}'s compiled kernels (numba, LLVM: about 200 MB of "
                          f"address space) failed with {_validate._bytes(_validate.available_memory())} left to "
                          "this process; raise its memory limit (ulimit -v).") from None
