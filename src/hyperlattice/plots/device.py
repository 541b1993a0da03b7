"""Figures of what a device measures: transmission ``|S₂₁|²`` against frequency (with the ideal levels
marked), a fitted trace over its data, an ensemble's mean and spread, a node impedance.
Each takes an optional ``ax`` and returns it."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from matplotlib.axes import Axes

    from ..device import DeviceEnsemble, Transmission, TransmissionComparison, TransmissionFit

__all__ = ["plot_transmission", "plot_ensemble", "plot_fit", "plot_comparison"]


def _axes(ax, size=(6.5, 3.6)):
    if ax is None:
        import matplotlib.pyplot as plt

        _, ax = plt.subplots(figsize=size, layout="constrained")
    return ax


def plot_transmission(tr: Transmission, ax: Axes | None = None, *, levels=None, log: bool = True,
                      **kwargs) -> Axes:
    """``|S₂₁|²`` against frequency, on a log scale; ``levels`` (e.g. the ideal device's eigenvalues) as ticks.

    Parameters
    ----------
    tr : Transmission
        From :func:`hyperlattice.device.transmission`.
    ax : matplotlib.axes.Axes, optional
        Where to draw; a new figure when None.
    levels : array_like, optional
        Frequencies to mark along the bottom (the ideal spectrum).
    log : bool, optional
        Logarithmic ``|S₂₁|²`` axis; default True.
    **kwargs
        Passed to :meth:`matplotlib.axes.Axes.plot`.

    Returns
    -------
    matplotlib.axes.Axes
        The axes with the trace.

    Examples
    --------
    >>> import matplotlib.pyplot as plt
    >>> import numpy as np
    >>> import hyperlattice as hl
    >>> from hyperlattice.device import resonator_device, transmission
    >>> from hyperlattice.plots.device import plot_transmission
    >>> dev = resonator_device(hl.ring_lattice(7, 3, 1), omega0=5.0, J=0.1, kappa_int=0.01,
    ...                        ports={"0": 0.05, "3": 0.05})
    >>> ax = plot_transmission(transmission(dev, np.linspace(4.7, 5.3, 50)))
    >>> ax.get_ylabel()
    '|S₂₁|²'
    >>> plt.close("all")
    """
    ax = _axes(ax)
    ax.plot(tr.omega, tr.power, lw=kwargs.pop("lw", 0.8), **kwargs)
    if log:
        ax.set_yscale("log")
    if levels is not None:
        lv = np.asarray(levels, float)
        lo = ax.get_ylim()[0]
        ax.plot(lv, np.full(lv.shape, lo), "|", color="C3", ms=10, label="ideal levels")
        ax.legend(loc="upper right", fontsize="small")
    ax.set_xlabel("frequency ω")
    ax.set_ylabel("|S₂₁|²" if len(tr.ports) > 1 else "|S₁₁|²")
    ax.set_title(f"{len(tr.resonators)} resonators, {tr.method} route", fontsize="medium")
    return ax


def plot_ensemble(ens: DeviceEnsemble, ax: Axes | None = None, *, log: bool = True, **kwargs) -> Axes:
    """Mean ``|S₂₁|²`` over fabricated devices with a band of ± one standard deviation; mean levels as ticks.

    Parameters
    ----------
    ens : DeviceEnsemble
        From :func:`hyperlattice.sweep.device.merge_device` or :func:`hyperlattice.device.ensemble_statistics`.
    ax : matplotlib.axes.Axes, optional
        Where to draw; a new figure when None.
    log : bool, optional
        Logarithmic ``|S₂₁|²`` axis; default True.
    **kwargs
        Passed to :meth:`matplotlib.axes.Axes.plot` (the mean).

    Returns
    -------
    matplotlib.axes.Axes
        The axes with the mean, the band and the mean levels.

    Examples
    --------
    >>> import matplotlib.pyplot as plt
    >>> import numpy as np
    >>> from hyperlattice.device import ensemble_statistics
    >>> from hyperlattice.plots.device import plot_ensemble
    >>> ens = ensemble_statistics([0.0, 1.0], [[0.1, 0.2], [0.3, 0.2]], [[0.2], [0.4]])
    >>> plot_ensemble(ens).get_ylabel()
    'mean |S₂₁|²'
    >>> plt.close("all")
    """
    ax = _axes(ax)
    ax.fill_between(ens.omega, np.maximum(ens.mean - ens.spread, 1e-300), ens.mean + ens.spread, color="C0",
                    alpha=0.25, lw=0, label="± one standard deviation")
    ax.plot(ens.omega, ens.mean, lw=kwargs.pop("lw", 0.8), label=kwargs.pop("label", "mean"), **kwargs)
    if log:
        ax.set_yscale("log")
    lo = ax.get_ylim()[0]
    ax.plot(ens.level_mean, np.full(ens.level_mean.shape, lo), "|", color="C3", ms=10, label="mean levels")
    ax.set_xlabel("frequency ω")
    ax.set_ylabel("mean |S₂₁|²")
    ax.set_title(f"{ens.realizations} fabricated devices", fontsize="medium")
    ax.legend(loc="upper right", fontsize="small")
    return ax


def plot_fit(fit: TransmissionFit, ax: Axes | None = None, *, log: bool = True) -> Axes:
    """The measured ``|S₂₁|`` (points) with the fitted model over it (line); the parameters in the legend.

    Parameters
    ----------
    fit : TransmissionFit
        From :func:`hyperlattice.device.fit_transmission`.
    ax : matplotlib.axes.Axes, optional
        Where to draw; a new figure when None.
    log : bool, optional
        Logarithmic ``|S₂₁|`` axis; default True.

    Returns
    -------
    matplotlib.axes.Axes
        The axes with data and fit.

    Examples
    --------
    >>> import matplotlib.pyplot as plt
    >>> import numpy as np
    >>> from hyperlattice.device import fit_transmission
    >>> from hyperlattice.plots.device import plot_fit
    >>> w = np.linspace(4.0, 6.0, 101)
    >>> s = np.abs(0.1 / (w - 5.0 + 0.125j))
    >>> f = fit_transmission(np.zeros((1, 1)), w, s, ports=[("0", 0.1), ("0", 0.1)], shared_ports=True)
    >>> plot_fit(f).get_ylabel()
    '|S₂₁|'
    >>> plt.close("all")
    """
    ax = _axes(ax)
    ax.plot(fit.omega, fit.data, ".", ms=2, color="0.4", label="measured")
    ax.plot(fit.omega, fit.fit, lw=0.9, color="C3",
            label=f"fit: ω₀ = {fit.omega0:.6g} ± {fit.omega0_err:.2g}, J = {fit.J:.5g} ± {fit.J_err:.2g}, "
                  f"κ_int = {fit.kappa_int:.4g} ± {fit.kappa_int_err:.2g}")
    if log:
        ax.set_yscale("log")
    ax.set_xlabel("frequency ω")
    ax.set_ylabel("|S₂₁|")
    ax.set_title(f"data over fit ({fit.supported} of 3 parameters determined)", fontsize="medium")
    ax.legend(loc="lower center", fontsize="x-small")
    return ax


def plot_comparison(cmp: TransmissionComparison, ax: Axes | None = None) -> Axes:
    """``|S₂₁|²`` of the lattice and of the continuum (through the dictionary) against frequency, levels marked.

    Parameters
    ----------
    cmp : TransmissionComparison
        From :func:`hyperlattice.device.continuum_transmission`.
    ax : matplotlib.axes.Axes, optional
        Where to draw; a new figure when None.

    Returns
    -------
    matplotlib.axes.Axes
        The axes with both curves.

    Examples
    --------
    >>> import matplotlib.pyplot as plt
    >>> import hyperlattice as hl
    >>> from hyperlattice.device import continuum_transmission
    >>> from hyperlattice.plots.device import plot_comparison
    >>> cmp = continuum_transmission(hl.ring_lattice(7, 3, 3), [-3.2, -3.1], ports=("0", "10"), kappa_int=0.05,
    ...                              kappa_port=0.002)
    >>> len(plot_comparison(cmp).get_lines())
    3
    >>> plt.close("all")
    """
    ax = _axes(ax)
    ax.plot(cmp.omega, cmp.lattice, lw=1.0, label="lattice (input–output)")
    ax.plot(cmp.omega, cmp.continuum, "--", lw=1.0, label="continuum (dictionary, weak coupling)")
    ax.set_yscale("log")
    lo = ax.get_ylim()[0]
    ax.plot(cmp.lowest_levels, np.full(cmp.lowest_levels.shape, lo), "|", color="C3", ms=10,
            label="lattice levels")
    ax.set_xlabel("frequency ω")
    ax.set_ylabel("|S₂₁|²")
    ax.set_title(f"{{{cmp.p},{cmp.q}}} ℓ = {cmp.rings}, ports {cmp.ports[0]} and {cmp.ports[1]} "
                 f"(distance {cmp.distance:.2f})", fontsize="medium")
    ax.legend(loc="upper left", fontsize="small")
    return ax


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
