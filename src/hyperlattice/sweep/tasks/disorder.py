"""The ``disorder`` task: one disorder realization of a flake or its line graph."""

from __future__ import annotations

from ... import _validate
from ._common import _check_geometry, _lattice

def _disorder(p: int = 7, q: int = 3, rings: int = 4, line_graph: bool = False, model: str = "box", W: float = 1.0,
              seed: int = 0, realization: int = 0, omega0: float | None = None, ipr: bool = False) -> dict:
    from ...compare.disorder import realization_observables

    lat = _lattice(p, q, rings, line_graph)
    return realization_observables(lat, model, W, seed=seed, realization=realization, omega0=omega0, ipr=ipr)


def _check_disorder(params: dict) -> None:
    from ...compare.disorder import DENSE_MAX
    from ...graph.disorder import MODELS, _realization, _seed, _strength

    _check_geometry(params, DENSE_MAX)
    model = _validate.choice("model", params["model"], MODELS)
    _strength(model, params["W"])
    _seed(params["seed"])
    _realization(params["realization"])
    if params["omega0"] is not None:
        _validate.positive_real("omega0", params["omega0"])
    _validate.flag("ipr", params["ipr"])
