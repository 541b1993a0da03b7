"""Figures. The only package (with ``report`` and ``cli``) that imports matplotlib.

Every plotting function takes an optional matplotlib ``ax`` and returns the axes it drew on.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from matplotlib.axes import Axes


def new_axes(ax=None, size=(6.0, 4.2)) -> Axes:
    """Return ``ax``, or a fresh axes of ``size`` inches (constrained layout) when it is None."""
    if ax is None:
        import matplotlib.pyplot as plt

        _, ax = plt.subplots(figsize=size, layout="constrained")
    return ax
