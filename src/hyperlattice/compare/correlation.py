r"""Correlation analysis of a two-point function on a lattice (``Fig3``, right panels).

Correlation analysis (``Fig3``, right panels)
----------------------------------------------
For a source site :math:`i`: pairs :math:`(d_{ij}, F_j)`, binned means and standard deviations
versus distance, and a collapse number

.. math:: S = \Bigl[\frac{\sum_b n_b\sigma_b^2}{\sum_b n_b|\mu_b|^2}\Bigr]^{1/2},

the rms spread within distance bins relative to the rms bin mean (0 for a function of
distance alone). Conformal (automorphism) invariance emerges as :math:`S\to 0` for large
:math:`\ell`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .. import _validate
from ..geometry import d0, distance
from ..graph.lattice import Lattice
from ..results import Result

__all__ = ["correlation_pairs", "bin_by_distance", "BinnedCorrelation", "collapse_measure"]


# ----------------------------------------------------------------------------
# correlation analysis
# ----------------------------------------------------------------------------

def correlation_pairs(lattice: Lattice, source: int, values) -> tuple[np.ndarray, np.ndarray]:
    r"""The list of pairs :math:`(d_{ij}, F_j)` for source i, all j except i, sorted by distance."""
    _validate.lattice(lattice)
    source = _validate.site_index("source", source, lattice.sites)
    v = np.asarray(values)
    if v.shape != (lattice.sites,):
        raise ValueError(f"values must have one entry per site ({lattice.sites}), got shape {v.shape}.")
    d = distance(lattice.z, lattice.z[source])
    keep = np.arange(lattice.sites) != source
    order = np.argsort(d[keep], kind="stable")
    return d[keep][order], v[keep][order]


@dataclass(frozen=True)
class BinnedCorrelation:
    """Means and standard deviations of F in distance bins (empty bins dropped)."""

    edges: np.ndarray
    centre: np.ndarray
    mean: np.ndarray
    std: np.ndarray
    count: np.ndarray


def bin_by_distance(dist, values, width: float | None = None, edges=None) -> BinnedCorrelation:
    r"""Bin :math:`F` by hyperbolic distance: mean and (population) standard deviation per bin.

    Default bins have width :math:`d_0/2` of {7,3} (0.141), fine enough to resolve the
    distance dependence and coarse enough to hold several sites each. Complex values: the
    std is :math:`\sqrt{\langle|F-\mu|^2\rangle}`.
    """
    d = np.asarray(dist, float)
    v = np.asarray(values)
    if d.shape != v.shape or d.ndim != 1:
        raise ValueError("distances and values must be one-dimensional arrays of equal length.")
    if d.size == 0 or not np.all(np.isfinite(d)) or not np.all(np.isfinite(v)):
        raise ValueError("distances and values must be finite and non-empty.")
    if edges is None:
        if width is None:
            width = 0.5 * d0(7, 3)
        if not (width > 0 and math.isfinite(width)):
            raise ValueError("the bin width must be a positive number.")
        edges = np.arange(0.0, d.max() + width, width)
        if edges[-1] <= d.max():
            edges = np.append(edges, edges[-1] + width)
    edges = np.asarray(edges, float)
    idx = np.clip(np.searchsorted(edges, d, side="right") - 1, 0, len(edges) - 2)
    nb = len(edges) - 1
    count = np.bincount(idx, minlength=nb)
    s1 = np.bincount(idx, weights=v.real, minlength=nb) + 1j * np.bincount(idx, weights=v.imag, minlength=nb) \
        if np.iscomplexobj(v) else np.bincount(idx, weights=v, minlength=nb)
    nz = count > 0
    mean = np.zeros(nb, s1.dtype)
    mean[nz] = s1[nz] / count[nz]
    dev2 = np.abs(v - mean[idx]) ** 2
    var = np.bincount(idx, weights=dev2, minlength=nb)
    std = np.zeros(nb)
    std[nz] = np.sqrt(var[nz] / count[nz])
    centre = 0.5 * (edges[:-1] + edges[1:])
    return BinnedCorrelation(edges=edges, centre=centre[nz], mean=mean[nz], std=std[nz], count=count[nz])


def collapse_measure(dist, values, width: float | None = None) -> float:
    r"""Collapse number :math:`S = [\sum_b n_b\sigma_b^2 / \sum_b n_b|\mu_b|^2]^{1/2}` (module docstring).

    0 when F is a function of distance alone (up to the bin width), larger when sites at
    equal distance disagree.
    """
    b = bin_by_distance(dist, values, width=width)
    den = float(np.sum(b.count * np.abs(b.mean) ** 2))
    if den == 0:
        raise ValueError("the values vanish identically; the collapse number is undefined.")
    return float(np.sqrt(np.sum(b.count * b.std ** 2) / den))
