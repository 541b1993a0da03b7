"""Every fenced Python and shell example of README.md and docs/*.md runs, as written (issue 21).

The collector and the annotation syntax are in ``tests/docs_examples.py``. One pytest item per
example, in page order; a page's examples share one working directory and, where a block says
``<!-- doctest: continue -->``, the previous block's namespace, so run a page's items together
(``-k docs/sweeps.md``), not one from its middle. ``slow`` and ``heavy`` come from the page's
comments; ``heavy`` items are deselected unless ``--run-heavy`` is given.
"""

import os
import re
import shutil
import textwrap
from pathlib import Path

import pytest

from docs_examples import ROOT, DocExampleError, compare_output, parse_file

PAGES = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]


def _examples():
    params = []
    for page in PAGES:
        document = parse_file(page)
        chain: set = set()  # the tiers of the Python block whose namespace the next 'continue' uses
        for example in document.examples():
            spec = example.parsed
            tiers = set(spec.options.markers())
            if spec.kind == "python":
                # a block that continues a slow (or heavy) one needs its namespace, so it runs in
                # that block's tier: `make test` (-m "not slow") never runs it without its start
                if spec.options.cont:
                    tiers |= chain
                chain = tiers
            marks = [getattr(pytest.mark, m) for m in sorted(tiers)]
            if spec.options.skip:
                marks.append(pytest.mark.skip(reason=spec.options.skip))
            rel = page.relative_to(ROOT)
            params.append(pytest.param(example, id=f"{rel}:{example.line}-{spec.kind}", marks=marks))
    return params


#: what the pages use as from the repository root: the benchmark scripts and the stored results
#: (copied: a command that regenerates them writes into the copy, never into the checkout)
STORED = ("benchmarks", "docs/data", "docs/img")


def _page_dir(tmp_path_factory, name):
    path = tmp_path_factory.mktemp(Path(name).stem)
    for stored in STORED:
        shutil.copytree(ROOT / stored, path / stored, ignore=shutil.ignore_patterns("__pycache__"))
    return path


@pytest.fixture(scope="module")
def page_dirs(tmp_path_factory):
    """One working directory per page, holding a copy of the stored results (``STORED``), and a
    private cache, so neither the checkout nor the user's cache is touched."""
    cache = tmp_path_factory.mktemp("doc-cache")
    old = os.environ.get("HYPERLATTICE_CACHE")
    os.environ["HYPERLATTICE_CACHE"] = str(cache)
    dirs = {}
    yield lambda name: dirs[name] if name in dirs else dirs.setdefault(name, _page_dir(tmp_path_factory, name))
    if old is None:
        del os.environ["HYPERLATTICE_CACHE"]
    else:
        os.environ["HYPERLATTICE_CACHE"] = old


@pytest.mark.parametrize("example", _examples())
def test_doc_example(example, page_dirs):
    example.namespace.setdefault("_doctest", {"python_ns": None})["cwd"] = page_dirs(example.path)
    example.evaluate()


# ------------------------------------------------------------------------------------------------
# the collector itself: a broken example must fail
# ------------------------------------------------------------------------------------------------

BROKEN = """\
# A page with three broken examples

```python
import math
print(math.sqrt(2.0))
```

<!-- doctest: output rtol=1e-6 -->
```text
1.5
```

```python
print(undefined_name)
```

```bash
hyperlattice lattice -p 7 -q 3 --rings 0 --json
```

```text
never runs
```

```{toctree}
:maxdepth: 1
not-an-example
```

<!-- doctest: continue -->
```python
import math
print(round(math.sqrt(2.0), 6))
```

<!-- doctest: output rtol=1e-6 -->
```text
1.414214
```

<!-- doctest: skip needs a cluster -->
```sh
hyperlattice sweep sweep.json --scheduler tcp://head-node:8786
```
"""


def _run_page(tmp_path, text):
    page = tmp_path / "page.md"
    page.write_text(text)
    document = parse_file(page)
    results = []
    for example in document.examples():
        example.namespace.setdefault("_doctest", {"python_ns": None})["cwd"] = tmp_path
        if example.parsed.options.skip:
            results.append(("skipped", example))
            continue
        try:
            example.evaluate()
        except Exception as exc:  # noqa: BLE001 - the outcome is what is asserted
            results.append(("failed", exc))
        else:
            results.append(("passed", example))
    return results


def test_broken_examples_fail(tmp_path):
    results = _run_page(tmp_path, BROKEN)
    outcomes = [r[0] for r in results]
    # wrong quoted output, NameError, failing command; the good continued block; the skip
    assert outcomes == ["failed", "failed", "failed", "passed", "skipped"]
    assert "number 1 of the output: expected 1.5, got 1.41421" in str(results[0][1])
    assert isinstance(results[1][1], NameError)
    assert "exited with 2" in str(results[2][1]) and "--rings 0" in str(results[2][1])


def test_fresh_namespace_unless_continued(tmp_path):
    page = textwrap.dedent("""\
        ```python
        x = 1
        ```

        ```python
        print(x)
        ```

        <!-- doctest: continue -->
        ```python
        print(x)
        ```
        """)
    results = _run_page(tmp_path, page)
    assert [r[0] for r in results] == ["passed", "failed", "failed"]
    assert isinstance(results[1][1], NameError)


@pytest.mark.parametrize("page", [
    "<!-- doctest: skip -->\n```python\npass\n```\n",              # skip without a reason
    "<!-- doctest: sometimes -->\n```python\npass\n```\n",         # unknown word
    "<!-- doctest: slow -->\n\nsome prose\n\n```python\npass\n```\n",  # not before its fence
    "<!-- doctest: output rtol=1e-3 -->\n```text\n1\n```\n",       # output of nothing
    "<!-- doctest: output tol=1 -->\n```python\npass\n```\n",      # not a tolerance
    "```python\npass\n```\n<!-- doctest: slow -->\n",              # dangling at the end
    "```\nsrc/\n  a.py\n```\n",                                  # a fence without a language
    "```python\nprint(1)\n```\n\n```\n1\n```\n",                  # ... also as an output
    "```python\nprint(1)\n```\n<!-- doctest: numbers 1e-3 -->\nIt is 1.\n",   # takes no argument
    "```python\nprint(1)\n```\n<!-- doctest: numbers -->\n\n```python\npass\n```\n",  # not prose
    "```python\nprint(1)\n```\n<!-- doctest: numbers -->\nno number here\n",  # quotes nothing
    "<!-- doctest: numbers -->\nIt is 1.\n",                         # no example before it
    "<!-- doctest: timing -->\n```text\n1.2 s\n```\n",               # timing without its command
    "<!-- doctest: timing python benchmarks/bench_nothing.py -->\nIn 1.2 s.\n",  # no such script
    "```python\npass\n```\n<!-- doctest: slow -->\n<!-- doctest: numbers -->\nIt is 1.\n",
    "```python\nprint(1)\n```\n<!-- doctest: numbers except-columns=2 -->\nIt is 1.\n",  # not a table
    "```python\nprint(1)\n```\n<!-- doctest: numbers columns=2 -->\n| 1 |\n",          # unknown option
    "```python\nprint(1)\n```\n<!-- doctest: numbers -->\nIt is 1.\n\n"
    "<!-- doctest: numbers except-columns=2 -->\n| 1 | 2 |\n",                       # not the only block
])
def test_bad_annotations_are_refused(tmp_path, page):
    path = tmp_path / "page.md"
    path.write_text(page)
    with pytest.raises(DocExampleError):
        parse_file(path)


@pytest.mark.parametrize("expected, actual, rtol, ok", [
    ("0.519 ± 0.004", "0.5191 ± 0.0040", 1e-3, True),
    ("0.519 ± 0.004", "0.516 ± 0.005", 1e-3, False),
    ("146 2", "146 2\n", 0.0, True),
    ("146 2", "148 2", 0.0, False),
    ("E = -2.894197", "E = −2.894197", 0.0, True),
    ("[1.0, 2.0]", "[1.0 2.0]", 0.0, False),
    ("a 1", "b 1", 1.0, False),
])
def test_compare_output(expected, actual, rtol, ok):
    assert (compare_output(expected, actual, rtol, 0.0) is None) is ok


@pytest.mark.parametrize("source, ok", [
    ("(2240, [7, 28])  # => 2240, [7, 28]", True),
    ("(2240, [7, 28])  # => 2241, [7, 28]", False),                 # integers exactly
    ("0.2831281  # => 0.283128...", True),                          # one unit of the last digit
    ("0.2831301  # => 0.283128...", False),
    ("(1.0, 2.0)  # => E0 = 1.0", False),                           # every number is quoted
    ("[-2.8941971, 1]  # => [-2.894197], n = 1", True),
    ("{'E0': 187.2}  # => {'E0': 187}", False),
    ("2.5e-14  # => 3e-14", True),
    ("5e-13  # => 3e-14", False),
    ("1.0  # a comment with 7 in it, not checked", True),
    ("-9.09541  # => b = -9.0954; N(r) ~ 14 rho + b", True),       # after ';' a remark
    ("'PSL(2,197)', 1274196  # => PSL(2,197): 1,274,196 sites", True),   # a string's numbers
    ("'PSL(2,193)', 1274196  # => PSL(2,197): 1,274,196 sites", False),
    ("'sector-dense', 3  # => 3", True),
])
def test_quoted_values(tmp_path, source, ok):
    results = _run_page(tmp_path, f"```python\n{source}\n```\n")
    assert (results[0][0] == "passed") is ok, results


def test_console_blocks_compare_their_output(tmp_path):
    page = textwrap.dedent("""\
        ```console
        $ echo 146 2
        146 2
        ```

        ```console
        $ echo 146 2
        148 2
        ```
        """)
    results = _run_page(tmp_path, page)
    assert [r[0] for r in results] == ["passed", "failed"]
    assert "expected output\n148 2\ngot\n146 2" in str(results[1][1])


def test_no_bare_fence_in_pages():
    """Every fence of README.md and docs/*.md says what it is (issue 21): an example's language or
    ```text; the collector refuses a page with a plain fence, this names the fences."""
    bare = []
    for page in PAGES:
        inside = False
        for k, line in enumerate(page.read_text().splitlines(), 1):
            if line.lstrip().startswith("```"):
                if not inside and not line.strip()[3:].strip():
                    bare.append(f"{page.relative_to(ROOT)}:{k}")
                inside = not inside
    assert not bare, f"fences without a language: {bare}"


NUMBERS = """\
# A page whose prose quotes numbers

```python
import math
print(f"pi = {math.pi:.6f}, e = {math.e:.4f}")
print("| n | n! |")
for n in (3, 4, 5):
    print(f"| {n} | {math.factorial(n)} |")
```

<!-- doctest: numbers -->
The constants are π = 3.141593 and e = 2.7183 (to the digits quoted).

<!-- doctest: numbers -->
| n | n! |
|---|---|
| 3 | 6 |
| 4 | 24 |
| 5 | 120 |

<!-- doctest: timing python benchmarks/bench_continuum.py -->
Computing them took 1.2 ms on one core; never checked.

```python
import math
print(f"2 {math.sqrt(2.0):.4f} 3 {math.sqrt(3.0):.4f}")
```

<!-- doctest: numbers -->
- √2 = 1.4142 and √3 = 1.7321,
- a second list item is not part of the block: 99.

```python
print(2.5, 7)
```

<!-- doctest: numbers -->
It prints 2.5.
"""


def test_numbers_in_prose_are_checked(tmp_path):
    results = _run_page(tmp_path, NUMBERS)
    assert [r[0] for r in results] == ["passed", "passed", "failed"]
    assert "quoted 1 numbers" in str(results[2][1]) and "the value has 2" in str(results[2][1])


@pytest.mark.parametrize("old, new, message", [
    ("π = 3.141593", "π = 3.141595", "quoted 3.141595"),          # two units off in the last digit
    ("e = 2.7183", "e = 2.7185", "quoted 2.7185"),
    ("| 4 | 24 |", "| 4 | 25 |", "quoted 25"),                     # integers exactly
    ("| 5 | 120 |", "| 5 | 120 | 720 |", "quoted 9 numbers"),      # a number the example never prints
    ("and e = 2.7183 (", "(", "quoted 7 numbers"),                 # a printed number not quoted
])
def test_a_broken_number_fails(tmp_path, old, new, message):
    """A deliberately wrong number in a ``doctest: numbers`` block fails its example."""
    assert old in NUMBERS
    results = _run_page(tmp_path, NUMBERS.replace(old, new, 1))
    assert results[0][0] == "failed" and message in str(results[0][1]), results[0]
    assert "the example at line 4 prints" in str(results[0][1])


TABLE = """\
```python
print("<!-- machine: 2 cores, numpy 2.4.6 -->")
print("| n | n² | time [s] |")
print("|---|---|---|")
for n in (2, 3):
    print(f"| {n} | {n * n} | {0.1 * n:.2f} |")
```

<!-- doctest: numbers except-columns=3 -->
| n | n² | time [s] |
|---|---|---|
| 2 | 4 | 0.55 |
| 3 | 9 | 0.01 |
"""


@pytest.mark.parametrize("old, new, ok", [
    ("", "", True),                                                  # times differ, not compared
    ("| 3 | 9 |", "| 3 | 8 |", False),                              # a broken number
    ("| 3 | 9 | 0.01 |\n", "| 3 | 9 | 0.01 |\n| 4 | 16 | 0.01 |\n", False),   # a row never printed
])
def test_numbers_table_except_columns(tmp_path, old, new, ok):
    results = _run_page(tmp_path, TABLE.replace(old, new) if old else TABLE)
    assert (results[0][0] == "passed") is ok, results


_LIST_ITEM = re.compile(r"\s*(?:[-*+]|\d+[.)])\s+")


def indented_code_blocks(text: str) -> list[int]:
    """Line numbers of Markdown indented code blocks: a line after a blank line, outside a fence,
    indented four or more columns past the text it continues (the page's margin or the content of
    the list item it is in) and not a list item itself. Such a block renders as code but is no
    fence, so the collector never sees it: a formula goes into a ```text (or ```math) fence."""
    found = []
    inside = False
    blank_before = True
    margin = 0
    for k, line in enumerate(text.splitlines(), 1):
        if line.lstrip().startswith("```"):
            inside = not inside
            blank_before = False
            continue
        if inside:
            continue
        if not line.strip():
            blank_before = True
            continue
        indent = len(line) - len(line.lstrip())
        item = _LIST_ITEM.match(line)
        if blank_before and not item and indent >= margin + 4:
            found.append(k)
        elif item:
            margin = len(item.group(0))
        elif blank_before or indent < margin:
            margin = indent
        blank_before = False
    return found


@pytest.mark.parametrize("text, lines", [
    ("Some prose:\n\n    H = -t A\n\nmore prose.\n", [3]),
    ("1. An item:\n\n       (A f) = q f\n\n   continued.\n", [3]),
    ("1. An item:\n\n   ```text\n   (A f) = q f\n   ```\n", []),
    ("- a list\n    - a nested item\n\n  continued\n", []),
    ("```python\n\n    x = 1\n```\n", []),
])
def test_indented_code_blocks_are_found(text, lines):
    assert indented_code_blocks(text) == lines


def test_no_indented_code_block_in_pages():
    """A formula or transcript in README.md and docs/*.md is a ```text fence, never an indented
    code block (which the collector cannot see, so which no check would cover)."""
    found = [f"{page.relative_to(ROOT)}:{k}" for page in PAGES for k in indented_code_blocks(page.read_text())]
    assert not found, f"indented code blocks (make them ```text fences): {found}"
