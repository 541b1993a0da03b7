"""The report's building blocks and writers: tables (CSV/JSON), figures (PNG/SVG), Markdown, HTML.

Nothing here computes physics; :mod:`.sections` fills :class:`Section` objects and
:func:`write_md` / :func:`write_html` render them. Output is deterministic (no dates in the
figure files), so two runs give byte-identical files.
"""

from __future__ import annotations

import base64
import csv
import html
import io
import json
import math
import numbers
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .. import _validate

__all__ = ["Table", "Figure", "Section", "fmt", "save_figure", "write_md", "write_html"]


@dataclass
class Table:
    """A table of the report, written as ``table_<name>.csv`` and ``table_<name>.json``."""

    name: str
    columns: list[str]
    rows: list[list]
    caption: str = ""

    def write(self, out: Path) -> None:
        """Write the CSV and JSON files into ``out``."""
        with open(out / f"table_{self.name}.csv", "w", newline="") as fh:
            w = csv.writer(fh)
            w.writerow(self.columns)
            w.writerows(self.rows)
        with open(out / f"table_{self.name}.json", "w") as fh:
            json.dump([dict(zip(self.columns, r)) for r in self.rows], fh, indent=1)


@dataclass
class Figure:
    """A figure already written as ``fig_<name>.png`` / ``.svg``; ``png`` is embedded in the HTML."""

    name: str
    caption: str
    png: bytes = b""


@dataclass
class Section:
    """One section of the report."""

    title: str
    labels: str  # paper labels reproduced, e.g. "Tab1, SuppTab1"
    text: list[str] = field(default_factory=list)
    tables: list[Table] = field(default_factory=list)
    figures: list[Figure] = field(default_factory=list)


def fmt(x, digits: int = 12) -> str:
    """A table cell: strings as they are, integers exactly, floats with ``digits`` decimals, NaN/None empty."""
    if isinstance(x, str):
        return x
    if isinstance(x, (int, np.integer)):
        return str(int(x))
    if x is None or (isinstance(x, float) and math.isnan(x)):
        return ""
    if not isinstance(x, numbers.Real):
        raise ValueError(f"a table cell must be a number, a string or None, got {type(x).__name__}.")
    return f"{x:.{digits}f}"


def save_figure(fig: matplotlib.figure.Figure, out: Path, name: str, caption: str) -> Figure:
    """Write ``fig`` as ``fig_<name>.png`` and ``.svg`` without timestamps, close it, return the Figure."""
    out = _validate.directory("out", out, create=False)
    import matplotlib.pyplot as plt

    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=110, metadata={"Software": None})
    png = buf.getvalue()
    (out / f"fig_{name}.png").write_bytes(png)
    fig.savefig(out / f"fig_{name}.svg", format="svg", metadata={"Date": None})
    plt.close(fig)
    return Figure(name=name, caption=caption, png=png)


def _md_table(t: Table) -> list[str]:
    lines = [f"*{t.caption}* (`table_{t.name}.csv`)", "", "| " + " | ".join(t.columns) + " |",
             "|" + "---|" * len(t.columns)]
    for r in t.rows:
        lines.append("| " + " | ".join(fmt(v) for v in r) + " |")
    return lines + [""]


def write_md(sections: list[Section], header: list[str], out: Path) -> None:
    """Write ``report.md`` (figures linked as ``fig_*.png``)."""
    out = _validate.directory("out", out, create=False)
    lines = list(header)
    for s in sections:
        lines += [f"## {s.title}", "", f"Reproduces: {s.labels}", ""]
        for p in s.text:
            lines += [p, ""]
        for t in s.tables:
            lines += _md_table(t)
        for f in s.figures:
            lines += [f"![{f.name}](fig_{f.name}.png)", "", f"*{f.caption}* (vector: `fig_{f.name}.svg`)", ""]
    (out / "report.md").write_text("\n".join(lines))


def write_html(sections: list[Section], header: list[str], out: Path) -> None:
    """Write ``report.html``, self-contained: figures embedded as base64 PNG, no external references."""
    out = _validate.directory("out", out, create=False)
    e = html.escape
    parts = ["<!DOCTYPE html>", '<html lang="en">', "<head>", '<meta charset="utf-8">',
             "<title>hyperlattice: reproduction of Boettcher et al., PRA 102, 032208</title>",
             "<style>body{font-family:sans-serif;max-width:1100px;margin:2em auto;line-height:1.4}"
             "table{border-collapse:collapse;font-size:0.85em;margin:0.5em 0}"
             "td,th{border:1px solid #bbb;padding:2px 6px;text-align:right}"
             "th{background:#eee}td.flag{color:#b00;font-weight:bold}"
             "img{max-width:100%}figcaption{font-size:0.9em;color:#333}.cap{font-style:italic}</style>",
             "</head>", "<body>"]
    for line in header:
        if line.startswith("# "):
            parts.append(f"<h1>{e(line[2:])}</h1>")
        elif line:
            parts.append(f"<p>{e(line)}</p>")
    for s in sections:
        parts.append(f"<h2>{e(s.title)}</h2>")
        parts.append(f"<p><b>Reproduces:</b> {e(s.labels)}</p>")
        for p in s.text:
            parts.append(f"<p>{e(p)}</p>")
        for t in s.tables:
            parts.append(f'<p class="cap">{e(t.caption)} (<code>table_{e(t.name)}.csv</code>)</p>')
            parts.append("<table><thead><tr>" + "".join(f"<th>{e(c)}</th>" for c in t.columns) + "</tr></thead><tbody>")
            for r in t.rows:
                cells = []
                for c, v in zip(t.columns, r):
                    cls = ' class="flag"' if c.endswith("flag") and v else ""
                    cells.append(f"<td{cls}>{e(fmt(v))}</td>")
                parts.append("<tr>" + "".join(cells) + "</tr>")
            parts.append("</tbody></table>")
        for f in s.figures:
            b64 = base64.b64encode(f.png).decode("ascii")
            parts.append(f'<figure><img alt="{e(f.name)}" src="data:image/png;base64,{b64}">'
                         f"<figcaption>{e(f.caption)}</figcaption></figure>")
    parts += ["</body>", "</html>", ""]
    (out / "report.html").write_text("\n".join(parts))


# every public function above checks its annotated argument types at the door (issue 19)
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
