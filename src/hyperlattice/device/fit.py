r"""Fit a measured transmission trace: the bare frequency ω₀ (a uniform offset), the coupling J and the
internal loss κ_int of an ideal device (ports' κ given), by least squares on ``|S₂₁|``.

The model is the device of :mod:`.resonators` without disorder, :math:`H = \omega_0 - J A`: the
eigenvectors of A are computed once, so a model evaluation costs O(N P) per frequency. Starting points:
the lowest and highest peaks of the trace are taken for the band edges of :math:`\omega_0 - J\,\mathrm{spec}(A)`,
for both signs of J, and the width of the tallest peak for κ_int; the better of the two fits is kept.
Errors: :math:`\mathrm{cov} = s^2 (J^T J)^{-1}`, :math:`s^2` the residual variance (the noise level is
read from the misfit, scipy.optimize.least_squares's Jacobian at the optimum). How many parameters the
trace supports: the numerical rank of the column-scaled Jacobian (singular values above
:data:`RANK_RTOL` of the largest), reported with its condition number.
"""

from __future__ import annotations

import csv
import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from .. import _validate
from ..results import Column, Result
from .resonators import _layout, _name_table, _ports
from .transmission import EIGEN_MAX, _woodbury

__all__ = ["TransmissionFit", "read_trace", "fit_transmission", "PARAMETERS"]

PARAMETERS = ("omega0", "J", "kappa_int")
#: a direction of parameter space the trace does not determine: singular value of the column-scaled
#: Jacobian below this fraction of the largest (numerical rank at the square root of the rounding of ``|S|``)
RANK_RTOL = 1e-7
#: most model evaluations of one least-squares run (from each start); the good start converges in ~10-30
MAX_EVALUATIONS = 150
#: most points of a trace
MAX_POINTS = 1_000_000


def read_trace(path) -> tuple[np.ndarray, np.ndarray]:
    """(ω, ``|S₂₁|``) of a measured trace: a CSV with header ``omega,mag_db`` (20 log₁₀``|S₂₁|``) or ``omega,re,im``.

    Parameters
    ----------
    path : str or path-like
        The CSV file (as a network analyser exports it, with that header row).

    Returns
    -------
    tuple of ndarray
        Frequencies and the linear magnitude ``|S₂₁|``.

    Raises
    ------
    ValueError
        Wrong columns, a non-number, NaN, fewer than 8 points.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> from hyperlattice.device import read_trace
    >>> p = pathlib.Path(tempfile.mkdtemp()) / "t.csv"
    >>> _ = p.write_text("omega,mag_db\\n1,-20\\n2,-40\\n3,-20\\n4,0\\n5,-6\\n6,-20\\n7,-40\\n8,-60\\n")
    >>> w, mag = read_trace(p)
    >>> [round(float(x), 3) for x in mag[:2]]
    [0.1, 0.01]
    """
    p = _validate.input_path("the measured trace", path, suffixes=(".csv", ".txt"))
    try:
        with open(p, newline="", encoding="utf-8") as fh:
            rows = list(csv.reader(fh))
    except (OSError, UnicodeDecodeError, csv.Error) as exc:
        raise ValueError(f"the measured trace {str(p)!r} cannot be read: {_validate.file_problem(exc)}.") from None
    rows = [r for r in rows if r and any(c.strip() for c in r)]
    if not rows:
        raise ValueError(f"the measured trace {str(p)!r} is empty.")
    header = [c.strip().lower() for c in rows[0]]
    if header not in (["omega", "mag_db"], ["omega", "re", "im"]):
        raise ValueError(f"the measured trace {str(p)!r} must have the columns omega,mag_db or omega,re,im, got "
                         f"{','.join(rows[0])[:60]!r}.")
    try:
        data = np.array([[float(c) for c in r] for r in rows[1:]], float)
    except ValueError:
        raise ValueError(f"the measured trace {str(p)!r} holds a value that is not a number.") from None
    if data.ndim != 2 or data.shape[1] != len(header):
        raise ValueError(f"every row of the measured trace {str(p)!r} must have {len(header)} values.")
    if data.shape[0] < 8:
        raise ValueError(f"the measured trace {str(p)!r} has {data.shape[0]} points; a fit needs at least 8.")
    if data.shape[0] > MAX_POINTS:
        raise ValueError(f"the measured trace {str(p)!r} has more than {MAX_POINTS:,} points.")
    if not np.all(np.isfinite(data)):
        raise ValueError(f"the measured trace {str(p)!r} holds NaN or infinite values.")
    w = data[:, 0]
    mag = 10 ** (data[:, 1] / 20) if header[1] == "mag_db" else np.hypot(data[:, 1], data[:, 2])
    return w, mag


@dataclass(frozen=True, eq=False, kw_only=True)
class TransmissionFit(Result):
    r"""A fitted trace: ω₀, J, κ_int with errors, the model over the data, how many parameters the data support.

    Attributes
    ----------
    omega : ndarray
        Frequencies of the trace.
    data : ndarray
        Measured ``|S₂₁|``.
    fit : ndarray
        Fitted ``|S₂₁|``.
    omega0, J, kappa_int : float
        Best-fit parameters (the user's units).
    omega0_err, J_err, kappa_int_err : float
        One-standard-deviation errors from the residual-scaled Jacobian.
    residual_rms : float
        Root-mean-square misfit of ``|S₂₁|``.
    singular_values : ndarray
        Of the column-scaled Jacobian (largest first).
    supported : int
        Number of parameters the trace determines (the numerical rank).
    condition : float
        Condition number of the column-scaled Jacobian.
    ports : tuple of str
        The ports (resonator names).

    Examples
    --------
    >>> import numpy as np
    >>> from hyperlattice.device import fit_transmission
    >>> one = np.zeros((1, 1))
    >>> w = np.linspace(4.0, 6.0, 201)
    >>> s = np.abs(-1j * 0.1 / (w - 5.0 + 0.5j * (0.1 + 0.1 + 0.05)))
    >>> f = fit_transmission(one, w, s, ports=[("0", 0.1), ("0", 0.1)], shared_ports=True)
    >>> round(f.omega0, 6), round(f.kappa_int, 6), f.supported
    (5.0, 0.05, 2)
    """

    COLUMNS: ClassVar[tuple] = (Column("omega", "omega", "user's frequency unit"), Column("data", "data", "1"),
                                Column("fit", "fit", "1"))

    omega: np.ndarray
    data: np.ndarray
    fit: np.ndarray
    omega0: float
    J: float
    kappa_int: float
    omega0_err: float
    J_err: float
    kappa_int_err: float
    residual_rms: float
    singular_values: np.ndarray
    supported: int
    condition: float
    ports: tuple = ()

    def sentence(self) -> str:
        """How many of the three parameters the trace determines, in words."""
        return (f"the trace determines {self.supported} of the 3 parameters (ω₀, J, κ_int): singular values of "
                f"the scaled Jacobian {', '.join(f'{x:.2g}' for x in self.singular_values)}, condition number "
                f"{self.condition:.2g}")


class _Model:
    """``|S21|`` of H = omega0 - J A with ports: eigenvectors of A once, then O(N P) per frequency."""

    def __init__(self, graph, ports, line: bool, shared: bool):
        names, bonds, weights, _, _, line = _layout(graph, line, "a fitted device")
        n = len(names)
        if n > EIGEN_MAX:
            raise ValueError(f"a fit takes devices of at most {EIGEN_MAX:,} resonators (its model is diagonalised "
                             f"once), this one has {n:,}.")
        _validate.require_memory("the fit's eigendecomposition", 4.0 * 8 * n * n)
        a = np.zeros((n, n))
        b = np.asarray(bonds, np.int64).reshape(-1, 2)
        a[b[:, 0], b[:, 1]] = weights
        a[b[:, 1], b[:, 0]] = weights
        self.a_levels, vec = np.linalg.eigh(a)
        pnames, idx, kap = _ports(ports, _name_table(names), names, line, shared)
        if len(pnames) < 2:
            raise ValueError("a transmission fit needs two ports (S21 from the first to the second).")
        self.ports = tuple(pnames)
        self.kap = kap
        w = vec[idx, :]
        self.pairs = (w[:, None, :] * w[None, :, :]).reshape(len(idx) ** 2, n).T
        self.P = len(idx)

    def __call__(self, omega: np.ndarray, params) -> np.ndarray:
        w0, J, ki = params
        lam = w0 - J * self.a_levels
        x = omega[:, None] - lam[None, :]
        eta = 0.5 * max(ki, 0.0)
        den = x * x + eta * eta
        den[den == 0] = 1e-300
        g0 = ((x / den) @ self.pairs - 1j * (eta / den) @ self.pairs).reshape(omega.size, self.P, self.P)
        return np.abs(_woodbury(g0, self.kap)[:, 1, 0])


def _starts(model: _Model, w: np.ndarray, mag: np.ndarray) -> list:
    from scipy.signal import find_peaks, peak_widths

    peaks, _ = find_peaks(mag, prominence=0.05 * float(np.max(mag) - np.min(mag)))
    if peaks.size == 0:
        raise ValueError("the measured trace has no resonance peak to fit (is it flat, or only noise?).")
    top = int(peaks[np.argmax(mag[peaks])])
    width = float(peak_widths(mag, [top], rel_height=0.5)[0][0]) * float(np.median(np.diff(w)))
    ki0 = max(width - float(np.sum(model.kap)) / 2, width / 4, 1e-12 * max(abs(w).max(), 1e-300))
    lo, hi = float(w[peaks.min()]), float(w[peaks.max()])
    a_min, a_max = float(model.a_levels[0]), float(model.a_levels[-1])
    starts = []
    if peaks.size == 1 or a_max - a_min <= 0:
        starts.append([float(w[top]) + 0.0, 0.0, ki0])
        if a_max - a_min > 0:
            starts.append([float(w[top]), (w[-1] - w[0]) / (a_max - a_min) / 4, ki0])
        return starts
    span = (hi - lo) / (a_max - a_min)
    # J < 0: omega0 + |J| a spans [lo, hi]; J > 0: omega0 - J a spans it reversed
    starts.append([lo - span * a_min, -span, ki0])
    starts.append([hi + span * a_min, span, ki0])
    return starts


def fit_transmission(graph, omega, magnitude, *, ports, line_graph: bool = False, shared_ports: bool = False,
                     start=None) -> TransmissionFit:
    r"""Fit ω₀, J, κ_int of an ideal device to a measured ``|S₂₁|`` (least squares, with errors).

    Parameters
    ----------
    graph : Lattice, Cluster or adjacency matrix
        The device's graph (as for :func:`resonator_device`).
    omega : array_like
        Frequencies of the trace.
    magnitude : array_like
        Measured ``|S₂₁|`` (linear), same length.
    ports : dict or list of (name, kappa)
        The two ports (in, out) and their known κ.
    line_graph : bool, optional
        Resonators on the edges of ``graph``; default False.
    shared_ports : bool, optional
        Allow both ports on one resonator; default False.
    start : sequence of 3 floats, optional
        A starting point (ω₀, J, κ_int) instead of the ones read from the peaks.

    Returns
    -------
    TransmissionFit

    Raises
    ------
    ValueError
        A flat trace, NaN, mismatched lengths, too few points, no peak, a device above EIGEN_MAX.

    Examples
    --------
    >>> import numpy as np
    >>> from hyperlattice.device import fit_transmission
    >>> fit_transmission(np.zeros((1, 1)), np.arange(10.0), np.ones(10), ports=[("0", 1.0), ("0", 1.0)],
    ...                  shared_ports=True)
    Traceback (most recent call last):
    ...
    ValueError: the measured trace is flat (no structure to fit).
    """
    from ..graph.solvers import single_threaded_blas

    with single_threaded_blas():
        return _fit(graph, omega, magnitude, ports, line_graph, shared_ports, start)


def _fit(graph, omega, magnitude, ports, line_graph, shared_ports, start) -> TransmissionFit:
    from scipy.optimize import least_squares

    w = _validate.real_array("omega", omega, ndim=1)
    mag = _validate.real_array("magnitude", magnitude, ndim=1)
    if w.size != mag.size:
        raise ValueError(f"omega has {w.size} points but magnitude {mag.size}.")
    if w.size < 8:
        raise ValueError(f"a fit needs at least 8 points, got {w.size}.")
    if not (np.all(np.isfinite(w)) and np.all(np.isfinite(mag))):
        raise ValueError("the measured trace holds NaN or infinite values.")
    if np.any(mag < 0):
        raise ValueError("a magnitude |S21| cannot be negative.")
    if float(np.ptp(mag)) <= 1e-9 * max(float(np.max(mag)), 1e-300):
        raise ValueError("the measured trace is flat (no structure to fit).")
    order = np.argsort(w)
    w, mag = w[order], mag[order]
    model = _Model(graph, ports, _validate.flag("line_graph", line_graph), _validate.flag("shared_ports", shared_ports))
    if start is not None:
        st = _validate.real_array("start", start, shape=(3,))
        if not np.all(np.isfinite(st)) or st[2] < 0:
            raise ValueError("start must be three finite numbers (omega0, J, kappa_int >= 0).")
        starts = [list(st)]
    else:
        starts = _starts(model, w, mag)
    best = None
    scale_w = max(float(np.ptp(w)), 1e-300)
    # the start closest to the data first; the other only when that fit leaves structure unexplained
    starts.sort(key=lambda x0: float(np.sum((model(w, x0) - mag) ** 2)))
    for x0 in starts:
        x0 = np.asarray(x0, float)
        xs = np.array([scale_w, max(abs(x0[1]), scale_w * 1e-3), max(x0[2], scale_w * 1e-6)])
        res = least_squares(lambda p: model(w, p) - mag, x0, bounds=([-np.inf, -np.inf, 0.0], np.inf),
                            x_scale=xs, method="trf", xtol=1e-10, ftol=1e-12, gtol=1e-12, max_nfev=MAX_EVALUATIONS)
        if best is None or res.cost < best.cost:
            best = res
        if math.sqrt(2 * best.cost / w.size) < 0.05 * float(np.ptp(mag)):
            break
    p = best.x
    jac = best.jac
    m, k = jac.shape
    dof = max(m - k, 1)
    s2 = 2.0 * best.cost / dof
    colscale = np.linalg.norm(jac, axis=0)
    colscale[colscale == 0] = 1.0
    sv = np.linalg.svd(jac / colscale, compute_uv=False)
    supported = int(np.sum(sv > RANK_RTOL * sv[0])) if sv[0] > 0 else 0
    cond = float(sv[0] / sv[-1]) if sv[-1] > 0 else math.inf
    try:
        cov = np.linalg.pinv(jac.T @ jac, rcond=RANK_RTOL ** 2) * s2
        err = np.sqrt(np.maximum(np.diag(cov), 0.0))
    except np.linalg.LinAlgError:
        err = np.full(3, np.nan)
    if supported < 3:
        # a direction the data do not fix has no finite error
        vt = np.linalg.svd(jac / colscale)[2]
        loose = np.abs(vt[supported:]).max(axis=0) > 1e-3
        err = np.where(loose, np.inf, err)
    fit = model(w, p)
    return TransmissionFit(omega=w, data=mag, fit=fit, omega0=float(p[0]), J=float(p[1]), kappa_int=float(p[2]),
                           omega0_err=float(err[0]), J_err=float(err[1]), kappa_int_err=float(err[2]),
                           residual_rms=float(np.sqrt(np.mean((fit - mag) ** 2))), singular_values=sv,
                           supported=supported, condition=cond, ports=model.ports)


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
