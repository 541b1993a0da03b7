"""Sphinx configuration of the hyperlattice documentation (``make docs``).

The pages in ``docs/*.md`` (MyST Markdown) and an API reference generated from the numpydoc
docstrings of every public module (``api.rst``: autosummary, recursive). Built with warnings as
errors in CI.
"""

project = "hyperlattice"
author = "hyperlattice developers"
copyright = "2026, hyperlattice developers (MIT licence)"
extensions = ["myst_parser", "sphinx.ext.autodoc", "sphinx.ext.autosummary", "sphinx.ext.mathjax", "numpydoc"]
source_suffix = {".md": "markdown", ".rst": "restructuredtext"}
exclude_patterns = ["_build", "data", "img/*.md"]
myst_enable_extensions = ["dollarmath"]
suppress_warnings = ["myst.header"]
# every public module is documented on its own page, each function once: members defined in the
# module itself (re-exports such as ``hyperlattice.Lattice`` are documented where they live)
autosummary_generate = True
autodoc_default_options = {"members": True, "ignore-module-all": True}
numpydoc_show_class_members = False
html_theme = "alabaster"
html_title = "hyperlattice"
