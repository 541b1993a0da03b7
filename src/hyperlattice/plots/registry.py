"""Which drawing :meth:`hyperlattice.results.Result.plot` uses for each result type.

The plotting layer fills the registry of :mod:`hyperlattice.results` here, in one table, when
:mod:`hyperlattice.plots` is imported (:meth:`Result.plot` imports it by name the first time it
is asked). Result modules never import ``plots``; ``plots`` imports them (the layer rule of
``docs/architecture.md``). Each entry is ``type tag -> function(result, ax=None, **kwargs)``;
a subclass without an entry uses its nearest registered base class.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from ..results import register_plotter
from . import basic, bosons, boundary, device, disorder, dos, green, limits, magnetic, paper, qmc_lobe, scaling
from . import spins_classical, topology

if TYPE_CHECKING:
    from matplotlib.axes import Axes

__all__: list[str] = []


def _gp_comparison(cmp, ax=None, **kwargs):
    # a three-panel figure: ``ax`` is the sequence of three axes (a new figure when None)
    return bosons.gp_comparison_figure(cmp, axes=ax, **kwargs)


def _delta_curve(curve, ax=None) -> Axes:
    return boundary.plot_delta_curve([curve], ax=ax)


def _partition(cmp, ax=None) -> Axes:
    return paper.plot_partition(cmp.beta, cmp.z_graph, cmp.z_continuum, cmp.e0_graph, ax=ax)


def _magnetic(cmp, ax=None) -> Axes:
    return magnetic.error_map(cmp.fluxes, cmp.rings, cmp.worst(), ax=ax,
                              title=f"{{{cmp.p},{cmp.q}}}: graph vs continuum, {cmp.graph.shape[2]} lowest levels")


_DRAWINGS = {
    # graph and continuum side
    "Levels": basic.plot_levels,
    "Lattice": basic.plot_lattice,
    "Butterfly": basic.plot_butterfly,
    "KPMDos": basic.plot_kpm_dos,
    "Bands": basic.plot_bands,
    "AbelianDOS": basic.plot_abelian_dos,
    "BoundState": basic.plot_bound_state,
    "DirichletTable": basic.plot_dirichlet_table,
    "MottLobe": basic.plot_mott_lobe,
    "MottLobeTable": bosons.plot_mott_lobes,
    # comparisons
    "GPComparison": _gp_comparison,
    "QMCLobe": qmc_lobe.plot_qmc_lobe,
    "BoundaryCorrelator": boundary.plot_boundary_correlator,
    "DeltaCurve": _delta_curve,
    "LatticeBFBound": boundary.plot_bf_bound,
    "ExchangeComparison": boundary.plot_exchange,
    "BoundStateSizes": boundary.plot_bound_state_sizes,
    "BinnedCorrelation": green.plot_binned,
    "GreenComparison": green.plot_distance_profile,
    "DisorderEnsemble": disorder.plot_dos,
    "RScan": disorder.plot_r_scan,
    "DisorderGreen": disorder.plot_green_distance,
    "SCBAComparison": disorder.plot_scba_comparison,
    "DosComparison": dos.comparison_axes,
    "LevelComparison": paper.plot_level_comparison,
    "RelativeErrorTrend": paper.plot_relative_error,
    "LevelCount": paper.plot_level_counting,
    "PartitionComparison": _partition,
    "BandBottomFit": limits.plot_band_fit,
    "BandBottom": limits.plot_band_bottom,
    "PlateauAnalysis": limits.plot_plateau,
    "DictionaryComparison": limits.plot_dictionaries,
    "MagneticComparison": _magnetic,
    "FrameAngles": scaling.plot_frame_angles,
    "RadialProfile": scaling.draw_radial_profile,
    "OperatorProfile": scaling.draw_operator_profile,
    "ConvergenceStudy": scaling.plot_convergence,
    "CountingFit": scaling.plot_counting,
    # what a device measures
    "Transmission": device.plot_transmission,
    "DeviceEnsemble": device.plot_ensemble,
    "TransmissionFit": device.plot_fit,
    "TransmissionComparison": device.plot_comparison,
    # classical spins
    "ClassicalResult": spins_classical.plot_classical,
    "TemperingResult": spins_classical.plot_tempering,
    # topological bands
    "Conductance": topology.plot_conductance,
}

for _tag, _func in _DRAWINGS.items():
    register_plotter(_tag)(_func)
