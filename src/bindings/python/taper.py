"""taper -- Python access to libtaper through ctypes (no compiled extension).

Pulse propagation in tapered granular chains: build a chain, compute the
binary-collision theory, integrate the full dynamics and read the
per-granule observables, all in the shared library libtaper.

    import taper
    chain = taper.Chain("backward_linear", n_granules=100, s=0.1)
    sim = taper.Sim(chain, rtol=1e-10)    # other settings: the library's defaults
    sim.run()                             # raises taper.TaperError on failure
    th = sim.theory                       # v, mu, T, t (computed once by the sim)
    print(sim.t_pass[:5], sim.v_peak[:5], th["t"][:5], sim.stats["steps"])

How it binds the library (docs/api.md, "Why opaque objects"): settings
live in objects the library allocates, so nothing here mirrors a struct
of settings.  A keyword argument `name=value` of Chain or Sim calls the
setter taper_chain_spec_set_<name> or taper_solver_spec_set_<name>, looked
up in the library by name; the setter checks the value and a refusal
raises TaperError whose .field names the setting (the keyword).  Profile,
method and fit model names, and the names of the statistics, come from
the library's own lists (taper_profile_name, ...).  Only the two structs
the library fills and never reorders are declared here: taper_error and
taper_progress.

Arrays are numpy arrays when numpy is importable and lists otherwise;
granule k sits at index k-1, values that do not exist are NaN (see
include/taper.h, docs/api.md).

The library is found, in this order, at $TAPER_LIBRARY (a path to
libtaper.so), in a Meson build directory of the source tree this file
belongs to (build*/src/libtaper.so), and by ctypes.util.find_library.

Thread safety: distinct Chain/Sim objects may be used from distinct threads;
ctypes releases the GIL during library calls, so runs in threads overlap.
"""

import ctypes
import ctypes.util
import glob
import math
import os

try:  # optional
    import numpy as _np
except ImportError:  # pragma: no cover - depends on the installation
    _np = None

__all__ = [
    "TaperError", "Chain", "Sim", "theory", "collision_time", "version", "fit",
    "library_path", "PROFILES", "METHODS", "FIT_MODELS", "STATISTICS", "OBSERVABLES",
    "THEORY", "LAWS", "CHAIN_SETTINGS", "SOLVER_SETTINGS", "FIT_SETTINGS",
    "asymptotic_exponent",
]

# Enums of taper.h that the library gives no names for, in enum order: the
# Python spelling of the observables, theory columns and laws.
OBSERVABLES = ("t_pass", "t_res", "v_peak", "t_peak", "x_pass")
THEORY = ("v", "mu", "T", "t")
LAWS = ("v_of_k", "t_res_of_k", "t_of_k", "k_of_t", "v_of_t", "x_of_t", "c_of_t",
        "fwd_v_of_k", "fwd_t_of_k", "fwd_v_of_t")
STATUS = {0: "TAPER_OK", 1: "TAPER_EINVAL", 2: "TAPER_ENOMEM", 3: "TAPER_ERANGE",
          4: "TAPER_ESOLVER", 5: "TAPER_EINTERRUPTED", 6: "TAPER_ELIMIT"}
MESSAGE_SIZE = 512  # TAPER_MESSAGE_SIZE

_c_double_p = ctypes.POINTER(ctypes.c_double)


class TaperError(Exception):
    """A failing libtaper call: .status (int), .name ('TAPER_ESOLVER', ...),
    .field (the setting at fault, spelt as its setter and keyword, e.g.
    'rtol'; None when no single setting is), .message (the library's)."""

    def __init__(self, status, message, field=None):
        self.status = status
        self.name = STATUS.get(status, "status %d" % status)
        self.field = field
        self.message = message
        super().__init__("%s%s: %s" % (self.name, " (%s)" % field if field else "", message))


# ---- the two structs the library fills (frozen: fields are only appended) --
class _Error(ctypes.Structure):
    _fields_ = [("status", ctypes.c_int), ("field", ctypes.c_char_p),
                ("message", ctypes.c_char * MESSAGE_SIZE)]


class _Progress(ctypes.Structure):
    _fields_ = [("granule", ctypes.c_size_t), ("target", ctypes.c_size_t),
                ("t", ctypes.c_double), ("steps", ctypes.c_long),
                ("window_lo", ctypes.c_size_t), ("window_hi", ctypes.c_size_t)]


_MonitorFn = ctypes.CFUNCTYPE(ctypes.c_int, ctypes.POINTER(_Progress), ctypes.c_void_p)
_LogFn = ctypes.CFUNCTYPE(None, ctypes.c_int, ctypes.c_char_p, ctypes.c_void_p)


# ---- loading --------------------------------------------------------------
def _candidates():
    env = os.environ.get("TAPER_LIBRARY")
    if env:
        yield env
        return
    here = os.path.dirname(os.path.abspath(__file__))
    root = os.path.dirname(os.path.dirname(os.path.dirname(here)))  # src/bindings/python -> source root
    builds = glob.glob(os.path.join(root, "build*", "src", "libtaper.so"))
    for path in sorted(builds, key=os.path.getmtime, reverse=True):
        yield path
    found = ctypes.util.find_library("taper")
    if found:
        yield found


def _load():
    errors = []
    for path in _candidates():
        try:
            return ctypes.CDLL(path), path
        except OSError as exc:
            errors.append("%s: %s" % (path, exc))
    raise ImportError("libtaper not found (set TAPER_LIBRARY to the path of libtaper.so)"
                      + ("; tried " + "; ".join(errors) if errors else ""))


_lib, library_path = _load()


def _fn(name, restype, *argtypes):
    f = getattr(_lib, name)
    f.restype = restype
    f.argtypes = list(argtypes)
    return f


_P = ctypes.c_void_p
_E = ctypes.POINTER(_Error)
_int_p = ctypes.POINTER(ctypes.c_int)
_size_p = ctypes.POINTER(ctypes.c_size_t)
_version = _fn("taper_version", ctypes.c_char_p)
_strerror = _fn("taper_strerror", ctypes.c_char_p, ctypes.c_int)
_name_fns = {kind: _fn("taper_%s_name" % kind, ctypes.c_char_p, ctypes.c_int)
             for kind in ("profile", "method", "fit_model", "statistic")}
_from_name_fns = {kind: _fn("taper_%s_from_name" % kind, ctypes.c_int, ctypes.c_char_p, _int_p, _E)
                  for kind in ("profile", "method", "fit_model")}
_chain_spec_alloc = _fn("taper_chain_spec_alloc", _P, _E)
_chain_spec_free = _fn("taper_chain_spec_free", None, _P)
_chain_spec_set_radii = _fn("taper_chain_spec_set_radii", ctypes.c_int, _P, _c_double_p,
                            ctypes.c_size_t, _E)
_chain_alloc = _fn("taper_chain_alloc", _P, _P, _E)
_chain_free = _fn("taper_chain_free", None, _P)
_chain_size = _fn("taper_chain_size", ctypes.c_size_t, _P)
_chain_exponent = _fn("taper_chain_exponent", ctypes.c_double, _P)
_chain_profile = _fn("taper_chain_profile", ctypes.c_int, _P)
_chain_arrays = {name: _fn("taper_chain_" + name, _c_double_p, _P)
                 for name in ("radius", "mass", "contact", "rest_position")}
_collision_time = _fn("taper_theory_collision_time", ctypes.c_double, ctypes.c_double,
                      ctypes.c_double, ctypes.c_double, ctypes.c_double)
_theory_compute = _fn("taper_theory_compute", ctypes.c_int, _P, _c_double_p, _c_double_p,
                      _c_double_p, _c_double_p, _E)
_solver_spec_alloc = _fn("taper_solver_spec_alloc", _P, _E)
_solver_spec_free = _fn("taper_solver_spec_free", None, _P)
_solver_spec_set_monitor = _fn("taper_solver_spec_set_monitor", None, _P, _MonitorFn, _P)
_solver_spec_set_log = _fn("taper_solver_spec_set_log", None, _P, _LogFn, _P)
_sim_alloc = _fn("taper_sim_alloc", _P, _P, _P, _E)
_sim_free = _fn("taper_sim_free", None, _P)
_sim_run = _fn("taper_sim_run", ctypes.c_int, _P, _E)
_sim_observable = _fn("taper_sim_observable", _c_double_p, _P, ctypes.c_int)
_sim_theory = _fn("taper_sim_theory", _c_double_p, _P, ctypes.c_int)
_sim_statistic = _fn("taper_sim_statistic", ctypes.c_double, _P, ctypes.c_int)
_sim_state = _fn("taper_sim_state", ctypes.c_int, _P, _c_double_p, _c_double_p, _E)
_asymptotic_exponent = _fn("taper_asymptotic_exponent", ctypes.c_double, ctypes.c_int,
                           ctypes.c_double)
_fit_spec_alloc = _fn("taper_fit_spec_alloc", _P, ctypes.c_int, _E)
_fit_spec_free = _fn("taper_fit_spec_free", None, _P)
_fit = _fn("taper_fit", _P, _P, _c_double_p, _c_double_p, ctypes.c_size_t, _E)
_fit_result_free = _fn("taper_fit_result_free", None, _P)
_fit_result_getters = {
    name: _fn("taper_fit_result_" + name, restype, _P)
    for name, restype in (("n_params", ctypes.c_size_t), ("n_points", ctypes.c_size_t),
                          ("n_skipped", ctypes.c_size_t), ("chi2", ctypes.c_double),
                          ("iterations", ctypes.c_size_t))}
_fit_result_param = _fn("taper_fit_result_param", ctypes.c_double, _P, ctypes.c_size_t)
_fit_result_param_error = _fn("taper_fit_result_param_error", ctypes.c_double, _P,
                              ctypes.c_size_t)


def _names(kind):
    """The library's list of names of one enum: name(0), name(1), ... until NULL."""
    out = []
    while True:
        name = _name_fns[kind](len(out))
        if name is None:
            return tuple(out)
        out.append(name.decode())


PROFILES = _names("profile")
METHODS = _names("method")
FIT_MODELS = _names("fit_model")
STATISTICS = _names("statistic")


def version():
    """Version of the loaded library ("0.2.0")."""
    return _version().decode()


def _raise(err):
    raise TaperError(err.status, err.message.decode(errors="replace"),
                     err.field.decode() if err.field else None)


def _check(status, err):
    if status != 0:
        _raise(err)


def _array(ptr, n):
    """A copy of n doubles at ptr: numpy array or list."""
    if _np is not None:
        return _np.ctypeslib.as_array(ptr, shape=(n,)).copy()
    return ptr[:n]


def _buffer(n):
    return (ctypes.c_double * n)()


def _from_buffer(buf):
    return _np.array(buf, dtype=float) if _np is not None else list(buf)


def _doubles(values):
    values = [float(x) for x in values]
    return (ctypes.c_double * len(values))(*values), len(values)


def _enum(value, names, what):
    """Index of a name of one of the Python-side lists above (or an int)."""
    if isinstance(value, int):
        return value
    try:
        return names.index(str(value).lower())
    except ValueError:
        raise ValueError("unknown %s %r: one of %s" % (what, value, ", ".join(names))) from None


def _from_name(kind, value):
    """An enum setting given by name, resolved by the library (which names the
    field when it does not know the name), or given as its number."""
    if isinstance(value, int):
        return value
    code, err = ctypes.c_int(), _Error()
    _check(_from_name_fns[kind](str(value).encode(), ctypes.byref(code), ctypes.byref(err)), err)
    return code.value


# ---- settings by name -------------------------------------------------------
# C has no reflection and ctypes must be told each prototype: the type of the
# value each setter takes.  Which setters exist, their ranges and their
# defaults are the library's (a setter missing from the loaded library
# raises AttributeError at import, not a silent mismatch).
CHAIN_SETTINGS = {"profile": ctypes.c_int, "n_granules": ctypes.c_size_t,
                  "s": ctypes.c_double, "q": ctypes.c_double, "exponent": ctypes.c_double}
SOLVER_SETTINGS = {"method": ctypes.c_int, "rtol": ctypes.c_double, "atol": ctypes.c_double,
                   "last_granule": ctypes.c_size_t, "window": ctypes.c_int,
                   "max_order": ctypes.c_int, "t_max": ctypes.c_double,
                   "max_steps": ctypes.c_long}
FIT_SETTINGS = {"exponent": (ctypes.c_double,), "index_window": (ctypes.c_size_t, ctypes.c_size_t),
                "x_window": (ctypes.c_double, ctypes.c_double), "skip_invalid": (ctypes.c_int,),
                "max_iter": (ctypes.c_size_t,), "xtol": (ctypes.c_double,)}
_ENUM_SETTINGS = {"profile": "profile", "method": "method"}


def _setters(prefix, settings):
    return {name: _fn("%s_set_%s" % (prefix, name), ctypes.c_int, _P,
                      *(types if isinstance(types, tuple) else (types,)), _E)
            for name, types in settings.items()}


_chain_setters = _setters("taper_chain_spec", CHAIN_SETTINGS)
_solver_setters = _setters("taper_solver_spec", SOLVER_SETTINGS)
_fit_setters = _setters("taper_fit_spec", FIT_SETTINGS)


def _c_value(name, ctype, value):
    """value as the setter's argument.  Only what ctypes itself cannot pass
    faithfully is refused here: a negative count would wrap around."""
    if name in _ENUM_SETTINGS:
        return _from_name(_ENUM_SETTINGS[name], value)
    if ctype is ctypes.c_double:
        return float(value)
    value = int(value)
    if ctype is ctypes.c_size_t and value < 0:
        raise TaperError(1, "%s = %d: must be >= 0" % (name, value), name)
    return value


def _apply(spec, setters, settings, what):
    """Calls the setter of each keyword; a refusal raises TaperError naming it."""
    for name, value in settings.items():
        setter = setters.get(name)
        if setter is None:
            raise TypeError("unknown %s setting %r: one of %s" % (what, name, ", ".join(setters)))
        types = setter.argtypes[1:-1]
        values = value if len(types) > 1 else (value,)
        if len(values) != len(types):
            raise TypeError("%s takes %d values" % (name, len(types)))
        err = _Error()
        args = [_c_value(name, t, v) for t, v in zip(types, values)]
        _check(setter(spec, *args, ctypes.byref(err)), err)


class _Owned:
    """A library object freed with its *_free."""

    def __init__(self, ptr, free):
        self.ptr, self._free = ptr, free

    def __enter__(self):
        return self.ptr

    def __exit__(self, *exc):
        self._free(self.ptr)


def _alloc(alloc, free, *args):
    err = _Error()
    ptr = alloc(*args, ctypes.byref(err))
    if not ptr:
        _raise(err)
    return _Owned(ptr, free)


# ---- chains ----------------------------------------------------------------
class Chain:
    """A granular chain: Chain(profile, n_granules=..., s=..., q=...,
    exponent=..., radii=None).  profile is a name of PROFILES (the library's
    list) or its number; every keyword calls the setter of that name
    (CHAIN_SETTINGS), settings not given keep the library's defaults.  radii
    (any sequence) makes a custom chain of len(radii) granules unless
    profile and n_granules are given.  Raises TaperError (TAPER_EINVAL,
    TAPER_ERANGE) with the library's message and .field naming the setting."""

    def __init__(self, profile=None, radii=None, **settings):
        if profile is None and radii is not None:
            profile = "custom"
        if profile is not None:
            settings = dict(profile=profile, **settings)
        if radii is not None:
            settings.setdefault("n_granules", len(radii))
        self._ptr = None
        with _alloc(_chain_spec_alloc, _chain_spec_free) as spec:
            _apply(spec, _chain_setters, settings, "chain")
            if radii is not None:
                buf, n = _doubles(radii)
                err = _Error()
                _check(_chain_spec_set_radii(spec, ctypes.cast(buf, _c_double_p), n,
                                             ctypes.byref(err)), err)  # copied
            err = _Error()
            ptr = _chain_alloc(spec, ctypes.byref(err))
        if not ptr:
            _raise(err)
        self._ptr = ptr

    def __del__(self):
        if getattr(self, "_ptr", None):
            _chain_free(self._ptr)
            self._ptr = None

    def __len__(self):
        return _chain_size(self._ptr)

    @property
    def n_granules(self):
        return _chain_size(self._ptr)

    @property
    def exponent(self):
        return _chain_exponent(self._ptr)

    @property
    def profile(self):
        return PROFILES[_chain_profile(self._ptr)]

    def _get(self, name):
        return _array(_chain_arrays[name](self._ptr), len(self))

    radius = property(lambda self: self._get("radius"), doc="R_k")
    mass = property(lambda self: self._get("mass"), doc="m_k = R_k^3")
    contact = property(lambda self: self._get("contact"), doc="r_k; last entry NaN")
    rest_position = property(lambda self: self._get("rest_position"), doc="X0(k)")

    def __repr__(self):
        return "Chain(%r, n_granules=%d, exponent=%g)" % (self.profile, len(self), self.exponent)


def collision_time(mu, r, zdot0, n=2.5):
    """Residence time T of one binary collision, eq. (18) (NaN for invalid
    arguments)."""
    return _collision_time(mu, r, zdot0, n)


def theory(chain):
    """Binary collision approximation for chain: dict with arrays
    v (v_k), mu (mu_k), T (T_k), t (t_k = T_1 + ... + T_k); NaN where an
    entry does not exist.  Raises TaperError (TAPER_ERANGE) on overflow.
    A Sim has the same numbers, computed once, as Sim.theory."""
    n = len(chain)
    bufs = {key: _buffer(n) for key in THEORY}
    err = _Error()
    _check(_theory_compute(chain._ptr, *(ctypes.cast(bufs[k], _c_double_p) for k in THEORY),
                           ctypes.byref(err)), err)
    return {k: _from_buffer(b) for k, b in bufs.items()}


def asymptotic_exponent(law, n=2.5):
    """Exponent p of a large-k law (a name of LAWS or its number)."""
    return _asymptotic_exponent(_enum(law, LAWS, "law"), n)


# ---- simulations -------------------------------------------------------------
class Sim:
    """A run of the full dynamics of chain.  Every keyword calls the setter of
    that name (SOLVER_SETTINGS: method='adams'|'bdf' (METHODS, the library's
    list), rtol, atol, last_granule, window, max_order, t_max, max_steps);
    settings not given keep the library's defaults.  monitor(progress_dict)
    may return True to stop the run; log(level, message) receives the
    library's diagnostics.  Raises TaperError, .field naming the setting,
    for a value the library refuses."""

    def __init__(self, chain, monitor=None, log=None, **settings):
        self._monitor_exc = None
        self._callbacks = []  # kept alive with the sim
        self.chain = chain  # the chain must outlive the sim
        self.status = None
        self.message = ""
        self._ptr = None
        with _alloc(_solver_spec_alloc, _solver_spec_free) as spec:
            _apply(spec, _solver_setters, settings, "solver")
            if monitor is not None:
                def trampoline(progress, user):
                    p = progress.contents
                    try:
                        return 1 if monitor({f[0]: getattr(p, f[0]) for f in _Progress._fields_}) else 0
                    except BaseException as exc:  # never unwind through C
                        self._monitor_exc = exc
                        return 1
                self._callbacks.append(_MonitorFn(trampoline))
                _solver_spec_set_monitor(spec, self._callbacks[-1], None)
            if log is not None:
                def log_trampoline(level, message, user):
                    try:
                        log(level, message.decode(errors="replace"))
                    except BaseException:  # never unwind through C; a log cannot fail a run
                        pass
                self._callbacks.append(_LogFn(log_trampoline))
                _solver_spec_set_log(spec, self._callbacks[-1], None)
            err = _Error()
            ptr = _sim_alloc(chain._ptr, spec, ctypes.byref(err))  # copies spec
        if not ptr:
            _raise(err)
        self._ptr = ptr

    def __del__(self):
        if getattr(self, "_ptr", None):
            _sim_free(self._ptr)
            self._ptr = None

    def run(self, check=True):
        """Integrates until every requested observable is known.  Returns the
        status (0).  With check=True (default) any other status raises
        TaperError; the partial observables stay readable either way."""
        err = _Error()
        self.status = _sim_run(self._ptr, ctypes.byref(err))
        self.message = err.message.decode(errors="replace")
        if self._monitor_exc is not None:
            exc, self._monitor_exc = self._monitor_exc, None
            raise exc
        if check and self.status != 0:
            _raise(err)
        return self.status

    def observable(self, which):
        """Array of length N: which is a name of OBSERVABLES or its number."""
        ptr = _sim_observable(self._ptr, _enum(which, OBSERVABLES, "observable"))
        if not ptr:
            raise ValueError("unknown observable %r" % (which,))
        return _array(ptr, len(self.chain))

    t_pass = property(lambda self: self.observable("t_pass"))
    t_res = property(lambda self: self.observable("t_res"))
    v_peak = property(lambda self: self.observable("v_peak"))
    t_peak = property(lambda self: self.observable("t_peak"))
    x_pass = property(lambda self: self.observable("x_pass"))

    @property
    def theory(self):
        """The binary collision theory of the chain, computed once by the sim:
        dict with arrays v, mu, T, t (as theory(chain))."""
        return {name: _array(_sim_theory(self._ptr, i), len(self.chain))
                for i, name in enumerate(THEORY)}

    @property
    def stats(self):
        """Statistics of the run: dict by the library's names (STATISTICS:
        'steps', 'rhs_evals', ..., 'complete'); all floats, counts exact."""
        return {name: _sim_statistic(self._ptr, i) for i, name in enumerate(STATISTICS)}

    def state(self):
        """(x, v): displacements and velocities at stats['t_final']."""
        n = len(self.chain)
        x, v = _buffer(n), _buffer(n)
        err = _Error()
        _check(_sim_state(self._ptr, ctypes.cast(x, _c_double_p), ctypes.cast(v, _c_double_p),
                          ctypes.byref(err)), err)
        return _from_buffer(x), _from_buffer(v)


# ---- fits ---------------------------------------------------------------------
def fit(model, x, y, **settings):
    """Least-squares fit of y(x) (taper.h, "Fits"): model is a name of
    FIT_MODELS (the library's list) or its number; every keyword calls the
    fit setter of that name (FIT_SETTINGS: exponent, index_window=(begin,
    end), x_window=(x_min, x_max), skip_invalid, max_iter, xtol).  Returns a
    dict: params, errors (lists), n_points, n_skipped, chi2, iterations.
    Raises TaperError (.field naming the setting) on failure."""
    code = _from_name("fit_model", model)
    xs, n = _doubles(x)
    ys, ny = _doubles(y)
    if ny != n:
        raise ValueError("x and y differ in length (%d, %d)" % (n, ny))
    with _alloc(_fit_spec_alloc, _fit_spec_free, code) as spec:
        _apply(spec, _fit_setters, settings, "fit")
        err = _Error()
        result = _fit(spec, ctypes.cast(xs, _c_double_p), ctypes.cast(ys, _c_double_p), n,
                      ctypes.byref(err))
    if not result:
        _raise(err)
    try:
        out = {name: getter(result) for name, getter in _fit_result_getters.items()}
        k = out.pop("n_params")
        out["params"] = [_fit_result_param(result, i) for i in range(k)]
        out["errors"] = [_fit_result_param_error(result, i) for i in range(k)]
        out["model"] = FIT_MODELS[code]
    finally:
        _fit_result_free(result)
    return out


def _main():  # python3 taper.py: a quick look
    chain = Chain("backward_linear", n_granules=50, s=0.1)
    sim = Sim(chain)
    sim.run()
    th = sim.theory
    print("libtaper %s (%s)" % (version(), library_path))
    for k in (1, 2, 5, 10, 20, 49):
        print("k=%2d  t_pass %.6f  theory %.6f   v_peak %.6f  theory %.6f" % (
            k, sim.t_pass[k - 1], th["t"][k - 1], sim.v_peak[k - 1], th["v"][k - 1]))
    if math.isnan(sim.t_pass[-1]):
        print("(t_pass of the last granule does not exist: NaN)")
    print("  ".join("%s %g" % kv for kv in sim.stats.items()))


if __name__ == "__main__":
    _main()
