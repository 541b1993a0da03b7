"""Every flag of every command is used by at least one invocation that runs (issue 28, item 5).

:data:`INVOCATIONS` lists cheap, valid command lines; :func:`test_every_flag_is_exercised` walks the
argparse parsers of :mod:`hyperlattice.cli` (every command and subcommand, found as the user finds
them) and fails with the list of flags that no invocation uses: a new flag needs an entry here, so
that no flag is dead (``bosons meanfield --plot`` could never work, and nothing noticed).
:func:`test_invocation_runs` runs each line (exit code 0). ``--help``, ``--version`` and
``--progress``/``--no-progress`` (one shared mechanism of every command) are left out of the count.

Command lines also take negative numbers as values, as people type them: ``--U -1``,
``--omega -2.5+0.1j``, ``--U -1e-3`` (:func:`test_negative_numbers_are_values`).
"""

from __future__ import annotations

import argparse
import json

import pytest

from hyperlattice.cli import build_parser, main

#: flags no invocation needs to use (shared by every command, or printing and exiting)
SHARED = {"--help", "--version", "--progress", "--no-progress"}

#: (argv, marks); "{tmp}" is the test's temporary directory. One entry per behaviour, cheap sizes.
INVOCATIONS = [
    ["reproduce", "--out", "{tmp}/r", "--max-rings", "2", "--cache-dir", "{tmp}/cache", "--clear-cache"],
    ["reproduce", "--out", "{tmp}/r2", "--no-cache"],
    ["geometry", "-p", "7", "-q", "3", "--json"],
    ["lattice", "-p", "7", "-q", "3", "--rings", "2", "--line-graph", "--out", "{tmp}/lat.npz", "--json"],
    ["cluster", "--list", "--max-sites", "100"],
    ["cluster", "-p", "7", "-q", "3", "--name", "klein", "--out", "{tmp}/klein.npz", "--json"],
    ["cluster", "--min-sites", "50", "--max-seconds", "60"],
    ["spectrum", "-p", "7", "-q", "3", "--rings", "3", "--levels", "2", "--sector", "1", "--method", "sector", "--tol", "1e-9", "--json"],
    ["spectrum", "--rings", "2", "--line-graph", "--flux", "0.1"],
    ["butterfly", "-p", "7", "-q", "3", "--rings", "2", "--fluxes", "3", "--out", "{tmp}/b.png", "--table", "{tmp}/b.csv", "--continuum",
     "--max-seconds", "120", "--checkpoint", "{tmp}/bc", "--json"],
    ["butterfly", "--rings", "1", "--fluxes", "2", "--line-graph"],
    ["fluxmap", "-p", "7", "-q", "3", "--rings", "2", "--fluxes", "2", "--fmax", "0.1", "--levels", "1", "--out", "{tmp}/f.png",
     "--table", "{tmp}/f.csv", "--checkpoint", "{tmp}/fc", "--json"],
    ["continuum", "-p", "7", "-q", "3", "--radius", "0.5", "--levels", "2", "--dictionary", "improved", "--max-seconds", "60", "--json"],
    ["continuum", "--rings", "3", "--flux", "0.1"],
    ["disorder", "-p", "7", "-q", "3", "--rings", "2", "--W", "0.1", "--realizations", "2", "--seed", "1", "--model", "resonator",
     "--omega0", "4", "--line-graph", "--no-ipr", "--plot", "{tmp}/d.png", "--max-seconds", "60", "--json"],
    ["sweep", "--task", "probe", "--grid", "x=1,2", "--out", "{tmp}/s", "--scheduler", "serial", "--workers", "1",
     "--retries", "0", "--timeout", "60", "--json"],
    ["sweep", "{tmp}/sweep.json", "--scheduler", "serial"],
    ["sweep", "--task", "conductance", "--grid", "rings=2", "--grid", "W=1", "--out", "{tmp}/sc", "--scheduler", "serial"],
    ["dos", "-p", "7", "-q", "3", "--rings", "3", "--moments", "16", "--vectors", "2", "--seed", "1", "--kind", "phase", "--exclude", "1",
     "--points", "11", "--out", "{tmp}/dos.csv", "--plot", "{tmp}/dos.png", "--checkpoint", "{tmp}/dc", "--json"],
    ["dos", "--cluster", "klein", "--moments", "16", "--vectors", "2", "--keep-uniform"],
    ["dos", "--rings", "3", "--site", "0", "--moments", "16"],
    ["green", "-p", "7", "-q", "3", "--rings", "3", "--omega", "-2.5+0.1j", "--site", "0", "--tol", "1e-10", "--out", "{tmp}/g.csv",
     "--max-seconds", "60", "--json"],
    ["boundary", "-p", "7", "-q", "3", "--rings", "4", "--mass2", "-0.1", "--ads-radius", "1", "--no-systematic", "--json"],
    ["boundary", "-p", "7", "-q", "3", "--rings", "4", "--omega", "-3.2", "--site", "112", "--depth", "2", "--continuum-disk", "dirichlet",
     "--out", "{tmp}/bd.csv", "--plot", "{tmp}/bd.png", "--json"],
    ["qubits", "-p", "7", "-q", "3", "--rings", "3", "--omega-q", "-3.2", "--g", "0.05", "--site", "0", "--qubit-sites", "0,10",
     "--threshold", "0.1", "--out", "{tmp}/q.csv", "--edges", "{tmp}/e.csv", "--json"],
    ["qubits", "--rings", "2", "--line-graph", "--omega-q", "-4.1"],
    ["scaling", "angles", "-p", "7", "-q", "3", "--rings", "3", "--plot", "{tmp}/a.png", "--json"],
    ["scaling", "operator", "-p", "7", "-q", "3", "--rings", "3", "--h", "0.1", "--function", "gaussian", "--plot", "{tmp}/o.png", "--json"],
    ["scaling", "convergence", "-p", "7", "-q", "3", "--rings", "3", "--function", "gaussian", "--h-min", "0.02", "--h-max", "0.05",
     "--points", "3", "--json"],
    ["scaling", "counting", "-p", "7", "-q", "3", "--rings", "4", "--window", "complete", "--slope", "1.0", "--plot", "{tmp}/c.png",
     "--json"],
    ["scaling", "sums", "-p", "7", "-q", "3", "--rings", "3", "--function", "gaussian", "--json"],
    ["dictionary", "-p", "7", "-q", "3", "--t", "1", "--mu", "-0.5", "--U", "0.1", "--inverse", "--json"],
    ["bosons", "ed", "--rings", "1", "-p", "7", "-q", "3", "--particles", "2", "--nmax", "2", "--U", "-1", "--t", "1",
     "--levels", "2", "--method", "sectors", "--observables", "--json"],
    ["bosons", "ed", "--cluster", "bolza", "--particles", "1", "--nmax", "1", "--U", "1"],
    ["bosons", "qmc", "--rings", "1", "-p", "7", "-q", "3", "--nmax", "2", "--U", "4", "--t", "1", "--mu", "1",
     "--beta", "1", "--sweeps", "400", "--thermalization", "100", "--seed", "3", "--checkpoint", "{tmp}/qmcck",
     "--json", "--no-progress"],
    ["bosons", "qmc", "--cluster", "bolza", "--nmax", "1", "--U", "0", "--mu", "0", "--beta", "0.5",
     "--sweeps", "400", "--seed", "1", "--progress"],
    ["bosons", "qmc", "--adjacency", "{tmp}/square.npz", "--windings", "{tmp}/square_windings.npy", "--nmax", "1",
     "--U", "0", "--mu", "0.3", "--beta", "0.5", "--sweeps", "200", "--seed", "1", "--json"],
    ["bosons", "qmc", "--cluster", "klein", "--no-windings", "--nmax", "1", "--U", "0", "--mu", "0", "--beta", "0.5",
     "--sweeps", "200", "--seed", "1"],
    ["bosons", "qmc", "--rings", "1", "--nmax", "1", "--U", "0", "--mu", "0", "--beta", "0.5", "--sweeps", "100",
     "--max-seconds", "60"],
    ["bosons", "lobe", "--rings", "1", "-p", "8", "-q", "3", "--t-over-U", "0.05", "--beta", "1", "--nmax", "2",
     "--sweeps", "100", "--thermalization", "50", "--iterations", "1", "--seed", "5", "--max-seconds", "600",
     "--out", "{tmp}/lobe", "--json"],
    ["bosons", "lobe", "--cluster", "klein", "--t-over-U", "0.05", "--beta", "0.5", "--nmax", "2", "--sweeps", "50",
     "--thermalization", "20", "--iterations", "1", "--out", "{tmp}/lobe2"],
    ["spins", "quantum", "--rings", "1", "-p", "8", "-q", "3", "--J", "1", "--Delta", "1", "--h", "0.1",
     "--beta", "1", "--sweeps", "400", "--thermalization", "100", "--seed", "3", "--checkpoint", "{tmp}/xxzck",
     "--json"],
    ["spins", "quantum", "--cluster", "bolza", "--no-windings", "--J", "1", "--beta", "0.5", "--sweeps", "200",
     "--seed", "1"],
    ["spins", "quantum", "--adjacency", "{tmp}/square.npz", "--J", "-1", "--Delta", "0.5", "--beta", "0.5",
     "--sweeps", "200", "--seed", "1"],
    ["bosons", "meanfield", "-p", "7", "-q", "3", "--rings", "2", "--filling", "1", "--points", "3", "--continuum", "--t", "0.01",
     "--mu", "0.5", "--plot", "{tmp}/m.png", "--json"],
    ["bosons", "meanfield", "--cluster", "klein", "--points", "3"],
    ["bosons", "meanfield", "--infinite", "--points", "3"],
    ["bosons", "gp", "-p", "7", "-q", "3", "--rings", "2", "--filling", "1", "--U", "0.5", "--t", "1", "--modes", "3", "--json"],
    ["bosons", "gp", "--rings", "2", "--particles", "35", "--U", "0.5"],
    ["spins", "classical", "--model", "ising", "--rings", "2", "-p", "7", "-q", "3", "--J", "1", "--h", "0", "--beta", "0.5",
     "--sweeps", "300", "--thermalization", "50", "--seed", "1", "--checkpoint", "{tmp}/spinck", "--json"],
    ["spins", "classical", "--model", "heisenberg", "--cluster", "bolza", "--J", "-1", "--T", "1", "--sweeps", "200",
     "--update", "local", "--no-correlation", "--seed", "2"],
    ["spins", "classical", "--model", "xy", "--rings", "2", "--line-graph", "--h", "0.2", "--beta", "1", "--sweeps", "200"],
    ["spins", "classical", "--model", "ising", "--adjacency", "{tmp}/square.npz", "--beta", "0.4", "--sweeps", "200"],
    ["spins", "classical", "--model", "ising", "--rings", "1", "--J", "-1", "--tempering", "1,2", "--exchange-every",
     "2", "--sweeps", "100", "--seed", "1"],
    ["device", "transmission", "-p", "7", "-q", "3", "--rings", "2", "--line-graph", "--omega0", "7000", "--J", "-66",
     "--kappa-int", "0.7", "--port", "0-1:1", "--port", "30-31:1", "--omegas", "{tmp}/device_omegas.txt",
     "--frequencies", "{tmp}/device_freq.json", "--hoppings", "{tmp}/device_hop.json", "--sigma-omega", "3",
     "--sigma-J", "0.03", "--seed", "1", "--plot", "{tmp}/device.png", "--json"],
    ["device", "transmission", "--cluster", "klein", "--kappa-int", "0", "--port", "0:1", "--omega-min", "-3",
     "--omega-max", "3", "--points", "11"],
    ["device", "impedance", "-p", "7", "-q", "3", "--rings", "2", "--edge", "C:1", "--ground", "L:1,R:100",
     "--between", "0", "20", "--omegas", "{tmp}/device_omegas.txt", "--json"],
    ["device", "impedance", "--cluster", "klein", "--edge", "C:1", "--ground", "R:1", "--to-ground", "0",
     "--omega-min", "0.5", "--omega-max", "2", "--points", "3"],
    ["device", "impedance", "--adjacency", "{tmp}/square.npz", "--edge", "C:1", "--ground", "R:1", "--to-ground", "0",
     "--omega-min", "0.5", "--omega-max", "2", "--points", "3"],
    ["device", "impedance", "--rings", "2", "--line-graph", "--edge", "L:1", "--ground", "C:1", "--to-ground", "0-1",
     "--omega-min", "0.5", "--omega-max", "2", "--points", "3"],
    ["device", "fit", "-p", "7", "-q", "3", "--rings", "1", "--port", "0:0.1", "--port", "3:0.1", "--measured",
     "{tmp}/device_trace.csv", "--plot", "{tmp}/fit.png", "--json"],
    ["device", "fit", "--cluster", "klein", "--port", "0:0.1", "--port", "3:0.1", "--measured", "{tmp}/device_trace.csv"],
    ["device", "fit", "--adjacency", "{tmp}/square.npz", "--port", "0:0.1", "--port", "3:0.1", "--measured",
     "{tmp}/device_trace.csv"],
    ["device", "fit", "--rings", "2", "--line-graph", "--port", "0-1:0.1", "--port", "30-31:0.1", "--measured",
     "{tmp}/device_trace.csv"],
    ["device", "transmission", "--adjacency", "{tmp}/square.npz", "--kappa-int", "0.1", "--port", "0:1",
     "--omega-min", "-3", "--omega-max", "3.1", "--points", "5"],
    ["topology", "flake", "--model", "haldane", "-p", "8", "-q", "3", "--rings", "2", "--M", "0.1", "--t2", "0.3",
     "--phi", "1.2", "--disorder", "0.5", "--seed", "3", "--json"],
    ["topology", "flake", "--rings", "2"],
    ["topology", "cluster", "--model", "qwz", "--cluster", "bolza", "-p", "8", "-q", "3", "--M", "1", "--t2", "0.2",
     "--phi", "1.5", "--json"],
    ["topology", "cluster", "--cluster", "bolza", "--M", "2.5"],
    ["topology", "cluster", "--model", "haldane", "--cluster", "bolza", "--M", "0", "--t2", "0.3", "--chern2"],
    ["topology", "cluster", "--model", "kane-mele", "--cluster", "bolza", "--M", "0", "--t2", "0.3", "--spin-chern"],
    ["topology", "landau", "--cluster", "bolza", "-p", "8", "-q", "3", "--nphi", "3", "--levels", "1", "--json"],
    ["topology", "cluster", "--cluster", "bolza", "--frame", "covariant", "--json"],
    ["topology", "cluster", "--model", "haldane", "--cluster", "bolza", "--M", "0", "--filling", "5/16"],
    ["topology", "cluster", "--model", "haldane", "--cluster", "bolza", "--M", "0", "--fermi-level", "-1.3", "--json"],
    ["topology", "cluster", "--model", "dirac4", "--cluster", "one-site", "-p", "8", "-q", "8", "--M", "-3"],
    ["topology", "conductance", "--model", "qwz", "-p", "8", "-q", "3", "--rings", "2", "--M", "1", "--t2", "0.2",
     "--phi", "1.5", "--disorder", "0.5", "--seed", "2", "--energies", "-0.1,0", "--coupling", "1.5", "--arc", "0.2",
     "--json"],
    ["topology", "conductance", "--rings", "2"],
    ["topology", "flake", "--model", "kane-mele", "--rings", "2", "--M", "0", "--rashba", "0.1", "--fermi", "-1.247",
     "--json"],
    ["topology", "flake", "--rings", "2", "--frame", "transport"],
    ["topology", "cluster", "--model", "kane-mele", "--cluster", "bolza", "--M", "0.3", "--rashba", "0.05", "--z2"],
    ["topology", "conductance", "--model", "kane-mele", "--rings", "2", "--M", "0", "--rashba", "0.1"],
]


def _parsers(parser: argparse.ArgumentParser, path=()):
    """(command words, parser) of every command and subcommand, as argparse builds them."""
    subs = [a for a in parser._actions if isinstance(a, argparse._SubParsersAction)]
    if path and not subs:
        yield path, parser
    for action in subs:
        for name, sub in action.choices.items():
            yield from _parsers(sub, path + (name,))


def _flags(parser: argparse.ArgumentParser) -> dict:
    """option string -> the flag's name (its longest spelling); a positional as <dest>."""
    out = {}
    for a in parser._actions:
        if isinstance(a, argparse._SubParsersAction):
            continue
        name = max(a.option_strings, key=len) if a.option_strings else f"<{a.dest}>"
        if name in SHARED or any(o in SHARED for o in a.option_strings):
            continue
        for o in a.option_strings or [name]:
            out[o] = name
    return out


def _used(argv: list[str], parsers: dict) -> set:
    """The (command, flag) pairs one command line uses."""
    for n in (2, 1):
        words = tuple(argv[:n])
        if words in parsers:
            flags = _flags(parsers[words])
            used = set()
            positional = [f for f in flags.values() if f.startswith("<")]
            for w in argv[n:]:
                key = w.split("=", 1)[0] if w.startswith("--") else w
                if key in flags:
                    used.add((" ".join(words), flags[key]))
                elif not w.startswith("-") and positional and w.endswith(".json"):
                    used.add((" ".join(words), positional[0]))
            return used
    raise AssertionError(f"no command in {argv}")


def test_every_flag_is_exercised():
    parsers = dict(_parsers(build_parser()))
    everything = {(" ".join(words), flag) for words, p in parsers.items() for flag in set(_flags(p).values())}
    used = set().union(*(_used(argv, parsers) for argv in INVOCATIONS))
    missing = sorted(everything - used)
    assert not missing, ("flags that no command line of tests/test_cli_every_flag.py uses (add one to "
                         "INVOCATIONS): " + ", ".join(f"`{c} {f}`" for c, f in missing))


def _fake_reproduce(out_dir, max_rings, *, cache, progress):
    # the flags, not the paper, are under test (the full run is tests/test_reproduce.py)
    return {"out_dir": str(out_dir), "sections": [], "seconds": 0.0,
            "cache_hits": cache.hits, "cache_misses": cache.misses, "cache_reused": cache.reused}


def _square_torus_files(where) -> None:
    """square.npz (the 3 x 3 torus's adjacency) and square_windings.npy (its windings in the CLI's edge order)."""
    import numpy as np
    import scipy.sparse as sp

    from hyperlattice.cli._bosons_qmc import edges
    from hyperlattice.compare.qmc_lobe import square_lattice, square_lattice_windings

    adj = square_lattice(3)
    sp.save_npz(where / "square.npz", sp.csr_matrix(adj))
    pairs, w = square_lattice_windings(3)
    lookup = {(int(i), int(j)): row for (i, j), row in zip(pairs, w)}
    lookup.update({(int(j), int(i)): -row for (i, j), row in zip(pairs, w)})
    np.save(where / "square_windings.npy", np.array([lookup[(int(i), int(j))] for i, j in edges(adj)]))


def _device_files(where) -> None:
    """The frequency list and the explicit disorder files of the ``device`` lines."""
    (where / "device_omegas.txt").write_text("6900\n7000.5\n7100\n")
    (where / "device_freq.json").write_text(json.dumps({"0-1": 7001.0}))
    (where / "device_hop.json").write_text(json.dumps({"0-1|1-2": -60.0}))
    import math

    # a trace with two resonances (the fits only need to run)
    rows = ["omega,mag_db"] + [f"{w},{20 * math.log10(0.01 + 0.1 / abs(w - 1 + 0.05j) + 0.05 / abs(w + 1 + 0.05j))}"
                               for w in [-3 + 6 * k / 120 for k in range(121)]]
    (where / "device_trace.csv").write_text("\n".join(rows) + "\n")


def _slow(argv: list[str]) -> bool:
    # the two lines above ~5 s (a butterfly with its continuum overlay; rho of the infinite lattice)
    return argv[0] == "butterfly" and "--continuum" in argv or "--infinite" in argv


@pytest.mark.parametrize("argv", [pytest.param(a, id=" ".join(a[:2]) + f" #{i}",
                                               marks=[pytest.mark.slow] if _slow(a) else [])
                                  for i, a in enumerate(INVOCATIONS)])
def test_invocation_runs(argv, tmp_path, monkeypatch, capsys):
    import hyperlattice.report as report

    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv("HYPERLATTICE_CACHE", str(tmp_path / "cache"))
    monkeypatch.setattr(report, "reproduce", _fake_reproduce)
    (tmp_path / "sweep.json").write_text(json.dumps({"task": "probe", "grid": {"x": [1.0]}, "out": str(tmp_path / "s2")}))
    _square_torus_files(tmp_path)
    _device_files(tmp_path)
    words = [w.replace("{tmp}", str(tmp_path)) for w in argv]
    code = main(words + ["--no-progress"])
    err = capsys.readouterr().err
    assert code == 0, err
    assert "Traceback" not in err


@pytest.mark.parametrize("argv, shown", [
    (["bosons", "ed", "--rings", "1", "--particles", "2", "--nmax", "2", "--U", "-1e-3", "--levels", "1", "--json"],
     '"U": -0.001'),
    (["bosons", "ed", "--rings", "1", "--particles", "2", "--nmax", "2", "--U", "-1", "--levels", "1", "--json"],
     '"U": -1.0'),
    (["green", "--rings", "2", "--omega", "-2.5+0.1j", "--site", "0", "--json"], None),
    (["dictionary", "--mu", "-3.5", "--json"], None),
])
def test_negative_numbers_are_values(argv, shown, capsys):
    # issue 28 item 5: argparse took "-1e-3" and "-2.5+0.1j" for unknown flags ("expected one argument")
    assert main(argv) == 0
    out = capsys.readouterr().out
    assert shown is None or shown in out


def test_a_negative_infinity_is_refused_as_a_number(capsys):
    with pytest.raises(SystemExit) as exc:
        main(["bosons", "ed", "--rings", "1", "--particles", "2", "--nmax", "2", "--U", "-inf"])
    assert exc.value.code == 2
    assert "expected a finite number, got '-inf'" in capsys.readouterr().err
