# SPDX-License-Identifier: GPL-3.0-or-later
"""granules.tsv loads as it is in numpy and pandas: the
column names are the first line, the '#' block follows, then the rows; a run
without numerics has no columns of the dynamics; &output columns and every
choose columns and thin rows; read_granules reads all of these."""
import numpy as np
import pytest

import taper

FULL = ("k", "R", "m", "X0", "t_pass", "T_res", "v_peak", "t_peak", "X_pass",
        "theory_v", "theory_T", "theory_t")
THEORY = ("k", "R", "m", "X0", "theory_v", "theory_T", "theory_t")

SCENE = "&chain profile = 'backward_linear', s = 0.2, n_granules = 30 /\n"


@pytest.mark.parametrize("extra,columns,rows", [
    ("", FULL, 30),
    ("&solver numerics = .false. /\n", THEORY, 30),
    ("&output columns = 'v_peak theory_v', every = 7 /\n", ("k", "v_peak", "theory_v"), 6),
])
def test_numpy_and_pandas_load_it_as_it_is(run_driver, extra, columns, rows):
    path = run_driver(SCENE + extra)
    g = np.genfromtxt(path, names=True)
    assert g.dtype.names == columns
    assert g.shape == (rows,)
    a = np.loadtxt(path, skiprows=1)
    assert a.shape == (rows, len(columns))
    # the same numbers, bit for bit, as read_granules
    r = taper.read_granules(path)
    assert tuple(r.columns) == columns
    for i, name in enumerate(columns):
        np.testing.assert_array_equal(a[:, i], np.asarray(r[name], dtype=float))
        np.testing.assert_array_equal(g[name], np.asarray(r[name], dtype=float))
    pd = pytest.importorskip("pandas")
    df = pd.read_csv(path, sep="\t", comment="#")
    assert tuple(df.columns) == columns and len(df) == rows
    np.testing.assert_array_equal(df["k"].to_numpy(), r["k"])
    if rows == 6:  # every = 7: granules 1, 8, 15, 22, 29 and the last
        assert list(r["k"]) == [1, 8, 15, 22, 29, 30]


def test_read_granules_keeps_the_comment_block(run_driver):
    r = taper.read_granules(run_driver(SCENE))
    assert r.complete and r.stats["granule_reached"] == 29 and r.untrusted == ""
