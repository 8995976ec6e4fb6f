#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""peer_heyoka.py -- heyoka (Taylor method, LLVM-compiled) as a peer of taper-bench.

    python3 peer_heyoka.py CHAIN_FILE TOL [--eps E] [--cpu-limit S] [--keep-gaps]
                           [--reference REF]

CHAIN_FILE: one line per granule k = 1..N, "m_k r_k" (mass, contact factor of
contact k with k + 1; the last line's r is nan), as libtaper computes them
(taper-bench --heyoka writes it from taper_chain_mass and taper_chain_contact).
The equations are eq. (6) (motion_rescaled) with Hertz contacts (n = 5/2):
m_k v_k' = r_{k-1} z_{k-1}^{3/2} - r_k z_k^{3/2}, z_k' = v_k - v_{k+1},
z_k = x_k - x_{k+1} the compressions of docs/design.md, v_1(0) = 1, every other
granule at rest and just touching.  The whole chain is integrated (heyoka has
no window), single-threaded.

Prints "key value" lines (heyoka, n, tol, eps, compile_seconds,
integration_seconds, steps, events, energy_drift, t_final, complete) and one
line "granule k t_pass v_peak t_peak" per granule (nan where unknown), the
observables of the C peers (peers/peers.h).  With --reference REF
(taper-reference's output for the chain, "k t_pass" per line, # comments)
also "err_t_pass E": the largest relative pass-time error over granules
1..N-2, as taper-bench measures it.  CPU seconds (process time):
compile_seconds is building the integrator (LLVM), integration_seconds
the propagation alone.  Exit 2 when heyoka cannot be imported (one line on
stderr), 1 on bad input.

The formulation, and why:

 * State in binary-collision units: u_k = v_k / V_k, w_k = z_k / Z_k with V_k
   the velocity of granule k in the binary collision approximation
   (V_1 = 1, V_{k+1} = 2 m_k V_k / (m_k + m_{k+1})) and Z_k the largest
   compression of the two-body collision of k and k + 1 at that velocity
   (mu_k V_k^2 / 2 = r_k Z_k^{5/2} / (5/2)).  heyoka controls one norm over
   the whole state; unscaled, the light granules of a backward chain (large
   velocities, tiny compressions) would set it and the pulse elsewhere
   would be under-resolved.
 * A contact's force is switched by a parameter p_k (0 or 1):
   F_k = p_k r_k Z_k^{3/2} (p_k w_k + 1 - p_k)^{3/2}.  With p_k = 0 the power
   sees the constant 1, so heyoka's Taylor recursion of the power (which
   divides by its argument) never meets z <= 0.
 * A contact is on while w_k > eps: a terminal event on w_k - eps (either
   direction) flips p_k.  The part of the contact's impulse that acts while
   0 < z < eps Z_k is applied at the switch as a kick, from the exact
   leading behaviour near a kink (z linear in time, dz/dt = u):
   J = r (eps Z)^{5/2} / ((5/2) |u|), to k backward and k + 1 forward.
   Momentum is exact; the error is of relative order eps Z |a| / u^2 in J
   (a: the relative acceleration), and the truncated precursor ahead of the
   pulse (granules ahead are exactly at rest until the compression behind
   them reaches eps Z) is of the same order.  Why a threshold at all: the
   force is not analytic where a contact opens or closes (z^{3/2}), so a
   Taylor step's radius of convergence near a kink is the time to the kink;
   a switch at z = 0 would need steps shrinking to zero there, and heyoka's
   power recursion is NaN at z = 0.
 * The terminal events have cooldown 0, and a switch moves w_k off the
   root by 1e-9 eps + 1e-15, more than the root's rounding: heyoka's
   automatic cooldown grows as the event function's slope at the trigger
   shrinks, and a contact closed slowly by the precursor then missed its
   opening (a NaN state from the power of a negative w).
 * A gap whose two granules fly freely apart (both neighbouring contacts
   open, separating, the pair's pass times and peaks known) leaves the
   state for its closed form z0 + (v_k - v_{k+1}) (t - t0) (its w_k held at
   -1, its derivative switched off by a second parameter) and comes back
   when a neighbouring contact closes.  Kept in the state (--keep-gaps),
   the open gaps behind a backward chain's pulse grow to thousands of
   compression scales and set heyoka's one norm, which loosens the error
   control of everything else.  Checked for at the run's stops (every
   100 time units or 10% of t, and at every switch).
 * Pass times: the first upward zero of v_{k+1} - v_k while armed as in
   src/sim/events.c (k the next granule to pass, or v_k > 1e-6 of the
   pulse velocity at the last pass); peaks: the first downward zero of
   rho_{k-1} z_{k-1} - rho_k z_k (rho_k = r_k^{2/3}, the sign of the
   acceleration; docs/design.md "Pulse events") while v_k > 1e-6 v_ref and
   v_k > 0; non-terminal events, the state at the root from heyoka's dense
   output.  The last granule's peak is its velocity when its contact opens.
   The pass of granule N - 1 is terminal: the run ends when every peak is
   known or 20 residence times after the last pass (peers/peer_common.c).
"""
import math
import sys
import time


def load_chain(path):
    m, r = [], []
    with open(path) as f:
        for line_no, line in enumerate(f, 1):
            s = line.split()
            if not s or s[0].startswith("#"):
                continue
            if len(s) != 2:
                raise ValueError(f"{path}:{line_no}: expected 'm r', got {line.strip()!r}")
            m.append(float(s[0]))
            r.append(float(s[1]))
    if len(m) < 2:
        raise ValueError(f"{path}: need at least 2 granules")
    for k in range(len(m) - 1):
        if not (m[k] > 0 and r[k] > 0 and math.isfinite(m[k]) and math.isfinite(r[k])):
            raise ValueError(f"{path}: granule {k + 1}: mass and contact factor must be positive and finite")
    if not (m[-1] > 0 and math.isfinite(m[-1])):
        raise ValueError(f"{path}: granule {len(m)}: mass must be positive and finite")
    return m, r[:-1]


def binary_collision_scales(m, r):
    """V_k (velocity) and Z_k (largest compression) of the binary collision approximation."""
    n = len(m)
    V = [1.0] * n
    for k in range(n - 1):
        V[k + 1] = 2.0 * m[k] * V[k] / (m[k] + m[k + 1])
    Z = []
    for k in range(n - 1):
        mu = m[k] * m[k + 1] / (m[k] + m[k + 1])
        Z.append((1.25 * mu * V[k] ** 2 / r[k]) ** 0.4)
    return V, Z


def run(m, r, tol, eps, cpu_limit, keep_gaps=False):
    import heyoka as hy
    import numpy as np

    n = len(m)
    V, Z = binary_collision_scales(m, r)
    iu = lambda k: 2 * k  # u_{k+1} (0-based granule k)
    iw = lambda k: 2 * k + 1  # w_{k+1} (0-based contact k)
    dim = 2 * n - 1
    names = []
    for k in range(n):
        names.append(f"u{k}")
        if k < n - 1:
            names.append(f"w{k}")
    sv = hy.make_vars(*names)
    u = [sv[iu(k)] for k in range(n)]
    w = [sv[iw(k)] for k in range(n - 1)]
    p = [hy.par[k] for k in range(n - 1)]
    f = [hy.par[n - 1 + k] for k in range(n - 1)]  # 0: the gap is frozen (below)
    # contact forces in physical units
    F = [r[k] * Z[k] ** 1.5 * p[k] * (p[k] * w[k] + (1.0 - p[k])) ** 1.5 for k in range(n - 1)]
    sys_eq = []
    for k in range(n):
        acc = 0.0
        if k > 0:
            acc = acc + F[k - 1]
        if k < n - 1:
            acc = acc - F[k]
        sys_eq.append((u[k], acc / (m[k] * V[k])))
        if k < n - 1:
            sys_eq.append((w[k], f[k] * (V[k] * u[k] - V[k + 1] * u[k + 1]) / Z[k]))
    state = np.zeros(dim)
    state[iu(0)] = 1.0 / V[0]
    pars = np.concatenate([np.zeros(n - 1), np.ones(n - 1)])

    t_pass = [math.nan] * n
    v_peak = [math.nan] * n
    t_peak = [math.nan] * n
    v_peak[0], t_peak[0] = 1.0, 0.0
    ev = {"next_pass": 1, "next_peak": 2, "v_ref": 1.0, "t_end": math.inf, "ta": None, "events": 0}

    def velocity(k0, t):
        """v of 0-based granule k0 at time t (dense output)."""
        d = ev["ta"].update_d_output(t)
        return d[iu(k0)] * V[k0]

    def record_pass(k, t, v_next):  # k 1-based
        t_pass[k - 1] = t
        if v_next > 0.0:
            ev["v_ref"] = v_next
        while ev["next_pass"] <= n - 1 and not math.isnan(t_pass[ev["next_pass"] - 1]):
            ev["next_pass"] += 1
        if ev["next_pass"] > n - 1 and math.isinf(ev["t_end"]):
            last = t_pass[n - 2] - (t_pass[n - 3] if n > 2 else 0.0)
            ev["t_end"] = t + 20.0 * max(last, 1e-3)

    def record_peak(k, t, v):  # k 1-based
        if not v > 0.0:
            return
        t_peak[k - 1], v_peak[k - 1] = t, v
        while ev["next_peak"] <= n and not math.isnan(t_peak[ev["next_peak"] - 1]):
            ev["next_peak"] += 1

    def make_pass_cb(k):  # pass of granule k (1-based): v_{k+1} - v_k upward
        def cb(ta, t, d_sgn):
            ev["events"] += 1
            if not math.isnan(t_pass[k - 1]):
                return
            d = ta.update_d_output(t)
            vk = d[iu(k - 1)] * V[k - 1]
            if k == ev["next_pass"] or vk > 1e-6 * ev["v_ref"]:
                record_pass(k, t, d[iu(k)] * V[k])
        return cb

    def make_peak_cb(k):  # peak of granule k (1-based, 2 <= k <= N-1)
        def cb(ta, t, d_sgn):
            ev["events"] += 1
            if not math.isnan(t_peak[k - 1]):
                return
            vk = ta.update_d_output(t)[iu(k - 1)] * V[k - 1]
            if vk > 1e-6 * ev["v_ref"]:
                record_peak(k, t, vk)
        return cb

    pos, neg = hy.event_direction.positive, hy.event_direction.negative
    rho = [r[k] ** (2.0 / 3.0) for k in range(n - 1)]
    nt_events = []
    for k in range(1, n - 1):  # passes of granules 1..N-2 (N-1 is terminal)
        nt_events.append(hy.nt_event(V[k] * u[k] - V[k - 1] * u[k - 1], make_pass_cb(k), direction=pos))
    for k in range(2, n):  # peaks of granules 2..N-1
        expr = rho[k - 2] * Z[k - 2] * w[k - 2] - rho[k - 1] * Z[k - 1] * w[k - 1]
        nt_events.append(hy.nt_event(expr, make_peak_cb(k), direction=neg))
    # cooldown 0: heyoka's automatic cooldown grows as the event equation's
    # slope at the trigger shrinks, and a contact closed slowly by the
    # precursor would then miss its opening; the switch instead moves w off
    # the root (below), so the root just handled cannot trigger again
    t_events = [hy.t_event(w[k] - eps, cooldown=0.0) for k in range(n - 1)]
    last_pass = len(t_events)
    t_events.append(hy.t_event(V[n - 1] * u[n - 1] - V[n - 2] * u[n - 2], direction=pos))

    c0 = time.process_time()
    ta = hy.taylor_adaptive(sys_eq, state, tol=tol, compact_mode=True, pars=pars,
                            t_events=t_events, nt_events=nt_events)
    compile_seconds = time.process_time() - c0
    ev["ta"] = ta

    frozen = {}  # contact k -> (t0, z0, dz/dt): its gap in closed form

    def freeze(k):
        """Freezes open gap k when both its granules fly freely apart and
        their observables are known."""
        if keep_gaps or ta.pars[k] != 0.0 or k in frozen:
            return
        if (k > 0 and ta.pars[k - 1] != 0.0) or (k < n - 2 and ta.pars[k + 1] != 0.0):
            return
        if any(math.isnan(t_peak[j]) for j in (k, k + 1)) or any(
                math.isnan(t_pass[j]) for j in (k, k + 1) if j < n - 1):
            return
        st = ta.state
        dz = V[k] * st[iu(k)] - V[k + 1] * st[iu(k + 1)]
        if not dz < 0.0:
            return
        frozen[k] = (ta.time, Z[k] * st[iw(k)], dz)
        st[iw(k)] = -1.0
        ta.pars[n - 1 + k] = 0.0

    def thaw(k):
        if k in frozen:
            t0, z0, dz = frozen.pop(k)
            ta.state[iw(k)] = (z0 + dz * (ta.time - t0)) / Z[k]
            ta.pars[n - 1 + k] = 1.0

    steps = 0
    switches = 0
    complete = 0
    c0 = time.process_time()
    while True:
        if time.process_time() - c0 > cpu_limit:
            break
        # the stops where gaps are frozen: about 20 per decade of time
        horizon = min(ta.time + max(100.0, 0.1 * ta.time), ev["t_end"])
        res = ta.propagate_until(horizon)
        steps += res[3]
        oc = res[0]
        if oc == hy.taylor_outcome.time_limit:
            if ta.time >= ev["t_end"]:
                break
            for k in range(n - 1):
                freeze(k)
            continue
        code = int(oc.value) if hasattr(oc, "value") else int(oc)
        if not -len(t_events) <= code <= -1:  # a non-finite state or another failure
            raise RuntimeError(f"heyoka stopped with outcome {oc} at t = {ta.time}")
        idx = -code - 1
        t = ta.time
        s = ta.state
        if idx == last_pass:
            k = n - 1
            if math.isnan(t_pass[k - 1]) and (k == ev["next_pass"] or s[iu(k - 1)] * V[k - 1] > 1e-6 * ev["v_ref"]):
                record_pass(k, t, s[iu(k)] * V[k])
        else:
            k = idx  # 0-based contact between granules k and k + 1
            switches += 1
            urel = V[k] * s[iu(k)] - V[k + 1] * s[iu(k + 1)]  # dz/dt
            mu = m[k] * m[k + 1] / (m[k] + m[k + 1])
            J = r[k] * (eps * Z[k]) ** 2.5 / (2.5 * max(abs(urel), 1e-300))
            J = min(J, 0.5 * mu * abs(urel))  # a grazing touch: never reverse the approach
            s[iu(k)] -= J / (m[k] * V[k])
            s[iu(k + 1)] += J / (m[k + 1] * V[k + 1])
            on = ta.pars[k] == 0.0
            ta.pars[k] = 1.0 if on else 0.0
            # off the root by more than its rounding (an error of 1e-15 Z_k in z)
            s[iw(k)] = eps + (1.0 if on else -1.0) * (1e-9 * eps + 1e-15)
            if not on and k == n - 2:  # the last granule leaves: its peak
                tp = t + eps * Z[k] / max(abs(urel), 1e-300)
                record_peak(n, tp, s[iu(n - 1)] * V[n - 1])
            for j in (k - 1, k + 1):
                if 0 <= j < n - 1:
                    if on:
                        thaw(j)  # a granule of gap j no longer flies freely
                    else:
                        freeze(j)
            if not on:
                freeze(k)
        if ev["next_pass"] > n - 1 and (ev["next_peak"] > n or ta.time >= ev["t_end"]):
            complete = 1
            break
    integration_seconds = time.process_time() - c0

    s = ta.state
    energy = 0.0
    for k in range(n):
        energy += 0.5 * m[k] * (V[k] * s[iu(k)]) ** 2
    for k in range(n - 1):
        z = Z[k] * s[iw(k)]
        if z > 0 and k not in frozen:
            energy += r[k] * z ** 2.5 / 2.5
    e0 = 0.5 * m[0]
    complete = complete and all(not math.isnan(x) for x in t_pass[: n - 1])
    return {
        "heyoka": hy.__version__, "n": n, "tol": tol, "eps": eps,
        "compile_seconds": compile_seconds, "integration_seconds": integration_seconds,
        "steps": int(steps), "events": ev["events"] + switches, "switches": switches,
        "energy_drift": float(abs(energy - e0) / e0), "t_final": ta.time, "complete": int(complete),
    }, t_pass, v_peak, t_peak


def main(argv):
    import argparse
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("chain_file")
    ap.add_argument("tol", type=float)
    ap.add_argument("--eps", type=float, default=None,
                    help="contact switch threshold in units of Z_k (default: 1e-2 tol^(2/3), at least 1e-12)")
    ap.add_argument("--cpu-limit", type=float, default=600.0)
    ap.add_argument("--reference", help="taper-reference's output for this chain: print err_t_pass")
    ap.add_argument("--keep-gaps", action="store_true",
                    help="integrate every gap to the end (no frozen gaps): to measure what freezing buys")
    a = ap.parse_args(argv)
    try:
        import heyoka  # noqa: F401
    except ImportError as e:
        print(f"peer_heyoka: heyoka not importable ({e})", file=sys.stderr)
        return 2
    try:
        m, r = load_chain(a.chain_file)
    except (OSError, ValueError) as e:
        print(f"peer_heyoka: {e}", file=sys.stderr)
        return 1
    if not (a.tol > 0):
        print("peer_heyoka: TOL must be positive", file=sys.stderr)
        return 1
    eps = a.eps if a.eps is not None else max(1e-2 * a.tol ** (2.0 / 3.0), 1e-12)
    try:
        info, t_pass, v_peak, t_peak = run(m, r, a.tol, eps, a.cpu_limit, a.keep_gaps)
    except RuntimeError as e:
        print(f"peer_heyoka: {a.chain_file} tol {a.tol:g}: {e}", file=sys.stderr)
        return 1
    out = sys.stdout
    for key, val in info.items():
        out.write(f"{key} {val!r}\n" if isinstance(val, float) else f"{key} {val}\n")
    if a.reference:
        ref = {}
        with open(a.reference) as f:
            for line in f:
                if line.strip() and not line.startswith("#"):
                    k, t = line.split()
                    ref[int(k)] = float(t)
        errs = [abs(t_pass[k - 1] - ref[k]) / abs(ref[k]) for k in range(1, len(m) - 1)]
        worst = math.nan if any(math.isnan(e) for e in errs) else max(errs)  # nan: a pass is missing
        out.write(f"err_t_pass {worst:.3e}\n")
    for k in range(len(m)):
        out.write(f"granule {k + 1} {float(t_pass[k])!r} {float(v_peak[k])!r} {float(t_peak[k])!r}\n")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
