"""Distil the classical-spin runs into the report's stored file ``src/hyperlattice/report/spins_scan.json``.

Reads ``benchmarks/spins_tc_P_Q.json`` (Binder crossings on closed surfaces, ``spins_tc.py``) and
``benchmarks/spins_flakes.json`` (open flakes and the correlation from the centre,
``spins_flakes.py``) and writes what the report's magnetism section shows: the U4 curves, the
crossings with their bootstrap errors, the cumulant at the last crossing, the slope of log chi
against log N there; per flake the specific heat and the bulk / boundary alignment against T with
the temperature where each alignment crosses 1/2 (linear interpolation, its error from the two
bracketing points' errors over the local slope); the correlation curves with the massive-propagator
fit. The runs take far longer than a report, hence the stored file.

Run: ``python benchmarks/spins_report_data.py``.
"""

from __future__ import annotations

import json
import math
import sys
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
TARGET = HERE.parent / "src" / "hyperlattice" / "report" / "spins_scan.json"


def _half(T, y, err):
    """Where y(T), falling with T, crosses 1/2: (T, error) or (nan, nan)."""
    for k in range(len(T) - 1):
        if y[k] >= 0.5 > y[k + 1]:
            slope = (y[k + 1] - y[k]) / (T[k + 1] - T[k])
            t = T[k] + (0.5 - y[k]) / slope
            return float(t), float(math.hypot(err[k], err[k + 1]) / abs(slope))
    return math.nan, math.nan


def tc_part() -> dict:
    import spins_tc as tc

    rng = np.random.default_rng(7)
    out = {}
    for p, q in tc.PLAN:
        path = Path(str(tc.OUT).format(p=p, q=q))
        if not path.exists():
            continue
        data = json.loads(path.read_text())
        entries = sorted(data.values(), key=lambda v: v["sites"])
        cross = [tc._crossing(a, b, rng) for a, b in zip(entries[:-1], entries[1:])]
        t, te, u, ue = cross[-1]
        Ns = np.array([e["sites"] for e in entries], dtype=float)
        chis = np.array([tc._chi_at(e, t) for e in entries])
        b = float(np.polyfit(np.log(Ns), np.log(chis), 1)[0])
        out[f"{p},{q}"] = {
            "p": p, "q": q, "tc": t, "tc_err": te, "U4": u, "U4_err": ue, "chi_exponent": b,
            "crossings": [{"T": c[0], "err": c[1]} for c in cross],
            "clusters": [{"name": e["name"], "sites": e["sites"], "sweeps": e["sweeps"],
                          "rows": [{k: r[k] for k in ("T", "U4", "U4_err", "chi", "chi_err")}
                                   for r in sorted(e["rows"], key=lambda r: r["T"])]} for e in entries]}
    return out


def flakes_part() -> tuple[dict, dict]:
    import spins_flakes as fl

    data = json.loads(fl.OUT.read_text())
    flakes = {}
    for key, rows in sorted(data["bulk"].items(), key=lambda kv: int(kv[0][1:])):
        rows = sorted(rows, key=lambda r: r["T"])
        T = np.array([r["T"] for r in rows])
        keep = ("T", "c", "c_err", "bulk", "bulk_err", "boundary", "boundary_err")
        tb, tbe = _half(T, [r["bulk"] for r in rows], [r["bulk_err"] for r in rows])
        to, toe = _half(T, [r["boundary"] for r in rows], [r["boundary_err"] for r in rows])
        c = np.array([r["c"] for r in rows])
        flakes[key[1:]] = {"rings": int(key[1:]), "sites": rows[0]["sites"], "rows": [{k: r[k] for k in keep} for r in rows],
                           "T_half_bulk": tb, "T_half_bulk_err": tbe, "T_half_boundary": to,
                           "T_half_boundary_err": toe, "c_max": float(c.max()),
                           "c_max_err": float(rows[int(np.argmax(c))]["c_err"]), "T_c_max": float(T[int(np.argmax(c))])}
    cont = {}
    for Tk, entry in sorted(data["continuum"].items(), key=lambda kv: float(kv[0])):
        f = fl.fit_continuum(entry)
        cont[Tk] = {"T": float(Tk), "d0": entry["d0"], "sites": entry["sites"], "d": entry["d"], "C": entry["C"],
                    "err": entry["err"], "fit_from_d0": fl.FIT_FROM, **f}
    return flakes, cont


def main() -> None:
    flakes, cont = flakes_part()
    out = {"meta": {"note": "Wolff chains of benchmarks/spins_tc.py and benchmarks/spins_flakes.py, distilled by "
                            "benchmarks/spins_report_data.py"},
           "closed": tc_part(), "flakes": flakes, "continuum": cont}
    text = json.dumps(out, indent=None, separators=(",", ":"), allow_nan=True)
    TARGET.write_text(text + "\n")
    print(f"wrote {TARGET} ({len(text) / 1024:.0f} KiB)")
    for k, f in flakes.items():
        print(f"l = {k}: T(bulk = 1/2) = {f['T_half_bulk']:.3f} +- {f['T_half_bulk_err']:.3f}, T(boundary = 1/2) = "
              f"{f['T_half_boundary']:.3f} +- {f['T_half_boundary_err']:.3f}, c max {f['c_max']:.3f} at {f['T_c_max']}")


if __name__ == "__main__":
    main()
