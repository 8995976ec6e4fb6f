# SPDX-License-Identifier: GPL-3.0-or-later
"""run_scene() reads scenes with the driver's reader and runs them as the
driver does."""

import pytest

import taper

from test_simulate import assert_bitwise


def test_run_scene_equals_driver_and_simulate(run_driver, tmp_path):
    text = """! a sweep of two chains
&chain profile = 'backward_linear', s = 0.2, 0.6, n_granules = 50 /
&solver rtol = 1d-9 /
&output progress = .false. /
"""
    scene = tmp_path / "sweep.nml"
    scene.write_text(text)
    results = taper.run_scene(scene)
    assert [r.settings["s"] for r in results] == [0.2, 0.6]
    for r, s in zip(results, (0.2, 0.6)):
        assert r.complete and r.settings["rtol"] == 1e-9
        assert r.equals(taper.simulate(profile="backward_linear", s=s, n_granules=50, rtol=1e-9))
    single = run_driver(text.replace("0.2, 0.6", "0.6"), "single")
    back = taper.read_granules(single)
    for c in back.columns:
        assert_bitwise(results[1][c], back[c], c)


def test_run_scene_theory_only(tmp_path):
    scene = tmp_path / "theory.nml"
    scene.write_text("&chain profile = 'monodisperse', n_granules = 20 /\n"
                     "&solver numerics = .false. /\n")
    (r,) = taper.run_scene(scene)
    assert r.columns == taper.THEORY_COLUMNS and (r.theory_v == 1.0).all()


def test_shipped_scene(source):
    (r,) = taper.run_scene(source / "share" / "scenes" / "monodisperse.nml")
    assert r.complete and r.settings["profile"] == "monodisperse"


def test_bad_scene_gives_the_readers_diagnostics(tmp_path):
    scene = tmp_path / "bad.nml"
    scene.write_text("&chain\n  profile = 'conical'\n/\n")
    with pytest.raises(taper.SceneError) as e:
        taper.run_scene(scene)
    assert f"{scene}:2" in str(e.value) and "profile" in str(e.value)
    assert isinstance(e.value, ValueError)
