# SPDX-License-Identifier: GPL-3.0-or-later
"""Results that prove themselves (issue 36, items 3 and 8): read_granules
checks a file's footer (row count, byte count, CRC-32 of the bytes above it)
before it parses anything, refuses what is not a granules table, and fails
fast on what is no file at all; the keywords refuse holes and lists beyond
the scene's limit, as a scene file does."""
import re
import time
import zlib

import numpy as np
import pytest

import taper

SCENE = ("&chain profile = 'backward_linear', s = 0.2, n_granules = 30 /\n"
         "&sensors interval = 1.0, granules = 1, 30 /\n")


def test_the_footer_is_what_the_docs_say(run_driver):
    data = run_driver(SCENE).read_bytes()
    cut = data.rindex(b"\n", 0, len(data) - 1) + 1
    body, line = data[:cut], data[cut:]
    rows, size, crc = re.fullmatch(rb"# end: rows (\d+), bytes (\d+), crc32 ([0-9a-f]{8})\n",
                                   line).groups()
    assert int(rows) == 30 and int(size) == len(body) and int(crc, 16) == zlib.crc32(body)


def test_damaged_results_are_refused_naming_the_file(run_driver, tmp_path):
    path = run_driver(SCENE)
    good = path.read_bytes()
    r = taper.read_granules(path)
    assert r.complete and len(r.k) == 30
    lines = good.splitlines(keepends=True)
    cases = {
        "ten lines cut": b"".join(lines[:-10]),
        "a number changed": good.replace(b"\t0.", b"\t1.", 1),
        "binary": bytes(range(256)) * 40,
        "empty": b"",
    }
    for what, data in cases.items():
        bad = tmp_path / "bad.tsv"
        bad.write_bytes(data)
        with pytest.raises(ValueError, match=re.escape(str(bad))):
            taper.read_granules(bad)
    # a file without footer (an older taper's) is read on request
    old = tmp_path / "old.tsv"
    old.write_bytes(b"".join(lines[:-1]))
    with pytest.raises(ValueError, match="no footer"):
        taper.read_granules(old)
    np.testing.assert_array_equal(taper.read_granules(old, verify=False).v_peak, r.v_peak)


def test_not_a_file_and_not_a_granules_table(run_driver):
    start = time.monotonic()
    with pytest.raises(ValueError, match="not a regular file"):
        taper.read_granules("/dev/zero")
    assert time.monotonic() - start < 1.0  # nothing read from it
    sensors = run_driver(SCENE).parent / "sensors.tsv"
    with pytest.raises(ValueError, match="not a granules.tsv: its columns are t, granule"):
        taper.read_granules(sensors)


def test_holes_and_limits_of_the_keywords():
    with pytest.raises(TypeError, match="element 1 .*is None"):
        taper.theory(profile="custom", radii=[1.0, None, 1.0])
    # one limit for a file and a program: 250000 values in a scene's lists
    with pytest.raises(taper.InvalidArgumentError, match="at most 250000 values.*radii_file"):
        taper.theory(profile="custom", radii=np.ones(250001))
    assert taper.theory(profile="custom", radii=np.ones(1000)).complete
