"""Every ``Examples`` section in a public docstring runs, as written, and prints what it says.

The API reference (``make docs``) shows these examples; this file makes them tests. Each public
module of ``hyperlattice`` (its ``__all__``) is searched with :mod:`doctest`: functions, classes and
their methods. Examples print rounded numbers (``f"{x:.6f}"``, ``round``) so that their output does
not depend on the last bits of a BLAS kernel; ``ELLIPSIS`` and ``NORMALIZE_WHITESPACE`` are on.

A second test states which public functions must carry the numpydoc sections (Parameters when the
function takes any, Returns, Examples): ``COMPLETE`` lists the modules whose public functions all do,
so a new function there without them fails.

A third test does the same for the public classes of the ``COMPLETE`` modules (public: named in the
module's ``__all__``, defined there, not starting with ``_``; every class the package exports lazily
is such a name, which a fourth test holds). The rule, as :func:`_class_sections_missing` checks it:

* the class docstring has a summary line and an Examples section;
* it names every constructor argument the class itself declares: for a dataclass (every result,
  frozen) its own ``init`` fields under numpydoc's **Attributes** (fields inherited from a base such
  as :class:`~hyperlattice.results.Levels` are documented on the base), for any other class with its
  own ``__init__`` the arguments under **Parameters**; ``p, q : int`` documents both names, and
  every entry has a description (prose after the list belongs under Notes);
* exceptions and warnings need only the summary (they carry a message; the summary says when they
  are raised);
* a public method defined in the class body (plain, class- or static method; properties and
  inherited methods are not counted) whose signature takes anything besides ``self``/``cls`` has
  Parameters, and Returns (or Yields) unless it is annotated ``-> None``. Methods without
  arguments need only their one-line summary.
"""

from __future__ import annotations

import dataclasses
import doctest
import importlib
import inspect
import pkgutil

import pytest

import hyperlattice

FLAGS = doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE

# modules whose every public function has Parameters (if it takes any), Returns and Examples
COMPLETE: tuple[str, ...] = (
    "hyperlattice.bosons.basis",
    "hyperlattice.bosons.ed",
    "hyperlattice.bosons.gp",
    "hyperlattice.bosons.meanfield",
    "hyperlattice.cache",
    "hyperlattice.bosons.thermal",
    "hyperlattice.bosons.strong_coupling",
    "hyperlattice.bosons.sse",
    "hyperlattice.graph.butterfly",
    "hyperlattice.graph.levels",
    "hyperlattice.compare.bosons",
    "hyperlattice.compare.boundary",
    "hyperlattice.compare.correlation",
    "hyperlattice.compare.disorder",
    "hyperlattice.compare.dos",
    "hyperlattice.compare.green",
    "hyperlattice.compare.levels",
    "hyperlattice.compare.limits",
    "hyperlattice.compare.magnetic",
    "hyperlattice.compare.qubits",
    "hyperlattice.compare.scaling",
    "hyperlattice.compare.sums",
    "hyperlattice.continuum.gp",
    "hyperlattice.continuum.green",
    "hyperlattice.continuum.magnetic",
    "hyperlattice.continuum.massive",
    "hyperlattice.continuum.scba",
    "hyperlattice.continuum.special",
    "hyperlattice.continuum.spectrum",
    "hyperlattice.dictionary",
    "hyperlattice.geometry",
    "hyperlattice.graph.bands",
    "hyperlattice.graph.clusters",
    "hyperlattice.graph.disorder",
    "hyperlattice.graph.factor",
    "hyperlattice.graph.flux",
    "hyperlattice.graph.green",
    "hyperlattice.graph.groups",
    "hyperlattice.graph.kpm",
    "hyperlattice.graph.lattice",
    "hyperlattice.graph.operators",
    "hyperlattice.graph.qubits",
    "hyperlattice.graph.sectors",
    "hyperlattice.graph.solvers",
    "hyperlattice.graph.spectrum",
    "hyperlattice.graph.symmetry",
    "hyperlattice.graph.walks",
    "hyperlattice.paper_labels",
    "hyperlattice.paper_values",
    "hyperlattice.plots.bands",
    "hyperlattice.plots.basic",
    "hyperlattice.plots.bosons",
    "hyperlattice.plots.boundary",
    "hyperlattice.plots.disorder",
    "hyperlattice.plots.dos",
    "hyperlattice.plots.green",
    "hyperlattice.plots.limits",
    "hyperlattice.plots.magnetic",
    "hyperlattice.plots.paper",
    "hyperlattice.plots.scaling",
    "hyperlattice.report",
    "hyperlattice.report.below_band",
    "hyperlattice.report.bosons",
    "hyperlattice.report.data",
    "hyperlattice.report.disorder",
    "hyperlattice.report.infinite",
    "hyperlattice.report.limits",
    "hyperlattice.report.sections",
    "hyperlattice.report.writers",
    "hyperlattice.results",
    "hyperlattice.sweep.engine",
    "hyperlattice.sweep.store",
    "hyperlattice.sweep.tasks",
)


def _public_modules() -> list[str]:
    names = []
    for info in pkgutil.walk_packages(hyperlattice.__path__, "hyperlattice."):
        parts = info.name.split(".")
        if any(p.startswith("_") for p in parts[1:]) or parts[1] == "cli":
            continue
        names.append(info.name)
    return sorted(names)


def _doctests(modname: str) -> list[doctest.DocTest]:
    mod = importlib.import_module(modname)
    finder = doctest.DocTestFinder(exclude_empty=True)
    tests = []
    for name in getattr(mod, "__all__", ()):
        obj = getattr(mod, name, None)
        if obj is None or getattr(obj, "__module__", None) != modname:
            continue                     # re-exported: tested where it is defined
        if not (inspect.isfunction(obj) or inspect.isclass(obj)):
            continue
        for t in finder.find(obj, f"{modname}.{name}", module=mod, globs={}):
            if t.examples:
                tests.append(t)
    return tests


_ALL = [t for m in _public_modules() for t in _doctests(m)]


def test_there_are_docstring_examples():
    assert len(_ALL) >= 5


@pytest.mark.parametrize("test", _ALL, ids=[t.name for t in _ALL])
def test_docstring_example(test):
    runner = doctest.DocTestRunner(optionflags=FLAGS)
    out: list[str] = []
    test.globs = dict(test.globs)
    result = runner.run(test, out=out.append, clear_globs=True)
    assert result.failed == 0, "".join(out)


def test_a_wrong_docstring_example_fails():
    def f():
        """
        >>> 1 + 1
        3
        """

    (t,) = doctest.DocTestFinder().find(f, "f", globs={})
    res = doctest.DocTestRunner(optionflags=FLAGS).run(t, out=lambda s: None)
    assert res.failed == 1


def _sections_missing(fn) -> list[str]:
    from numpydoc.docscrape import FunctionDoc

    doc = FunctionDoc(fn)
    missing = []
    if inspect.signature(fn).parameters and not doc["Parameters"]:
        missing.append("Parameters")
    if not (doc["Returns"] or doc["Yields"]):
        missing.append("Returns")
    if not doc["Examples"]:
        missing.append("Examples")
    return missing


def test_public_functions_have_numpydoc_sections():
    pytest.importorskip("numpydoc")
    bad = {}
    for modname in COMPLETE:
        mod = importlib.import_module(modname)
        for name in mod.__all__:
            obj = getattr(mod, name)
            if inspect.isfunction(obj) and obj.__module__ == modname:
                missing = _sections_missing(obj)
                if missing:
                    bad[f"{modname}.{name}"] = missing
    assert not bad, f"public functions without numpydoc sections: {bad}"


def test_the_section_check_finds_a_missing_section():
    pytest.importorskip("numpydoc")

    def f(x):
        """One line.

        Parameters
        ----------
        x : float
            A number.
        """
        return x

    assert _sections_missing(f) == ["Returns", "Examples"]


def _documented_names(doc, section: str) -> set[str]:
    # numpydoc keeps "p, q" as one entry; "*args" keeps its star
    return {n.strip().lstrip("*") for item in doc[section] for n in item.name.split(",")}


def _own_arguments(cls) -> tuple[str, list[str]]:
    """The section and the constructor arguments a class docstring must name (see the module doc)."""
    if dataclasses.is_dataclass(cls):
        own = cls.__dict__.get("__annotations__", {})
        return "Attributes", [f.name for f in dataclasses.fields(cls) if f.init and f.name in own]
    if "__init__" in vars(cls):
        params = inspect.signature(cls.__init__).parameters
        return "Parameters", [n for n, p in params.items() if n != "self"
                              and p.kind not in (p.VAR_POSITIONAL, p.VAR_KEYWORD)]
    return "Parameters", []


def _class_sections_missing(cls) -> list[str]:
    from numpydoc.docscrape import ClassDoc, FunctionDoc

    doc = ClassDoc(cls, config={"show_class_members": False})
    missing = []
    if not doc["Summary"]:
        missing.append("Summary")
    if issubclass(cls, (BaseException, Warning)):
        return missing
    section, names = _own_arguments(cls)
    undocumented = [n for n in names if n not in _documented_names(doc, section)]
    if undocumented:
        missing.append(f"{section}: {', '.join(undocumented)}")
    # an entry without a description is usually prose that fell into the section (a paragraph
    # after the list is read as one more name): it belongs under Notes
    for sec in ("Parameters", "Attributes"):
        bare = [item.name for item in doc[sec] if not "".join(item.desc).strip()]
        if bare:
            missing.append(f"{sec} without description: {', '.join(bare)}")
    if not doc["Examples"]:
        missing.append("Examples")
    for name, member in vars(cls).items():
        if name.startswith("_"):
            continue
        fn = member.__func__ if isinstance(member, (classmethod, staticmethod)) else member
        if not inspect.isfunction(fn):
            continue                                  # properties, class constants
        sig = inspect.signature(fn)
        if not [n for n in sig.parameters if n not in ("self", "cls")]:
            continue
        mdoc = FunctionDoc(fn)
        if not mdoc["Parameters"]:
            missing.append(f"{name}: Parameters")
        returns_none = sig.return_annotation in (None, "None")
        if not returns_none and not (mdoc["Returns"] or mdoc["Yields"]):
            missing.append(f"{name}: Returns")
    return missing


def _classes_missing(modname: str) -> dict[str, list[str]]:
    mod = importlib.import_module(modname)
    bad = {}
    for name in mod.__all__:
        obj = getattr(mod, name)
        if inspect.isclass(obj) and obj.__module__ == modname and not name.startswith("_"):
            missing = _class_sections_missing(obj)
            if missing:
                bad[f"{modname}.{name}"] = missing
    return bad


def test_public_classes_have_numpydoc_sections():
    pytest.importorskip("numpydoc")
    bad = {}
    for modname in COMPLETE:
        bad.update(_classes_missing(modname))
    assert not bad, f"public classes without numpydoc sections: {bad}"


def test_exported_classes_are_checked():
    # the package's lazy exports (hyperlattice.X) are covered by the class check above only if they
    # live in a COMPLETE module and are named in its __all__
    unchecked = []
    for name in hyperlattice._EXPORTS:
        obj = getattr(hyperlattice, name)
        if inspect.isclass(obj):
            mod = importlib.import_module(obj.__module__)
            if obj.__module__ not in COMPLETE or name not in getattr(mod, "__all__", ()):
                unchecked.append(f"{name} ({obj.__module__})")
    assert not unchecked, f"exported classes outside the class check: {unchecked}"


def test_the_class_check_finds_missing_sections():
    pytest.importorskip("numpydoc")

    @dataclasses.dataclass(frozen=True)
    class Good:
        """A level.

        Attributes
        ----------
        energy, width : float
            In units of t.

        Examples
        --------
        >>> Good(energy=1.0, width=0.5).energy
        1.0
        """

        energy: float
        width: float

        def shifted(self, by: float) -> "Good":
            """Shifted.

            Parameters
            ----------
            by : float
                Shift.

            Returns
            -------
            Good
                The shifted level.
            """
            return Good(energy=self.energy + by, width=self.width)

        def show(self) -> None:
            """Print nothing."""

    @dataclasses.dataclass(frozen=True)
    class Bad:
        """A level.

        Attributes
        ----------
        energy : float
            In units of t.

        Energies are in units of t.
        """

        energy: float
        width: float

        def shifted(self, by):
            """Shifted."""

    class Plain:
        """Holds x.

        Parameters
        ----------
        x : int
            A number.

        Examples
        --------
        >>> Plain(1, y=2).x
        1
        """

        def __init__(self, x, *, y=0):
            self.x = x

    assert _class_sections_missing(Good) == []
    assert _class_sections_missing(Bad) == ["Attributes: width",
                                            "Attributes without description: Energies are in units of t.",
                                            "Examples", "shifted: Parameters", "shifted: Returns"]
    assert _class_sections_missing(Plain) == ["Parameters: y"]
    assert _class_sections_missing(ValueError) == []
