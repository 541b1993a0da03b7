"""Report section "Topological bands on {8,3}": the QWZ phase diagram in M and the Haldane scan.

The QWZ rows are computed by the run (the l = 3 flake, dense, and the Bolza cluster's Abelian
bands: a few seconds); the Haldane scan is stored (``topology_haldane_scan.json`` next to this
module, written by ``benchmarks/topology_haldane_scan.py``: minutes, far longer than a report run).
"""

from __future__ import annotations

import json
import warnings
from importlib import resources
from pathlib import Path
from typing import Callable

from .writers import Section, Table, save_figure as _save_figure

__all__ = ["stored_haldane_scan", "qwz_phase_rows", "topology_section", "QWZ_MASSES", "QWZ_RINGS"]

SCAN_FILE = "topology_haldane_scan.json"
SCAN_COMMAND = "PYTHONPATH=src python benchmarks/topology_haldane_scan.py | tail -n 1"
#: the masses of the QWZ rows (M -> -M flips every invariant's sign, so M > 0 is shown)
QWZ_MASSES = (0.25, 0.5, 0.75, 1.0, 1.25, 1.5, 1.75, 2.0, 2.5, 3.0)
#: rings of the report's QWZ flake (dense, 400 rows)
QWZ_RINGS = 3


def stored_haldane_scan() -> dict:
    """The stored Haldane scan on {8,3} (``{"meta", "scan", "confirm"}``, see ``benchmarks/topology_haldane_scan.py``).

    Returns
    -------
    dict
        The scan as the benchmark writes it.

    Examples
    --------
    >>> from hyperlattice.report.topology import stored_haldane_scan
    >>> scan = stored_haldane_scan()
    >>> scan["meta"]["rings"], len(scan["confirm"]) > 0
    (4, True)
    """
    text = resources.files("hyperlattice.report").joinpath(SCAN_FILE).read_text(encoding="utf-8")
    return json.loads(text)


def qwz_phase_rows(masses=QWZ_MASSES, rings: int = QWZ_RINGS) -> list:
    """The {8,3} QWZ rows: flake marker, Kitaev sum, LDOS gap, conductance; Bolza gcd, Pfaffian, gap.

    Parameters
    ----------
    masses : sequence of float, optional
        The masses M (default :data:`QWZ_MASSES`).
    rings : int, optional
        Rings of the flake (default 3).

    Returns
    -------
    list of dict
        One per M: ``M``, ``marker``, ``kitaev``, ``gap``, ``conductance`` (e²/h at E = 0),
        ``gcd``, ``pfaffian``, ``cluster_gap`` (the last three None where the cluster's gap closes).

    Examples
    --------
    >>> from hyperlattice.report.topology import qwz_phase_rows
    >>> row = qwz_phase_rows([1.0], rings=2)[0]
    >>> row["gcd"], round(row["conductance"], 2)
    (1, 1.0)
    """
    import numpy as np

    from .. import _validate
    from ..graph.clusters import pbc_cluster
    from ..graph.lattice import ring_lattice
    from ..topology import flake_topology
    from ..topology.surfaces import cluster_chern
    from ..topology.transport import conductance

    masses = np.atleast_1d(_validate.real_array("masses", masses)).ravel()
    if masses.size == 0 or masses.size > 1000 or not np.all(np.isfinite(masses)) or np.any(np.abs(masses) > 1e6):
        raise ValueError("masses must be between 1 and 1,000 finite numbers of magnitude at most 1e6.")
    rings = _validate.integer("rings", rings, minimum=1, maximum=4)
    lat = ring_lattice(8, 3, rings)
    cl = pbc_cluster(8, 3, "bolza")
    rows = []
    for M in masses:
        with warnings.catch_warnings():
            warnings.filterwarnings("ignore", "the Bott index is unreliable")
            top = flake_topology(lat, "qwz", M=M, per_ring=1)
        g = float(conductance(lat, "qwz", M=M, energies=[0.0]).conductance[0])
        try:
            c = cluster_chern(cl, "qwz", M=M)
            gcd, pf, cgap = c.gcd, c.pfaffian, c.gap
        except ValueError:              # the gap closes on the grid: no Chern numbers
            gcd, pf, cgap = None, None, None
        rows.append(dict(M=float(M), marker=float(top.marker), kitaev=float(top.kitaev), gap=float(top.gap),
                         conductance=g, gcd=gcd, pfaffian=pf, cluster_gap=cgap))
    return rows


def _phi(x: float) -> str:
    import math

    for k, name in ((2, "π/2"), (4, "π/4"), (3, "π/3"), (6, "π/6")):
        if abs(x - math.pi / k) < 1e-9:
            return name
    return f"{x:.3f}"


def topology_section(out: Path, progress: Callable[[str], None]) -> Section:
    """The topology section: the {8,3} QWZ phase diagram in M (table, figure) and the Haldane tables.

    Parameters
    ----------
    out : Path
        The report directory (must exist); the figure ``fig_topology_qwz.png``/``.svg`` goes there.
    progress : callable
        Called with one line of progress text.

    Returns
    -------
    Section
        Anchor ``"topology"``, part ``"beyond"``; its provenance names the stored Haldane scan.
    """
    from .. import _validate
    from ..plots.topology import plot_phase_diagram

    out = _validate.directory("out", out)
    progress("beyond the paper: topological bands on {8,3}")
    rows = qwz_phase_rows()
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7.0, 4.0), layout="constrained")
    plot_phase_diagram(rows, ax)
    ax.set_title(f"QWZ on {{8,3}}: ℓ = {QWZ_RINGS} flake and the Bolza cluster")
    figs = [_save_figure(fig, out, "topology_qwz", "QWZ on {8,3} against M: the hyperbolic local marker and "
                         "Kitaev's sum at the centre of the ℓ = 3 flake, its two-terminal conductance at E = 0 "
                         "(e²/h, wide-band leads on two quarter arcs of the edge), its ring-1 LDOS gap, and the gcd "
                         "of the first Chern numbers C_ij of the Bolza cluster's Abelian bands with their smallest "
                         "gap (missing where that gap closes).")]

    def cell(v, fmt):
        return "gap closes" if v is None else format(v, fmt)

    qwz = Table("topology_qwz", ["M", "marker (flake centre)", "Kitaev (flake centre)", "LDOS gap (t)",
                                 "G (e²/h)", "Bolza gcd", "Bolza Pf", "Bolza gap (t)"],
                [[f"{r['M']:.2f}", f"{r['marker']:.4f}", f"{r['kitaev']:.4f}", f"{r['gap']:.3f}",
                  f"{r['conductance']:.4f}", cell(r["gcd"], "d"), cell(r["pfaffian"], "d"), cell(r["cluster_gap"], ".3f")]
                 for r in rows],
                f"QWZ on {{8,3}}: the ℓ = {QWZ_RINGS} flake (dense; marker: mean over ring 1, disk of four bond "
                "lengths; conductance at E = 0) beside the Bolza cluster's Abelian Chern numbers (gcd and Pfaffian of "
                "C_ij, smallest direct gap on the grid). M → −M flips the sign of every invariant.")
    scan = stored_haldane_scan()
    hal = Table("topology_haldane", ["t2", "φ", "M", "gap", "E_F (t)", "filling", "LDOS gap (t)", "marker",
                                     "G (e²/h)"],
                [[f"{r['t2']:.1f}", _phi(r["phi"]), f"{r['M']:.1f}", r["gap_kind"], f"{r['fermi']:.3f}",
                  f"{r['filling']:.3f}", f"{r['gap']:.3f}", f"{r['marker']:.3f}", f"{r['conductance']:.3f}"]
                 for r in scan["scan"]],
                f"Haldane on the ℓ = {scan['meta']['rings']} {{8,3}} flake (stored scan): for the widest gap of "
                "the ring-1 LDOS and for the gap at half filling, the Fermi level at its middle, the filling, the "
                "gap, the local marker at the centre and the two-terminal conductance there.")
    conf = Table("topology_haldane_confirm", ["t2", "φ", "M", "gap", "E_F (t)", "marker R = 4", "marker R = 6",
                                              "G (e²/h)"],
                 [[f"{r['t2']:.1f}", _phi(r["phi"]), f"{r['M']:.1f}", r["gap_kind"], f"{r['fermi']:.3f}",
                   f"{r['marker_R4']:.3f}", f"{r['marker_R6']:.3f}", f"{r['conductance']:.4f}"]
                  for r in scan["confirm"]],
                 f"The chosen Haldane rows on the ℓ = {scan['meta']['confirm_rings']} flake: the centre marker "
                 "(Chebyshev projector, 512 moments) with disks of four and six bond lengths, and the conductance.")
    text = [_qwz_sentence(rows), _haldane_sentence(scan)]
    provenance = [f"The Haldane tables are the stored scan {SCAN_FILE}; regenerate with `{SCAN_COMMAND}`. The QWZ "
                  "table and figure are computed by this run."]
    return Section("Topological bands on {8,3}: QWZ phase diagram and Haldane", (), text, [qwz, hal, conf], figs,
                   anchor="topology", part="beyond", provenance=provenance)


def _qwz_sentence(rows) -> str:
    topo = [r["M"] for r in rows if r["gcd"] == 1 and abs(r["conductance"] - 1) < 0.05]
    span = f"{min(topo):g} ≤ M ≤ {max(topo):g}" if topo else "no M of the table"
    return (f"QWZ on {{8,3}} is a Chern insulator for {span} on this grid: there the Bolza cluster's Chern matrix has "
            "gcd 1, the flake conducts one e²/h through its edge at E = 0 and the centre marker approaches −1 where the "
            "centre's gap is open; at larger M all three vanish (the transition near M ≈ 1.5, against M = 2 on the "
            "square lattice).")


def _haldane_sentence(scan) -> str:
    clean = [r for r in scan["confirm"] if abs(r["conductance"] - round(r["conductance"])) < 0.01
             and round(r["conductance"]) >= 1 and abs(r["marker_R6"] - round(r["conductance"])) < 0.05]
    if not clean:
        return "No row of the Haldane scan is a clean Chern insulator on the confirmation flake."
    parts = [f"t2 = {r['t2']:g}, φ = {_phi(r['phi'])}, M = {r['M']:g} at E_F = {r['fermi']:.2f} "
             f"(G = {r['conductance']:.3f} e²/h, marker {r['marker_R6']:.3f})" for r in clean]
    return ("Haldane on {8,3} is a clean Chern insulator (quantised conductance, marker converging to the same "
            "integer as its disk grows) at " + "; ".join(parts) + ".")


from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
