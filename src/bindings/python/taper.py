"""taper -- Python access to libtaper through ctypes (no compiled extension).

Pulse propagation in tapered granular chains: build a chain, compute the
binary-collision theory, integrate the full dynamics and read the
per-granule observables, all in the shared library libtaper.

    import taper
    chain = taper.Chain("backward_linear", n_granules=100, s=0.1)
    th = taper.theory(chain)              # v, mu, T, t
    sim = taper.Sim(chain)                # library defaults (Adams, measured tolerances)
    sim.run()                             # raises taper.TaperError on failure
    print(sim.t_pass[:5], sim.v_peak[:5], th["t"][:5])

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
    "TaperError", "Chain", "Sim", "theory", "collision_time", "version",
    "library_path", "PROFILES", "METHODS", "OBSERVABLES", "asymptotic_exponent",
    "LAWS",
]

PROFILES = ("monodisperse", "backward_linear", "forward_linear",
            "backward_exponential", "forward_exponential", "custom")
METHODS = ("adams", "bdf")
OBSERVABLES = ("t_pass", "t_res", "v_peak", "t_peak", "x_pass")
LAWS = ("v_of_k", "t_res_of_k", "t_of_k", "k_of_t", "v_of_t", "x_of_t", "c_of_t",
        "fwd_v_of_k", "fwd_t_of_k", "fwd_v_of_t")
STATUS = {0: "TAPER_OK", 1: "TAPER_EINVAL", 2: "TAPER_ENOMEM", 3: "TAPER_ERANGE",
          4: "TAPER_ESOLVER", 5: "TAPER_EINTERRUPTED", 6: "TAPER_ELIMIT", 7: "TAPER_EIO"}
MESSAGE_SIZE = 512

_c_double_p = ctypes.POINTER(ctypes.c_double)


class TaperError(Exception):
    """A failing libtaper call: .status (int), .name ('TAPER_ESOLVER', ...),
    .message (the library's message)."""

    def __init__(self, status, message):
        self.status = status
        self.name = STATUS.get(status, "status %d" % status)
        self.message = message
        super().__init__("%s: %s" % (self.name, message))


# ---- the C structs of taper.h, field by field ---------------------------
class _Error(ctypes.Structure):
    _fields_ = [("status", ctypes.c_int), ("message", ctypes.c_char * MESSAGE_SIZE)]


class _ChainSpec(ctypes.Structure):
    _fields_ = [("profile", ctypes.c_int), ("n_granules", ctypes.c_size_t),
                ("s", ctypes.c_double), ("q", ctypes.c_double),
                ("exponent", ctypes.c_double), ("radii", _c_double_p)]


class _Progress(ctypes.Structure):
    _fields_ = [("granule", ctypes.c_size_t), ("target", ctypes.c_size_t),
                ("t", ctypes.c_double), ("steps", ctypes.c_long),
                ("window_lo", ctypes.c_size_t), ("window_hi", ctypes.c_size_t)]


_MonitorFn = ctypes.CFUNCTYPE(ctypes.c_int, ctypes.POINTER(_Progress), ctypes.c_void_p)
_LogFn = ctypes.CFUNCTYPE(None, ctypes.c_int, ctypes.c_char_p, ctypes.c_void_p)


class _SolverSpec(ctypes.Structure):
    _fields_ = [("method", ctypes.c_int), ("rtol", ctypes.c_double),
                ("atol", ctypes.c_double), ("last_granule", ctypes.c_size_t),
                ("window", ctypes.c_int), ("max_order", ctypes.c_int),
                ("t_max", ctypes.c_double), ("max_steps", ctypes.c_long),
                ("monitor", _MonitorFn), ("monitor_data", ctypes.c_void_p),
                ("log", _LogFn), ("log_data", ctypes.c_void_p)]


class _Stats(ctypes.Structure):
    _fields_ = [("steps", ctypes.c_long), ("rhs_evals", ctypes.c_long),
                ("root_evals", ctypes.c_long), ("jac_evals", ctypes.c_long),
                ("nonlin_iters", ctypes.c_long), ("err_test_fails", ctypes.c_long),
                ("window_changes", ctypes.c_long), ("restarts", ctypes.c_long),
                ("max_window", ctypes.c_size_t), ("granule_reached", ctypes.c_size_t),
                ("t_final", ctypes.c_double), ("energy_error", ctypes.c_double),
                ("momentum_error", ctypes.c_double), ("complete", ctypes.c_int)]


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
_ErrP = ctypes.POINTER(_Error)
_version = _fn("taper_version", ctypes.c_char_p)
_strerror = _fn("taper_strerror", ctypes.c_char_p, ctypes.c_int)
_profile_from_name = _fn("taper_profile_from_name", ctypes.c_int, ctypes.c_char_p,
                         ctypes.POINTER(ctypes.c_int))
_chain_spec_init = _fn("taper_chain_spec_init", None, ctypes.POINTER(_ChainSpec))
_chain_alloc = _fn("taper_chain_alloc", _P, ctypes.POINTER(_ChainSpec), _ErrP)
_chain_free = _fn("taper_chain_free", None, _P)
_chain_size = _fn("taper_chain_size", ctypes.c_size_t, _P)
_chain_exponent = _fn("taper_chain_exponent", ctypes.c_double, _P)
_chain_profile = _fn("taper_chain_profile", ctypes.c_int, _P)
_chain_arrays = {name: _fn("taper_chain_" + name, _c_double_p, _P)
                 for name in ("radius", "mass", "contact", "rest_position")}
_collision_time = _fn("taper_theory_collision_time", ctypes.c_double, ctypes.c_double,
                      ctypes.c_double, ctypes.c_double, ctypes.c_double)
_theory_compute = _fn("taper_theory_compute", ctypes.c_int, _P, _c_double_p, _c_double_p,
                      _c_double_p, _c_double_p, _ErrP)
_solver_spec_init = _fn("taper_solver_spec_init", None, ctypes.POINTER(_SolverSpec))
_sim_alloc = _fn("taper_sim_alloc", _P, _P, ctypes.POINTER(_SolverSpec), _ErrP)
_sim_free = _fn("taper_sim_free", None, _P)
_sim_run = _fn("taper_sim_run", ctypes.c_int, _P, _ErrP)
_sim_observable = _fn("taper_sim_observable", _c_double_p, _P, ctypes.c_int)
_sim_stats = _fn("taper_sim_stats", None, _P, ctypes.POINTER(_Stats))
_sim_state = _fn("taper_sim_state", ctypes.c_int, _P, _c_double_p, _c_double_p, _ErrP)
_asymptotic_exponent = _fn("taper_asymptotic_exponent", ctypes.c_double, ctypes.c_int,
                           ctypes.c_double)


def version():
    """Version of the loaded library ("0.1.0")."""
    return _version().decode()


def _raise(err):
    raise TaperError(err.status, err.message.decode(errors="replace"))


def _array(ptr, n):
    """A copy of n doubles at ptr: numpy array or list."""
    if _np is not None:
        return _np.ctypeslib.as_array(ptr, shape=(n,)).copy()
    return ptr[:n]


def _buffer(n):
    return (ctypes.c_double * n)()


def _from_buffer(buf):
    return _np.array(buf, dtype=float) if _np is not None else list(buf)


def _enum(value, names, what):
    if isinstance(value, int):
        return value
    try:
        return names.index(str(value).lower())
    except ValueError:
        raise ValueError("unknown %s %r: one of %s" % (what, value, ", ".join(names))) from None


# ---- chains ----------------------------------------------------------------
class Chain:
    """A granular chain: Chain(profile, n_granules=100, s=0, q=0, exponent=2.5,
    radii=None).  profile is a name of PROFILES (or its number); radii (any
    sequence) makes a custom chain and sets n_granules.  Raises TaperError
    (TAPER_EINVAL, TAPER_ERANGE) with the library's message."""

    def __init__(self, profile="monodisperse", n_granules=None, s=None, q=None,
                 exponent=None, radii=None):
        spec = _ChainSpec()
        _chain_spec_init(ctypes.byref(spec))
        if radii is not None and profile == "monodisperse":
            profile = "custom"
        if isinstance(profile, str):
            code = ctypes.c_int()
            if _profile_from_name(profile.encode(), ctypes.byref(code)) != 0:
                raise ValueError("unknown profile %r: one of %s" % (profile, ", ".join(PROFILES)))
            profile = code.value
        spec.profile = profile
        if n_granules is not None:
            spec.n_granules = int(n_granules)
        if s is not None:
            spec.s = float(s)
        if q is not None:
            spec.q = float(q)
        if exponent is not None:
            spec.exponent = float(exponent)
        radii_buf = None
        if radii is not None:
            values = [float(r) for r in radii]
            radii_buf = (ctypes.c_double * len(values))(*values)
            spec.radii = ctypes.cast(radii_buf, _c_double_p)
            spec.n_granules = len(values)
        err = _Error()
        self._ptr = None
        ptr = _chain_alloc(ctypes.byref(spec), ctypes.byref(err))  # copies radii
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
    """Residence time T of one binary collision (NaN for invalid arguments)."""
    return _collision_time(mu, r, zdot0, n)


def theory(chain):
    """Binary collision approximation for chain: dict with arrays
    v (v_k), mu (mu_k), T (T_k), t (t_k = T_1 + ... + T_k); NaN where an
    entry does not exist.  Raises TaperError (TAPER_ERANGE) on overflow."""
    n = len(chain)
    bufs = {key: _buffer(n) for key in ("v", "mu", "T", "t")}
    err = _Error()
    status = _theory_compute(chain._ptr, *(ctypes.cast(bufs[k], _c_double_p)
                                           for k in ("v", "mu", "T", "t")), ctypes.byref(err))
    if status != 0:
        _raise(err)
    return {k: _from_buffer(b) for k, b in bufs.items()}


def asymptotic_exponent(law, n=2.5):
    """Exponent p of a large-k law (a name of LAWS or its number)."""
    return _asymptotic_exponent(_enum(law, LAWS, "law"), n)


# ---- simulations -------------------------------------------------------------
class Sim:
    """A run of the full dynamics of chain.  Keyword arguments set fields of
    taper_solver_spec (method='adams'|'bdf', rtol, atol, last_granule, window,
    max_order, t_max, max_steps); the others keep the library's defaults.
    monitor(progress_dict) may return True to stop the run.  Raises
    TaperError for invalid settings."""

    def __init__(self, chain, method=None, monitor=None, **settings):
        spec = _SolverSpec()
        _solver_spec_init(ctypes.byref(spec))
        if method is not None:
            spec.method = _enum(method, METHODS, "method")
        names = {f[0] for f in _SolverSpec._fields_} - {"method", "monitor", "monitor_data",
                                                         "log", "log_data"}
        for key, value in settings.items():
            if key not in names:
                raise TypeError("unknown solver setting %r: one of %s" % (key, ", ".join(sorted(names))))
            setattr(spec, key, int(value) if key in ("last_granule", "window", "max_order",
                                                     "max_steps") else float(value))
        self._monitor_exc = None
        self._monitor_cb = None
        if monitor is not None:
            def trampoline(progress, user):
                p = progress.contents
                try:
                    return 1 if monitor({f[0]: getattr(p, f[0]) for f in _Progress._fields_}) else 0
                except BaseException as exc:  # never unwind through C
                    self._monitor_exc = exc
                    return 1
            self._monitor_cb = _MonitorFn(trampoline)  # kept alive with the sim
            spec.monitor = self._monitor_cb
        self.chain = chain  # the chain must outlive the sim
        self.status = None
        self.message = ""
        err = _Error()
        self._ptr = None
        ptr = _sim_alloc(chain._ptr, ctypes.byref(spec), ctypes.byref(err))
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
    def stats(self):
        """Solver statistics (dict of taper_stats' fields)."""
        s = _Stats()
        _sim_stats(self._ptr, ctypes.byref(s))
        return {f[0]: getattr(s, f[0]) for f in _Stats._fields_}

    def state(self):
        """(x, v): displacements and velocities at stats['t_final']."""
        n = len(self.chain)
        x, v = _buffer(n), _buffer(n)
        err = _Error()
        if _sim_state(self._ptr, ctypes.cast(x, _c_double_p), ctypes.cast(v, _c_double_p),
                      ctypes.byref(err)) != 0:
            _raise(err)
        return _from_buffer(x), _from_buffer(v)


def _main():  # python3 taper.py: a quick look
    chain = Chain("backward_linear", n_granules=50, s=0.1)
    sim = Sim(chain)
    sim.run()
    th = theory(chain)
    print("libtaper %s (%s)" % (version(), library_path))
    for k in (1, 2, 5, 10, 20, 49):
        print("k=%2d  t_pass %.6f  theory %.6f   v_peak %.6f  theory %.6f" % (
            k, sim.t_pass[k - 1], th["t"][k - 1], sim.v_peak[k - 1], th["v"][k - 1]))
    if math.isnan(sim.t_pass[-1]):
        print("(t_pass of the last granule does not exist: NaN)")


if __name__ == "__main__":
    _main()
