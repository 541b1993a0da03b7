"""The ``probe`` task: ``x -> x**2`` after a sleep, for the engine's own overhead and fault handling."""

from __future__ import annotations

import time

from ... import _validate

def _probe(x: float = 0.0, sleep: float = 0.0) -> dict:
    if sleep:
        time.sleep(sleep)
    return {"y": x * x}


def _check_probe(params: dict) -> None:
    _validate.real("x", params["x"])
    _validate.real("sleep", params["sleep"], minimum=0.0, maximum=3600.0)
