r"""Electric circuits on the graphs of the package: node impedances of LC(R) networks.

One element spec on every edge and one to ground (``"C:1"``, ``"L:1,R:100"``: elements given together
are in parallel, their admittances add: capacitor :math:`i\omega C`, inductor :math:`1/(i\omega L)`,
resistor :math:`1/R`; the user's units, e.g. nF, µH, Ω and rad/µs), so that

.. math::

    Y(\omega) = y_e(\omega) \sum_{\langle ij\rangle} w_{ij} (e_i - e_j)(e_i - e_j)^T + y_g(\omega)\,1
             = y_e(\omega)\,\mathcal{L} + y_g(\omega)\,1,

with :math:`\mathcal{L}` the graph Laplacian (weights :math:`w_{ij}` = adjacency entries). The two-point
impedance is :math:`Z_{ab} = (e_a - e_b)^T Y^{-1} (e_a - e_b)`, the impedance to ground
:math:`Z_a = [Y^{-1}]_{aa}`. With :math:`\mathcal{L} = \sum_k \mu_k v_k v_k^T`,
:math:`Y^{-1} = \sum_k v_k v_k^T / (y_e \mu_k + y_g)`: resonances where :math:`y_e\mu_k + y_g = 0`,
for the lossless parts :math:`\omega_k^2 = (\mu_k/L_e + 1/L_g)/(\mu_k C_e + C_g)` (Lenggenhager et al.,
Nat. Commun. 13, 4373 (2022), Eq. 2: the circuit Laplacian's spectrum is the graph's). Devices up to
:data:`EIGEN_MAX` nodes use that eigendecomposition; larger ones one sparse LU of
:math:`\mathcal{L} + y_g/y_e` per frequency through the factor layer.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np
import scipy.sparse as sp

from .. import _validate
from ..results import Column, Result
from .resonators import _layout, _name_table, _resonator
from .transmission import EIGEN_MAX, _omegas

__all__ = ["element_admittance", "parse_elements", "Impedance", "NodeVoltages", "impedance", "node_voltages",
           "circuit_resonances"]

_KINDS = {"C": "capacitor", "L": "inductor", "R": "resistor"}


def parse_elements(spec) -> dict:
    """Elements in parallel from ``"C:1"``, ``"L:1,R:100"`` or a dict ``{"L": 1.0, "R": 100.0}``.

    Parameters
    ----------
    spec : str or dict
        Element letters C, L, R with positive finite values (each letter at most once).

    Returns
    -------
    dict
        Letter → value.

    Examples
    --------
    >>> from hyperlattice.device import parse_elements
    >>> parse_elements("L:1,R:100")
    {'L': 1.0, 'R': 100.0}
    >>> parse_elements("C:-1")
    Traceback (most recent call last):
    ...
    ValueError: the capacitor value C must be positive and finite, got -1.
    """
    if isinstance(spec, dict):
        items = list(spec.items())
    elif isinstance(spec, str):
        items = []
        for part in spec.split(","):
            letter, sep, value = part.strip().partition(":")
            if not sep:
                raise ValueError(f"an element is LETTER:VALUE such as C:1 or L:1,R:100, got {part.strip()!r}.")
            try:
                items.append((letter.strip().upper(), float(value)))
            except ValueError:
                raise ValueError(f"the value of element {part.strip()!r} is not a number.") from None
    else:
        raise ValueError(f"an element spec is a string like 'C:1' or 'L:1,R:100', got {_validate._shown(spec)}.")
    out: dict = {}
    for letter, value in items:
        if letter not in _KINDS:
            raise ValueError(f"unknown element {letter!r}; use C (capacitor), L (inductor) or R (resistor).")
        if letter in out:
            raise ValueError(f"element {letter} is given twice; give one value per kind (parallel ones add).")
        if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, float, np.integer, np.floating)):
            raise ValueError(f"the {_KINDS[letter]} value {letter} must be a number, got {_validate._shown(value)}.")
        v = float(value)
        if not (math.isfinite(v) and v > 0):
            raise ValueError(f"the {_KINDS[letter]} value {letter} must be positive and finite, got {value:g}.")
        out[letter] = v
    if not out:
        raise ValueError("an element spec needs at least one element.")
    return out


def element_admittance(elements: dict, omegas) -> np.ndarray:
    r"""Admittance of elements in parallel: :math:`i\omega C + 1/(i\omega L) + 1/R` at each frequency.

    Parameters
    ----------
    elements : dict
        From :func:`parse_elements`.
    omegas : array_like
        Angular frequencies (an inductor needs ω ≠ 0).

    Returns
    -------
    ndarray of complex

    Examples
    --------
    >>> from hyperlattice.device import element_admittance
    >>> complex(element_admittance({"C": 2.0, "R": 4.0}, [3.0])[0])
    (0.25+6j)
    """
    el = parse_elements(elements)
    w = _omegas(omegas)
    y = np.zeros(w.size, np.complex128)
    if "C" in el:
        y += 1j * w * el["C"]
    if "L" in el:
        if np.any(w == 0):
            raise ValueError("an inductor has no admittance at ω = 0 (a short circuit); leave 0 out of the frequencies.")
        y += 1.0 / (1j * w * el["L"])
    if "R" in el:
        y += 1.0 / el["R"]
    return y


@dataclass(frozen=True, eq=False, kw_only=True)
class Impedance(Result):
    r"""A node impedance Z(ω) of a circuit.

    Attributes
    ----------
    omega : ndarray
        Angular frequencies (the user's units).
    z : ndarray
        Z(ω), complex (the user's units of impedance).
    kind : str
        ``"two-point"`` (:math:`Z_{ab}`) or ``"to ground"`` (:math:`Z_a`).
    nodes : tuple of str
        (a, b) or (a,).
    resonances : ndarray
        Resonance frequencies of the lossless LC parts (from the Laplacian's spectrum), ascending;
        empty above :data:`~hyperlattice.device.transmission.EIGEN_MAX` nodes (see :func:`circuit_resonances`).
    method : str
        ``"eigen"`` or ``"direct"``.
    description : str
        The circuit.

    Examples
    --------
    >>> import numpy as np
    >>> from hyperlattice.device import impedance
    >>> one = np.zeros((1, 1))
    >>> z = impedance(one, [2.0], edge="C:1", ground="R:50", to_ground="0").z[0]
    >>> complex(z)
    (50+0j)
    """

    COLUMNS: ClassVar[tuple] = (Column("omega", "omega", "user's angular frequency unit"),
                                Column("z_re", "z_re", "user's impedance unit"),
                                Column("z_im", "z_im", "user's impedance unit"),
                                Column("z_abs", "z_abs", "user's impedance unit"))

    omega: np.ndarray
    z: np.ndarray
    kind: str
    nodes: tuple
    resonances: np.ndarray
    method: str = "eigen"
    description: str = ""

    @property
    def z_re(self) -> np.ndarray:
        """Re Z."""
        return np.asarray(self.z).real

    @property
    def z_im(self) -> np.ndarray:
        """Im Z."""
        return np.asarray(self.z).imag

    @property
    def z_abs(self) -> np.ndarray:
        """``|Z|``."""
        return np.abs(np.asarray(self.z))


@dataclass(frozen=True, eq=False, kw_only=True)
class NodeVoltages(Result):
    r"""Node voltages of a circuit driven by a unit current at one node (returning through ground or a sink).

    Attributes
    ----------
    omega : float
        The drive frequency.
    names : tuple of str
        Node names.
    v : ndarray
        Complex voltages :math:`V = Y^{-1}(e_a - e_b)` (per unit current).
    drive : str
        Node a.
    sink : str or None
        Node b (None: the current returns through ground).

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.device import node_voltages
    >>> nv = node_voltages(hl.ring_lattice(7, 3, 1), 1.0, edge="C:1", ground="R:1", drive="0")
    >>> len(nv.names), round(float(abs(nv.v).max()), 6)
    (7, 0.492548)
    """

    COLUMNS: ClassVar[tuple] = (Column("node", "names", "1"), Column("v_re", "v_re", "user's impedance unit × current"),
                                Column("v_im", "v_im", "user's impedance unit × current"),
                                Column("v_abs", "v_abs", "user's impedance unit × current"))

    omega: float
    names: tuple
    v: np.ndarray
    drive: str
    sink: str | None = None

    def __post_init__(self) -> None:
        super().__post_init__()
        if np.ndim(self.v) != 1 or len(self.names) != np.size(self.v):
            raise ValueError(f"NodeVoltages holds one voltage per node name, got {len(self.names)} names and "
                             f"{np.size(self.v)} voltages.")

    @property
    def v_re(self) -> np.ndarray:
        """Re V."""
        return np.asarray(self.v).real

    @property
    def v_im(self) -> np.ndarray:
        """Im V."""
        return np.asarray(self.v).imag

    @property
    def v_abs(self) -> np.ndarray:
        """``|V|``."""
        return np.abs(np.asarray(self.v))


def _laplacian(graph, line: bool):
    names, bonds, weights, _, desc, line = _layout(graph, line, "a circuit")
    n = len(names)
    b = np.asarray(bonds, np.int64).reshape(-1, 2)
    a = sp.coo_matrix((np.concatenate([weights, weights]), (np.concatenate([b[:, 0], b[:, 1]]),
                                                            np.concatenate([b[:, 1], b[:, 0]]))), shape=(n, n)).tocsr()
    lap = (sp.diags(np.asarray(a.sum(axis=1)).ravel()) - a).tocsr()
    return names, lap, desc, line


def _resonances(mu: np.ndarray, edge: dict, ground: dict) -> np.ndarray:
    ce, cg = edge.get("C", 0.0), ground.get("C", 0.0)
    ie = 1.0 / edge["L"] if "L" in edge else 0.0
    ig = 1.0 / ground["L"] if "L" in ground else 0.0
    num = mu * ie + ig
    den = mu * ce + cg
    with np.errstate(divide="ignore", invalid="ignore"):
        w2 = num / den
    ok = (den > 0) & (num > 0) & np.isfinite(w2)
    return np.sort(np.sqrt(w2[ok]))


def _prepare(graph, edge, ground, line_graph):
    line = _validate.flag("line_graph", line_graph)
    e = parse_elements(edge)
    g = parse_elements(ground)
    names, lap, desc, line = _laplacian(graph, line)
    return names, lap, desc, line, e, g


def impedance(graph, omegas, *, edge, ground, between=None, to_ground=None, line_graph: bool = False) -> Impedance:
    r"""Two-point impedance :math:`Z_{ab}` or impedance to ground :math:`Z_a` of a circuit, per frequency.

    Parameters
    ----------
    graph : Lattice, Cluster or adjacency matrix
        The circuit's nodes (sites) and edges.
    omegas : array_like
        Angular frequencies.
    edge, ground : str or dict
        Element specs on every edge and from every node to ground (:func:`parse_elements`).
    between : pair of node names, optional
        (a, b) for :math:`Z_{ab}`.
    to_ground : node name, optional
        a for :math:`Z_a` (exactly one of ``between`` / ``to_ground``).
    line_graph : bool, optional
        Nodes on the edges of ``graph`` (named ``"i-j"``); default False.

    Returns
    -------
    Impedance

    Raises
    ------
    ValueError
        Bad element specs (NaN, ≤ 0, unknown letters), unknown nodes, a frequency where Y is singular.

    Examples
    --------
    >>> import numpy as np
    >>> from hyperlattice.device import impedance
    >>> dimer = np.array([[0.0, 1.0], [1.0, 0.0]])
    >>> z = impedance(dimer, [1.0], edge="R:2", ground="R:1", between=("0", "1")).z[0]   # 2 || (1 + 1)
    >>> round(float(z.real), 12)
    1.0
    """
    names, lap, desc, line, e, g = _prepare(graph, edge, ground, line_graph)
    w = _omegas(omegas)
    table = _name_table(names)
    if (between is None) == (to_ground is None):
        raise ValueError("give exactly one of between=(a, b) and to_ground=a.")
    if between is not None:
        if not isinstance(between, (list, tuple)) or len(between) != 2:
            raise ValueError(f"between must be a pair of node names, got {_validate._shown(between)}.")
        ia = _resonator(table, between[0], "the node", line)
        ib = _resonator(table, between[1], "the node", line)
        if ia == ib:
            raise ValueError("the two nodes of a two-point impedance must differ.")
        vec = np.zeros(len(names))
        vec[ia], vec[ib] = 1.0, -1.0
        kind, nodes = "two-point", (names[ia], names[ib])
    else:
        ia = _resonator(table, to_ground, "the node", line)
        vec = np.zeros(len(names))
        vec[ia] = 1.0
        kind, nodes = "to ground", (names[ia],)
    ye = element_admittance(e, w)
    yg = element_admittance(g, w)
    n = len(names)
    if n <= EIGEN_MAX:
        _validate.require_memory(f"the eigendecomposition of a {n:,}-node Laplacian", 4.0 * 8 * n * n)
        mu, v = np.linalg.eigh(lap.toarray())
        proj = (v.T @ vec) ** 2
        den = ye[:, None] * mu[None, :] + yg[:, None]
        scale = np.abs(ye[:, None]) * max(float(np.max(np.abs(mu))), 1.0) + np.abs(yg[:, None])
        if np.any(np.abs(den) <= 1e-14 * scale):
            f = int(np.argmax(np.any(np.abs(den) <= 1e-14 * scale, axis=1)))
            raise ValueError(f"ω = {w[f]:g} is a resonance of the lossless circuit (Y is singular there); move the "
                             "frequency or add a resistor.")
        z = (proj[None, :] / den).sum(axis=1)
        method = "eigen"
    else:
        from ..graph.factor import FactorizationError, analyze

        mu = None
        an = analyze(lap.tocsc(), backend="superlu", what="the circuit Laplacian")
        z = np.empty(w.size, np.complex128)
        for f in range(w.size):
            # Y = y_e (L - sigma), sigma = -y_g / y_e
            try:
                x = an.factor(complex(-yg[f] / ye[f]), pivoting=True).solve(vec.astype(np.complex128))
            except FactorizationError:
                raise ValueError(f"ω = {w[f]:g} is a resonance of the lossless circuit (Y is singular there); move "
                                 "the frequency or add a resistor.") from None
            z[f] = vec @ x / ye[f]
        method = "direct"
    # above EIGEN_MAX nodes the spectrum is not computed: no resonances are listed (circuit_resonances
    # gives them up to 4 EIGEN_MAX nodes)
    res = _resonances(mu, e, g) if mu is not None else np.zeros(0)
    return Impedance(omega=w, z=z, kind=kind, nodes=nodes, resonances=res,
                     method=method, description=desc + (" (line graph)" if line else ""))


def circuit_resonances(graph, *, edge, ground, line_graph: bool = False) -> np.ndarray:
    r"""Resonance frequencies of the lossless LC parts: :math:`\omega_k^2 = (\mu_k/L_e + 1/L_g)/(\mu_k C_e + C_g)`.

    Parameters
    ----------
    graph : Lattice, Cluster or adjacency matrix
        The circuit.
    edge, ground : str or dict
        Element specs (:func:`parse_elements`); resistors are left out.
    line_graph : bool, optional
        Nodes on the edges of ``graph``; default False.

    Returns
    -------
    ndarray
        One frequency per Laplacian eigenvalue μ_k that has one (ascending, repeated for degenerate μ).

    Examples
    --------
    >>> import numpy as np
    >>> from hyperlattice.device import circuit_resonances
    >>> dimer = np.array([[0.0, 1.0], [1.0, 0.0]])       # Laplacian eigenvalues 0, 2
    >>> [round(float(x), 6) for x in circuit_resonances(dimer, edge="C:1", ground="L:1,C:1")]
    [0.57735, 1.0]
    """
    names, lap, desc, line, e, g = _prepare(graph, edge, ground, line_graph)
    n = len(names)
    _validate.require_memory(f"the eigenvalues of a {n:,}-node Laplacian", 3.0 * 8 * n * n)
    if n > 4 * EIGEN_MAX:
        raise ValueError(f"all resonances of a {n:,}-node circuit need a dense eigensolver; at most "
                         f"{4 * EIGEN_MAX:,} nodes.")
    return _resonances(np.linalg.eigvalsh(lap.toarray()), e, g)


def node_voltages(graph, omega: float, *, edge, ground, drive, sink=None, line_graph: bool = False) -> NodeVoltages:
    r"""Voltages of every node for a unit current into ``drive`` (out of ``sink``, or to ground): :math:`Y^{-1}(e_a - e_b)`.

    Parameters
    ----------
    graph : Lattice, Cluster or adjacency matrix
        The circuit.
    omega : float
        Drive frequency.
    edge, ground : str or dict
        Element specs (:func:`parse_elements`).
    drive : str
        Node a.
    sink : str, optional
        Node b (default: ground).
    line_graph : bool, optional
        Nodes on the edges of ``graph``; default False.

    Returns
    -------
    NodeVoltages

    Examples
    --------
    >>> import numpy as np
    >>> from hyperlattice.device import node_voltages
    >>> dimer = np.array([[0.0, 1.0], [1.0, 0.0]])
    >>> nv = node_voltages(dimer, 1.0, edge="R:1", ground="R:1", drive="0")
    >>> [round(float(x), 6) for x in nv.v.real]
    [0.666667, 0.333333]
    """
    names, lap, desc, line, e, g = _prepare(graph, edge, ground, line_graph)
    w = _omegas([omega])
    table = _name_table(names)
    vec = np.zeros(len(names), np.complex128)
    ia = _resonator(table, drive, "the drive node", line)
    vec[ia] = 1.0
    sink_name = None
    if sink is not None:
        ib = _resonator(table, sink, "the sink node", line)
        if ib == ia:
            raise ValueError("the sink must differ from the drive node.")
        vec[ib] = -1.0
        sink_name = names[ib]
    ye = element_admittance(e, w)[0]
    yg = element_admittance(g, w)[0]
    from ..graph.factor import FactorizationError, analyze

    an = analyze(lap.tocsc(), backend="superlu", what="the circuit Laplacian")
    try:
        v = an.factor(complex(-yg / ye), pivoting=True).solve(vec) / ye
    except FactorizationError:
        raise ValueError(f"ω = {w[0]:g} is a resonance of the lossless circuit (Y is singular there); move the "
                         "frequency or add a resistor.") from None
    return NodeVoltages(omega=float(w[0]), names=tuple(names), v=v, drive=names[ia], sink=sink_name)


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
