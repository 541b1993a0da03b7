"""Sphinx configuration of the hyperlattice documentation (``make docs``).

The pages in ``docs/*.md`` (MyST Markdown) and an API reference generated from the numpydoc
docstrings of every public module (``api.rst``: autosummary, recursive). Built with warnings as
errors in CI.

The maths is converted to MathML while the site is built (``_ext/mathml.py``, with
``latex2mathml`` from PyPI), so the pages show it without a network or a script; code blocks wrap
instead of scrolling sideways (``_static/hyperlattice.css``).
"""

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent / "_ext"))

project = "hyperlattice"
author = "hyperlattice developers"
copyright = "2026, hyperlattice developers (MIT licence)"
extensions = ["myst_parser", "sphinx.ext.autodoc", "sphinx.ext.autosummary", "numpydoc", "mathml"]
# MathML at build time, no MathJax from a CDN (see _ext/mathml.py)
html_math_renderer = "mathml"
source_suffix = {".md": "markdown", ".rst": "restructuredtext"}
exclude_patterns = ["_build", "data", "img/*.md", "_ext"]
myst_enable_extensions = ["dollarmath"]
suppress_warnings = ["myst.header"]
# every public module is documented on its own page, each function once: members defined in the
# module itself (re-exports such as ``hyperlattice.Lattice`` are documented where they live)
autosummary_generate = True
autodoc_default_options = {"members": True, "ignore-module-all": True}
numpydoc_show_class_members = False
html_theme = "alabaster"
html_title = "hyperlattice"
html_theme_options = {"page_width": "1180px", "sidebar_width": "230px"}
html_static_path = ["_static"]
html_css_files = ["hyperlattice.css"]
