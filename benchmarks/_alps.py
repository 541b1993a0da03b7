"""ALPS as the QMC peer: its ``dirloop_sse`` and ``worm`` applications on any graph of the package.

ALPS is never a dependency of hyperlattice. It lives in its own virtualenv (the ``pyalps`` wheel
pins its own numpy and bundles its libraries): ``.venv-alps`` at the repository's root, created
on first use (``python3.11 -m venv .venv-alps && .venv-alps/bin/pip install pyalps==3.0.0``), or
the interpreter named by the environment variable ``HYPERLATTICE_ALPS_PYTHON``.

The driver side (:func:`run_alps`, run with the package's own Python) writes the graph as an ALPS
lattice-library file and a job description, then runs this same file as a script under the ALPS
interpreter (the worker side, which imports only numpy and pyalps): the worker writes the ALPS
input files, runs the application, measures its CPU time (``RUSAGE_CHILDREN``: the application's
own seconds, thermalisation included) and prints the observables as JSON.

The graph. ALPS's plain ``<GRAPH>`` element works for ``dirloop_sse`` but not for ``worm`` (which
measures winding numbers and needs a lattice dimension: a ``<GRAPH>`` stops with "Cannot save a
measurement of size 0", and one with a dimension crashes), so the graph is written as one unit
cell holding every site and every bond (offsets 0) of a one-cell open chain: the same graph, with
a dimension. Bond weights w (an adjacency with entries other than 1, e.g. a double edge of a small
cluster) become bond types with hopping ``t{k} = t * w``.

Conventions, checked against exact thermal averages (``benchmarks/bench_qmc.py --validate``):
ALPS's "boson Hubbard" model is H = -t sum_<ij> (b_i^+ b_j + h.c.) + U/2 sum n_i (n_i - 1)
- mu sum n_i with at most ``Nmax`` bosons per site, the package's Hamiltonian; its ``Energy`` is
the total <H> (the -mu N term included), ``Density`` is <N>/sites and ``Density^2`` is
<N^2>/sites. The compressibility kappa = beta (<N^2> - <N>^2) / sites = beta (Density^2 -
sites Density^2) is not an ALPS observable: it is computed here with a jackknife over ALPS's
stored bins of ``Density`` and ``Density^2`` (the same measurements, bin by bin).
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
VENV = ROOT / ".venv-alps"
PYALPS = "pyalps==3.0.0"
APPS = ("dirloop_sse", "worm")


# ----------------------------------------------------------------------------------------------
# driver side (the package's Python)
# ----------------------------------------------------------------------------------------------

def alps_python(*, create: bool = True) -> Path:
    """The interpreter of the ALPS virtualenv, created (with pyalps installed) when missing."""
    env = os.environ.get("HYPERLATTICE_ALPS_PYTHON")
    if env:
        return Path(env)
    py = VENV / "bin" / "python"
    if not py.exists():
        if not create:
            raise RuntimeError(f"no ALPS environment at {VENV} (run benchmarks/bench_qmc.py once to create it).")
        base = os.environ.get("HYPERLATTICE_ALPS_BASE", "python3.11")
        sys.stderr.write(f"creating {VENV} with {base} and installing {PYALPS} (once)...\n")
        subprocess.run([base, "-m", "venv", str(VENV)], check=True)
        subprocess.run([str(py), "-m", "pip", "install", "-q", PYALPS], check=True)
    return py


def adjacency_of(system):
    """The symmetric adjacency (scipy CSR, weights) of a flake, a periodic cluster or a matrix."""
    import scipy.sparse as sp

    if sp.issparse(system):
        a = sp.csr_matrix(system, dtype=float)
    elif hasattr(system, "faces") and hasattr(system, "adjacency"):   # a periodic cluster
        a = system.adjacency
        a = sp.csr_matrix(a() if callable(a) else a, dtype=float)
    else:
        from hyperlattice.graph.operators import adjacency

        a = sp.csr_matrix(adjacency(system), dtype=float)
    a.sum_duplicates()
    a.eliminate_zeros()
    if abs(a - a.T).max() > 0 if a.nnz else False:
        raise ValueError("the adjacency must be symmetric.")
    return a


def lattice_xml(adjacency, name: str = "graph") -> tuple[str, dict]:
    """The ALPS lattice library text of ``adjacency`` and the bond-type weights {type: w}.

    One unit cell holds every site and bond (see the module docstring); bonds of equal weight
    share a type, numbered from 0 in order of first appearance.
    """
    import scipy.sparse as sp

    a = sp.triu(adjacency, k=1).tocoo()
    if sp.tril(adjacency, k=0).diagonal().any():
        raise ValueError("the adjacency has diagonal entries (on-site terms): not a hopping graph.")
    types: dict[float, int] = {}
    lines = ['<LATTICES>',
             '<LATTICE name="one cell" dimension="1"><BASIS><VECTOR>1</VECTOR></BASIS></LATTICE>',
             f'<UNITCELL name="{name} cell" dimension="1">']
    lines += ["  <VERTEX/>"] * adjacency.shape[0]
    for i, j, w in sorted(zip(a.row.tolist(), a.col.tolist(), a.data.tolist())):
        k = types.setdefault(float(w), len(types))
        lines.append(f'  <EDGE type="{k}"><SOURCE vertex="{i + 1}" offset="0"/>'
                     f'<TARGET vertex="{j + 1}" offset="0"/></EDGE>')
    lines += ['</UNITCELL>',
              f'<LATTICEGRAPH name="{name}"><FINITELATTICE><LATTICE ref="one cell"/>'
              '<EXTENT dimension="1" size="1"/><BOUNDARY type="open"/></FINITELATTICE>'
              f'<UNITCELL ref="{name} cell"/></LATTICEGRAPH>',
              '</LATTICES>', '']
    return "\n".join(lines), {k: w for w, k in types.items()}


def run_alps(app: str, system, *, U: float, mu: float, beta: float, nmax: int, t: float = 1.0,
             sweeps: int, thermalization: int, seed: int, workdir, timeout: float | None = None) -> dict:
    """Run ALPS ``app`` ("dirloop_sse" or "worm") on ``system``; the observables as a dict.

    Keys: ``energy``, ``energy_err`` (total <H>, ALPS's binning error), ``density``,
    ``density_err`` (per site), ``compressibility``, ``compressibility_err`` (per site, jackknife
    over ALPS's bins), ``cpu_seconds`` (the application's user + system time), ``measurements``,
    ``bins``, ``converged`` (ALPS's error_convergence flag of the energy is 0), ``sites``.
    """
    if app not in APPS:
        raise ValueError(f"app must be one of {APPS}, got {app!r}.")
    adj = adjacency_of(system)
    text, weights = lattice_xml(adj)
    work = Path(workdir)
    work.mkdir(parents=True, exist_ok=True)
    (work / "lattice.xml").write_text(text)
    parms = {"LATTICE_LIBRARY": "lattice.xml", "LATTICE": "graph", "MODEL": "boson Hubbard",
             "U": float(U), "mu": float(mu), "Nmax": int(nmax), "T": 1.0 / float(beta),
             "THERMALIZATION": int(thermalization), "SWEEPS": int(sweeps), "SEED": int(seed)}
    for k, w in weights.items():
        parms[f"t{k}"] = float(t) * float(w)
    parms["t"] = float(t) * float(weights.get(0, 1.0))
    spec = {"app": app, "parms": parms, "sites": int(adj.shape[0]), "beta": float(beta)}
    (work / "job.json").write_text(json.dumps(spec))
    proc = subprocess.run([str(alps_python()), str(Path(__file__).resolve()), "--worker", str(work / "job.json")],
                          cwd=work, capture_output=True, text=True, timeout=timeout)
    (work / "alps.log").write_text(proc.stdout + proc.stderr)
    if proc.returncode != 0:
        tail = " | ".join((proc.stdout + proc.stderr).strip().splitlines()[-5:])
        raise RuntimeError(f"ALPS {app} failed (exit {proc.returncode}): {tail}")
    last = [ln for ln in proc.stdout.splitlines() if ln.startswith("{")][-1]
    return json.loads(last)


#: the classical peer: ALPS's spinmc (MODEL "Ising", "XY" or "Heisenberg"; UPDATE "cluster" is Wolff's)
SPIN_APPS = ("spinmc",)


def run_spinmc(system, *, model: str = "Ising", J: float = 1.0, beta: float, sweeps: int, thermalization: int,
               seed: int, update: str = "cluster", workdir, timeout: float | None = None) -> dict:
    """Run ALPS ``spinmc`` (classical spins) on ``system``; the observables as a dict.

    Keys: ``energy`` (ALPS's "Energy Density", <H>/N), ``energy_err``, ``m2`` ("Magnetization^2",
    <m^2> per site), ``m2_err``, ``chi`` ("Susceptibility", beta N <m^2>), ``chi_err``,
    ``cpu_seconds`` (the application's user + system time, thermalisation included),
    ``converged`` (ALPS's error_convergence flag of the energy is 0), ``sites``. The couplings are
    ``J`` times the adjacency's weights (bond types ``J0``, ``J1``, ...); ``J`` > 0 is the
    ferromagnet in the package's sign convention (checked against exact enumeration by
    ``benchmarks/bench_spins.py --validate``).
    """
    adj = adjacency_of(system)
    text, weights = lattice_xml(adj)
    work = Path(workdir)
    work.mkdir(parents=True, exist_ok=True)
    (work / "lattice.xml").write_text(text)
    parms = {"LATTICE_LIBRARY": "lattice.xml", "LATTICE": "graph", "MODEL": str(model), "UPDATE": str(update),
             "T": 1.0 / float(beta), "THERMALIZATION": int(thermalization), "SWEEPS": int(sweeps), "SEED": int(seed)}
    for k, w in weights.items():
        parms[f"J{k}"] = float(J) * float(w)
    parms["J"] = float(J) * float(weights.get(0, 1.0))
    spec = {"app": "spinmc", "parms": parms, "sites": int(adj.shape[0]), "beta": float(beta)}
    (work / "job.json").write_text(json.dumps(spec))
    proc = subprocess.run([str(alps_python()), str(Path(__file__).resolve()), "--worker", str(work / "job.json")],
                          cwd=work, capture_output=True, text=True, timeout=timeout)
    (work / "alps.log").write_text(proc.stdout + proc.stderr)
    if proc.returncode != 0:
        tail = " | ".join((proc.stdout + proc.stderr).strip().splitlines()[-5:])
        raise RuntimeError(f"ALPS spinmc failed (exit {proc.returncode}): {tail}")
    last = [ln for ln in proc.stdout.splitlines() if ln.startswith("{")][-1]
    return json.loads(last)


# ----------------------------------------------------------------------------------------------
# worker side (the ALPS interpreter: numpy and pyalps only)
# ----------------------------------------------------------------------------------------------

def _jackknife(fn, *bins):
    import numpy as np

    bins = [np.asarray(b, float) for b in bins]
    n = len(bins[0])
    full = fn(*[b.mean() for b in bins])
    tot = [b.sum() for b in bins]
    loo = np.array([fn(*[(s - b[i]) / (n - 1) for s, b in zip(tot, bins)]) for i in range(n)])
    return float(full), float(np.sqrt((n - 1) / n * ((loo - loo.mean()) ** 2).sum()))


def _worker(job: str) -> None:
    import resource

    import numpy as np
    import pyalps
    import pyalps.hdf5 as h5

    spec = json.loads(Path(job).read_text())
    app, parms, sites, beta = spec["app"], spec["parms"], spec["sites"], spec["beta"]
    if app == "spinmc":
        return _spinmc_worker(spec)
    infile = pyalps.writeInputFiles(app, [parms])
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    code, _ = pyalps.runApplication(app, infile, Tmin=1)   # (pyalps spells its Tmax flag wrongly)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    if code != 0:
        sys.exit(f"{app} exited with status {code}")
    ar = h5.archive(f"{app}.task1.out.h5", "r")
    base = "/simulation/results/"

    def mean(name):
        m = ar[base + name + "/mean"]
        return float(m["value"]), float(m["error"]), int(m.get("error_convergence", 0))

    def bins(name):
        # ALPS keeps the sums of complete bins of 2^k measurements (k grows with the run) and
        # one partial bin of at most 2^k: the bin size is the power of 2 that leaves at most one
        # bin over (seen: 2272 measurements in 70 bins of 32)
        data = np.asarray(ar[base + name + "/timeseries/data"], float)
        count = int(ar[base + name + "/count"])
        size = 1 << int(np.floor(np.log2(count / len(data))))
        if not 0 <= count - size * len(data) <= size:
            sys.exit(f"cannot read the bins of {name!r}: {count} measurements in {len(data)} bins")
        return data / size, count

    e, de, conv = mean("Energy")
    d, dd, _ = mean("Density")
    eb, ecount = bins("Energy")
    nb, count = bins("Density")
    n2b, _ = bins("Density^2")
    m = min(len(nb), len(n2b))
    # rebin to at most 32 bins so that each is long against the autocorrelation time
    k = max(1, m // 32)
    use = (m // k) * k
    nb = nb[:use].reshape(-1, k).mean(axis=1)
    n2b = n2b[:use].reshape(-1, k).mean(axis=1)
    kappa, dkappa = _jackknife(lambda x, x2: beta * (x2 - sites * x * x), nb, n2b)
    print(json.dumps({"app": app, "sites": sites, "energy": e, "energy_err": de, "density": d, "density_err": dd,
                      "compressibility": kappa, "compressibility_err": dkappa, "cpu_seconds": cpu,
                      "measurements": count, "bins": int(len(nb)), "converged": conv == 0,
                      # the energy's time series in bins of energy_bin_size sweeps (its first bins show
                      # what the thermalisation left: benchmarks/bench_qmc.py --therm-scan)
                      "energy_bins": [float(x) for x in eb],
                      # tau_int of the energy in the package's convention (sigma^2 = 2 tau var / n, 1/2
                      # uncorrelated; hyperlattice.mcstats), from ALPS's error and per-measurement variance
                      "energy_tau": ecount * de * de / (2.0 * float(ar[base + "Energy/variance"]["value"])), "energy_bin_size": 1 << int(np.floor(np.log2(ecount / len(eb))))}))


def _spinmc_worker(spec: dict) -> None:
    import resource

    import pyalps
    import pyalps.hdf5 as h5

    app, parms, sites = spec["app"], spec["parms"], spec["sites"]
    infile = pyalps.writeInputFiles(app, [parms])
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    code, _ = pyalps.runApplication(app, infile, Tmin=1)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    if code != 0:
        sys.exit(f"{app} exited with status {code}")
    ar = h5.archive(f"{app}.task1.out.h5", "r")
    base = "/simulation/results/"
    names = list(ar.list_children(base)) if hasattr(ar, "list_children") else []

    def mean(name):
        m = ar[base + name + "/mean"]
        return float(m["value"]), float(m["error"]), int(m.get("error_convergence", 0))

    e, de, conv = mean("Energy Density")
    m2, dm2, _ = mean("Magnetization^2")
    chi, dchi, _ = mean("Susceptibility")
    count = int(ar[base + "Energy Density/count"])
    print(json.dumps({"app": app, "sites": sites, "energy": e, "energy_err": de, "m2": m2, "m2_err": dm2,
                      "chi": chi, "chi_err": dchi, "cpu_seconds": cpu, "measurements": count,
                      "converged": conv == 0, "observables": names}))


if __name__ == "__main__":
    if len(sys.argv) == 3 and sys.argv[1] == "--worker":
        _worker(sys.argv[2])
    else:
        sys.exit("usage: _alps.py --worker JOB.json (called by run_alps)")
