"""Sphinx extension: the maths of the docs as MathML, converted while the site is built.

The default ``sphinx.ext.mathjax`` leaves ``\\(...\\)`` in the pages for a script from a CDN to
typeset in the reader's browser: without a network the reader sees raw LaTeX. Here every
``:math:`` role, ``$...$``/``$$...$$`` (MyST ``dollarmath``) and ``.. math::`` block is converted to
MathML by ``latex2mathml`` (pure Python, from PyPI) at build time; browsers draw MathML natively
(MathML Core: Chromium >= 109, Firefox, Safari), so the pages need no script and no network.

A formula ``latex2mathml`` cannot convert is a build warning (an error under ``sphinx -W``), naming
the document and the formula, never raw LaTeX in a page.
"""

from __future__ import annotations

from docutils import nodes
from sphinx.util import logging

logger = logging.getLogger(__name__)


def to_mathml(latex: str, display: bool) -> str:
    """The MathML ``<math>`` element of ``latex`` (``display="block"`` for a displayed formula)."""
    from latex2mathml.converter import convert

    return convert(latex.strip(), display="block" if display else "inline")


def _render(self, node, display: bool) -> None:
    latex = node.astext()
    try:
        markup = to_mathml(latex, display)
    except Exception as exc:  # latex2mathml raises its own exception types for unknown commands
        logger.warning("formula not converted to MathML (%s): %s", type(exc).__name__, latex,
                       location=node)
        markup = f'<code class="math-source">{self.encode(latex)}</code>'
    if display:
        self.body.append(f'<div class="math-display">{markup}</div>\n')
    else:
        self.body.append(markup)
    raise nodes.SkipNode


def visit_math(self, node) -> None:
    _render(self, node, display=False)


def visit_displaymath(self, node) -> None:
    _render(self, node, display=True)


def setup(app):
    app.add_html_math_renderer("mathml", (visit_math, None), (visit_displaymath, None))
    return {"parallel_read_safe": True, "parallel_write_safe": True}
