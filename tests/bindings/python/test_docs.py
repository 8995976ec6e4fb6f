# SPDX-License-Identifier: GPL-3.0-or-later
"""The Python code in the docs runs, with the plain install, and prints what
the docs say it prints.

Each page's ```python blocks run in order in one namespace (a page reads as
one session: a later block uses the `import taper` of an earlier one), in a
subprocess whose working directory is a temporary one, with matplotlib
hidden: `pip install .` does not install it, so the docs' plots must be
optional.  Where a block is followed by a sentence ending in "prints" and a
```text block, the block's standard output must be that text exactly (the
numbers in the docs are the numbers the code gives).
"""

import json
import pathlib
import re
import subprocess
import sys
import textwrap

import pytest

PAGES = ["docs/python.md", "README.md"]

FENCE = re.compile(r"^```(\w*)\n(.*?)^```\n", re.M | re.S)

# Runs the blocks of one page; prints one JSON line per block (its output).
RUNNER = textwrap.dedent("""
    import contextlib, io, json, sys
    class NoMatplotlib:
        def find_spec(self, name, path=None, target=None):
            if name == "matplotlib" or name.startswith("matplotlib."):
                raise ImportError("matplotlib is hidden: the plain install has none")
            return None
    sys.meta_path.insert(0, NoMatplotlib())
    blocks = json.load(open(sys.argv[1]))
    space = {"__name__": "__main__"}
    for i, code in enumerate(blocks):
        out = io.StringIO()
        with contextlib.redirect_stdout(out):
            exec(compile(code, f"block {i + 1}", "exec"), space)
        print(json.dumps(out.getvalue()), flush=True)
""")


def blocks_of(text):
    """[(code, expected output or None)] of the page's python blocks."""
    fences = [(m.group(1), m.group(2), m.start(), m.end()) for m in FENCE.finditer(text)]
    out = []
    for i, (lang, body, _, end) in enumerate(fences):
        if lang != "python":
            continue
        expected = None
        if i + 1 < len(fences) and fences[i + 1][0] == "text":
            between = text[end:fences[i + 1][2]]
            if re.search(r"prints\b[^.]*$", between.strip(), re.S):
                expected = fences[i + 1][1]
        out.append((body, expected))
    return out


@pytest.mark.parametrize("page", PAGES)
def test_page_runs_and_prints_what_it_says(page, source, tmp_path):
    text = (source / page).read_text()
    blocks = blocks_of(text)
    if not blocks:
        pytest.skip(f"{page} has no Python code")
    (tmp_path / "blocks.json").write_text(json.dumps([code for code, _ in blocks]))
    (tmp_path / "runner.py").write_text(RUNNER)
    proc = subprocess.run([sys.executable, "runner.py", "blocks.json"], cwd=tmp_path,
                          capture_output=True, text=True, timeout=900)
    assert proc.returncode == 0, f"{page}: {proc.stderr}"
    outputs = [json.loads(line) for line in proc.stdout.splitlines()]
    assert len(outputs) == len(blocks)
    checked = 0
    for (code, expected), got in zip(blocks, outputs):
        if expected is not None:
            assert got == expected, f"{page}: the block\n{code}\nprints\n{got}\nnot\n{expected}"
            checked += 1
    if page == "docs/python.md":
        assert checked >= 2, "docs/python.md shows the output of at least two examples"


def test_blocks_of_finds_expected_output():
    page = "```python\nprint(1)\n```\n\nprints\n\n```text\n1\n```\n```python\nx = 2\n```\n"
    assert blocks_of(page) == [("print(1)\n", "1\n"), ("x = 2\n", None)]
