#!/usr/bin/python3
"""Regular adaptive control (mode `rac`) on scenario 1, written the way a researcher would
prototype it: plain Python + numpy, one loop iteration per sample.

It is the baseline of the "C++ vs prototype" row of docs/performance.md (bench/run_bench.sh
times it against `preadapt_sim --scenario 1 --mode rac --json` on the same work), and a
cross-check of the C++ engine: same equations (docs/spec.md), same dt = 1 ms, RK4 plant with theta
held at theta(t_k + dt/2), and the same per-sample order as src/core/controller/controller.cpp and
src/core/closed_loop.cpp:

    e_v = x - x_r; e = e_v[1]; dirty-derivative estimate of de/dt; attention (events only, rac
    never resets theta_hat); u = -K x - theta_hat.x + k0 r; theta_hat += dt gamma (e_v.PB) x
    (forward Euler); x_r advanced one RK4 step with r held; plant advanced one RK4 step with u.

Usage:
    /usr/bin/python3 bench/prototype_rac.py [--config-dir DIR] [--cli-json FILE|-] [--quiet]
        [--delay-steps D]

With --cli-json FILE (or --cli-json - and the CLI's JSON piped on stdin:
    preadapt_sim --scenario 1 --mode rac --json | bench/prototype_rac.py --cli-json -)
it prints the largest difference of the
per-window peak |e| (and IAE) from the CLI's. The last line of stdout is one JSON object
(windows, events, wall_time_s, ...).
"""
import argparse
import collections
import json
import os
import sys
import time

import numpy as np
import yaml
from scipy.linalg import solve_continuous_are, solve_continuous_lyapunov

HERE = os.path.dirname(os.path.abspath(__file__))


def load(path):
    with open(path) as f:
        return yaml.safe_load(f)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--config-dir", default=os.path.join(HERE, "..", "config"))
    ap.add_argument("--cli-json", help="the CLI's --json output (a file, or - for stdin)")
    ap.add_argument("--quiet", action="store_true", help="only the JSON line")
    ap.add_argument(
        "--delay-steps",
        type=int,
        default=0,
        help="servo transport delay in samples (docs/research/conditions.md: the command of step k "
        "acts from k + D, 0 before); an independent check of preadapt_margins",
    )
    args = ap.parse_args()

    plant = load(os.path.join(args.config_dir, "plant", "b747.yaml"))["plant"]
    ctrl = load(os.path.join(args.config_dir, "controller", "default.yaml"))["controller"]
    scen = load(os.path.join(args.config_dir, "scenarios", "scenario1.yaml"))["scenario"]

    A = np.array(plant["A"], dtype=float)
    B = np.array(plant["B"], dtype=float)
    B1r = np.array(plant["B1r"], dtype=float)
    x0 = np.array(plant["x0"], dtype=float)
    out = int(plant["output_index"])
    n = A.shape[0]
    dt = float(ctrl["sample_time"])
    Q = np.array(ctrl["lqr"]["Q"], dtype=float)
    R = float(ctrl["lqr"]["R"])
    k0 = float(ctrl["reference_model"]["k0"])
    gamma = float(ctrl["adaptation"]["gamma"])
    theta_hat0 = np.array(ctrl["adaptation"]["theta_hat0"], dtype=float)
    tau = float(ctrl["velocity_estimator"]["tau"])
    c_e = float(ctrl["attention"]["c_e"])
    c_ed = float(ctrl["attention"]["c_ed"])

    # theta segments hold on (previous until, until]
    seg_until = [float(s["until"]) for s in scen["theta"]]
    seg_theta = [
        float(s["scale"]) * np.ones(n) if "scale" in s else np.array(s["theta"], float)
        for s in scen["theta"]
    ]
    ref = scen.get("reference", [{"until": seg_until[-1], "r": 0.1}])
    ref_until = [float(s["until"]) for s in ref]
    ref_r = [float(s["r"]) for s in ref]
    t_end = seg_until[-1]

    def theta_at(t):
        for until, th in zip(seg_until, seg_theta):
            if t <= until:
                return th
        return seg_theta[-1]

    def r_at(t):
        for until, r in zip(ref_until, ref_r):
            if t <= until:
                return r
        return ref_r[-1]

    t0 = time.perf_counter()  # like the CLI's wall_time_s: design + run, not file loading

    # --- design: LQR gain from the CARE, P from the Lyapunov equation ---
    Pc = solve_continuous_are(A, B.reshape(-1, 1), Q, np.array([[R]]))
    K = (B @ Pc) / R
    Ar = A - np.outer(B, K)
    P = solve_continuous_lyapunov(Ar.T, -np.eye(n))  # Ar^T P + P Ar = -I
    if np.max(np.linalg.eigvals(Ar).real) >= 0 or np.min(np.linalg.eigvalsh(P)) <= 0:
        sys.exit("A_r not Hurwitz or P not positive definite")
    PB = P @ B
    b_ref = B1r + k0 * B

    def f_plant(x, theta, u, r):
        return A @ x + B * (theta @ x + u) + B1r * r

    def f_ref(xr, r):
        return Ar @ xr + b_ref * r

    def rk4(f, x, h, *a):
        k1 = f(x, *a)
        k2 = f(x + 0.5 * h * k1, *a)
        k3 = f(x + 0.5 * h * k2, *a)
        k4 = f(x + h * k3, *a)
        return x + (h / 6.0) * (k1 + 2 * k2 + 2 * k3 + k4)

    # --- metrics windows: (t_start, t_end] between switches, sample 0 in the first ---
    w_end = seg_until
    w_start = [0.0] + seg_until[:-1]
    peak = [0.0] * len(w_end)
    iae = [0.0] * len(w_end)

    # --- state ---
    x = x0.copy()
    xr = x0.copy()
    theta_hat = theta_hat0.copy()
    e_prev, e_dot, s_prev, primed, active = 0.0, 0.0, 0.0, False, False
    events = []
    max_u = 0.0

    steps = int(np.ceil(t_end / dt - 1e-9))
    delayed = collections.deque([0.0] * args.delay_steps) if args.delay_steps > 0 else None
    for k in range(steps):
        t = k * dt
        r = r_at(t)
        theta = theta_at(t + 0.5 * dt)

        # controller
        ev = x - xr
        e = ev[out]
        if not primed:
            e_dot = 0.0
        else:
            e_dot = (tau * e_dot + (e - e_prev)) / (tau + dt)
        e_prev = e
        s = abs(e) - c_e
        if primed:
            up = s_prev < 0 <= s
            down = s_prev > 0 >= s
            if up and abs(e_dot) > c_ed:
                events.append(("ignored_onset" if active else "onset", t))
                active = True
            elif down and abs(e_dot) < c_ed:
                events.append(("recovered" if active else "ignored_recovery", t))
                active = False
        s_prev = s
        primed = True
        u = -K @ x - theta_hat @ x + k0 * r
        theta_hat = theta_hat + dt * gamma * (ev @ PB) * x
        xr = rk4(f_ref, xr, dt, r)

        # metrics
        w = next(i for i, te in enumerate(w_end) if t <= te) if t <= w_end[-1] else len(w_end) - 1
        peak[w] = max(peak[w], abs(e))
        iae[w] += abs(e) * dt
        max_u = max(max_u, abs(u))

        # plant
        if delayed is not None:
            delayed.append(u)
            u = delayed.popleft()
            if not np.all(np.isfinite(x)):
                break
        x = rk4(f_plant, x, dt, theta, u, r)

    wall = time.perf_counter() - t0

    windows = [
        {"t_start": a, "t_end": b, "peak_abs_e": p, "iae": q}
        for a, b, p, q in zip(w_start, w_end, peak, iae)
    ]
    result = {
        "scenario": "1",
        "mode": "rac",
        "dt": dt,
        "steps": steps,
        "K": K.tolist(),
        "windows": windows,
        "events": [{"type": a, "t": b} for a, b in events],
        "iae": sum(iae),
        "peak_abs_e": max(peak),
        "max_abs_u": max_u,
        "wall_time_s": wall,
    }

    cli = None
    if args.cli_json:
        cli = sys.stdin.read() if args.cli_json == "-" else open(args.cli_json).read()
    if cli:
        line = [ln for ln in cli.strip().splitlines() if ln.startswith("{")][-1]
        c = json.loads(line)
        if len(c["windows"]) != len(windows):
            sys.exit(
                "the CLI's JSON has %d windows, the prototype %d"
                % (len(c["windows"]), len(windows))
            )
        dpeak = max(abs(a["peak_abs_e"] - b["peak_abs_e"]) for a, b in zip(windows, c["windows"]))
        diae = max(abs(a["iae"] - b["iae"]) for a, b in zip(windows, c["windows"]))
        cev = [(e["type"], round(e["t"], 6)) for e in c["events"]]
        same_events = cev == [(a, round(b, 6)) for a, b in events]
        result["vs_cli"] = {
            "max_abs_diff_peak_abs_e": dpeak,
            "max_abs_diff_iae": diae,
            "same_events": same_events,
            "cli_wall_time_s": c.get("wall_time_s"),
        }

    if not args.quiet:
        print(
            "prototype rac, scenario 1: %d steps, wall time %.3f s (%.1f us/step)"
            % (steps, wall, 1e6 * wall / steps)
        )
        print("%-8s %-8s %-14s %-14s" % ("t_start", "t_end", "peak|e|", "IAE"))
        for w in windows:
            print(
                "%-8.2f %-8.2f %-14.8g %-14.8g"
                % (w["t_start"], w["t_end"], w["peak_abs_e"], w["iae"])
            )
        print("events: %s" % ", ".join("%s@%.3f" % e for e in events))
        if "vs_cli" in result:
            v = result["vs_cli"]
            print(
                "vs CLI: max |diff| of per-window peak |e| = %.3g rad, of IAE = %.3g rad s, "
                "events %s"
                % (
                    v["max_abs_diff_peak_abs_e"],
                    v["max_abs_diff_iae"],
                    "identical" if v["same_events"] else "DIFFER",
                )
            )
    print(json.dumps(result))


if __name__ == "__main__":
    main()
