r"""Figures of App. ``AppAdj``, ``AppFS`` and ``AppSum``: FigScos3delta, FigSh, FigS1.

Each function takes an optional matplotlib ``ax`` and returns the axes it drew on.
"""

from __future__ import annotations

import re
from typing import TYPE_CHECKING

import numpy as np

from . import new_axes
from .. import geometry
from ..compare.scaling import (ConvergenceStudy, FrameAngles, OperatorProfile, RadialProfile, SmoothFunction,
                               angle_profile, frame_angles, operator_profile)
from ..compare.sums import CountingFit, fit_counting
from ..graph.lattice import Lattice, ring_lattice
from ..paper_labels import cite

if TYPE_CHECKING:
    from matplotlib.axes import Axes

__all__ = ["draw_radial_profile", "plot_frame_angles", "draw_operator_profile", "plot_formal_operator", "plot_convergence", "plot_counting"]


def _shown(name: str) -> str:
    """A test function's name as the figure shows it: cos(pi d(z,0)) -> cos(π d(z,0)) (the name
    itself, stored in results and accepted by the CLI, stays ASCII)."""
    return re.sub(r"\bpi\b", "π", name)


def _axes(ax, size=(6.0, 4.2)) -> Axes:
    return new_axes(ax, size)


def draw_radial_profile(profile: RadialProfile, ax: Axes | None = None, *, label: str = r"mean over sites at equal $r$") -> Axes:
    """Mean of a :class:`RadialProfile` against r; red bars span min..max where it is not unique.

    Parameters
    ----------
    profile : RadialProfile
        Site values averaged at equal radius, e.g. from
        :func:`~hyperlattice.compare.scaling.angle_profile`.
    ax : matplotlib.axes.Axes, optional
        Where to draw; a new figure and axes when None (the default).
    label : str, optional
        Legend label of the means.

    Returns
    -------
    matplotlib.axes.Axes
        The axes with the means (circles) and, at radii where the sites disagree, red min..max bars.
        Labels and legend are left to the caller.

    Examples
    --------
    >>> import matplotlib.pyplot as plt
    >>> import hyperlattice as hl
    >>> from hyperlattice.compare.scaling import angle_profile
    >>> from hyperlattice.plots.scaling import draw_radial_profile
    >>> ax = draw_radial_profile(angle_profile(hl.ring_lattice(7, 3, 3)))
    >>> print(ax.lines[0].get_label())
    mean over sites at equal $r$
    >>> plt.close("all")
    """
    ax = _axes(ax)
    ax.plot(profile.r, profile.mean, "o", ms=3.5, color="C0", label=label)
    bad = ~profile.unique
    if np.any(bad):
        ax.vlines(profile.r[bad], profile.min[bad], profile.max[bad], color="red", lw=1.2,
                  label=fr"not unique ({int(bad.sum())} radii)")
    return ax


def _artanh(r):
    """artanh, finite at the ends of [-1, 1] (the top axis of ``plot_frame_angles`` asks for them)."""
    return np.arctanh(np.clip(r, -1.0 + 1e-15, 1.0 - 1e-15))


def plot_frame_angles(lattice: Lattice | FrameAngles | None = None, ax: Axes | None = None, *,
                      distance: bool = False) -> Axes:
    r"""Fig. FigScos3delta: :math:`\cos(q\delta_i)` against :math:`r_i`, averaged at equal radius.

    :math:`\delta_i` is defined modulo :math:`2\pi/q`, so :math:`\cos(q\delta_i)` (the quantity
    entering ``adj36``) is plotted; red bars span min..max where sites of one radius
    disagree (the map :math:`r \mapsto \delta` is not unique). Default lattice: {7,3}, 5 rings.
    The profile is :func:`hyperlattice.compare.scaling.angle_profile`.

    Parameters
    ----------
    lattice : Lattice or FrameAngles, optional
        A flake, or its frame angles from :func:`~hyperlattice.compare.scaling.frame_angles`; the
        5-ring {7,3} flake when None.
    ax : matplotlib.axes.Axes, optional
        Where to draw; a new figure and axes when None (the default).
    distance : bool, optional
        Plot against the hyperbolic distance :math:`d(r_i, 0) = \operatorname{artanh} r_i` instead
        of :math:`r_i` (default False), with :math:`r_i` on a second axis on top: the outer rings,
        crowded below :math:`r = 1`, spread out, and the legend goes above the axes, off the data.

    Returns
    -------
    matplotlib.axes.Axes
        The axes with the profile, a legend and a title naming {p,q} and the sites.

    Examples
    --------
    >>> import matplotlib.pyplot as plt
    >>> import hyperlattice as hl
    >>> from hyperlattice.plots.scaling import plot_frame_angles
    >>> print(plot_frame_angles(hl.ring_lattice(7, 3, 3)).get_title())
    $\{7,3\}$, 112 sites
    >>> plt.close("all")
    """
    ax = _axes(ax)
    angles = lattice if isinstance(lattice, FrameAngles) else frame_angles(
        lattice if lattice is not None else ring_lattice(7, 3, 5))
    q = angles.q
    profile = angle_profile(angles)
    if distance:
        import dataclasses

        profile = dataclasses.replace(profile, r=np.arctanh(profile.r))
    draw_radial_profile(profile, ax)
    ax.set_ylabel(fr"$\cos({q}\delta_i)$,  $\delta_i=\chi_i-\phi_i$", fontsize=12)
    ax.set_title(fr"$\{{{angles.p},{q}\}}$, {angles.z.size} sites", fontsize=12)
    ax.tick_params(labelsize=10)
    if distance:
        ax.set_xlabel(r"hyperbolic distance $d(r_i, 0)$ from the centre", fontsize=12)
        ax.set_ylim(-1.1, 1.1)
        top = ax.secondary_xaxis("top", functions=(np.tanh, _artanh))
        top.set_xlabel(r"site radius $r_i$", fontsize=11)
        top.set_xticks([0.3, 0.6, 0.8, 0.9, 0.95, 0.98])
        top.tick_params(labelsize=9)
        ax.set_title("")
        ax.legend(fontsize=10, loc="lower center", bbox_to_anchor=(0.5, 1.22), ncol=2, frameon=False,
                  title=fr"$\{{{angles.p},{q}\}}$, {angles.z.size} sites", title_fontsize=11)
    else:
        ax.set_xlabel(r"site radius $r_i$", fontsize=12)
        ax.set_ylim(-1.08, 1.4)  # headroom for the legend above the data
        ax.legend(fontsize=10, loc="upper center", ncol=2)
    return ax


def draw_operator_profile(profile: OperatorProfile, ax: Axes | None = None) -> Axes:
    r"""Fig. FigSh for one :class:`OperatorProfile`: :math:`\hat A_h f - qf` against :math:`d(r,0)`.

    Circles: ``adj34``; squares: cubic approximation (adj36); line: quadratic (adj35),
    all averaged over fully coordinated sites of equal radius (the quadratic one as a curve in r
    when f is radial).

    Parameters
    ----------
    profile : OperatorProfile
        From :func:`~hyperlattice.compare.scaling.operator_profile`.
    ax : matplotlib.axes.Axes, optional
        Where to draw; a new figure and axes when None (the default).

    Returns
    -------
    matplotlib.axes.Axes
        The axes with the three curves, a legend and a title naming f and h.

    See Also
    --------
    plot_formal_operator : computes the profile and draws it.

    Examples
    --------
    >>> import matplotlib.pyplot as plt
    >>> import hyperlattice as hl
    >>> from hyperlattice.compare.scaling import operator_profile
    >>> from hyperlattice.plots.scaling import draw_operator_profile
    >>> ax = draw_operator_profile(operator_profile(hl.ring_lattice(7, 3, 3)))
    >>> ax.get_title(), len(ax.lines)
    ('f = cos(π d(z,0)),  h = 0.275798', 3)
    >>> plt.close("all")
    """
    ax = _axes(ax)
    if profile.curve_distance is not None:
        quad_d, quad_v = profile.curve_distance, profile.curve_quadratic
    else:
        quad_d, quad_v = profile.quadratic.distance, profile.quadratic.mean
    cubic, exact = profile.cubic, profile.exact
    ax.plot(quad_d, quad_v, "-", color="0.55", lw=2, label=r"quadratic $\hat A^{(2)}_h$, " + cite("adj35"))
    ax.plot(cubic.distance, cubic.mean, "s", color="C0", ms=4, label=r"cubic $\hat A^{(3)}_h$, " + cite("adj36"))
    ax.plot(exact.distance, exact.mean, "o", mfc="none", mec="k", ms=6, label=r"$\hat A_h f$, " + cite("adj34"))
    ax.set_xlabel(r"$d(r,0)$", fontsize=12)
    ax.set_ylabel(fr"$\hat A_h f - {profile.q}f$", fontsize=12)
    ax.set_title(f"f = {_shown(profile.function)},  h = {profile.h:.6g}", fontsize=12)
    ax.tick_params(labelsize=10)
    ax.legend(fontsize=9)
    return ax


def plot_formal_operator(lattice: Lattice | FrameAngles | None = None, h: float | None = None,
                         f: SmoothFunction | None = None, ax=None) -> Axes:
    r"""Fig. FigSh: :math:`\hat A_h f - qf` against :math:`d(r,0)` with the approximations.

    Default {7,3}, 5 rings, :math:`f = \cos[\pi d(r,0)]`, h the lattice value. The numbers are
    :func:`hyperlattice.compare.scaling.operator_profile`; see :func:`draw_operator_profile`.

    Parameters
    ----------
    lattice : Lattice or FrameAngles, optional
        A flake or its frame angles; the 5-ring {7,3} flake when None.
    h : float, optional
        The parameter h of the formal operator; the lattice's h = tanh(d0) when None.
    f : SmoothFunction, optional
        The test function; :math:`\cos[\pi d(z,0)]` when None.
    ax : matplotlib.axes.Axes, optional
        Where to draw; a new figure and axes when None (the default).

    Returns
    -------
    matplotlib.axes.Axes
        The axes of :func:`draw_operator_profile`.

    Examples
    --------
    >>> import matplotlib.pyplot as plt
    >>> import hyperlattice as hl
    >>> from hyperlattice.plots.scaling import plot_formal_operator
    >>> plot_formal_operator(hl.ring_lattice(7, 3, 3), h=0.15).get_title()
    'f = cos(π d(z,0)),  h = 0.15'
    >>> plt.close("all")
    """
    angles = lattice if isinstance(lattice, FrameAngles) else frame_angles(
        lattice if lattice is not None else ring_lattice(7, 3, 5))
    return draw_operator_profile(operator_profile(angles, f, h), ax)


def plot_convergence(study: ConvergenceStudy, ax: Axes | None = None) -> Axes:
    r"""Errors of the order-k approximations of :math:`\hat A_h` against h (log-log); returns the axes.

    One line per order, each with a dashed line of its expected power through its last point.

    Parameters
    ----------
    study : ConvergenceStudy
        From :func:`~hyperlattice.compare.scaling.convergence_study`.
    ax : matplotlib.axes.Axes, optional
        Where to draw; a new figure and axes when None (the default).

    Returns
    -------
    matplotlib.axes.Axes
        The axes with two lines per order (measured errors with their fitted exponent; expected power)
        and a legend.

    Examples
    --------
    >>> import matplotlib.pyplot as plt
    >>> import hyperlattice as hl
    >>> from hyperlattice.compare.scaling import SmoothFunction, convergence_study
    >>> from hyperlattice.plots.scaling import plot_convergence
    >>> study = convergence_study(hl.ring_lattice(7, 3, 3), SmoothFunction.exp_x())
    >>> ax = plot_convergence(study)
    >>> ax.get_xscale(), len(ax.lines)
    ('log', 6)
    >>> plt.close("all")
    """
    ax = _axes(ax)
    h = study.h
    for i, (k, err) in enumerate(study.errors.items()):
        color = f"C{i}"
        ax.loglog(h, err, "o-", color=color, ms=4,
                  label=fr"order {k}: $h^{{{study.exponents[k]:.2f}}}$")
        ref = err[-1] * (h / h[-1]) ** study.expected[k]
        ax.loglog(h, ref, "--", color=color, lw=1, label=fr"$h^{{{study.expected[k]}}}$")
    ax.set_xlabel(r"$h$", fontsize=12)
    ax.set_ylabel(r"$\max_i|\hat A_h f - \hat A^{(k)}_h f|$", fontsize=12)
    ax.set_title(fr"$\{{{study.p},{study.q}\}}$, f = {_shown(study.function)}", fontsize=12)
    ax.legend(fontsize=9)
    return ax


def plot_counting(lattice: Lattice | CountingFit | None = None, ax: Axes | None = None) -> Axes:
    r"""Fig. FigS1: the counting function :math:`\mathcal{N}(r)` (``sum2``) against
    :math:`\rho` with the fitted line :math:`s\rho + b` (``sum4``). Default {7,3}, 4 rings.

    Given a :class:`~hyperlattice.compare.sums.CountingFit`, draws its own points (one per
    distinct radius of its window) instead of the staircase of every site.

    Parameters
    ----------
    lattice : Lattice or CountingFit, optional
        A flake (the staircase of all its sites and a fresh fit), or a fit from
        :func:`~hyperlattice.compare.sums.fit_counting`; the 4-ring {7,3} flake when None.
    ax : matplotlib.axes.Axes, optional
        Where to draw; a new figure and axes when None (the default).

    Returns
    -------
    matplotlib.axes.Axes
        The axes with the staircase, the fitted line, the line of the expected slope through the same
        intercept, and a legend; :math:`\rho = (1 + r^2)/(1 - r^2)` on the horizontal axis.

    Examples
    --------
    >>> import matplotlib.pyplot as plt
    >>> import hyperlattice as hl
    >>> from hyperlattice.plots.scaling import plot_counting
    >>> print(plot_counting(hl.ring_lattice(7, 3, 3)).get_title())
    $\{7,3\}$, $\ell=3$ (112 sites)
    >>> plt.close("all")
    """
    ax = _axes(ax)
    if isinstance(lattice, CountingFit):
        fit = lattice
        ax.step(fit.rho, fit.counts, where="post", color="C0", lw=1.5, label=r"$\mathcal{N}(r)$")
        rmax, title = fit.radii[-1], fr"$\{{{fit.p},{fit.q}\}}$, $\ell={fit.rings}$ ({fit.window} radii)"
    else:
        lat = lattice if lattice is not None else ring_lattice(7, 3, 4)
        fit = fit_counting(lat)
        r = np.sort(np.abs(lat.z))
        grid = np.linspace(0.0, r[-1], 2000)
        n = np.searchsorted(r, grid, side="right")
        ax.step(geometry.rho(grid), n, where="post", color="C0", lw=1.5, label=r"$\mathcal{N}(r)$")
        rmax, title = r[-1], fr"$\{{{lat.p},{lat.q}\}}$, $\ell={lat.rings}$ ({lat.sites} sites)"
    rr = np.linspace(1.0, geometry.rho(rmax), 50)
    ax.plot(rr, fit.slope * rr + fit.intercept, "--", color="C3", lw=1.5,
            label=fr"${fit.slope:.3f}\,\rho {fit.intercept:+.3f}$ (fit)")
    ax.plot(rr, fit.expected_slope * rr + fit.intercept, ":", color="0.4", lw=1.5,
            label=fr"${fit.expected_slope:g}\,\rho {fit.intercept:+.3f}$")
    ax.set_xlabel(r"$\rho=(1+r^2)/(1-r^2)$", fontsize=12)
    ax.set_ylabel(r"$\mathcal{N}(r)$", fontsize=12)
    ax.set_title(title, fontsize=12)
    ax.tick_params(labelsize=10)
    ax.legend(fontsize=10)
    return ax


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
