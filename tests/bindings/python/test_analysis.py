# SPDX-License-Identifier: GPL-3.0-or-later
"""taper.chain(), taper.asymptotic, taper.fit() and the name tuples: against
closed forms, the formulas stated in include/taper.h, and each other."""

import math

import numpy as np
import pytest

import taper
from taper import asymptotic


# ---- names: walked from the library (taper_X_name), none kept in Python -------
def test_name_tuples_come_from_the_library():
    assert taper.OBSERVABLES == ("t_pass", "T_res", "v_peak", "t_peak", "X_pass")
    assert taper.THEORY_QUANTITIES == ("v", "mu", "T", "t")
    assert taper.LAWS == ("v_of_k", "t_res_of_k", "t_of_k", "k_of_t", "v_of_t", "x_of_t",
                          "c_of_t", "fwd_v_of_k", "fwd_t_of_k", "fwd_v_of_t")
    assert asymptotic.LAWS is taper.LAWS
    assert taper.FIT_MODELS == ("power", "exponential", "divergence_b", "divergence_c",
                                "divergence_m")
    assert taper.PROFILES == ("monodisperse", "backward_linear", "forward_linear",
                              "backward_exponential", "forward_exponential", "custom",
                              "decorated")
    assert taper.METHODS == ("adams", "bdf", "rk8")
    assert len(taper.STATISTICS) == 25
    assert taper.STATISTICS[0] == "steps" and taper.STATISTICS[13] == "complete"
    assert taper.STATISTICS[-1] == "wall_impulse_right"
    # granules.tsv's columns, as the driver's scene module names them
    assert taper.COLUMNS == ("k", "R", "m", "X0") + taper.OBSERVABLES + \
        ("theory_v", "theory_T", "theory_t")
    assert taper.THEORY_COLUMNS == tuple(c for c in taper.COLUMNS if c not in taper.OBSERVABLES)
    # The observables are columns of a run, the theory's (but mu) theory_<name>.
    r = taper.simulate(n_granules=5)
    assert all(name in r.columns for name in taper.OBSERVABLES)
    assert [c for c in r.columns if c.startswith("theory_")] == \
        ["theory_" + q for q in taper.THEORY_QUANTITIES if q != "mu"]


# ---- chain() ------------------------------------------------------------------
@pytest.mark.parametrize("kw", [
    dict(profile="monodisperse", n_granules=10),
    dict(profile="backward_linear", s=0.3, n_granules=25),
    dict(profile="forward_exponential", q=0.1, n_granules=20, exponent=3.0),
    dict(profile="custom", radii=[1.0, 1.5, 0.7, 2.0]),
])
def test_chain_columns_against_their_definitions(kw):
    c = taper.chain(**kw)
    n = len(c)
    assert c.columns == taper.CHAIN_COLUMNS == ("k", "R", "m", "X0", "r", "mu")
    assert list(c.k) == list(range(1, n + 1)) and c.k.dtype == np.int64
    R, m = c.R, c.m
    assert c["R"] is R and "mu" in c and list(c) == list(c.columns)
    assert m == pytest.approx(R ** 3, rel=1e-15)
    assert c.X0[0] == 0.0
    assert c.X0[1:] == pytest.approx(np.cumsum(R[:-1] + R[1:]), rel=1e-14)
    # r_k = (2 R_k R_{k+1} / (R_k + R_{k+1}))^(1/2), mu_k = m_k m_{k+1}/(m_k + m_{k+1})
    assert c.r[:-1] == pytest.approx(np.sqrt(2 * R[:-1] * R[1:] / (R[:-1] + R[1:])), rel=1e-14)
    assert c.mu[:-1] == pytest.approx(m[:-1] * m[1:] / (m[:-1] + m[1:]), rel=1e-14)
    assert math.isnan(c.r[-1]) and math.isnan(c.mu[-1])
    assert c.exponent == kw.get("exponent", 2.5)
    assert c.profile == kw["profile"]
    assert c.settings["n_granules"] == n
    # The chain's columns are the Result's, bit for bit.
    th = taper.theory(**kw)
    for name in ("k", "R", "m", "X0"):
        assert np.array_equal(c[name], th[name])


def test_chain_mu_gives_the_theory_T():
    """T_k of eq. (18) from chain()'s mu_k and r_k and the theory's v_k is the
    theory's own T_k."""
    kw = dict(profile="backward_linear", s=0.4, n_granules=30)
    c, th = taper.chain(**kw), taper.theory(**kw)
    T = [taper.collision_time(c.mu[i], c.r[i], th.theory_v[i]) for i in range(29)]
    assert np.asarray(T) == pytest.approx(th.theory_T[:-1], rel=1e-13)


def test_chain_refusals_name_the_argument():
    with pytest.raises(taper.InvalidArgumentError) as e:
        taper.chain(profile="monodisperse", n_granules=1)
    assert e.value.field == "n_granules"
    with pytest.raises(taper.InvalidArgumentError) as e:
        taper.chain(profile="forward_linear", s=0.5, n_granules=100)
    assert e.value.field == "n_granules"
    with pytest.raises(taper.InvalidArgumentError) as e:
        taper.chain(radii=[1.0, -1.0])
    assert e.value.field == "radii"
    with pytest.raises(TypeError, match="s"):
        taper.chain(s="0.1")
    # every scene variable is a keyword of chain() (solver settings are
    # checked as in a file); an unknown one is a TypeError with the nearest
    with pytest.raises(TypeError, match="did you mean 'rtol'"):
        taper._core.chain(rtoll=1e-8)
    assert taper.chain(n_granules=5, rtol=1e-8).settings["rtol"] == 1e-8
    with pytest.raises(TypeError):
        taper._core.chain("monodisperse")


# ---- asymptotic -----------------------------------------------------------------
def test_law_exponents_for_n_five_halves():
    want = {"v_of_k": -1.5, "t_res_of_k": 1.3, "t_of_k": 2.3, "k_of_t": 10 / 23,
            "v_of_t": -15 / 23, "x_of_t": 20 / 23, "c_of_t": -3 / 23,
            "fwd_v_of_k": -1.5, "fwd_t_of_k": 2.3, "fwd_v_of_t": -15 / 23}
    assert set(want) == set(taper.LAWS)
    for law, p in want.items():
        assert asymptotic.exponent(law) == pytest.approx(p, rel=1e-15), law
    assert asymptotic.exponent("v_of_k") == -1.5


@pytest.mark.parametrize("n", [1.5, 2.0, 3.0, 7.0])
def test_law_exponents_general_n(n):
    beta = 1.5 - 0.5 / n
    assert asymptotic.exponent("t_res_of_k", n) == pytest.approx(beta, rel=1e-15)
    assert asymptotic.exponent("k_of_t", n) == pytest.approx(1 / (beta + 1), rel=1e-15)
    assert asymptotic.exponent("c_of_t", n) == pytest.approx(2 / (beta + 1) - 1, abs=1e-15)


def test_law_refusals():
    with pytest.raises(taper.InvalidArgumentError) as e:
        asymptotic.exponent("v_of_x")
    assert e.value.field == "law" and isinstance(e.value, ValueError)
    assert "v_of_k" in str(e.value)  # the message lists the names
    with pytest.raises(TypeError, match="law"):
        asymptotic.exponent(0)
    with pytest.raises(TypeError, match="n"):
        asymptotic.exponent("v_of_k", "2.5")
    assert math.isnan(asymptotic.exponent("v_of_k", 1.0))  # n <= 1: outside the domain


@pytest.mark.parametrize("q", [0.01, 0.1, 0.3, -0.2])
@pytest.mark.parametrize("n", [2.5, 3.0])
def test_exponential_laws_against_the_formulas(q, n):
    A = (1 + (1 - q) ** -3) / 2                            # eq. (35)
    assert asymptotic.A(q) == pytest.approx(A, rel=1e-15)
    assert asymptotic.lnA(q) == pytest.approx(math.log(A), rel=1e-13)
    eta = (1 - 2 / n) * math.log(A) - 2.5 / n * math.log(1 - q)
    assert asymptotic.eta(q, n) == pytest.approx(eta, rel=1e-12)
    assert asymptotic.f(q, n) == pytest.approx(math.log(A) / eta, rel=1e-12)  # eq. (41)
    if n == 2.5:  # eq. (39): eta = ln(A^(1/5) / (1-q))
        assert asymptotic.eta(q) == pytest.approx(math.log(A ** 0.2 / (1 - q)), rel=1e-12)
    # tau = T_1 / (e^eta - 1), T_1 of eq. (18) with v = 1, mu_1 = 1/(1 + (1-q)^3),
    # r_1 = (1 - q/2)^(-1/2)
    T1 = taper.collision_time(1 / (1 + (1 - q) ** 3), (1 - q / 2) ** -0.5, 1.0, n)
    assert asymptotic.timescale(q, n) == pytest.approx(T1 / math.expm1(eta), rel=1e-12)
    if q > 0:
        p = -math.log(1 - q) / eta
        assert asymptotic.position_exponent(q, n) == pytest.approx(p, rel=1e-12)
        assert asymptotic.speed_exponent(q, n) == pytest.approx(p - 1, rel=1e-12, abs=1e-15)
        if n == 2.5:  # eqs. (44), (45)
            f = asymptotic.f(q)
            assert asymptotic.position_exponent(q) == pytest.approx(1 - f / 5, rel=1e-12)
            assert asymptotic.speed_exponent(q) == pytest.approx(-f / 5, rel=1e-12)
        assert asymptotic.M(q, n) == asymptotic.timescale(-q, n)  # eq. (57)
        assert asymptotic.M(q, n) < 0


@pytest.mark.parametrize("q", [0.05, 0.2])
def test_timescale_is_the_exact_theory(q):
    """t_k = tau (e^(k eta) - 1) for every k of a backward exponential chain."""
    th = taper.theory(profile="backward_exponential", q=q, n_granules=40)
    k = np.arange(1, 40)
    tau, eta = asymptotic.timescale(q), asymptotic.eta(q)
    assert th.theory_t[:-1] == pytest.approx(tau * np.expm1(k * eta), rel=1e-11)
    # v_k = A^(1-k), eq. (34)
    assert th.theory_v == pytest.approx(asymptotic.A(q) ** -np.arange(40.0), rel=1e-12)


@pytest.mark.parametrize("S", [0.01, 0.02, 0.05, 0.2])
def test_forward_linear_laws(S):
    n = 2.5
    beta = 1.5 - 0.5 / n
    C0 = (math.sqrt(math.pi) * math.gamma(1 + 1 / n) / math.gamma(1 / n + 0.5)
          * (n / 4) ** (1 / n) / ((beta + 1) * S))
    assert asymptotic.C0(S) == pytest.approx(C0, rel=1e-13)
    assert asymptotic.C(S) == pytest.approx(C0 * (1 + 57 / 130 * S), rel=1e-13)
    assert asymptotic.forward_linear_b(S) == pytest.approx(S / (1 + S), rel=1e-15)
    if S <= 0.05:
        # C is the time the pulse needs to cross the longest chain (N < 1 + 1/S):
        # C0 within O(S), C within O(S^2) (measured: 4.3 S^2 at S = 0.01 to 3.7 S^2
        # at 0.05).
        N = math.ceil(1 + 1 / S) - 1
        t = taper.theory(profile="forward_linear", s=S, n_granules=N).theory_t[-2]
        assert abs(t / asymptotic.C(S) - 1) <= 5 * S ** 2
        assert abs(t / asymptotic.C(S) - 1) < abs(t / asymptotic.C0(S) - 1)


def test_asymptotic_domains_and_arrays():
    assert math.isnan(asymptotic.A(1.0)) and math.isnan(asymptotic.lnA(2.0))
    assert math.isnan(asymptotic.f(0.0)) and math.isnan(asymptotic.eta(0.1, 1.0))
    assert math.isnan(asymptotic.C(1.5)) and math.isnan(asymptotic.position_exponent(-0.1))
    assert isinstance(asymptotic.A(0.1), float)
    q = np.array([0.05, 0.1, 0.2])
    out = asymptotic.f(q)
    assert isinstance(out, np.ndarray) and out.dtype == np.float64 and out.shape == (3,)
    assert list(out) == [asymptotic.f(x) for x in q]
    grid = asymptotic.eta(q[:, None], np.array([2.0, 2.5, 3.0]))  # broadcasting
    assert grid.shape == (3, 3) and grid[1, 1] == asymptotic.eta(0.1, 2.5)
    assert asymptotic.exponent("v_of_t", [2.5, 3.0]).shape == (2,)
    with pytest.raises(TypeError, match="q"):
        asymptotic.A("0.1")
    with pytest.raises(TypeError, match="S"):
        asymptotic.C(True)


# ---- fit() ------------------------------------------------------------------------
def test_power_fit_of_exact_data_recovers_its_parameters():
    x = np.arange(1.0, 30.0)
    y = 2.5 * x ** -1.5
    f = taper.fit(x, y)  # model="power" by default
    assert isinstance(f, taper.FitResult) and f.model == "power"
    assert f.params == pytest.approx([2.5, -1.5], rel=1e-12)
    assert f.errors.shape == (2,) and np.all(f.errors < 1e-10)
    assert f.n_params == 2 and f.n_points == 29 and f.n_skipped == 0 and f.iterations == 0
    assert f.chi2 < 1e-25
    g = taper.fit([1.0, 2.0, 4.0, 8.0], [1.0, 0.25, 0.0625, 0.015625], model="power")
    assert g.params[1] == pytest.approx(-2.0, abs=1e-12) and g.n_points == 4


def test_exponential_and_divergence_fits_of_exact_data():
    x = np.linspace(0.0, 5.0, 40)
    f = taper.fit(x, 3.0 * np.exp(-0.7 * x), model="exponential")
    assert f.params == pytest.approx([3.0, -0.7], rel=1e-12)
    # y = a (1 - b x)^-p, p = 3/2 by default (divergence_b), reported with error 0
    x = np.linspace(0.0, 8.0, 50)
    f = taper.fit(x, 0.8 * (1 - 0.1 * x) ** -1.5, model="divergence_b")
    assert f.params == pytest.approx([0.8, 0.1, 1.5], rel=1e-9)
    assert f.n_params == 2 and f.errors[2] == 0.0
    # y = a (1 - x/C)^-p with p fitted (the default of divergence_c)
    f = taper.fit(x, 1.3 * (1 - x / 9.0) ** (-15 / 23), model="divergence_c")
    assert f.n_params == 3 and f.iterations >= 0
    assert f.params == pytest.approx([1.3, 9.0, 15 / 23], rel=1e-7)
    # ... or given
    f = taper.fit(x, 1.3 * (1 - x / 9.0) ** -2.0, model="divergence_c", exponent=2.0)
    assert f.params == pytest.approx([1.3, 9.0, 2.0], rel=1e-9) and f.n_params == 2
    # y = a (1 + x/M)^-f
    f = taper.fit(x, 2.0 * (1 + x / 3.0) ** -0.6, model="divergence_m")
    assert f.params == pytest.approx([2.0, 3.0, 0.6], rel=1e-7)


def test_fit_windows_and_skipping():
    x = np.arange(1.0, 101.0)
    y = np.where(x < 50, 7.0 * x ** 0.5, 2.0 * x ** -1.0)   # two laws
    f = taper.fit(x, y, index_window=(49, None))
    assert f.params == pytest.approx([2.0, -1.0], rel=1e-12) and f.n_points == 51
    f = taper.fit(x, y, index_window=(0, 49))
    assert f.params == pytest.approx([7.0, 0.5], rel=1e-12) and f.n_points == 49
    f = taper.fit(x, y, x_window=(60.0, None))
    assert f.params[1] == pytest.approx(-1.0, rel=1e-12) and f.n_points == 41
    f = taper.fit(x, y, x_window=(None, 10.0))
    assert f.params[1] == pytest.approx(0.5, rel=1e-12) and f.n_points == 10
    z = y.copy()
    z[60] = np.nan
    z[70] = -1.0
    f = taper.fit(x, z, index_window=(49, 0))
    assert f.n_skipped == 2 and f.n_points == 49
    with pytest.raises(taper.InvalidArgumentError):
        taper.fit(x, z, index_window=(49, 0), skip_invalid=False)


@pytest.mark.parametrize("kw,field", [
    (dict(model="cubic"), "model"),
    (dict(xtol=0.0), "xtol"),
    (dict(xtol=1.0), "xtol"),
    (dict(max_iter=0), "max_iter"),
    (dict(exponent=-1.0), "exponent"),
    (dict(exponent=math.nan), "exponent"),          # fitting p: divergence_c only
    (dict(index_window=(5, 5)), "index_window"),
    (dict(index_window=(3, 200)), "index_window"),  # beyond the data
    (dict(x_window=(2.0, 1.0)), "x_window"),
    (dict(index_window=(-1, 4)), "index_window"),
    (dict(max_iter=-3), "max_iter"),
])
def test_fit_refusals_are_value_errors_naming_the_keyword(kw, field):
    x = np.arange(1.0, 11.0)
    with pytest.raises(ValueError) as e:
        taper.fit(x, x ** 2, **kw)
    assert isinstance(e.value, taper.InvalidArgumentError)
    assert e.value.field == field, (kw, e.value.field, str(e.value))
    assert str(e.value).startswith(field)


def test_fit_bad_data():
    with pytest.raises(taper.InvalidArgumentError) as e:
        taper.fit([1.0, 2.0, 3.0], [1.0, 2.0])
    assert e.value.field == "y"
    with pytest.raises(taper.InvalidArgumentError, match="usable points"):
        taper.fit([1.0, 2.0], [1.0, 2.0])
    with pytest.raises(taper.InvalidArgumentError, match="all equal"):
        taper.fit([2.0, 2.0, 2.0], [1.0, 2.0, 3.0])
    for kw, value in (("x", "123"), ("x", [[1.0, 2.0]]), ("y", ["a", "b"]), ("y", None)):
        args = {"x": [1.0, 2.0, 3.0], "y": [1.0, 2.0, 3.0], kw: value}
        with pytest.raises(TypeError, match=kw):
            taper.fit(args["x"], args["y"])
    for kw, value in (("model", 1), ("exponent", "2"), ("index_window", 3),
                      ("index_window", (1.0, 3)), ("x_window", (0, "1")), ("x_window", [1.0]),
                      ("skip_invalid", "yes"), ("max_iter", 2.0), ("xtol", [1e-9])):
        with pytest.raises(TypeError, match=kw):
            taper.fit([1.0, 2.0, 3.0], [1.0, 2.0, 3.0], **{kw: value})
    with pytest.raises(TypeError):
        taper.fit([1.0, 2.0, 3.0], [1.0, 2.0, 3.0], "power")  # keywords only


def test_fit_of_a_run_recovers_the_paper_law():
    """The theory of a long backward linear chain decays as k^-3/2, eq. (22):
    fitted over its last granules, as the driver's &fit does."""
    th = taper.theory(profile="backward_linear", s=0.5, n_granules=2000)
    f = taper.fit(th.k, th.theory_v, index_window=(1000, None))
    assert f.params[1] == pytest.approx(asymptotic.exponent("v_of_k"), abs=2e-3)
    f = taper.fit(th.theory_t, th.theory_v, index_window=(1000, 1999))
    assert f.params[1] == pytest.approx(asymptotic.exponent("v_of_t"), abs=3e-3)
