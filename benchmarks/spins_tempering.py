"""Does parallel tempering pay? Replica exchange against independent heat-bath chains at equal cost.

Two frustrated Ising cases on {7,3} graphs (heat-bath is the only update that applies):

* ``glass``: the +-J spin glass (each bond's sign drawn with probability 1/2, seed 11) on the
  Macbeath surface (168 sites, 3-regular; the Bethe-lattice +-J glass transition of a 3-regular
  graph is at tanh(1/T) = 1/sqrt(2), T = 1.13);
* ``afm``: the antiferromagnet on the {7,3} flake l = 3 (odd faces: not bipartite).

At the coldest temperature T_min both methods spend the same sweeps: tempering runs R temperatures
of S sweeps; the reference runs R independent heat-bath chains of S sweeps each at T_min (merged).
Each method is repeated with ``--repeats`` seeds. The *true* error of the energy at T_min is the
root-mean-square deviation from a reference (one tempering run of 10 x the sweeps), which counts
both the seed-to-seed spread and the bias of chains that have not left the valley they started in
(a stuck chain reports a binning error that is too small). Efficiency = 1 / (true error^2 x CPU
seconds), CPU of the process (both methods in one process, interleaved).

Run: ``nice -n 5 python benchmarks/spins_tempering.py [--sweeps 4000] [--repeats 8]``.
"""

from __future__ import annotations

import argparse
import json
import time
import warnings
from pathlib import Path

import numpy as np
import scipy.sparse as sp

import hyperlattice as hl
from hyperlattice.graph.clusters import pbc_cluster
from hyperlattice.spins import classical_mc, merge_classical, tempering_mc
from hyperlattice.spins.classical import SpinWarning


def _glass():
    cl = pbc_cluster(7, 3, "macbeath")
    a = sp.triu(sp.csr_matrix(cl.adjacency(), dtype=float), k=1).tocoo()
    sign = np.random.default_rng(11).choice([-1.0, 1.0], size=a.nnz)
    up = sp.coo_matrix((sign, (a.row, a.col)), shape=a.shape)
    return (up + up.T).tocsr(), 1.0, np.geomspace(0.5, 1.8, 10)


def _afm():
    return hl.ring_lattice(7, 3, 3), -1.0, np.geomspace(0.3, 2.1, 12)


CASES = {"glass": _glass, "afm": _afm}


def measure(case: str, sweeps: int, repeats: int) -> dict:
    system, J, temps = CASES[case]()
    R = temps.size
    out = {"case": case, "temperatures": temps.tolist(), "sweeps": sweeps, "repeats": repeats}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", SpinWarning)
        ref = tempering_mc(system, model="ising", J=J, T=temps, sweeps=10 * sweeps, seed=7, progress=False,
                           measure_correlation=False).chains[-1]
    out["reference"] = {"e": ref.e, "e_err": ref.e_err}
    pt_e, pt_err, pt_cpu, pt_tau, acc, trips = [], [], [], [], [], []
    ind_e, ind_err, ind_cpu, ind_tau = [], [], [], []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", SpinWarning)
        for k in range(repeats):
            t0 = time.process_time()
            r = tempering_mc(system, model="ising", J=J, T=temps, sweeps=sweeps, seed=100 + k, progress=False,
                             measure_correlation=False)
            pt_cpu.append(time.process_time() - t0)
            cold = r.chains[-1]
            pt_e.append(cold.e)
            pt_err.append(cold.e_err)
            pt_tau.append(cold.tau_int["e"])
            acc.append(r.acceptance)
            trips.append(r.round_trips)
            t0 = time.process_time()
            runs = [classical_mc(system, model="ising", J=J, T=float(temps[0]), sweeps=sweeps, seed=1000 * (k + 1) + j,
                                 progress=False, measure_correlation=False) for j in range(R)]
            ind_cpu.append(time.process_time() - t0)
            m = merge_classical(runs)
            ind_e.append(m.e)
            ind_err.append(m.e_err)
            ind_tau.append(float(np.mean([x.tau_int["e"] for x in runs])))
    for name, e, err, cpu, tau in (("tempering", pt_e, pt_err, pt_cpu, pt_tau),
                                   ("independent", ind_e, ind_err, ind_cpu, ind_tau)):
        true = float(np.sqrt(np.mean((np.asarray(e) - ref.e) ** 2)))
        out[name] = {"e_mean": float(np.mean(e)), "spread_e": float(np.std(e, ddof=1)), "true_sigma_e": true,
                     "claimed_sigma_e": float(np.mean(err)),
                     "tau_e": float(np.mean(tau)), "cpu": float(np.mean(cpu)),
                     "efficiency": float(1.0 / (true ** 2 * np.mean(cpu)))}
    out["tempering"]["acceptance"] = np.mean(acc, axis=0).tolist()
    out["tempering"]["round_trips"] = float(np.mean(trips))
    out["ratio"] = out["tempering"]["efficiency"] / out["independent"]["efficiency"]
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sweeps", type=int, default=4000)
    ap.add_argument("--repeats", type=int, default=8)
    ap.add_argument("--cases", default="glass,afm")
    ap.add_argument("--out", default=str(Path(__file__).with_name("spins_tempering.json")))
    args = ap.parse_args()
    res = {}
    for case in args.cases.split(","):
        r = measure(case, args.sweeps, args.repeats)
        res[case] = r
        for name in ("tempering", "independent"):
            d = r[name]
            print(f"{case:6s} {name:12s} e(T_min) = {d['e_mean']:.5f} (reference {r['reference']['e']:.5f})  "
                  f"spread {d['spread_e']:.2e}  rms error {d['true_sigma_e']:.2e}  "
                  f"claimed {d['claimed_sigma_e']:.2e}  tau_e {d['tau_e']:.1f}  cpu {d['cpu']:.2f} s  "
                  f"efficiency {d['efficiency']:.3g}")
        print(f"{case:6s} acceptance {np.round(r['tempering']['acceptance'], 3).tolist()}  round trips "
              f"{r['tempering']['round_trips']:.0f}  efficiency ratio tempering/independent = {r['ratio']:.2f}")
    Path(args.out).write_text(json.dumps(res, indent=1))


if __name__ == "__main__":
    main()
