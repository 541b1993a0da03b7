"""Figures. The only package (with ``report`` and ``cli``) that imports matplotlib.

Every plotting function takes an optional matplotlib ``ax`` and returns the axes it drew on.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from matplotlib.axes import Axes


def _check_axes(name: str, ax) -> None:
    """Refuse, in one sentence, an ``ax``-like argument that is neither None nor a matplotlib Axes."""
    if ax is not None and not (hasattr(ax, "plot") and hasattr(ax, "figure")):
        raise ValueError(f"{name} must be a matplotlib Axes (or None for a new figure), got {type(ax).__name__}.")


def new_axes(ax: Axes | None = None, size=(6.0, 4.2)) -> Axes:
    """Return ``ax``, or a fresh axes of ``size`` inches (constrained layout) when it is None.

    Every plotting function starts with it, so that ``ax=None`` means a new figure.

    Parameters
    ----------
    ax : matplotlib.axes.Axes, optional
        Axes to draw on; returned as it is.
    size : tuple of float, optional
        Width and height in inches of a new figure (default 6 x 4.2); used only when ``ax`` is None.

    Returns
    -------
    matplotlib.axes.Axes
        ``ax``, or the axes of a new figure.

    Raises
    ------
    ValueError
        If ``ax`` is not a matplotlib Axes, or ``size`` is not two positive numbers.

    Examples
    --------
    >>> import matplotlib.pyplot as plt
    >>> from hyperlattice.plots import new_axes
    >>> ax = new_axes(size=(3, 2))
    >>> ax.figure.get_size_inches().tolist(), new_axes(ax) is ax
    ([3.0, 2.0], True)
    >>> new_axes(size=(0, 2))
    Traceback (most recent call last):
        ...
    ValueError: size must be two positive numbers (width, height in inches).
    >>> plt.close("all")
    """
    _check_axes("ax", ax)
    if ax is None:
        from .. import _validate

        size = _validate.real_array("size", size, shape=(2,))
        if not (size > 0).all():
            raise ValueError("size must be two positive numbers (width, height in inches).")
        size = tuple(float(v) for v in size)
        import matplotlib.pyplot as plt

        _, ax = plt.subplots(figsize=size, layout="constrained")
    return ax


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())

# fills the registry behind Result.plot (hyperlattice.results.register_plotter): importing the
# plotting layer is what makes every drawing available, whoever imports it first
from . import registry  # noqa: E402,F401
