"""Imports run one way: the layer rule of docs/architecture.md, read from the source with ast.

Every ``import`` of a hyperlattice module, also one inside a function (a lazy import is still
an arrow between layers), must point to the same layer or a lower one. Imports under
``if TYPE_CHECKING:`` are for the type checker only and do not count. The few lazy arrows that
must point up are listed in ``ALLOWED`` with their reason; the package root is a lazy facade
(its names are imported by ``importlib`` on first use) and sits at the bottom.
"""

from __future__ import annotations

import ast
import dataclasses
import subprocess
import sys
from pathlib import Path

import pytest

import hyperlattice

PACKAGE = Path(hyperlattice.__file__).parent

#: layer of each top-level module or sub-package, lowest first
LAYERS = {
    "hyperlattice": 0, "errors": 0, "_ties": 0, "_validate": 0, "results": 0, "geometry": 0,
    "cache": 0, "paper_values": 0, "paper_labels": 0, "_progress": 0, "mcstats": 0, "_mc_chain": 0,
    "dictionary": 1,
    "graph": 2, "continuum": 2,
    "bosons": 3, "device": 3, "spins": 3, "topology": 3,
    "compare": 4,
    "plots": 5,
    "report": 6, "sweep": 6,
    "cli": 7, "__main__": 8,
}

#: upward arrows that stay, each a lazy import inside one function: (importer, imported) -> reason
ALLOWED = {
    ("hyperlattice.dictionary", "hyperlattice.graph.lattice"):
        "the disk radius of an l-ring flake needs the graph's exact site count N(l), and the "
        "improved map's radius shift is measured on a built flake",
    ("hyperlattice.bosons.meanfield", "hyperlattice.compare.limits"):
        "mott_lobes adds the infinite lattice, whose lambda_max is the extrapolated band bottom",
}


def _module_name(path: Path, root: Path = PACKAGE) -> str:
    parts = list(path.relative_to(root.parent).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def _is_type_checking(node: ast.AST) -> bool:
    return isinstance(node, ast.If) and "TYPE_CHECKING" in ast.unparse(node.test)


def _imports(path: Path, modules: set[str], root: Path = PACKAGE) -> list[tuple[str, int, bool]]:
    """(imported hyperlattice module, line, at module level) for every import outside TYPE_CHECKING."""
    name = _module_name(path, root)
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    out = []

    def resolve(target: str) -> str:
        while target not in modules and "." in target:
            target = target.rpartition(".")[0]
        return target

    def visit(node: ast.AST, top: bool) -> None:
        for child in ast.iter_child_nodes(node):
            if _is_type_checking(child):
                continue
            inner = top and not isinstance(child, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda))
            if isinstance(child, ast.Import):
                out.extend((resolve(a.name), child.lineno, top) for a in child.names
                           if a.name.split(".")[0] == "hyperlattice")
            elif isinstance(child, ast.ImportFrom):
                if child.level:
                    base = package.split(".")[: len(package.split(".")) - (child.level - 1)]
                    target = ".".join(base + ([child.module] if child.module else []))
                else:
                    target = child.module or ""
                if target.split(".")[0] != "hyperlattice":
                    continue
                if child.module is None:
                    out.extend((resolve(f"{target}.{a.name}"), child.lineno, top) for a in child.names)
                else:
                    for a in child.names:
                        sub = f"{target}.{a.name}"
                        out.append((sub if sub in modules else resolve(target), child.lineno, top))
            visit(child, inner)

    visit(ast.parse(path.read_text(encoding="utf-8")), True)
    return out


def _layer(module: str) -> int:
    parts = module.split(".")
    return LAYERS[parts[1] if len(parts) > 1 else "hyperlattice"]


@pytest.fixture(scope="module")
def edges() -> dict[str, list[tuple[str, int, bool]]]:
    files = sorted(PACKAGE.rglob("*.py"))
    modules = {_module_name(p) for p in files}
    return {_module_name(p): _imports(p, modules) for p in files}


def test_every_module_has_a_layer(edges):
    missing = sorted({m for m in edges if m.split(".")[1:2] and m.split(".")[1] not in LAYERS})
    assert not missing, f"give these modules a layer in LAYERS (and docs/architecture.md): {missing}"


def test_no_import_points_up(edges):
    upward = [f"{m}:{line} imports {t} (layer {_layer(m)} -> {_layer(t)})"
              for m, imports in edges.items() for t, line, _ in imports
              if _layer(t) > _layer(m) and (m, t) not in ALLOWED]
    assert not upward, "imports must point to the same or a lower layer:\n" + "\n".join(upward)


def test_allowed_arrows_are_lazy_and_still_needed(edges):
    for (importer, imported), reason in ALLOWED.items():
        found = [top for t, _, top in edges[importer] if t == imported]
        assert found, f"{importer} no longer imports {imported}: drop it from ALLOWED ({reason})"
        assert not any(found), f"{importer} imports {imported} at module level; only a lazy import may point up"


def test_layer_graph_has_no_cycle(edges):
    arrows: dict[int, set[int]] = {}
    for m, imports in edges.items():
        for t, _, _ in imports:
            if (m, t) not in ALLOWED and _layer(t) != _layer(m):
                arrows.setdefault(_layer(m), set()).add(_layer(t))
    # with every arrow pointing down the layer graph is acyclic; check it directly anyway
    state: dict[int, int] = {}

    def visit(v: int, path: tuple) -> None:
        state[v] = 1
        for w in arrows.get(v, ()):
            assert state.get(w) != 1, f"import cycle between layers {path + (w,)}"
            if w not in state:
                visit(w, path + (w,))
        state[v] = 2

    for v in sorted(arrows):
        if v not in state:
            visit(v, (v,))


def test_package_root_imports_nothing_eagerly(edges):
    eager = [t for t, _, top in edges["hyperlattice"] if top]
    assert eager == [], f"hyperlattice/__init__.py must stay a lazy facade, imports {eager}"


def test_the_rule_sees_an_upward_import(tmp_path):
    """The checker itself: a module of layer 0 that imports plots is reported."""
    probe = tmp_path / "hyperlattice"
    probe.mkdir()
    (probe / "geometry.py").write_text("def f():\n    from .plots import new_axes\n")
    (probe / "plots.py").write_text("")
    modules = {"hyperlattice", "hyperlattice.geometry", "hyperlattice.plots"}
    found = _imports(probe / "geometry.py", modules, root=probe)
    assert found == [("hyperlattice.plots", 2, False)]
    assert _layer("hyperlattice.plots") > _layer("hyperlattice.geometry")


@pytest.mark.parametrize("module", ["hyperlattice.graph.lattice", "hyperlattice.graph.spectrum",
                                    "hyperlattice.compare.levels", "hyperlattice.results"])
def test_graph_and_results_do_not_load_matplotlib(module):
    code = (f"import sys, {module}; "
            "bad = sorted(m for m in sys.modules if m.split('.')[0] == 'matplotlib' or m.startswith('hyperlattice.plots')); "
            "print(' '.join(bad))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "", f"import {module} loads {out.stdout.strip()}"


def test_result_plot_finds_the_registered_drawing():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from hyperlattice.graph.lattice import ring_lattice
    from hyperlattice.results import _PLOTTERS, plotter

    lat = ring_lattice(7, 3, 2)
    ax = lat.plot(sites=False)
    try:
        assert plotter(type(lat)) is _PLOTTERS["Lattice"]
        assert ax.get_title().startswith("{7,3}, 2 rings")
    finally:
        plt.close(ax.figure)


def test_every_registered_drawing_names_a_result_type():
    import importlib
    import pkgutil

    from hyperlattice.plots.registry import _DRAWINGS
    from hyperlattice.results import plotter, result_types

    for info in pkgutil.walk_packages(hyperlattice.__path__, "hyperlattice."):
        if not info.name.startswith(("hyperlattice.cli", "hyperlattice.__main__")):
            importlib.import_module(info.name)
    types = result_types()
    unknown = sorted(set(_DRAWINGS) - set(types))
    assert not unknown, f"drawings registered for unknown result types: {unknown}"
    for tag in _DRAWINGS:
        assert plotter(types[tag]) is _DRAWINGS[tag]


def test_a_result_without_a_drawing_says_so():
    from hyperlattice.results import _REGISTRY, Result, plotter

    @dataclasses.dataclass(frozen=True, eq=False, kw_only=True)
    class NoFigureProbe(Result):
        value: float

    try:
        assert plotter(NoFigureProbe) is None
        with pytest.raises(NotImplementedError, match="NoFigureProbe has no standard plot"):
            NoFigureProbe(value=1.0).plot()
    finally:   # tests/test_results.py walks every registered type: leave no probe behind
        _REGISTRY.pop("NoFigureProbe")


#: order inside the sub-packages whose modules import each other (lowest first): every import
#: between two of their modules, also a lazy one, points to an earlier module, so a level request
#: flows down once (spectrum chooses the route -> sectors / symmetry build the blocks -> factor and
#: solvers solve) and flux, operators and symmetry are leaves below every route (issue 28, item 9).
#: The modules of a package inside one of them (sweep/tasks/: one module per task family) take the
#: package's place; TASK_FAMILIES holds them apart.
INNER_ORDER = {
    "graph": ("lattice", "groups", "flux", "operators", "symmetry", "solvers", "factor", "walks", "clusters",
              "bands", "disorder", "kpm", "green", "qubits", "levels", "sectors", "spectrum", "butterfly"),
    "sweep": ("tasks", "keys", "store", "qmc", "device", "engine"),
}


@pytest.mark.parametrize("package", sorted(INNER_ORDER))
def test_imports_inside_a_package_point_down(edges, package):
    order = INNER_ORDER[package]
    prefix = f"hyperlattice.{package}."
    mods = sorted(m for m in edges if m.startswith(prefix))

    def place(module: str) -> str:
        return module[len(prefix):].split(".")[0]

    unknown = [m for m in mods if place(m) not in order]
    assert not unknown, f"give these modules a place in INNER_ORDER[{package!r}]: {unknown}"
    rank = {name: k for k, name in enumerate(order)}
    upward = [f"{m}:{line} imports {t}" + ("" if top else " (lazily)")
              for m in mods for t, line, top in edges[m]
              if t.startswith(prefix) and t != m and rank[place(t)] > rank[place(m)]]
    assert not upward, f"imports inside {package}/ must point to an earlier module of INNER_ORDER:\n" + "\n".join(upward)


def test_sweep_task_families_stand_alone(edges):
    """A task family of sweep/tasks/ imports of the sweep only the shared helpers (tasks._common), never
    another family, the registry or the engine above it: a family is added or changed on its own."""
    prefix = "hyperlattice.sweep."
    families = [m for m in edges if m.startswith(prefix + "tasks.") and m != prefix + "tasks._common"]
    assert len(families) >= 8, families
    found = sorted(f"{m} imports {t}" for m in families for t, _, _ in edges[m]
                   if t.startswith(prefix) and t != prefix + "tasks._common")
    assert not found, "\n".join(found)


#: the leaves of a level request: the graph modules each may import (lazily too). Nothing else of graph/,
#: so no block builder of flakes (sectors), solver (solvers, factor), route (spectrum) or anything that uses
#: them; flux holds the Peierls phases, operators the matrices and tables (with those phases), symmetry the
#: rotation orbits and the Bloch blocks of a built lattice (issue 28, item 9)
LEAVES = {
    "flux": {"lattice"},
    "operators": {"lattice", "flux"},
    "symmetry": {"lattice", "flux", "operators"},
}


@pytest.mark.parametrize("leaf", sorted(LEAVES))
def test_graph_leaves_import_only_the_primitives_below_them(edges, leaf):
    """flux, operators and symmetry import of graph/ only the primitives listed in LEAVES."""
    prefix = "hyperlattice.graph."
    found = sorted({t for t, _, _ in edges[prefix + leaf]
                    if t.startswith(prefix) and t[len(prefix):] not in LEAVES[leaf]})
    assert not found, f"graph/{leaf}.py imports {found}; a leaf imports of graph/ only {sorted(LEAVES[leaf])}"
    # and below graph/ only the bottom layers (the package root, errors, _validate, geometry, ...; dictionary)
    low = sorted({t for t, _, _ in edges[prefix + leaf] if not t.startswith(prefix) and _layer(t) > 1})
    assert not low, f"graph/{leaf}.py imports {low}"


def test_the_leaf_rule_sees_a_forbidden_import(tmp_path):
    """The checker itself: symmetry importing sectors lazily is reported."""
    probe = tmp_path / "hyperlattice"
    (probe / "graph").mkdir(parents=True)
    (probe / "graph" / "symmetry.py").write_text("from .lattice import Lattice\n\ndef f():\n    from .sectors import x\n")
    modules = {"hyperlattice", "hyperlattice.graph", "hyperlattice.graph.symmetry", "hyperlattice.graph.lattice",
               "hyperlattice.graph.sectors"}
    found = _imports(probe / "graph" / "symmetry.py", modules, root=probe)
    assert ("hyperlattice.graph.sectors", 4, False) in found
    assert "sectors" not in LEAVES["symmetry"]
