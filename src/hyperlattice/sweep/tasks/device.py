"""The ``device`` task: one fabricated resonator device with drawn disorder and its transmission."""

from __future__ import annotations

import numpy as np

from ... import _validate
from ._common import _check_geometry, _lattice

#: largest device of the ``device`` task (its levels come from a dense eigensolver)
DEVICE_MAX = 5000


def _device_ports(text) -> dict:
    if not isinstance(text, str) or not text.strip():
        raise ValueError(f"ports must be a string 'RES:KAPPA,RES:KAPPA', got {_validate._shown(text)}.")
    import re

    out = {}
    # "0-1:0.1,30-31:0.1", or without the characters the sweep command's --grid reserves: "0-1@0.1+30-31@0.1"
    for item in re.split(r"[,+;]", text):
        name, sep, kappa = item.strip().replace("@", ":").rpartition(":")
        if not sep or not name:
            raise ValueError(f"each port is RES:KAPPA, got {item.strip()!r}.")
        try:
            out[name] = float(kappa)
        except ValueError:
            raise ValueError(f"the kappa of port {item.strip()!r} is not a number.") from None
    return out


def _device_of(params: dict):
    from ...device import resonator_device

    lat = _lattice(params["p"], params["q"], params["rings"], False)
    return resonator_device(lat, line_graph=params["line_graph"], omega0=params["omega0"], J=params["J"],
                            kappa_int=params["kappa_int"], ports=_device_ports(params["ports"]),
                            sigma_omega=params["sigma_omega"], sigma_J=params["sigma_J"], seed=params["seed"])


def _device(p: int = 7, q: int = 3, rings: int = 3, line_graph: bool = True, omega0: float = 0.0, J: float = 1.0,
            kappa_int: float = 0.05, ports: str = "0-1:0.1,110-111:0.1", sigma_omega: float = 0.0,
            sigma_J: float = 0.0, seed: int = 0, omega_min: float = -4.5, omega_max: float = 2.5,
            points: int = 701) -> dict:
    from ...device import transmission

    params = dict(p=p, q=q, rings=rings, line_graph=line_graph, omega0=omega0, J=J, kappa_int=kappa_int,
                  ports=ports, sigma_omega=sigma_omega, sigma_J=sigma_J, seed=seed)
    dev = _device_of(params)
    tr = transmission(dev, np.linspace(omega_min, omega_max, points))
    levels = tr.levels if tr.levels is not None and len(tr.levels) else np.linalg.eigvalsh(dev.hamiltonian().toarray())
    return {"omega": np.asarray(tr.omega, float), "s21_abs2": np.asarray(tr.power, float),
            "levels": np.asarray(levels, float), "method": tr.method}


def _check_device(params: dict) -> None:
    _check_geometry(params, DEVICE_MAX)
    for name in ("omega_min", "omega_max"):
        _validate.real(name, params[name])
    if not params["omega_max"] > params["omega_min"]:
        raise ValueError(f"omega_max {params['omega_max']!r} must exceed omega_min {params['omega_min']!r}.")
    _validate.positive_int("points", params["points"], maximum=1_000_000)
    _device_of(params)          # refuses bad ports, rates and seeds in one sentence
