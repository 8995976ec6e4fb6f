# SPDX-License-Identifier: GPL-3.0-or-later
"""The code in the docs runs, and prints what the docs say it prints.

docs/python.md and the README: each page's ```python blocks run in order in
one namespace (a page reads as one session: a later block uses the `import
taper` of an earlier one), in a subprocess whose working directory is a
temporary one, with matplotlib hidden: `pip install .` does not install it,
so the docs' plots must be optional.

docs/tutorial.md: every block runs, in the order of the page, in one scratch
directory: ```sh blocks with `sh -e` and the build's driver first on PATH,
```python blocks in one namespace with the test venv's packages (matplotlib
too, when it is installed there, drawing with the Agg backend), and a block
the paragraph before it says to save as `NAME` is written to that file (the
scene: it must be share/scenes/tutorial.nml, the copy that ships).  Every
other block of the page is the output of one of these, and every number the
prose quotes with a decimal point or an exponent is in a block: no number of
the page escapes the comparison.

Output: where a code block is followed by a sentence ending in "prints" and
a ```text block, the block's standard output must be that text exactly (the
numbers in the docs are the numbers the code gives).
"""

import importlib.util
import json
import os
import re
import subprocess
import sys
import textwrap

import pytest

PAGES = ["docs/python.md", "README.md"]
TUTORIAL = "docs/tutorial.md"
TUTORIAL_SCENE = "share/scenes/tutorial.nml"

FENCE = re.compile(r"^```(\w*)\n(.*?)^```\n", re.M | re.S)
# "Save this as `tutorial.nml`": the last paragraph before a block.
SAVE_AS = re.compile(r"\b[Ss]ave\b[^`]*`([\w.-]+)`")
# A number quoted in prose that a run could change: a decimal point or an exponent.
PROSE_NUMBER = re.compile(r"(?<![\w.])\d+(?:\.\d+(?:e[-+]?\d+)?|e[-+]?\d+)(?![\w])")

# Runs a page's blocks; prints one JSON line per block (its standard output).
# argv: blocks.json, then "hide-matplotlib" or "matplotlib".
RUNNER = textwrap.dedent("""
    import contextlib, io, json, subprocess, sys
    class NoMatplotlib:
        def find_spec(self, name, path=None, target=None):
            if name == "matplotlib" or name.startswith("matplotlib."):
                raise ImportError("matplotlib is hidden: the plain install has none")
            return None
    if sys.argv[2] == "hide-matplotlib":
        sys.meta_path.insert(0, NoMatplotlib())
    blocks = json.load(open(sys.argv[1]))
    space = {"__name__": "__main__"}
    for i, block in enumerate(blocks):
        if block["lang"] == "python":
            out = io.StringIO()
            with contextlib.redirect_stdout(out):
                exec(compile(block["code"], f"block {i + 1}", "exec"), space)
            got = out.getvalue()
        elif block["lang"] == "sh":
            proc = subprocess.run(["sh", "-e", "-c", block["code"]], capture_output=True,
                                  text=True)
            if proc.returncode != 0:
                sys.exit(f"block {i + 1} (sh) exits with status {proc.returncode}:\\n"
                         f"{block['code']}{proc.stderr}")
            got = proc.stdout
        else:
            with open(block["save_as"], "w") as f:
                f.write(block["code"])
            got = ""
        print(json.dumps(got), flush=True)
""")


def page_blocks(text, langs):
    """The page's fenced blocks as ([block], [unclaimed]): each block a dict
    with `lang`, `code`, `expected` (the ```text block after it when the
    prose between them ends in a sentence with "prints", else None) and
    `save_as`; a block runs when its language is in `langs`, is saved when
    the paragraph before it says "save ... as `NAME`", and `unclaimed` holds
    the (lang, first line) of every block that is none of these nor an
    expected output."""
    fences = [(m.group(1), m.group(2), m.start(), m.end()) for m in FENCE.finditer(text)]
    blocks, outputs, unclaimed = [], set(), []
    for i, (lang, body, start, end) in enumerate(fences):
        if i in outputs:
            continue
        paragraph = text[fences[i - 1][3] if i else 0:start].strip().split("\n\n")[-1]
        saved = SAVE_AS.search(paragraph)
        if lang in langs or (saved and lang != "text"):
            expected = None
            if i + 1 < len(fences) and fences[i + 1][0] == "text":
                between = text[end:fences[i + 1][2]]
                if re.search(r"prints\b[^.]*$", between.strip(), re.S):
                    expected = fences[i + 1][1]
                    outputs.add(i + 1)
            blocks.append({"lang": lang, "code": body, "expected": expected,
                           "save_as": None if lang in langs else saved.group(1)})
        else:
            unclaimed.append((lang, body.split("\n", 1)[0]))
    return blocks, unclaimed


def blocks_of(text):
    """[(code, expected output or None)] of the page's python blocks."""
    return [(b["code"], b["expected"]) for b in page_blocks(text, ("python",))[0]]


def run_blocks(blocks, tmp_path, cwd, matplotlib, env=None):
    """The standard output of each block, run by RUNNER in cwd."""
    (tmp_path / "blocks.json").write_text(json.dumps(blocks))
    (tmp_path / "runner.py").write_text(RUNNER)
    proc = subprocess.run([sys.executable, str(tmp_path / "runner.py"),
                           str(tmp_path / "blocks.json"),
                           "matplotlib" if matplotlib else "hide-matplotlib"],
                          cwd=cwd, env=env, capture_output=True, text=True, timeout=900)
    assert proc.returncode == 0, proc.stderr
    outputs = [json.loads(line) for line in proc.stdout.splitlines()]
    assert len(outputs) == len(blocks)
    return outputs


def compare(page, blocks, outputs):
    """Asserts each expected output; returns how many were compared."""
    checked = 0
    for block, got in zip(blocks, outputs):
        if block["expected"] is not None:
            assert got == block["expected"], \
                f"{page}: the block\n{block['code']}\nprints\n{got}\nnot\n{block['expected']}"
            checked += 1
    return checked


@pytest.mark.parametrize("page", PAGES)
def test_page_runs_and_prints_what_it_says(page, source, tmp_path):
    text = (source / page).read_text()
    blocks = page_blocks(text, ("python",))[0]
    if not blocks:
        pytest.skip(f"{page} has no Python code")
    outputs = run_blocks(blocks, tmp_path, tmp_path, matplotlib=False)
    checked = compare(page, blocks, outputs)
    if page == "docs/python.md":
        assert checked >= 2, "docs/python.md shows the output of at least two examples"


def test_tutorial_runs_and_prints_what_it_says(source, driver, tmp_path):
    text = (source / TUTORIAL).read_text()
    blocks, unclaimed = page_blocks(text, ("sh", "python"))
    assert not unclaimed, f"{TUTORIAL}: blocks the test neither runs, saves nor compares: " \
        f"{unclaimed}"
    saved = {b["save_as"]: b["code"] for b in blocks if b["save_as"]}
    assert saved.get("tutorial.nml") == (source / TUTORIAL_SCENE).read_text(), \
        f"{TUTORIAL}'s scene is not {TUTORIAL_SCENE}"
    # Every number of the prose is in a block, which the run checks.
    prose = FENCE.sub("", text)
    in_blocks = "\n".join(m.group(2) for m in FENCE.finditer(text))
    loose = [n for n in PROSE_NUMBER.findall(prose) if n not in in_blocks]
    assert not loose, f"{TUTORIAL}: numbers in the prose that no block prints: {loose}"
    for figure in re.findall(r"!\[[^]]*\]\((figures/[\w.-]+\.png)\)", text):
        assert (source / "docs" / figure).read_bytes()[:4] == b"\x89PNG", figure

    scratch = tmp_path / "scratch"
    scratch.mkdir()
    env = dict(os.environ, MPLBACKEND="Agg",
               PATH=f"{driver.resolve().parent}{os.pathsep}{os.environ.get('PATH', '')}")
    outputs = run_blocks(blocks, tmp_path, scratch, matplotlib=True, env=env)
    checked = compare(TUTORIAL, blocks, outputs)
    assert checked >= 7, f"{TUTORIAL} shows the output of its steps ({checked} compared)"
    # The figures the steps draw: the driver's (gnuplot) and matplotlib's.
    drawn = [p.name for p in scratch.rglob("*.png")]
    assert "spacetime.png" in drawn, drawn
    if importlib.util.find_spec("matplotlib"):
        assert "tutorial-wall.png" in drawn, drawn


def test_blocks_of_finds_expected_output():
    page = "```python\nprint(1)\n```\n\nprints\n\n```text\n1\n```\n```python\nx = 2\n```\n"
    assert blocks_of(page) == [("print(1)\n", "1\n"), ("x = 2\n", None)]


def test_page_blocks_saves_runs_and_finds_what_is_not_checked():
    page = ("Save this as `a.nml`:\n\n```fortran\n&chain /\n```\n\n"
            "```sh\necho 1.5\n```\n\nprints\n\n```text\n1.5\n```\n\n"
            "```text\nnobody prints this\n```\n")
    blocks, unclaimed = page_blocks(page, ("sh", "python"))
    assert [(b["lang"], b["save_as"], b["expected"]) for b in blocks] == \
        [("fortran", "a.nml", None), ("sh", None, "1.5\n")]
    assert unclaimed == [("text", "nobody prints this")]
    assert PROSE_NUMBER.findall("v = 0.74 m/s, 2.2e-3 s, 31 beads, arXiv.org, x1.5") == \
        ["0.74", "2.2e-3"]
