"""The package's one progress mechanism: tqdm bars on stderr, drawn only where someone watches.

Every long loop of the package (flux points, sectors, random vectors, realizations, report
sections, sweep tasks) opens a :func:`progress_bar`. Whether it draws is decided in one place,
:func:`enabled`, from the ``progress`` argument the caller passed:

* ``True`` / ``False``: on / off;
* ``None`` (the default everywhere): *auto*, i.e. on when stderr is a terminal, unless the
  environment variable ``HYPERLATTICE_PROGRESS`` says ``0`` (off) or ``1`` (on), or the command
  line said ``--no-progress`` / ``--progress`` (:func:`default`), and never inside another bar:
  the outer loop owns the terminal line, so the solves it calls stay quiet;
* a function: the older interface, kept: it receives one-line messages instead of a bar.

Bars go to stderr only (stdout stays clean for JSON and tables), appear after :data:`DELAY`
seconds (a call that finishes sooner draws nothing; a bar asked for with ``True`` or
``--progress`` is drawn at once) and vanish when their loop ends if they are
nested. Pipes, logs, CI and the tests (stderr captured) see no bars.
"""

from __future__ import annotations

import contextlib
import contextvars
import os
import sys
import time
from typing import Callable

from . import _validate

__all__ = ["ENV", "DELAY", "enabled", "default", "progress_bar", "Bar"]

#: environment variable: ``0`` turns auto bars off, ``1`` turns them on (also without a terminal)
ENV = "HYPERLATTICE_PROGRESS"
#: seconds before a bar is drawn; shorter loops stay silent
DELAY = 1.0

#: what ``progress=None`` means in this context (``--progress`` / ``--no-progress``); None: auto
_DEFAULT: contextvars.ContextVar[bool | None] = contextvars.ContextVar("hyperlattice_progress_default",
                                                                      default=None)
#: bars open in this context (drawn or not): auto bars inside one stay off
_DEPTH: contextvars.ContextVar[int] = contextvars.ContextVar("hyperlattice_progress_depth", default=0)


def _terminal() -> bool:
    stream = sys.stderr
    try:
        return stream is not None and bool(stream.isatty())
    except (AttributeError, ValueError, OSError):  # closed or replaced stream
        return False


def enabled(progress=None) -> bool:
    """Whether a bar is drawn for this value of a ``progress`` argument (see the module docstring).

    A function gets messages, never a bar (False here). Raises ValueError for anything that is not
    True, False, None or a function.
    """
    progress = _validate.progress("progress", progress)
    if callable(progress):
        return False
    if progress is not None:
        return progress
    if _DEPTH.get() > 0:
        return False
    chosen = _DEFAULT.get()
    if chosen is not None:
        return chosen
    env = os.environ.get(ENV, "").strip().lower()
    if env in ("0", "false", "no", "off"):
        return False
    if env in ("1", "true", "yes", "on"):
        return True
    return _terminal()


@contextlib.contextmanager
def default(progress: bool | None):
    """Within the block, ``progress=None`` means ``progress`` (the CLI's ``--progress`` / ``--no-progress``)."""
    if progress is not None:
        progress = _validate.flag("progress", progress)
    token = _DEFAULT.set(progress)
    try:
        yield
    finally:
        _DEFAULT.reset(token)


class Bar:
    """A progress bar, or nothing: :meth:`update` advances, :meth:`note` says what runs now.

    Use as a context manager (:func:`progress_bar`); ``drawn`` tells whether a tqdm bar exists.
    """

    def __init__(self, total: int | None, desc: str, unit: str, progress) -> None:
        progress = _validate.progress("progress", progress)
        self.total, self.desc, self.count = total, desc, 0
        self._say: Callable[[str], None] | None = progress if callable(progress) else None
        self._tqdm = None
        self._token = None
        # progress=True is the caller's (or --progress's) explicit request: such a bar may draw at once
        self._forced = progress is True
        self._born = time.monotonic()
        if enabled(progress):
            from tqdm import tqdm

            nested = _DEPTH.get() > 0
            self._tqdm = tqdm(total=total, desc=desc, unit=unit, file=sys.stderr, delay=0.0 if self._forced else DELAY,
                              dynamic_ncols=True, leave=not nested)

    @property
    def drawn(self) -> bool:
        return self._tqdm is not None

    def update(self, n: int = 1) -> None:
        """``n`` more items done."""
        self.count += n
        if self._tqdm is not None:
            self._tqdm.update(n)
        if self._say is not None:
            of = f"/{self.total}" if self.total is not None else ""
            self._say(f"{self.desc}: {self.count}{of}")

    def note(self, text: str) -> None:
        """What the loop is doing now: the bar's postfix, or one message to a function."""
        if self._tqdm is not None:
            self._tqdm.set_postfix_str(text, refresh=False)
        if self._say is not None:
            self._say(text)

    def item(self, text: str) -> None:
        """The next item starts (``text`` says which): the bar shows it at once when it was asked
        for explicitly or has existed for :data:`DELAY` seconds, so a loop of long items (a serial
        sweep of QMC runs) shows where it is before its first item ends."""
        if self._tqdm is not None:
            self._tqdm.set_postfix_str(text, refresh=False)
            if self._forced or time.monotonic() - self._born >= DELAY:
                self._tqdm.refresh()
        if self._say is not None:
            self._say(text)

    def close(self) -> None:
        if self._tqdm is not None:
            self._tqdm.close()
            self._tqdm = None

    def __enter__(self) -> "Bar":
        self._token = _DEPTH.set(_DEPTH.get() + 1)
        return self

    def __exit__(self, *exc) -> bool:
        self.close()
        if self._token is not None:
            _DEPTH.reset(self._token)
            self._token = None
        return False


def progress_bar(total: int | None, desc: str, *, unit: str = "it", progress=None) -> Bar:
    """A :class:`Bar` over ``total`` items (None: unknown), labelled ``desc``, for the argument ``progress``.

    ::

        with progress_bar(len(points), "fluxmap", unit="point", progress=progress) as bar:
            for point in points:
                ...
                bar.update()
    """
    return Bar(total, desc, unit, progress)
