"""Every fenced example of README.md and docs/*.md as a test (issue 21): the collector.

Sybil does the lexing and the bookkeeping: its Markdown lexers find the fences and the
``<!-- doctest: ... -->`` comments with their line numbers, a ``Document`` holds the examples
of one page in order with one namespace per page, and each ``Example`` evaluates through the
evaluator its ``Region`` carries. This module adds only what is particular to this project:
which fences are examples, what the comments mean, how a shell line runs, and how a quoted
output is compared with a tolerance. ``tests/test_docs_examples.py`` turns the examples into
parametrized pytest items (so markers, ids and ``-k`` are ordinary pytest ones, and the pages
need no conftest at the repository root, which Sybil's own pytest plugin would).

Which fences run
    ```python                          Python, in a fresh namespace (a reader pasting this block alone)
    ```bash ```sh ```shell ```console  shell; each command line runs with the package's
                                       virtualenv first on PATH, in a temporary directory, and
                                       must exit with 0; in ```console only ``$ `` lines are
                                       commands, the other lines are their output, compared
    anything else (```text, ```{toctree}, ...) is prose and never runs; a fence without a
    language (plain ```) fails the page's collection: write ```text for what is not an example.

Comments placed directly before a fence (only blank lines between; several may stack):
    <!-- doctest: continue -->            Python: run in the namespace of the page's previous
                                          Python block (a reader who pasted that one first)
    <!-- doctest: skip REASON -->         not run; REASON is required and shows in the report
    <!-- doctest: slow -->                pytest marker ``slow`` (CI still runs it)
    <!-- doctest: heavy REASON -->        pytest marker ``heavy``: minutes or GBs, deselected
                                          unless pytest runs with ``--run-heavy``
    <!-- doctest: output rtol=1e-3 atol=0 -->  before a ```text fence: what the previous example
                                          prints (stdout), numbers compared within the tolerances,
                                          all other text word for word (whitespace runs equal)

Comments placed directly before a paragraph, list item or table (its lines up to the next blank
line or the next list item) or before a ```text fence:
    <!-- doctest: numbers -->             the numbers of that block are numbers the page's previous
                                          example prints: the marked blocks after one example,
                                          read in order, must hold all its printed numbers and no
                                          others, each within one unit of its last quoted digit
                                          (the ``# =>`` rule below)
    <!-- doctest: numbers except-columns=7,8 -->  before a Markdown table: the table rows the
                                          previous example prints (its lines starting with
                                          ``|``), columns 7 and 8 (1-based: times, residuals that
                                          vary by machine) left out of both; the only numbers
                                          block after its example
    <!-- doctest: timing COMMAND -->      the block quotes measured times (or ratios of times):
                                          never checked; COMMAND, required, regenerates them
                                          (a ``benchmarks/NAME.py`` it names must exist)

Inside a Python block, a top-level expression whose line ends in ``# => QUOTED`` is checked: the
numbers of QUOTED (words between them are labels and are ignored) must equal, in order and in
number, the numbers of the expression's value (tuples, lists, dicts' values and arrays
flattened, a complex number as its real and imaginary parts, a string as the numbers in it),
each within one unit of its last quoted digit (``0.283128...`` or ``0.283128`` both mean
|x - 0.283128| <= 1e-6); a quoted integer must match exactly. A ``;`` ends QUOTED: what
follows is a remark, never checked (``# => b = -9.0954; N(r) ~ 14 rho + b``).

A comment that is not followed by a fence, or an unknown word, fails the page's collection:
a typo must not silently switch a check off.

All the examples of one page share one working directory (a file written by one example is read
by a later one, as in a reader's shell session), created for the test run.
"""

from __future__ import annotations

import ast
import contextlib
import io
import math
import os
import re
import subprocess
import sys
import tokenize
from dataclasses import dataclass, field
from pathlib import Path

from sybil import Document, Region
from sybil.parsers.markdown.lexers import DirectiveInHTMLCommentLexer, RawFencedCodeBlockLexer

ROOT = Path(__file__).resolve().parents[1]
PYTHON_LANGUAGES = frozenset({"python", "py"})
SHELL_LANGUAGES = frozenset({"bash", "sh", "shell", "console"})
OUTPUT_LANGUAGES = frozenset({"text"})
#: a shell line running longer than this is a failure, not a hang (heavy examples get more)
SHELL_TIMEOUT = 900
HEAVY_SHELL_TIMEOUT = 4 * 3600

_NUMBER = re.compile(r"[-+−]?(?:\d+(?:[.,]\d+)*\.?\d*|\.\d+)(?:[eE][-+]?\d+)?|[-+]?(?:nan|inf)\b")


class DocExampleError(ValueError):
    """A page's ``<!-- doctest: ... -->`` annotations cannot be understood."""


@dataclass
class Options:
    """What the comments before one fence asked for."""

    cont: bool = False
    skip: str | None = None
    slow: bool = False
    heavy: str | None = None
    output: dict | None = None       # {"rtol": float, "atol": float} for an output fence

    def markers(self) -> tuple[str, ...]:
        return tuple(m for m, on in (("slow", self.slow), ("heavy", self.heavy is not None)) if on)


@dataclass
class Expected:
    """A quoted output: the text of a ```text fence and its tolerances."""

    text: str
    line: int
    rtol: float
    atol: float


@dataclass
class Spec:
    """One runnable example: its kind, source, first source line and what it expects."""

    kind: str                        # "python" or "shell"
    language: str
    source: str
    line: int                        # line of the first source line in the page
    options: Options
    expected: Expected | None = None
    path: str = ""
    numbers: list = field(default_factory=list)   # [(text, line)] of its ``doctest: numbers`` blocks
    except_columns: tuple | None = None           # a numbers table compared without these columns


# ------------------------------------------------------------------------------------------------
# parsing
# ------------------------------------------------------------------------------------------------

_FENCES = RawFencedCodeBlockLexer(info_pattern=re.compile(r"(?P<info>[^\n]*)$\n", re.MULTILINE))
_DIRECTIVES = DirectiveInHTMLCommentLexer(directive="doctest", arguments=r"[^\n]*?")


def _line_of(text: str, position: int) -> int:
    return text.count("\n", 0, position) + 1


_BLOCK_DIRECTIVES = ("numbers", "timing")


def _following_block(text: str, end: int) -> tuple[str, int]:
    """The block after a comment ending at ``end``: its lines up to a blank line or the next list
    item (a fence: up to its closing fence), and its first line's position."""
    lines = text[end:].split("\n")
    k = 1 if lines and not lines[0].strip() else 0   # the rest of the comment's own line
    while k < len(lines) and not lines[k].strip():
        k += 1
    start = end + sum(len(line) + 1 for line in lines[:k])
    block = []
    fence = k < len(lines) and lines[k].lstrip().startswith("```")
    for j in range(k, len(lines)):
        line = lines[j]
        if not fence and (not line.strip() or (block and line.lstrip().startswith(("- ", "* ")))):
            break
        block.append(line)
        if fence and j > k and line.strip() == "```":
            break
    return "\n".join(block), start


def _parse_block_directive(word: str, rest: str, text: str, end: int, where: str):
    block, start = _following_block(text, end)
    if not block.strip() or block.lstrip().startswith("<!--"):
        raise DocExampleError(f"{where}: 'doctest: {word}' must be followed by a paragraph, a table "
                              "or a ```text fence.")
    if word == "timing":
        if not rest:
            raise DocExampleError(f"{where}: 'doctest: timing' needs the command that regenerates "
                                  "the times.")
        for script in re.findall(r"benchmarks/\w+\.py", rest):
            if not (ROOT / script).is_file():
                raise DocExampleError(f"{where}: 'doctest: timing' names {script}, which does not exist.")
        return None
    columns = None
    if rest:
        name, sep, value = rest.partition("=")
        if name != "except-columns" or not re.fullmatch(r"\d+(,\d+)*", value):
            raise DocExampleError(f"{where}: 'doctest: numbers' takes only except-columns=N,M, not {rest!r}.")
        columns = tuple(int(v) for v in value.split(","))
        if not all(line.lstrip().startswith("|") for line in block.splitlines()):
            raise DocExampleError(f"{where}: 'doctest: numbers except-columns=...' goes before a table.")
        block = table_without(block, columns)
    if block.lstrip().startswith("```"):
        body = block.split("\n")[1:-1]
        if block.lstrip()[3:].split("\n", 1)[0].strip() not in OUTPUT_LANGUAGES:
            raise DocExampleError(f"{where}: 'doctest: numbers' goes before prose or a ```text fence.")
        block = "\n".join(body)
    if not _QUOTED.findall(block):
        raise DocExampleError(f"{where}: the block after 'doctest: numbers' quotes no number.")
    return block, _line_of(text, start), columns


def table_without(text: str, columns) -> str:
    """The Markdown table rows of ``text`` (lines starting with ``|``) without the given 1-based
    columns; other lines are dropped."""
    rows = []
    for line in text.splitlines():
        if line.lstrip().startswith("|"):
            cells = line.strip().strip("|").split("|")
            rows.append("| " + " | ".join(c.strip() for k, c in enumerate(cells, 1) if k not in columns) + " |")
    return "\n".join(rows)


def _parse_options(arguments: str, where: str, options: Options) -> None:
    words = arguments.strip().split(None, 1)
    if not words:
        raise DocExampleError(f"{where}: an empty doctest comment.")
    word, rest = words[0], (words[1].strip() if len(words) > 1 else "")
    if word == "continue":
        options.cont = True
    elif word == "slow":
        options.slow = True
    elif word == "skip":
        if not rest:
            raise DocExampleError(f"{where}: 'doctest: skip' needs a reason.")
        options.skip = rest
    elif word == "heavy":
        options.heavy = rest or "heavy"
    elif word == "output":
        tol = {"rtol": 0.0, "atol": 0.0}
        for item in rest.split():
            name, sep, value = item.partition("=")
            if not sep or name not in tol:
                raise DocExampleError(f"{where}: 'doctest: output' takes rtol=X and atol=X, not {item!r}.")
            tol[name] = float(value)
        options.output = tol
    else:
        raise DocExampleError(f"{where}: unknown doctest comment {word!r}.")


def parse_markdown(document: Document):
    """Sybil parser: one Region per runnable fence, evaluated by :func:`evaluate`."""
    text = document.text
    items = []
    for region in _DIRECTIVES(document):
        items.append((region.start, "directive", region))
    for region in _FENCES(document):
        items.append((region.start, "fence", region))
    items.sort(key=lambda item: item[0])

    pending: Options | None = None
    pending_end = 0
    last_spec: Spec | None = None
    specs: list[tuple[Region, Spec]] = []
    for start, kind, region in items:
        where = f"{document.path}:{_line_of(text, start)}"
        if kind == "directive":
            if pending is not None and text[pending_end:start].strip():
                raise DocExampleError(f"{where}: a doctest comment must be followed by a fence.")
            words = region.lexemes["arguments"].strip().split(None, 1)
            if words and words[0] in _BLOCK_DIRECTIVES:
                if pending is not None:
                    raise DocExampleError(f"{where}: 'doctest: {words[0]}' does not stack with "
                                          "other doctest comments.")
                end = text.find("-->", start) + 3
                quoted = _parse_block_directive(words[0], words[1].strip() if len(words) > 1 else "",
                                                text, end, where)
                if quoted is not None:
                    if last_spec is None:
                        raise DocExampleError(f"{where}: 'doctest: numbers' must follow the example "
                                              "that prints them.")
                    block, line, columns = quoted
                    if (columns is not None and last_spec.numbers) or last_spec.except_columns is not None:
                        raise DocExampleError(f"{where}: a 'doctest: numbers except-columns=...' table "
                                              "must be the only numbers block after its example.")
                    last_spec.numbers.append((block, line))
                    last_spec.except_columns = columns
                continue
            pending = pending or Options()
            _parse_options(region.lexemes["arguments"], where, pending)
            pending_end = text.find("-->", start) + 3
            continue
        options = Options()
        if pending is not None:
            if text[pending_end:start].strip():
                raise DocExampleError(f"{document.path}:{_line_of(text, pending_end)}: "
                                      "a doctest comment must be followed by a fence.")
            options, pending = pending, None
        language = region.lexemes["info"].strip().split(None, 1)[0] if region.lexemes["info"].strip() else ""
        if not language:
            raise DocExampleError(f"{where}: a fence without a language; an example gets its "
                                  "language (```python, ```bash, ...), anything else ```text.")
        source = str(region.lexemes["source"])
        first_line = _line_of(text, start) + 1
        if options.output is not None:
            if language not in OUTPUT_LANGUAGES:
                raise DocExampleError(f"{where}: 'doctest: output' goes before a ```text fence.")
            if last_spec is None or last_spec.expected is not None:
                raise DocExampleError(f"{where}: an output fence must follow the example that prints it.")
            last_spec.expected = Expected(source, first_line, options.output["rtol"], options.output["atol"])
            continue
        if language in PYTHON_LANGUAGES:
            spec_kind = "python"
        elif language in SHELL_LANGUAGES:
            spec_kind = "shell"
        else:
            if options != Options():
                raise DocExampleError(f"{where}: a doctest comment before a ```{language} fence, "
                                      "which never runs.")
            continue
        if options.cont and spec_kind != "python":
            raise DocExampleError(f"{where}: 'doctest: continue' applies to Python blocks only.")
        spec = Spec(spec_kind, language, source, first_line, options, path=document.path)
        specs.append((Region(region.start, region.end, parsed=spec, evaluator=evaluate), spec))
        last_spec = spec
    if pending is not None:
        raise DocExampleError(f"{document.path}:{_line_of(text, pending_end)}: "
                              "a doctest comment at the end of the page.")
    return [region for region, _ in specs]


def parse_file(path: Path) -> Document:
    return Document.parse(str(path), parse_markdown)


# ------------------------------------------------------------------------------------------------
# comparing a quoted output
# ------------------------------------------------------------------------------------------------

def _to_float(token: str) -> float:
    return float(token.replace("−", "-").replace(",", ""))


def compare_output(expected: str, actual: str, rtol: float, atol: float) -> str | None:
    """None if ``actual`` matches ``expected``, else a message naming the first difference."""
    def split(s):
        numbers = [m.group(0) for m in _NUMBER.finditer(s)]
        words = " ".join(_NUMBER.sub(" # ", s).split())
        return numbers, words

    e_num, e_words = split(expected)
    a_num, a_words = split(actual)
    if e_words != a_words or len(e_num) != len(a_num):
        return f"expected output\n{expected.rstrip()}\ngot\n{actual.rstrip()}"
    for k, (e, a) in enumerate(zip(e_num, a_num)):
        x, y = _to_float(e), _to_float(a)
        if x != x and y != y:
            continue
        if not abs(x - y) <= atol + rtol * abs(x):
            return (f"number {k + 1} of the output: expected {e}, got {a} (rtol={rtol}, atol={atol})\n"
                    f"expected output\n{expected.rstrip()}\ngot\n{actual.rstrip()}")
    return None


# ------------------------------------------------------------------------------------------------
# running
# ------------------------------------------------------------------------------------------------

def _state(namespace: dict) -> dict:
    """Per-page state kept in Sybil's document namespace (set by the test: ``cwd``)."""
    return namespace.setdefault("_doctest", {"python_ns": None})


_QUOTED = re.compile(r"(?<![\w.^])[-−+]?\d+(?:,\d{3})*(?:\.\d+)?(?:[eE][-+]?\d+)?")


def _flatten(value) -> list[float]:
    """The numbers of an expression's value, in reading order."""
    import numpy as np  # noqa: PLC0415

    if isinstance(value, str):                    # a name such as 'PSL(2,197)' quotes its numbers
        return [_to_float(token) for token in _QUOTED.findall(value)]
    if isinstance(value, bool) or value is None:
        return []
    if isinstance(value, (int, float, np.integer, np.floating)):
        return [float(value)]
    if isinstance(value, (complex, np.complexfloating)):
        return [float(value.real), float(value.imag)]
    if isinstance(value, np.ndarray):
        return [x for v in value.ravel().tolist() for x in _flatten(v)]
    if isinstance(value, dict):
        return [x for v in value.values() for x in _flatten(v)]
    if isinstance(value, (tuple, list)):
        return [x for v in value for x in _flatten(v)]
    raise TypeError(f"cannot read numbers from a {type(value).__name__}.")


def check_quoted(quoted: str, value) -> str | None:
    """None if ``value`` carries the numbers quoted in ``quoted`` (see the module docstring)."""
    expected = _QUOTED.findall(quoted)
    got = _flatten(value)
    return _check_numbers(expected, got, quoted, value)


def check_printed_numbers(quoted: str, printed: str) -> str | None:
    """None if the numbers of ``quoted`` are those of ``printed`` (a ``doctest: numbers`` check)."""
    got = [_to_float(token) for token in _QUOTED.findall(printed)]
    return _check_numbers(_QUOTED.findall(quoted), got, quoted, printed)


def _check_numbers(expected: list[str], got: list[float], quoted: str, value) -> str | None:
    if len(expected) != len(got):
        return f"quoted {len(expected)} numbers ({quoted!r}), the value has {len(got)}: {value!r}"
    for token, y in zip(expected, got):
        mantissa, _, exponent = token.replace("−", "-").lower().partition("e")
        x = float(mantissa.replace(",", "")) * 10.0 ** int(exponent or 0)
        if "." not in mantissa:
            tol = 0.0 if not exponent else 10.0 ** int(exponent)
        else:
            tol = 10.0 ** (int(exponent or 0) - len(mantissa.split(".")[1]))
        if not (abs(x - y) <= tol * (1 + 1e-9) or (math.isnan(x) and math.isnan(y))):
            return f"quoted {token}, the value has {y!r} (tolerance {tol:g}): {quoted!r}"
    return None


def _instrument(source: str, filename: str):
    """Compile ``source``, wrapping every ``expr  # => QUOTED`` in a check of its value."""
    tree = ast.parse(source, filename)
    comments = {tok.start[0]: tok.string for tok in tokenize.generate_tokens(io.StringIO(source).readline)
                if tok.type == tokenize.COMMENT}
    for node in tree.body:
        comment = comments.get(node.end_lineno, "").lstrip("#").strip()
        if isinstance(node, ast.Expr) and comment.startswith("=>"):
            quoted = comment[2:].split(";", 1)[0].strip()
            node.value = ast.Call(func=ast.Name("__doctest_quoted__", ast.Load()),
                                  args=[ast.Constant(node.end_lineno), ast.Constant(quoted),
                                        node.value], keywords=[])
    return compile(ast.fix_missing_locations(tree), filename, "exec")


def _run_python(spec: Spec, state: dict) -> str:
    if spec.options.cont:
        if state["python_ns"] is None:
            raise DocExampleError(f"{spec.path}:{spec.line}: 'doctest: continue' on the page's first "
                                  "Python block.")
        namespace = state["python_ns"]
    else:
        namespace = {"__name__": "__main__"}
    state["python_ns"] = namespace
    # line numbers of tracebacks are the page's own
    code = _instrument("\n" * (spec.line - 1) + spec.source, spec.path)

    def quoted_check(line, quoted, value):
        message = check_quoted(quoted, value)
        if message is not None:
            raise AssertionError(f"{spec.path}:{line}: {message}")
        return value

    namespace["__doctest_quoted__"] = quoted_check
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        exec(code, namespace)
    import matplotlib.pyplot as plt  # noqa: PLC0415 - only after the example imported what it wanted

    plt.close("all")
    return out.getvalue()


def shell_commands(spec: Spec) -> list[tuple[int, str]]:
    """(line, command) of a shell block: backslash continuations joined, comments and blanks
    dropped; in a ```console block only the ``$ `` lines are commands."""
    commands: list[tuple[int, str]] = []
    buffer, first = "", 0
    for k, raw in enumerate(spec.source.splitlines()):
        line = raw.rstrip()
        if spec.language == "console" and not buffer:
            if not line.startswith("$ "):
                continue
            line = line[2:]
        if not buffer:
            first = spec.line + k
            if not line.strip() or line.lstrip().startswith("#"):
                continue
        if line.endswith("\\"):
            buffer += line[:-1] + " "
            continue
        commands.append((first, buffer + line))
        buffer = ""
    if buffer:
        commands.append((first, buffer))
    return commands


def shell_environment() -> dict:
    env = dict(os.environ)
    env["PATH"] = os.pathsep.join([str(Path(sys.executable).parent), env.get("PATH", "")])
    return env


def _run_shell(spec: Spec, state: dict) -> str:
    timeout = HEAVY_SHELL_TIMEOUT if spec.options.heavy else SHELL_TIMEOUT
    outputs = []
    for line, command in shell_commands(spec):
        res = subprocess.run(["bash", "-c", command], cwd=state["cwd"], env=shell_environment(),
                             capture_output=True, text=True, timeout=timeout)
        if res.returncode != 0:
            raise AssertionError(f"{spec.path}:{line}: `{command}` exited with {res.returncode}\n"
                                 f"stderr:\n{res.stderr.strip()}")
        outputs.append(res.stdout)
    printed = "".join(outputs)
    if spec.language == "console":
        # the lines of a console block that are not commands are what the commands print
        quoted = "\n".join(line for line in spec.source.splitlines()
                           if line.strip() and not line.startswith(("$ ", "> ")))
        message = compare_output(quoted, printed, 0.0, 0.0) if quoted else None
        if message is not None:
            raise AssertionError(f"{spec.path}:{spec.line}: the console output differs: {message}")
    return printed


def evaluate(example) -> str | None:
    """Sybil evaluator: run one example; a string return value is Sybil's failure message."""
    spec: Spec = example.parsed
    state = _state(example.namespace)
    if "cwd" not in state:
        raise RuntimeError("the page's working directory was not set (tests/test_docs_examples.py does).")
    old = os.getcwd()
    os.chdir(state["cwd"])
    try:
        printed = _run_python(spec, state) if spec.kind == "python" else _run_shell(spec, state)
    finally:
        os.chdir(old)
    if spec.expected is not None:
        message = compare_output(spec.expected.text, printed, spec.expected.rtol, spec.expected.atol)
        if message is not None:
            return f"{spec.path}:{spec.expected.line}: the quoted output differs: {message}"
    if spec.numbers:
        lines = ", ".join(str(line) for _, line in spec.numbers)
        if spec.except_columns is not None:
            printed = table_without(printed, spec.except_columns)
        message = check_printed_numbers("\n".join(text for text, _ in spec.numbers), printed)
        if message is not None:
            return (f"{spec.path}:{lines}: the numbers of the 'doctest: numbers' blocks are not the "
                    f"ones the example at line {spec.line} prints: {message}")
    return None
