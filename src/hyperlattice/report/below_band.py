"""Report sections below the band: holography (boundary correlators, Δ(m²), BF bounds)
and circuit-QED qubits (bound states, exchange J(d)). Each runs in a few seconds (small flakes)."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Callable

from ..graph.lattice import ring_lattice
from ..paper_labels import cite
from .writers import Section, Table, save_figure

__all__ = ["holography_section", "qubits_section", "delta_scaling"]

_OMEGAS = (-3.8, -3.5, -3.2, -3.0, -2.95)


def holography_section(out: Path, progress: Callable[[str], None]) -> Section:
    """Beyond the paper: boundary correlators of the massive scalar and the lattice BF bound.

    Boundary correlators on l = 5..7 flakes: Δ_lattice vs Δ_continuum, the lattice BF bound E0(l)
    against E_inf, one boundary correlator figure (about 3 s).

    Parameters
    ----------
    out : path-like
        The report directory, which must exist; the figure files ``fig_*.png`` and ``fig_*.svg`` are
        written there.
    progress : callable
        Called with a short message (str) before each expensive stage; ``lambda msg: None`` for silence.

    Returns
    -------
    Section
        The section ``"Boundary correlators and the BF bound (holography)"`` (anchor
        ``"holography"``, part ``"beyond"``) with the tables ``"boundary_delta"`` and ``"bf_bound"``
        and the figure ``"holography"``.

    Raises
    ------
    ValueError
        If an argument has the wrong type (e.g. ``out`` is not a path).

    See Also
    --------
    hyperlattice.compare.boundary.delta_curve, hyperlattice.compare.boundary.lattice_bf_bound

    Examples
    --------
    The section takes about 3 s; the argument check is immediate:

    >>> from hyperlattice.report.below_band import holography_section
    >>> holography_section(42, print)
    Traceback (most recent call last):
        ...
    ValueError: out must be a path, got 42.
    """
    import matplotlib.pyplot as plt
    import numpy as np

    from ..compare.boundary import boundary_correlator, delta_curve, lattice_bf_bound

    progress("beyond the paper: boundary correlators (holography)")
    curves = [delta_curve(ring_lattice(7, 3, ell), _OMEGAS) for ell in (5, 6, 7)]
    rows = []
    for c in curves:
        for w, m2, dl, de, dc in zip(c.omegas, c.mass2, c.delta_lattice, c.delta_lattice_err, c.delta_continuum):
            rows.append([c.rings, f"{w:g}", f"{m2:.4f}", f"{dc:.4f}", f"{dl:.4f}", f"{de:.4f}",
                         f"{(dl - dc) / dc:+.3f}"])
    table = Table("boundary_delta", ["rings", "omega", "mass2", "delta_continuum", "delta_lattice",
                                     "delta_lattice_err", "rel_diff"], rows,
                  "Conformal dimension of the outer-ring two-point function G_ij ~ [sin(theta/2)]^(-2 Delta): fitted "
                  "on the lattice (window: geodesic at least 2 rings deep; error = standard error + window "
                  "systematic) and Delta = 1/2 + sqrt(1 + m^2)/2, m^2 = -4(omega+3)/(3h^2) (AdS2, R = 1/2).")
    bf = lattice_bf_bound(7, 3, (3, 4, 5, 6, 7))
    t2 = Table("bf_bound", ["rings", "E0", "mass2_at_E0"],
               [[int(r), f"{e:.6f}", f"{m:.4f}"] for r, e, m in zip(bf.rings, bf.e0, bf.mass2)],
               f"Lattice BF bound (bottom of the flake's spectrum) against the continuum bound E_inf = "
               f"{bf.omega_continuum:.6f} (m^2 = -1).")
    fig, axes = plt.subplots(1, 3, figsize=(15.0, 4.2), layout="constrained")
    boundary_correlator(ring_lattice(7, 3, 7), -3.2).plot(ax=axes[0])
    from ..plots.boundary import plot_delta_curve

    plot_delta_curve(curves, ax=axes[1])
    bf.plot(ax=axes[2])
    figs = [save_figure(fig, out, "holography", "(a) Outer-ring correlators of the ℓ = 7 flake at ω = −3.2 "
                        f"against sin(θ/2): graph (red dots), continuum {cite('eq21')} with the whole-disk propagator "
                        "(black dots, translucent), the fitted slope −2Δ over the window (blue line) and "
                        "the window edge (dotted). (b) Δ against m², lattice ℓ = 5–7 and continuum (black line). "
                        "(c) Lattice BF bound E₀(ℓ) (red) and the continuum E∞ (dashed).")]
    heavy = [r for r in rows if r[1] in ("-3.5", "-3.2")]
    worst = max(abs(float(r[6])) for r in heavy)
    near = [r for r in rows if r[1] == "-2.95"]
    text = ["Not in the paper (its discussion names holography as future work). Below the band G = (H - omega)^-1 "
            "is the propagator of a scalar of mass^2 = -lambda in AdS2 of radius 1/2; with both points on the outer "
            "ring it decays as [sin(theta/2)]^(-2 Delta).",
            f"For masses well above the BF bound (omega = -3.5, -3.2) the lattice Delta agrees with the continuum to "
            f"{100 * worst:.1f} % and no longer changes with l; near the bound (omega = -2.95) it lies above the "
            "continuum and approaches it as l grows (" + ", ".join(f"l = {r[0]}: {r[4]}" for r in near)
            + f" against {near[0][3]}): the continuum holds where the field varies slowly on the lattice "
            "scale and the flake is large compared with the decay length, and stops near the bound, where "
            "the propagator reaches the edge. " + bf.statement()]
    return Section("Boundary correlators and the BF bound (holography)", ("eq21", "green30"), text, [table, t2], figs,
                   anchor="holography", part="beyond")


def qubits_section(out: Path, progress: Callable[[str], None]) -> Section:
    """Beyond the paper: circuit-QED qubits on the l = 6 flake.

    Exact bound state vs leading order, size against detuning, exchange J(d) graph vs continuum
    (about 1-3 s).

    Parameters
    ----------
    out : path-like
        The report directory, which must exist; the figure files ``fig_*.png`` and ``fig_*.svg`` are
        written there.
    progress : callable
        Called with a short message (str) before each expensive stage; ``lambda msg: None`` for silence.

    Returns
    -------
    Section
        The section ``"Circuit-QED qubits below the band"`` (anchor ``"qubits"``, part ``"beyond"``)
        with the tables ``"qubit_bound_state"`` and ``"qubit_exchange"`` and the figure ``"qubits"``.

    Raises
    ------
    ValueError
        If an argument has the wrong type (e.g. ``out`` is not a path).

    See Also
    --------
    hyperlattice.graph.qubits.bound_state, hyperlattice.compare.qubits.exchange_comparison

    Examples
    --------
    >>> import tempfile
    >>> from pathlib import Path
    >>> from hyperlattice.report.below_band import qubits_section
    >>> with tempfile.TemporaryDirectory() as d:
    ...     s = qubits_section(Path(d), lambda msg: None)
    >>> s.reference_line, [t.name for t in s.tables], [f.name for f in s.figures]
    ('Builds on: Eq. (18), Eq. (19)', ['qubit_bound_state', 'qubit_exchange'], ['qubits'])
    """
    import matplotlib.pyplot as plt
    import numpy as np

    from ..compare.qubits import bound_state_sizes, exchange_comparison
    from ..graph.qubits import bound_state

    progress("beyond the paper: circuit-QED qubits")
    lat = ring_lattice(7, 3, 6)
    sizes = bound_state_sizes(lat, [-3.8, -3.5, -3.2, -3.0, -2.95, -2.92, -2.90], 0.05)
    rows = [[f"{r[0]:g}", f"{r[1]:.4f}", f"{r[2]:.6f}", f"{r[3]:.4f}", f"{r[4]:.4f}", f"{r[5]:.4f}",
             "" if math.isnan(r[6]) else f"{r[6]:.4f}"] for r in sizes.table()]
    t1 = Table("qubit_bound_state", ["omega_q", "detuning", "E_bound", "size_graph", "size_continuum",
                                     "decay_length_graph", "decay_length_continuum_asymptotic"], rows,
               "One qubit (g = 0.05) on site 0 of the l = 6 flake: exact bound-state energy, mean hyperbolic "
               f"distance of the photon from the qubit (graph: exact profile; continuum: {cite('eq21')} profile on the same "
               "sites), fitted decay length, and 1/(2 Delta) of the whole-disk propagator (empty beyond E_inf).")
    scal = [bound_state(lat, 0, -3.1, g).profile_error for g in (0.2, 0.1, 0.05)]
    ex = exchange_comparison(lat, -3.1, 0.05, 0)
    t2 = Table("qubit_exchange", ["d", "J_graph", "J_continuum", "rel_diff"],
               [[f"{d:.3f}", f"{a:.6e}", f"{b:.6e}", f"{r:+.3f}"] for d, a, b, r in ex.table()],
               "Exchange J = g^2 G_ij(omega_q) between a qubit on site 0 and a second qubit at hyperbolic distance d "
               f"(binned means, bin width d0/2), ℓ = 6, ω_q = −3.1, g = 0.05, graph vs {cite('eq21')}.")
    fig, axes = plt.subplots(1, 2, figsize=(11.0, 4.0), layout="constrained")
    ex.plot(ax=axes[0])
    sizes.plot(ax=axes[1])
    cm = np.asarray(ex.continuum_mean, dtype=float)
    neg = np.asarray(ex.bins, dtype=float)[cm < 0]
    sign = (f" The continuum J turns negative beyond d ≈ {neg[0]:.2f} (near the disk edge, where the Dirichlet "
            "propagator changes sign); |J| is drawn there as a dashed line, negative graph values as open circles."
            if neg.size else " Both J stay positive over the flake.")
    figs = [save_figure(fig, out, "qubits", "(a) |J(d)|, graph vs continuum (ℓ = 6, ω_q = −3.1), log axis. "
                        "(b) Bound-state size and decay length against the detuning from the band bottom E₀(ℓ)."
                        + sign)]
    text = ["Not in the paper (its conclusion names qubits coupled to the resonators). A qubit below the band binds a "
            "photon; the exact single-excitation state is compared with its leading-order form G_{i j0}(omega_q): "
            "the profile difference is " + ", ".join(f"{e:.2e}" for e in scal) + " for g = 0.2, 0.1, 0.05 "
            "(ratios {:.2f}, {:.2f}: order g^2).".format(scal[0] / scal[1], scal[1] / scal[2]),
            f"The exchange J(d) follows the continuum (relative L2 distance {ex.rel_l2:.3f}, decay lengths "
            f"{ex.decay_length_graph:.3f} graph and {ex.decay_length_continuum:.3f} continuum). The bound state grows "
            "as the detuning shrinks, but its continuum decay length 1/(2 Delta) stays below 2R = 1 down to the BF "
            "bound: the curvature limits its size (cf. Bienias et al., PRL 128, 013601 (2022)); on the flake the "
            "growth continues up to E0(l), where the edge takes over."]
    return Section("Circuit-QED qubits below the band", ("eq20", "eq21"), text, [t1, t2], figs, anchor="qubits",
                   part="beyond")


#: the rings and frequencies of the Delta(l) table and figure of docs/below-band.md
DELTA_RINGS = (5, 6, 7, 8, 9, 10, 11, 12)
BF_RINGS = (3, 4, 5, 6, 7, 8, 9, 10, 11, 12)


def delta_scaling(out=None, rings=DELTA_RINGS, omegas=_OMEGAS, bf_rings=BF_RINGS, *, p: int = 7, q: int = 3,
                  progress: Callable[[str], None] | None = None) -> dict:
    r"""Δ_lattice(m²) for several ℓ against Δ_continuum, and the lattice BF bound E0(ℓ): table data and figure.

    One :func:`~hyperlattice.compare.boundary.delta_curve` per ℓ (source = first outer-ring site, depth 2)
    and one :func:`~hyperlattice.compare.boundary.lattice_bf_bound`. With ``out`` (a directory) writes
    ``below-band-delta.png`` (left: Δ against m², lattice and continuum; middle: Δ_lattice − Δ_continuum
    against ℓ per mass; right: E0(ℓ) and E∞) and ``below-band-delta.json`` (the numbers).
    Regenerates the tables of ``docs/below-band.md``; ℓ = 12 (725,760 sites) needs about 2 GB and a
    minute or two.

    Parameters
    ----------
    out : path-like, optional
        Directory for the figure and the JSON file (created if needed); nothing is written when None
        (the default).
    rings : sequence of int, optional
        Flakes of the Δ curves, each in 1..14 (default :data:`DELTA_RINGS`, l = 5..12).
    omegas : sequence of float, optional
        Frequencies ω below the band, in units of t (default -3.8, -3.5, -3.2, -3.0, -2.95).
    bf_rings : sequence of int, optional
        Flakes of the BF bound E0(ℓ), each in 1..14 (default :data:`BF_RINGS`, l = 3..12).
    p, q : int, optional
        The {p,q} lattice (default {7,3}).
    progress : callable, optional
        Called with one line (str) after each flake; silent when None.

    Returns
    -------
    dict
        ``{"curves": [DeltaCurve.as_dict() ...], "bf": LatticeBFBound.as_dict(), "seconds": {...}}``
        (``seconds`` maps each ℓ, as a string, and ``"bf"`` to wall-clock times).

    Raises
    ------
    ValueError
        If the rings are not integers in 1..14, the frequencies not real, {p,q} not hyperbolic, or
        ``out`` cannot be used as a directory (all checked before any computation).

    See Also
    --------
    holography_section : the report's short version (l = 5..7).

    Examples
    --------
    >>> from hyperlattice.report.below_band import delta_scaling
    >>> data = delta_scaling(rings=(4,), omegas=(-3.5,), bf_rings=(3, 4))
    >>> sorted(data), len(data["curves"]), sorted(data["seconds"])
    (['bf', 'curves', 'seconds'], 1, ['4', 'bf'])
    >>> round(data["curves"][0]["delta_lattice"]["data"][0], 3)
    2.032
    >>> [round(e, 6) for e in data["bf"]["e0"]["data"]]
    [-2.786702, -2.846633]
    >>> delta_scaling(rings=(0,))
    Traceback (most recent call last):
        ...
    ValueError: rings must be a list of integers: rings must be at least 1, got 0.
    """
    import time

    import numpy as np

    from ..compare.boundary import delta_curve, lattice_bf_bound

    from .. import _validate

    # everything at the door: the curves take minutes, and a bad ``out`` used to fail only after them
    rings = _validate.int_list("rings", rings, minimum=1, maximum=14)
    bf_rings = _validate.int_list("bf_rings", bf_rings, minimum=1, maximum=14)
    omegas = _validate.real_array("omegas", omegas, ndim=1)
    p, q = _validate.pq(p, q)
    if out is not None:
        out = _validate.directory("out", out)
    say = progress if progress is not None else (lambda s: None)
    curves, secs = [], {}
    for ell in rings:
        t0 = time.perf_counter()
        lat = ring_lattice(p, q, ell)
        curves.append(delta_curve(lat, omegas))
        secs[str(ell)] = time.perf_counter() - t0
        say(f"l = {ell}: {lat.sites} sites, {secs[str(ell)]:.1f} s")
        del lat
    t0 = time.perf_counter()
    bf = lattice_bf_bound(p, q, tuple(bf_rings))
    secs["bf"] = time.perf_counter() - t0
    say(f"BF bound l = {bf_rings[0]}..{bf_rings[-1]}: {secs['bf']:.1f} s")
    data = {"curves": [c.as_dict() for c in curves], "bf": bf.as_dict(), "seconds": secs}
    if out is not None:
        import json

        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        from ..plots.boundary import plot_bf_bound, plot_delta_curve

        out = Path(out)
        fig, axes = plt.subplots(1, 3, figsize=(15.0, 4.2), layout="constrained")
        plot_delta_curve(curves, ax=axes[0])
        ax = axes[1]
        ells = np.array([c.rings for c in curves])
        for k, w in enumerate(curves[0].omegas):
            dl = np.array([c.delta_lattice[k] for c in curves])
            de = np.array([c.delta_lattice_err[k] for c in curves])
            dc = curves[0].delta_continuum[k]
            ax.errorbar(ells, dl - dc, yerr=de, fmt="o-", ms=3, capsize=2,
                        label=fr"$\omega = {w:g}$, $m^2 = {round(float(curves[0].mass2[k]), 2) + 0.0:.2f}$")
        ax.axhline(0.0, color="k", lw=0.8)
        ax.set_xlabel(r"rings $\ell$")
        ax.set_ylabel(r"$\Delta_{\rm lattice} - \Delta_{\rm continuum}$")
        ax.legend(fontsize=7)
        plot_bf_bound(bf, ax=axes[2])
        fig.savefig(out / "below-band-delta.png", dpi=100, metadata={"Software": None})
        plt.close(fig)
        (out / "below-band-delta.json").write_text(json.dumps(data, indent=1, default=float) + "\n",
                                                    encoding="utf-8")
    return data


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
