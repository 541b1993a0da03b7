r"""``hyperlattice reproduce``: every table and figure of the paper, recomputed, in one report.

The report puts the paper's printed values (:mod:`hyperlattice.paper_values`) beside the
package's numbers and flags every printed value that differs from the computed one by more than
half a unit of its last printed digit, with the reason where it is known (misprint, rounding, or
the paper's ~3-digit sparse estimates for l >= 8). Outputs in ``out_dir``:

* ``report.md`` and ``report.html`` (self-contained: figures embedded as base64 PNG),
* ``table_*.csv`` / ``table_*.json`` for every table (``table_paper_table4.csv`` is the paper's Table IV),
* ``fig_*.png`` and ``fig_*.svg`` for every figure (``fig_paper_fig3.png`` is the paper's Fig. 3; the
  report's own figures are named by what they show),
* ``timings.json`` (wall-clock times; kept out of the report so that it is deterministic),
* ``_report.json``, the manifest: every file the report wrote, with its SHA-256
  (:mod:`.manifest`). ``out_dir`` must be new, empty, or an earlier report's whose manifest
  verifies (every file listed, none changed), so that no file of the user's is ever overwritten.

Expensive results (graph spectra, Green functions) are cached with :class:`hyperlattice.cache.Cache`.

Layout: :mod:`.sections` builds the sections (formatting only), :mod:`.data` fetches the cached
numbers, :mod:`.writers` writes tables, figures, Markdown and HTML.
"""

from __future__ import annotations

import json
import time
from pathlib import Path
from typing import Callable

import numpy as np

from .. import __version__, _validate
from ..cache import Cache
from . import manifest

__all__ = ["reproduce"]


#: the report's manifest (:mod:`.manifest`): written first and updated with every file the report
#: writes (name and SHA-256), so that a rerun may overwrite exactly those files; a directory whose
#: manifest does not verify, or without one and with anything in it, is refused
MARKER = manifest.NAME


def _out_directory(name: str, value) -> Path:
    """The report's output directory, checked (and created) before any work: new, empty, or one an
    earlier :func:`reproduce` wrote whose manifest verifies (:func:`.manifest.problem`); anything
    else is refused in one sentence."""
    path = _validate.directory(name, value)
    if (path / MARKER).is_file():
        why = manifest.problem(path)
        if why is not None:
            raise ValueError(f"{name} {str(path)!r} is not a report directory that may be overwritten ({why}); "
                             "give a new or empty directory, so that nothing of yours is overwritten.")
        return path
    return _validate.owned_directory(name, value, marker=MARKER, what="a report")


def reproduce(out_dir: str | Path = "reproduction", max_rings: int = 10, *, cache: Cache | None = None,
              progress: Callable[[str], None] | None = None) -> dict:
    """Recompute the paper's tables and figures into ``out_dir``; return a summary dict.

    Parameters
    ----------
    out_dir : path
        Output directory (created if needed).
    max_rings : int
        Largest number of rings in the spectrum tables (2..14; the paper's tables stop at 10).
    cache : Cache, optional
        Result cache (default: :class:`Cache` in the default directory).
    progress : callable, optional
        Called with a short message before each stage.

    Returns
    -------
    dict
        ``out_dir``, ``sections`` (titles, in the report's order), ``records`` (one dict per l of the
        spectrum table), ``cache_hits`` (entries read from earlier runs), ``cache_misses`` (values
        computed), ``cache_reused`` (entries this run wrote and read again), ``seconds``.

    Raises
    ------
    ValueError
        If ``max_rings`` is not an integer in [2, 14], ``cache`` is not a :class:`Cache`, or
        ``out_dir`` cannot be created or written to, or holds files that an earlier run did not
        write (a directory of the user's is never written into).

    See Also
    --------
    hyperlattice.paper_values : the printed values the report compares with.

    Examples
    --------
    A full run takes minutes (``hyperlattice reproduce`` on the command line does the same); the
    arguments are checked before anything is computed or written:

    >>> import tempfile
    >>> from hyperlattice.report import reproduce
    >>> with tempfile.TemporaryDirectory() as d:
    ...     reproduce(d, max_rings=1)
    Traceback (most recent call last):
        ...
    ValueError: max_rings must be an integer between 2 and 14, got 1.

    A run is ``reproduce("reproduction", max_rings=10)``; it returns, e.g.,
    ``summary["sections"]`` (the section titles) and ``summary["seconds"]``.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from . import sections as sec
    from .below_band import holography_section, qubits_section
    from .bosons import bosons_section
    from .qmc_lobe import qmc_lobe_section
    from .disorder import disorder_section
    from .infinite import band_interval_sentence, infinite_section
    from .limits import limits_section
    from .magnetism import magnetism_section
    from .topology import topology_section
    from .writers import write_html, write_md

    if isinstance(max_rings, bool) or not isinstance(max_rings, (int, np.integer)) or not 2 <= max_rings <= 14:
        raise ValueError(f"max_rings must be an integer between 2 and 14, got {max_rings!r}.")
    if cache is not None and not isinstance(cache, Cache):
        raise ValueError(f"cache must be a Cache (or None for the default one), got {type(cache).__name__}.")
    out = _out_directory("out_dir", out_dir)
    manifest.start(out, __version__)
    cache = cache if cache is not None else Cache()
    progress = progress or (lambda msg: None)
    timings: dict = {}
    t_start = time.perf_counter()
    plt.rcParams["svg.hashsalt"] = "hyperlattice"  # deterministic SVG ids

    geometry, counts, fig1 = sec.geometry_section(), sec.counts_section(max_rings), sec.fig1_section(out)
    spec_section, records = sec.spectrum_section(cache, max_rings, timings, progress)
    fig2 = sec.fig2_section(records, out, progress)
    limits = limits_section(cache, max_rings, out, progress)
    green = sec.green_section(cache, max_rings, out, progress)
    scaling = sec.scaling_section(out, progress)
    # beyond the paper, each from its own module
    magnetic = sec.magnetic_section(out, progress, cache)
    infinite = infinite_section(out, progress)
    infinite.text.append(band_interval_sentence(limits, infinite))
    beyond = [magnetic, limits, infinite, holography_section(out, progress), qubits_section(out, progress),
              disorder_section(out, progress), bosons_section(out, progress), qmc_lobe_section(out, progress),
              magnetism_section(out, progress),
              topology_section(out, progress)]
    # the paper's sections in the order the paper prints them (main text, then the appendices), then the rest
    sections = [fig1, counts, spec_section, fig2, green, scaling, geometry] + beyond

    stored = [s for s in sections if s.provenance]
    header = ["# Reproduction of Boettcher, Bienias, Belyansky, Kollár, Gorshkov, PRA 102, 032208 (2020)", "",
              f"Computed by hyperlattice {__version__} with max_rings = {max_rings}. Every number below is computed "
              "by this run (expensive results through the result cache, which holds only what the package "
              "computed for the same inputs and version)"
              + (", except where a section's Provenance line names stored values: "
                 + "; ".join(f"“{s.title}”" for s in stored) if stored else "")
              + ". The paper's printed values stand beside the computed ones. A flag (≠) marks a printed value "
              "that differs from the computation by more than half a unit of its last printed digit; the reason "
              "is given where known. Equations, figures, tables and appendices are numbered as the paper prints "
              "them.", ""]
    for s in sections:
        for t in s.tables:
            t.write(out)
    write_md(sections, header, out)
    write_html(sections, header, out)
    timings["total"] = time.perf_counter() - t_start
    with manifest.writing(out, "timings.json") as path:
        path.write_text(json.dumps(timings, indent=1, sort_keys=True))
    return {"out_dir": str(out), "sections": [s.title for s in sections], "records": records,
            "cache_hits": cache.hits, "cache_misses": cache.misses, "cache_reused": cache.reused,
            "seconds": timings["total"]}


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
