#!/usr/bin/env python3
"""Research aid for the JSBSim plant engine: drives the Debian JSBSim 2020.3 binary through its
input socket with the package's aircraft, measures the protocol facts the C++ coupling relies
on, trims with JSBSim's own trim and identifies the short-period model from a 1 ms lockstep run.

    jsbsim_probe.py linearise [--altitude-ft 40000] [--mach 0.8] [--set PROP=VALUE] [--check]
    jsbsim_probe.py facts

The binary: $PMRAC_JSBSIM, else /usr/games/JSBSim, else <repo>/build/jsbsim/bin/JSBSim
(scripts/install_jsbsim puts it there). Every JSBSim process it starts is ended before it exits.
"""
import argparse
import math
import os
import shutil
import socket
import subprocess
import sys
import tempfile
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)  # the jsbsim/ folder: aircraft/, engine/
PROMPT = b"JSBSim> "
SCRIPT = """<?xml version="1.0"?>
<runscript name="pmrac-lockstep">
  <use aircraft="b747_pmrac" initialize="cruise_m080_h40k"/>
  <input port="{port}"/>
  <run start="0.0" end="1.0e9" dt="{dt}">
  </run>
</runscript>
"""
# Condition 9 of Heffley and Jewell (NASA CR-2144, 1972) as a short-period model, and the paper's.
COND9 = (-0.310, 0.987, -0.794, -0.425, -0.023, -1.152)
PAPER = (-0.32, 0.86, -0.93, -0.43, -0.02, -1.16)


def jsbsim_binary():
    for cand in (
        os.environ.get("PMRAC_JSBSIM"),
        "/usr/games/JSBSim",
        os.path.join(os.path.dirname(ROOT), "build", "jsbsim", "bin", "JSBSim"),
    ):
        if cand and os.access(cand, os.X_OK):
            return cand
    sys.exit("jsbsim_probe: no JSBSim binary (run scripts/install_jsbsim or set PMRAC_JSBSIM)")


def free_port():
    s = socket.socket()
    s.bind(("127.0.0.1", 0))
    port = s.getsockname()[1]
    s.close()
    return port


class Sim:
    """One JSBSim process in socket lockstep (started held, --nice=0: no sleep while held)."""

    def __init__(self, port=None, dt=0.001, nice="0", quickack=True, root=ROOT):
        self.port = port or free_port()
        self.dir = tempfile.mkdtemp(prefix="pmrac_jsbsim_")
        script = os.path.join(self.dir, "lockstep.xml")
        with open(script, "w") as f:
            f.write(SCRIPT.format(port=self.port, dt=dt))
        self.log_path = os.path.join(self.dir, "jsbsim.log")
        self.log = open(self.log_path, "w")
        argv = [jsbsim_binary(), "--root=" + root, "--script=" + script, "--nohighlight"]
        argv += ["--suspend"] + (["--nice=" + nice] if nice is not None else [])
        self.argv = argv
        self.proc = subprocess.Popen(argv, stdout=self.log, stderr=subprocess.STDOUT, cwd=self.dir)
        self.quickack = quickack
        self.s = None
        self.buf = b""
        self.chunks = []
        try:
            t0 = time.time()
            while self.s is None:
                try:
                    self.s = socket.create_connection(("127.0.0.1", self.port), timeout=5)
                except ConnectionRefusedError:
                    if self.proc.poll() is not None or time.time() - t0 > 10:
                        raise RuntimeError("JSBSim did not open port %d" % self.port)
                    time.sleep(0.005)
            self.s.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
            self.read_prompts(1)  # "Connected to JSBSim server"
        except BaseException:
            self.close()
            raise

    def _ack(self):
        if self.quickack:
            self.s.setsockopt(socket.IPPROTO_TCP, socket.TCP_QUICKACK, 1)

    def read_prompts(self, n):
        out = []
        while len(out) < n:
            i = self.buf.find(PROMPT)
            if i >= 0:
                out.append(self.buf[:i].decode())
                self.buf = self.buf[i + len(PROMPT) :]
                continue
            self._ack()
            data = self.s.recv(65536)
            self._ack()
            if not data:
                raise EOFError("JSBSim closed the connection")
            self.chunks.append(data)
            self.buf += data
        return out

    def cmds(self, lines):
        """Send the lines in one packet; return one reply per line."""
        self.s.sendall("".join(line + "\n" for line in lines).encode())
        return self.read_prompts(len(lines))

    def get(self, *props):
        vals = []
        for p, r in zip(props, self.cmds(["get " + p for p in props])):
            name, _, v = r.partition("=")
            if name.strip() != p:
                raise ValueError("bad reply to get %s: %r" % (p, r))
            vals.append(float(v))
        return vals

    def setp(self, pairs):
        for (p, _), r in zip(pairs, self.cmds(["set %s %.17g" % pv for pv in pairs])):
            if r != "set successful\n":
                raise ValueError("set %s: %r" % (p, r))

    def step_get(self, props, sets=()):
        """One packet `set ...; iterate 1`, then read props once the step has completed (a
        reply served mid-step is repeated, see jsbsim/README.md)."""
        reply = self.cmds(["set %s %.17g" % pv for pv in sets] + ["iterate 1"])
        if any(r != "set successful\n" for r in reply[:-1]):
            raise ValueError("set: %r" % reply)
        repolls = 0
        while True:
            r = self.get("simulation/frame", "pmrac/sync/frame", *props)
            if r[0] == r[1]:
                return r[2:], repolls
            repolls += 1

    def trim(self, altitude_ft, mach):
        """JSBSim's longitudinal trim at (h, M, gamma 0); the process ends if it fails."""
        self.setp([("ic/h-sl-ft", altitude_ft), ("ic/mach", mach), ("ic/gamma-rad", 0.0)])
        return self.cmds(["resume", "set simulation/do_simple_trim 0", "hold"])

    def close(self):
        if self.s is not None:
            self.s.close()
        if self.proc.poll() is None:
            self.proc.terminate()
            try:
                self.proc.wait(2)
            except subprocess.TimeoutExpired:
                self.proc.kill()
                self.proc.wait()
        self.log.close()
        shutil.rmtree(self.dir, ignore_errors=True)


def elevator_input(t, amp):
    """A doublet, then a 1.7 Hz square wave of half its amplitude."""
    d = amp if 0.2 <= t < 1.2 else (-amp if 1.2 <= t < 2.2 else 0.0)
    if t >= 2.5:
        d += 0.5 * amp * (1 if math.sin(2 * math.pi * 1.7 * t) >= 0 else -1)
    return d


def linearise(args):
    sim = Sim(dt=args.dt)
    try:
        if args.set:
            sim.setp([(kv.split("=")[0], float(kv.split("=")[1])) for kv in args.set])
        t0 = time.perf_counter()
        sim.trim(args.altitude_ft, args.mach)
        trim_ms = (time.perf_counter() - t0) * 1e3
        names = [
            "aero/alpha-rad",
            "attitude/theta-rad",
            "fcs/elevator-pos-rad",
            "fcs/throttle-cmd-norm",
            "propulsion/engine/thrust-lbs",
            "velocities/vt-fps",
            "velocities/q-rad_sec",
            "aero/pmrac/CL",
            "aero/pmrac/CD",
            "aero/qbar-psf",
        ]
        v = dict(zip(names, sim.get(*names)))
        print(
            "trim at %.0f ft, Mach %.3f (%.1f ms): alpha %.4f deg, theta %.4f deg, "
            "elevator %.4f deg, throttle %.6f (thrust %.0f lbf), vt %.2f fps, "
            "CL %.4f, CD %.5f, qbar %.2f psf"
            % (
                args.altitude_ft,
                args.mach,
                trim_ms,
                math.degrees(v["aero/alpha-rad"]),
                math.degrees(v["attitude/theta-rad"]),
                math.degrees(v["fcs/elevator-pos-rad"]),
                v["fcs/throttle-cmd-norm"],
                v["propulsion/engine/thrust-lbs"],
                v["velocities/vt-fps"],
                v["aero/pmrac/CL"],
                v["aero/pmrac/CD"],
                v["aero/qbar-psf"],
            )
        )
        q0 = v["velocities/q-rad_sec"]
        refs = [
            ("pmrac/ref/alpha-rad", v["aero/alpha-rad"]),
            ("pmrac/ref/theta-rad", v["attitude/theta-rad"]),
            ("pmrac/ref/vt-fps", v["velocities/vt-fps"]),
            ("pmrac/ref/q-rad_sec", q0),
        ]
        sim.setp(refs)
        out = [
            "pmrac/dev/alpha-rad",
            "pmrac/dev/q-rad_sec",
            "pmrac/dev/theta-rad",
            "pmrac/dev/vt-fps",
            "accelerations/udot-ft_sec2",
            "accelerations/wdot-ft_sec2",
            "accelerations/qdot-rad_sec2",
            "velocities/u-fps",
            "velocities/w-fps",
        ]
        amp = math.radians(args.amplitude_deg)
        n = int(round(args.duration / args.dt))
        rows, repolls = [], 0
        t0 = time.perf_counter()
        for k in range(n):
            de = elevator_input(k * args.dt, amp)
            r, rp = sim.step_get(out, [("fcs/pmrac-elevator-cmd-rad", de)])
            repolls += rp
            rows.append([de] + r)
        wall = time.perf_counter() - t0
        print(
            "lockstep: %d steps in %.2f s = %.3f ms/step (%d reads came mid-step and were repeated)"
            % (n, wall, wall / n * 1e3, repolls)
        )
    finally:
        sim.close()
    de, da, dq, dth, dv, udot, wdot, qdot, u, w = np.array(rows).T
    adot = (u * wdot - w * udot) / (u * u + w * w)
    X = np.column_stack([da, dq + q0, de, dv, dth, np.ones_like(da)])
    ca = np.linalg.lstsq(X, adot, rcond=None)[0]
    cq = np.linalg.lstsq(X, qdot, rcond=None)[0]
    print(
        "fit residual rms: alphadot %.1e rad/s of %.1e, qdot %.1e rad/s^2 of %.1e"
        % ((adot - X @ ca).std(), adot.std(), (qdot - X @ cq).std(), qdot.std())
    )
    got = (ca[0], ca[1], cq[0], cq[1], ca[2], cq[2])
    print("            Z_alpha/mU  1+Z_q/mU  M_alpha/Iy  M_q/Iy  Z_delta/mU  M_delta/Iy")
    for name, row in (("JSBSim", got), ("condition 9", COND9), ("paper", PAPER)):
        print("%-11s %10.3f %9.3f %11.3f %7.3f %11.4f %11.3f" % ((name,) + tuple(row)))
    if args.check:
        bad = [i for i in range(6) if abs(got[i] - COND9[i]) > 0.02 * abs(COND9[i]) + 1e-3]
        if bad:
            print("CHECK FAILED: entries %s differ from condition 9 by more than 2 %%" % bad)
            return 1
        print("check: every entry within 2 % of condition 9")
    return 0


def extra_client_greeting(port, wait):
    """Connect one more client; return what the server sends it within `wait` seconds."""
    c = socket.create_connection(("127.0.0.1", port), timeout=1)
    c.settimeout(wait)
    try:
        return c, c.recv(100)
    except socket.timeout:
        return c, None


def facts(_args):
    # One client per process.
    sim = Sim()
    try:
        c2, greeting = extra_client_greeting(sim.port, 0.5)
        print("second client while the first is connected: greeting %r" % greeting)
        sim.s.close()
        sim.s = None
        c3, greeting = extra_client_greeting(sim.port, 1.0)
        print("new client after the first closed: greeting %r" % greeting)
        c2.close()
        c3.close()
    finally:
        sim.close()
    # Prompt sent separately; reply to iterate before the step; models twice per iterate.
    sim = Sim()
    try:
        sim.chunks.clear()
        sim.cmds(["get simulation/frame"])
        print("recv() chunks for one get: %r" % sim.chunks)
        before = sim.get("simulation/frame", "aero/pmrac/CL")
        r = sim.cmds(["iterate 1", "get simulation/frame"])
        print(
            "`iterate 1` + `get simulation/frame` in one packet: %r (frame before: %g)"
            % (r, before[0])
        )
    finally:
        sim.close()
    # Models run twice per `iterate 1`: a copy of the aircraft with an FCS integrator of 1000/s
    # (it adds 1000 x dt = 1 each time the FCS runs).
    counting = tempfile.mkdtemp(prefix="pmrac_jsbsim_count_")
    try:
        os.symlink(os.path.join(ROOT, "engine"), os.path.join(counting, "engine"))
        src = os.path.join(ROOT, "aircraft", "b747_pmrac")
        dst = os.path.join(counting, "aircraft", "b747_pmrac")
        shutil.copytree(src, dst)
        with open(os.path.join(dst, "b747_pmrac.xml")) as f:
            xml = f.read()
        counter = (
            '<property value="1.0"> pmrac/test/one </property>\n'
            '    <channel name="count"><integrator name="pmrac/test/count">'
            "<input>pmrac/test/one</input><c1>1000.0</c1></integrator></channel>\n"
            "  </system>"
        )
        with open(os.path.join(dst, "b747_pmrac.xml"), "w") as f:
            f.write(xml.replace("</system>", counter, 1))
        sim = Sim(root=counting)
        try:
            c0 = sim.get("pmrac/test/count")[0]
            c1 = sim.step_get(["pmrac/test/count"])[0][0]
            print("FCS integrator advance per `iterate 1`: %g model passes" % (c1 - c0))
        finally:
            sim.close()
    finally:
        shutil.rmtree(counting, ignore_errors=True)
    # Port reuse when JSBSim ends first.
    sim = Sim()
    port = sim.port
    sim.proc.terminate()
    sim.proc.wait()
    try:
        again = Sim(port=port)
        print("restart on port %d at once: works" % port)
        again.close()
    except RuntimeError as e:
        print("restart on port %d at once: %s" % (port, e))
    # Failed trim ends the process.
    sim = Sim()
    try:
        sim.trim(40000.0, 0.3)
        print("trim at Mach 0.3, 40,000 ft: succeeded?")
    except EOFError:
        sim.proc.wait(5)
        print(
            "trim at Mach 0.3, 40,000 ft: connection closed, JSBSim exit code %s"
            % sim.proc.returncode
        )
    finally:
        sim.close()
    # Step cost without --nice=0 (JSBSim sleeps 10 ms per loop while held), without
    # TCP_QUICKACK, and with both.
    for nice, quickack in ((None, True), ("0", False), ("0", True)):
        sim = Sim(nice=nice, quickack=quickack)
        try:
            n = 2000 if nice and quickack else 20
            t0 = time.perf_counter()
            for _ in range(n):
                sim.step_get(["aero/alpha-rad"], [("fcs/pmrac-elevator-cmd-rad", 0.0)])
            print(
                "%s, TCP_QUICKACK %s: %.3f ms/step over %d steps"
                % (
                    "--nice=0" if nice else "no --nice",
                    "on" if quickack else "off",
                    (time.perf_counter() - t0) / n * 1e3,
                    n,
                )
            )
        finally:
            sim.close()
    return 0


def main():
    ap = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    sub = ap.add_subparsers(dest="cmd", required=True)
    lin = sub.add_parser("linearise", help="trim and identify the short-period model")
    lin.add_argument("--altitude-ft", type=float, default=40000.0)
    lin.add_argument("--mach", type=float, default=0.8)
    lin.add_argument("--dt", type=float, default=0.001)
    lin.add_argument("--duration", type=float, default=6.0)
    lin.add_argument("--amplitude-deg", type=float, default=0.1)
    lin.add_argument(
        "--set", action="append", metavar="PROP=VALUE", help="set before the trim (faults)"
    )
    lin.add_argument(
        "--check", action="store_true", help="exit 1 unless within 2 %% of condition 9"
    )
    lin.set_defaults(func=linearise)
    sub.add_parser("facts", help="measure the socket protocol facts").set_defaults(func=facts)
    args = ap.parse_args()
    return args.func(args)


if __name__ == "__main__":
    sys.exit(main())
