#!/usr/bin/env python3
"""The speed (phugoid) and short-period modes of the package's JSBSim B-747 against the
longitudinal model built from the same published data.

    jsbsim_speed_modes.py [--mach 0.8] [--duration 300] [--check] [--data-only]

Data: R. K. Heffley and W. F. Jewell, "Aircraft Handling Qualities Data", NASA CR-2144, 1972,
B-747 conditions 5 (Mach 0.5, 20,000 ft), 9 (Mach 0.8, 40,000 ft) and 10 (Mach 0.9, 40,000 ft):
mass, Iy, reference geometry and the non-dimensional derivatives, speed derivatives (per Mach)
included. From them the tool builds the classical small-perturbation model in stability axes,
states (u [ft/s], alpha, q, theta), constant thrust (the aircraft's engine has no speed or
altitude lapse), and the same with the altitude h as a fifth state (the density falls with
height; JSBSim's atmosphere has that, the 4-state model does not).

JSBSim: one run of the aircraft in plain JSBSim (`--script`, no socket; well under a second of
wall time per minute of flight), trimmed by JSBSim's own trim at the condition's Mach and
altitude, an elevator pulse, then free flight logged at 20 Hz. An equation-error least-squares
fit of vtdot, alphadot, qdot (from JSBSim's own body accelerations) and hdot on the deviations
(vt, alpha, q, theta, h), the elevator and a constant gives the linear model; its eigenvalues
are the aircraft's modes, with (5-state) and without (4-state, the h column dropped) height.

The binary: $PMRAC_JSBSIM, else /usr/games/JSBSim, else <repo>/build/jsbsim/bin/JSBSim.
"""
import argparse
import math
import os
import subprocess
import sys
import tempfile

import numpy as np

from jsbsim_probe import jsbsim_binary

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)  # the jsbsim/ folder: aircraft/, engine/

G = 32.174  # ft/s^2
W_LBF = 636636.0
IY = 33.1e6  # slug ft^2
S = 5500.0  # ft^2
CBAR = 27.3  # ft

# Heffley and Jewell (NASA CR-2144), B-747 clean conditions; derivatives per rad, q and alphadot
# derivatives per rad of q c/(2U) and alphadot c/(2U), speed derivatives per unit Mach.
# fmt: off
COLUMNS = ("h", "M", "CL", "CD", "CLa", "CDa", "Cma", "CLad", "Cmad", "CLq", "Cmq",
           "CLM", "CDM", "CmM", "CLde", "Cmde")
CONDITIONS = {
    cond: dict(zip(COLUMNS, row))
    for cond, row in {
        5: (20000.0, 0.5, 0.680, 0.0393, 4.67, 0.366, -1.146, 6.53, -3.35, 5.13, -20.7,
            -0.0875, 0.0, 0.121, 0.356, -1.43),
        9: (40000.0, 0.8, 0.660, 0.0415, 4.92, 0.425, -1.033, 5.91, -6.41, 6.00, -24.0,
            0.205, 0.0275, 0.166, 0.367, -1.45),
        10: (40000.0, 0.9, 0.521, 0.0415, 5.57, 0.527, -1.613, 5.53, -8.82, 6.94, -25.1,
             -0.278, 0.242, -0.114, 0.300, -1.20),
    }.items()
}
# fmt: on
CONDITION_OF_MACH = {0.5: 5, 0.8: 9, 0.9: 10}


def isa(h_ft):
    """US/ICAO standard atmosphere below 65,617 ft: density [slug/ft^3], speed of sound [ft/s],
    d(ln rho)/dh [1/ft]."""
    hm = h_ft * 0.3048
    r, g0 = 287.053, 9.80665
    if hm < 11000.0:
        t = 288.15 - 0.0065 * hm
        p = 101325.0 * (t / 288.15) ** (g0 / (0.0065 * r))
        dlnrho = (-g0 / (r * t) + 0.0065 / t) * 0.3048
    else:
        t = 216.65
        p = 22632.06 * math.exp(-g0 * (hm - 11000.0) / (r * t))
        dlnrho = -g0 / (r * t) * 0.3048
    rho = p / (r * t) * 0.00194032  # kg/m^3 -> slug/ft^3
    return rho, math.sqrt(1.4 * r * t) / 0.3048, dlnrho


def data_model(cond, with_height=False):
    """Small-perturbation model of a [HJ] condition, stability axes, level flight, constant
    thrust: x = (u [ft/s], alpha, q, theta[, h [ft]]); returns A."""
    d = CONDITIONS[cond]
    rho, a, dlnrho = isa(d["h"])
    mach = d["M"]
    u0 = mach * a
    qbar = 0.5 * rho * u0 * u0
    m = W_LBF / G
    qs_m = qbar * S / m
    qsc_i = qbar * S * CBAR / IY
    k = CBAR / (2.0 * u0)
    xu = -qs_m / u0 * (2.0 * d["CD"] + mach * d["CDM"])
    xa = qs_m * (d["CL"] - d["CDa"])
    zu = -qs_m / u0 * (2.0 * d["CL"] + mach * d["CLM"])
    za = -qs_m * (d["CLa"] + d["CD"])
    zad = -qs_m * d["CLad"] * k
    zq = -qs_m * d["CLq"] * k
    mu = qsc_i / u0 * mach * d["CmM"]  # 2 Cm = 0 at trim
    ma = qsc_i * d["Cma"]
    mad = qsc_i * d["Cmad"] * k
    mq = qsc_i * d["Cmq"] * k
    # Height: the density, hence every force, scales with exp(dlnrho h); at trim lift = weight,
    # drag = thrust, moment 0.
    xh = -dlnrho * qs_m * d["CD"]
    zh = -dlnrho * qs_m * d["CL"]
    den = u0 - zad
    n = 5 if with_height else 4
    A = np.zeros((n, n))
    A[0, :4] = [xu, xa, 0.0, -G]
    A[1, :4] = [zu / den, za / den, (u0 + zq) / den, 0.0]
    A[2, :4] = mad * A[1, :4] + np.array([mu, ma, mq, 0.0])
    A[3, :4] = [0.0, 0.0, 1.0, 0.0]
    if with_height:
        A[0, 4] = xh
        A[1, 4] = zh / den
        A[2, 4] = mad * A[1, 4]
        A[4, :4] = [0.0, -u0, 0.0, u0]
    return A


def modes(A):
    """(phugoid, short period, real roots): the oscillatory pairs as (period s, damping) in
    order of frequency (the slower is the phugoid), and the real eigenvalues."""
    ev = np.linalg.eigvals(A)
    pairs = sorted((e for e in ev if e.imag > 1e-9), key=lambda e: e.imag)
    osc = [(2.0 * math.pi / e.imag, -e.real / abs(e)) for e in pairs]
    real = sorted(e.real for e in ev if abs(e.imag) <= 1e-9)
    phugoid = osc[0] if len(osc) >= 2 else None
    short = osc[-1] if osc else None
    return phugoid, short, real


SCRIPT = """<?xml version="1.0"?>
<runscript name="pmrac-speed-modes">
  <use aircraft="b747_pmrac" initialize="ic"/>
  <run start="0.0" end="{end}" dt="{dt}">
    <event name="trim">
      <condition> simulation/sim-time-sec ge 0.0 </condition>
      <set name="simulation/do_simple_trim" value="0"/>
    </event>
{pulses}  </run>
</runscript>
"""
PULSE = """    <event name="elevator {i}">
      <condition> simulation/sim-time-sec ge {t} </condition>
      <set name="fcs/pmrac-elevator-cmd-rad" value="{v}"/>
    </event>
"""
IC = """<?xml version="1.0"?>
<initialize name="ic">
  <latitude unit="DEG"> 0.0 </latitude>
  <longitude unit="DEG"> 0.0 </longitude>
  <altitude unit="FT"> {h} </altitude>
  <psi unit="DEG"> 0.0 </psi>
  <phi unit="DEG"> 0.0 </phi>
  <mach> {mach} </mach>
  <alpha unit="DEG"> 4.6 </alpha>
  <beta unit="DEG"> 0.0 </beta>
  <gamma unit="DEG"> 0.0 </gamma>
</initialize>
"""
OUTPUTS = (
    "velocities/vt-fps",
    "aero/alpha-rad",
    "velocities/q-rad_sec",
    "attitude/theta-rad",
    "position/h-sl-ft",
    "accelerations/udot-ft_sec2",
    "accelerations/wdot-ft_sec2",
    "accelerations/qdot-rad_sec2",
    "velocities/u-fps",
    "velocities/w-fps",
    "fcs/elevator-pos-rad",
    "velocities/mach",
)
LOG = """<?xml version="1.0"?>
<output name="out.csv" type="CSV" rate="{rate}">
{props}</output>
"""


def fly(mach, altitude_ft, duration, dt, pulses, rate=20.0):
    """Trim, the elevator steps `pulses` [(t, rad)], free flight; returns the logged columns.
    JSBSim writes its output relative to --root, so the run gets a root of its own (links to
    the package's aircraft and engine folders, this run's aircraft copy with its initial
    condition)."""
    with tempfile.TemporaryDirectory(prefix="pmrac_speed_") as tmp:
        os.symlink(os.path.join(ROOT, "engine"), os.path.join(tmp, "engine"))
        acdir = os.path.join(tmp, "aircraft", "b747_pmrac")
        os.makedirs(acdir)
        src = os.path.join(ROOT, "aircraft", "b747_pmrac", "b747_pmrac.xml")
        os.symlink(src, os.path.join(acdir, "b747_pmrac.xml"))
        with open(os.path.join(acdir, "ic.xml"), "w") as f:
            f.write(IC.format(h=altitude_ft, mach=mach))
        ev = "".join(PULSE.format(i=i, t=t, v=v) for i, (t, v) in enumerate(pulses))
        with open(os.path.join(tmp, "run.xml"), "w") as f:
            f.write(SCRIPT.format(end=duration, dt=dt, pulses=ev))
        with open(os.path.join(tmp, "log.xml"), "w") as f:
            props = "".join("  <property> %s </property>\n" % p for p in OUTPUTS)
            f.write(LOG.format(rate=rate, props=props))
        cmd = [
            jsbsim_binary(),
            "--root=" + tmp,
            "--script=run.xml",
            "--logdirectivefile=log.xml",
            "--nohighlight",
        ]
        proc = subprocess.run(
            cmd, cwd=tmp, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, timeout=120
        )
        log = proc.stdout.decode(errors="replace")
        path = os.path.join(tmp, "out.csv")
        if proc.returncode != 0 or "Trim failed" in log or not os.path.exists(path):
            sys.exit(
                "jsbsim_speed_modes: JSBSim failed (exit %d):\n%s"
                % (proc.returncode, "\n".join(log.splitlines()[-15:]))
            )
        data = np.genfromtxt(path, delimiter=",", skip_header=1)
    return {name: data[:, i + 1] for i, name in enumerate(OUTPUTS)} | {"t": data[:, 0]}


def identify(run, t_from, height_column):
    """Equation-error fit of x' = A x + b de + c, x = (vt, alpha, q, theta, h) deviations from
    the first sample at or after t_from. Returns (A5, A4, r): A5 with every entry fitted; A4
    (vt, alpha, q, theta) fitted with the h column held at `height_column` (the atmosphere's
    density gradient acting on the trimmed forces), since within the phugoid the height and
    speed deviations are too nearly collinear for a fit to split the speed derivatives from the
    height ones; r = the residual rms of vtdot, alphadot, qdot in the A4 fit."""
    keep = run["t"] >= t_from - 1e-9
    r = {k: v[keep] for k, v in run.items()}
    u, w = r["velocities/u-fps"], r["velocities/w-fps"]
    ud, wd = r["accelerations/udot-ft_sec2"], r["accelerations/wdot-ft_sec2"]
    vt, al, th = r["velocities/vt-fps"], r["aero/alpha-rad"], r["attitude/theta-rad"]
    q, h, de = r["velocities/q-rad_sec"], r["position/h-sl-ft"], r["fcs/elevator-pos-rad"]
    vtd = (u * ud + w * wd) / vt
    ald = (u * wd - w * ud) / (u * u + w * w)
    hd = vt * np.sin(th - al)  # wings level, no wind
    one = np.ones_like(vt)
    dx = [vt - vt[0], al - al[0], q, th - th[0]]
    dh, dde = h - h[0], de - de[0]
    Y = np.column_stack([vtd, ald, r["accelerations/qdot-rad_sec2"], q, hd])
    X5 = np.column_stack(dx + [dh, dde, one])
    A5 = np.linalg.lstsq(X5, Y, rcond=None)[0][:5, :].T
    Y4 = Y[:, :3] - np.outer(dh, height_column[:3])
    X4 = np.column_stack(dx + [dde, one])
    c4 = np.linalg.lstsq(X4, Y4, rcond=None)[0]
    A4 = np.vstack([c4[:4, :].T, [0.0, 0.0, 1.0, 0.0]])
    rms = np.sqrt(np.mean((Y4 - X4 @ c4) ** 2, axis=0))
    return A5, A4, rms


def fmt_modes(md):
    ph, sp, real = md
    out = []
    out.append("phugoid %6.1f s %7.4f" % ph if ph else "phugoid   none        ")
    out.append("short period %5.2f s %6.3f" % sp if sp else "short period none")
    if real:
        out.append("real " + " ".join("%+.5f" % e for e in real))
    return "  ".join(out)


def main():
    ap = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    ap.add_argument(
        "--mach",
        default="0.5,0.8,0.85,0.9",
        help="Mach numbers to fly (0.5 at 20,000 ft, the rest at 40,000 ft)",
    )
    ap.add_argument("--duration", type=float, default=120.0, help="s of flight per run")
    ap.add_argument("--dt", type=float, default=0.002)
    ap.add_argument(
        "--pulse-rad",
        type=float,
        default=0.005,
        help="elevator pulse (trailing edge up) from 2 to 4 s",
    )
    ap.add_argument(
        "--check",
        action="store_true",
        help="fail unless, at every condition flown, the phugoid period is within "
        "5 %% and its damping within 0.01 + 10 %% of the data's model, the speed "
        "derivatives X_u, Z_u, M_u within 10 %% (same sign), and no mode is unstable",
    )
    args = ap.parse_args()
    failures = []
    for mach in (float(x) for x in args.mach.split(",")):
        cond = CONDITION_OF_MACH.get(round(mach, 3))
        alt = 20000.0 if mach < 0.65 else 40000.0
        run = fly(mach, alt, args.duration, args.dt, [(2.0, -args.pulse_rad), (4.0, 0.0)])
        ref5 = data_model(cond if cond else 9, with_height=True)
        if cond is None:  # no published condition: the nearest's density gradient column
            ref5 = data_model(10, with_height=True)
        A5, A4, rms = identify(run, 0.05, ref5[:, 4])
        label = "condition %d" % cond if cond else "(no published condition)"
        print("Mach %.3f, %.0f ft, %s" % (mach, alt, label))
        i0 = int(np.searchsorted(run["t"], 0.05 - 1e-9))
        print(
            "  trim: alpha %.3f deg, elevator %.3f deg from the datum, true airspeed %.2f ft/s"
            % (
                math.degrees(run["aero/alpha-rad"][i0]),
                math.degrees(run["fcs/elevator-pos-rad"][i0]),
                run["velocities/vt-fps"][i0],
            )
        )
        print("  JSBSim, 4-state  " + fmt_modes(modes(A4)))
        print("  JSBSim, 5-state  " + fmt_modes(modes(A5)))
        print(
            "  fit residual rms: vtdot %.1e ft/s^2, alphadot %.1e rad/s, qdot %.1e rad/s^2"
            % tuple(rms)
        )
        unstable = [e for e in np.linalg.eigvals(A4) if e.real > 0.0]
        if unstable:
            failures.append("Mach %.3f: unstable modes %s" % (mach, unstable))
        if not cond:
            continue
        ref4 = data_model(cond)
        print("  [HJ] 4-state     " + fmt_modes(modes(ref4)))
        print("  [HJ] 5-state     " + fmt_modes(modes(ref5)))
        names = ("X_u [1/s]", "Z_u/U [1/ft]", "M_u [1/(ft s)]")
        for i, name in enumerate(names):
            print("  %-15s JSBSim %+.4e  [HJ] %+.4e" % (name, A4[i, 0], ref4[i, 0]))
            if A4[i, 0] * ref4[i, 0] <= 0 or abs(A4[i, 0] / ref4[i, 0] - 1.0) > 0.10:
                failures.append(
                    "Mach %.3f: %s %.4e, the data's %.4e" % (mach, name, A4[i, 0], ref4[i, 0])
                )
        ph, ph_ref = modes(A4)[0], modes(ref4)[0]
        if (
            ph is None
            or abs(ph[0] / ph_ref[0] - 1.0) > 0.05
            or abs(ph[1] - ph_ref[1]) > 0.01 + 0.1 * ph_ref[1]
        ):
            failures.append(
                "Mach %.3f: phugoid %s, the data's %.1f s, damping %.4f"
                % (
                    mach,
                    "none" if ph is None else "%.1f s, damping %.4f" % ph,
                    ph_ref[0],
                    ph_ref[1],
                )
            )
    if args.check:
        for f in failures:
            print("FAIL: " + f)
        if failures:
            return 1
        print("check: phugoid and speed derivatives as the data's model, no unstable mode")
    return 0


if __name__ == "__main__":
    sys.exit(main())
