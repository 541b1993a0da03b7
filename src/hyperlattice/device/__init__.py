"""The device room: what an experiment measures on a resonator lattice or an electric circuit.

* :mod:`.resonators` — a resonator lattice with ports, as fabricated (names, couplings, disorder);
* :mod:`.transmission` — its scattering matrix S(ω) by input–output theory, swept fast;
* :mod:`.circuit` — electric circuits: admittance, node impedances, resonances, voltage profiles;
* :mod:`.fit` — fitting ω₀, J, κ_int to a measured trace, with errors;
* :mod:`.continuum` — the same S₂₁ from the continuum Green function through the dictionary;
* :mod:`.ensemble` — mean and spread over fabricated devices (realisations run as a sweep);

Resonators sit on any graph of the package (flake, cluster, line graph, user adjacency); units
are the user's. See ``docs/device.md``.
"""

from __future__ import annotations

from .circuit import (Impedance, NodeVoltages, circuit_resonances, element_admittance, impedance, node_voltages,
                      parse_elements)
from .continuum import TransmissionComparison, continuum_transmission
from .fit import TransmissionFit, fit_transmission, read_trace
from .ensemble import DeviceEnsemble, ensemble_statistics
from .resonators import Device, flat_band_degeneracy, graph_edges, resonator_device
from .transmission import Transmission, transmission

__all__ = ["Device", "resonator_device", "graph_edges", "flat_band_degeneracy", "Transmission", "transmission",
           "DeviceEnsemble", "ensemble_statistics", "Impedance", "NodeVoltages", "impedance", "node_voltages",
           "circuit_resonances", "element_admittance", "parse_elements", "TransmissionFit", "fit_transmission",
           "read_trace", "TransmissionComparison", "continuum_transmission"]
