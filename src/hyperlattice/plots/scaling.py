r"""Figures of App. ``AppAdj``, ``AppFS`` and ``AppSum``: FigScos3delta, FigSh, FigS1.

Each function takes an optional matplotlib ``ax`` and returns the axes it drew on.
"""

from __future__ import annotations

import numpy as np

from . import new_axes
from .. import geometry
from ..dictionary import laplacian_coefficient
from ..compare.sums import fit_counting
from ..graph.lattice import Lattice, ring_lattice
from ..compare.scaling import (FrameAngles, SmoothFunction, expansion, formal_operator, frame_angles,
                       radial_profile)


def _axes(ax, size=(6.0, 4.2)):
    return new_axes(ax, size)


def plot_frame_angles(lattice: Lattice | FrameAngles | None = None, ax=None):
    r"""Fig. FigScos3delta: :math:`\cos(q\delta_i)` against :math:`r_i`, averaged at equal radius.

    :math:`\delta_i` is defined modulo :math:`2\pi/q`, so :math:`\cos(q\delta_i)` (the quantity
    entering Eq. (adj36)) is plotted; red bars span min..max where sites of one radius
    disagree (the map :math:`r \mapsto \delta` is not unique). Default lattice: {7,3}, 5 rings.
    """
    ax = _axes(ax)
    angles = lattice if isinstance(lattice, FrameAngles) else frame_angles(
        lattice if lattice is not None else ring_lattice(7, 3, 5))
    q = angles.q
    sel = np.isfinite(angles.delta)
    prof = radial_profile(angles.z[sel], np.cos(q * angles.delta[sel]))
    ax.plot(prof.r, prof.mean, "o", ms=3.5, color="C0", label=r"mean over sites at equal $r$")
    bad = ~prof.unique
    if np.any(bad):
        ax.vlines(prof.r[bad], prof.min[bad], prof.max[bad], color="red", lw=1.2,
                  label=fr"not unique ({int(bad.sum())} radii)")
    ax.set_xlabel(r"site radius $r_i$", fontsize=12)
    ax.set_ylabel(fr"$\cos({q}\delta_i)$,  $\delta_i=\chi_i-\phi_i$", fontsize=12)
    ax.set_title(fr"$\{{{angles.p},{q}\}}$, {angles.z.size} sites", fontsize=12)
    ax.set_ylim(-1.08, 1.4)  # headroom for the legend above the data
    ax.tick_params(labelsize=10)
    ax.legend(fontsize=10, loc="upper center", ncol=2)
    return ax


def plot_formal_operator(lattice: Lattice | FrameAngles | None = None, h: float | None = None,
                         f: SmoothFunction | None = None, ax=None):
    r"""Fig. FigSh: :math:`\hat A_h f - qf` against :math:`d(r,0)` with the approximations.

    Circles: Eq. (adj34); squares: cubic approximation (adj36); line: quadratic (adj35),
    all averaged over fully coordinated sites of equal radius. Default {7,3}, 5 rings,
    :math:`f = \cos[\pi d(r,0)]`, h the lattice value.
    """
    ax = _axes(ax)
    angles = lattice if isinstance(lattice, FrameAngles) else frame_angles(
        lattice if lattice is not None else ring_lattice(7, 3, 5))
    f = f if f is not None else SmoothFunction.cos_distance()
    hh = angles.h if h is None else h
    z = angles.z[angles.full]
    base = angles.q * f(z)
    exact = radial_profile(z, (formal_operator(angles, f, hh) - base).real)
    cubic = radial_profile(z, (expansion(angles, f, hh, 3) - base).real)
    # the quadratic approximation has no chi_i: for radial f it is a function of r alone and is
    # drawn as a curve; for other f it is averaged over sites like the rest
    if _is_radial(f, z):
        grid = np.linspace(0.0, np.abs(z).max(), 400)[1:] + 0j
        quad_d, quad_v = np.arctanh(grid.real), (laplacian_coefficient(angles.q, hh) * f.laplacian(grid)).real
    else:
        quad = radial_profile(z, (expansion(angles, f, hh, 2) - base).real)
        quad_d, quad_v = quad.distance, quad.mean
    ax.plot(quad_d, quad_v, "-", color="0.55", lw=2, label=r"quadratic $\hat A^{(2)}_h$, Eq. (adj35)")
    ax.plot(cubic.distance, cubic.mean, "s", color="C0", ms=4, label=r"cubic $\hat A^{(3)}_h$, Eq. (adj36)")
    ax.plot(exact.distance, exact.mean, "o", mfc="none", mec="k", ms=6, label=r"$\hat A_h f$, Eq. (adj34)")
    ax.set_xlabel(r"$d(r,0)$", fontsize=12)
    ax.set_ylabel(fr"$\hat A_h f - {angles.q}f$", fontsize=12)
    ax.set_title(f"f = {f.name},  h = {hh:.6g}", fontsize=12)
    ax.tick_params(labelsize=10)
    ax.legend(fontsize=9)
    return ax


def _is_radial(f: SmoothFunction, z: np.ndarray) -> bool:
    """True if f takes equal values on the sites' radii rotated to the real axis."""
    r = np.abs(z[:50]) + 0j
    return bool(np.allclose(f(z[:50]), f(r), rtol=1e-12, atol=1e-12))


def plot_counting(lattice: Lattice | None = None, ax=None):
    r"""Fig. FigS1: the counting function :math:`\mathcal{N}(r)` (Eq. (sum2)) against
    :math:`\rho` with the fitted line :math:`s\rho + b` (Eq. (sum4)). Default {7,3}, 4 rings."""
    ax = _axes(ax)
    lat = lattice if lattice is not None else ring_lattice(7, 3, 4)
    fit = fit_counting(lat)
    r = np.sort(np.abs(lat.z))
    grid = np.linspace(0.0, r[-1], 2000)
    n = np.searchsorted(r, grid, side="right")
    ax.step(geometry.rho(grid), n, where="post", color="C0", lw=1.5, label=r"$\mathcal{N}(r)$")
    rr = np.linspace(1.0, geometry.rho(r[-1]), 50)
    ax.plot(rr, fit.slope * rr + fit.intercept, "--", color="C3", lw=1.5,
            label=fr"${fit.slope:.3f}\,\rho {fit.intercept:+.3f}$ (fit)")
    ax.plot(rr, fit.expected_slope * rr + fit.intercept, ":", color="0.4", lw=1.5,
            label=fr"${fit.expected_slope:g}\,\rho {fit.intercept:+.3f}$")
    ax.set_xlabel(r"$\rho=(1+r^2)/(1-r^2)$", fontsize=12)
    ax.set_ylabel(r"$\mathcal{N}(r)$", fontsize=12)
    ax.set_title(fr"$\{{{lat.p},{lat.q}\}}$, $\ell={lat.rings}$ ({lat.sites} sites)", fontsize=12)
    ax.tick_params(labelsize=10)
    ax.legend(fontsize=10)
    return ax
