#!/usr/bin/python3
"""Helpers of bench/run_bench.sh (standard library only).

    perf_report.py timeloop --reps N --out FILE -- CLI_CMD... ::: PY_CMD...
        Runs the two commands N times each, interleaved (CLI, prototype, CLI, ...), so that a
        change of load on the shared machine hits both alike. Records per run: process wall time,
        the child's CPU time (user + sys), and the in-process wall_time_s of its JSON line.
    perf_report.py callgrind --out FILE --mode M --ir-file F
        (internal) Extracts inclusive instruction counts from a callgrind_annotate listing.
    perf_report.py report --results DIR --out docs/performance.md
        Builds the markdown table from DIR/{bench.json, timeloop.json, hyperfine.json,
        callgrind.json, meta.json} and prints it.
"""
import json
import os
import re
import resource
import statistics
import subprocess
import sys
import time


def median(xs):
    return statistics.median(xs) if xs else float("nan")


def last_json(text):
    lines = [ln for ln in text.strip().splitlines() if ln.startswith("{")]
    return json.loads(lines[-1]) if lines else {}


def run_once(cmd):
    ru0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    p = subprocess.run(
        cmd, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True
    )
    wall = time.perf_counter() - t0
    ru1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    if p.returncode != 0:
        sys.exit("command failed (%d): %s\n%s" % (p.returncode, " ".join(cmd), p.stderr))
    cpu = (ru1.ru_utime - ru0.ru_utime) + (ru1.ru_stime - ru0.ru_stime)
    return {
        "wall": wall,
        "cpu": cpu,
        "inproc": last_json(p.stdout).get("wall_time_s"),
        "json": last_json(p.stdout),
    }


def timeloop(argv):
    reps, out = 5, None
    while argv and argv[0] != "--":
        a = argv.pop(0)
        if a == "--reps":
            reps = int(argv.pop(0))
        elif a == "--out":
            out = argv.pop(0)
    argv.pop(0)
    sep = argv.index(":::")
    cli, py = argv[:sep], argv[sep + 1 :]
    res = {"cli_cmd": cli, "py_cmd": py, "reps": reps, "cli": [], "py": []}
    run_once(cli)  # warm-up (page cache, dynamic loader)
    for i in range(reps):
        for key, cmd in (("cli", cli), ("py", py)):
            r = run_once(cmd)
            r.pop("json")
            res[key].append(r)
            print(
                "  %s run %d/%d: wall %.4f s, cpu %.4f s, in-process %.4f s"
                % (key, i + 1, reps, r["wall"], r["cpu"], r["inproc"]),
                flush=True,
            )
    with open(out, "w") as f:
        json.dump(res, f, indent=1)


def callgrind(argv):
    args = dict(zip(argv[::2], argv[1::2]))
    text = open(args["--ir-file"]).read()
    pats = {
        "total": r"PROGRAM TOTALS",
        "closed_loop_run": r"ClosedLoop::run\(",
        "controller_step": r"Controller::step\(",
        "plant_step": r"Plant::step\(",
        "sensitivity_accumulate": r"SensitivityTracker::accumulate\(",
    }
    found = {}
    for line in text.splitlines():
        m = re.match(r"\s*([\d,]+)\s", line)
        if not m:
            continue
        for k, p in pats.items():
            if k not in found and re.search(p, line):
                found[k] = int(m.group(1).replace(",", ""))
    if "--excl-file" in args:  # exclusive listing: instructions inside Eigen's GEMV kernel
        gemv = 0
        for line in open(args["--excl-file"]):
            m = re.match(r"\s*([\d,]+)\s", line)
            if m and "general_matrix_vector_product" in line:
                gemv += int(m.group(1).replace(",", ""))
        found["eigen_gemv"] = gemv
    data = json.load(open(args["--out"])) if os.path.exists(args["--out"]) else {}
    data[args["--mode"]] = found
    json.dump(data, open(args["--out"], "w"), indent=1)


AIM_STEP = {"rac": 1000.0, "pa": 1000.0, "pa_learn": 3000.0, "pa_learn_exact": 3000.0}
MODES = ["rac", "pa", "pa_learn", "pa_learn_exact"]


def to_ns(v, unit):
    return v * {"ns": 1.0, "us": 1e3, "ms": 1e6, "s": 1e9}[unit]


def verdict(cpu, wall, aim, higher_is_better=False):
    ok = (lambda v: v >= aim) if higher_is_better else (lambda v: v < aim)
    if ok(cpu) and ok(wall):
        return "met"
    if ok(cpu):
        return "met on CPU time, **missed on wall time** (load)"
    return "**missed**"


def report(argv):
    args = dict(zip(argv[::2], argv[1::2]))
    d = args["--results"]
    meta = json.load(open(os.path.join(d, "meta.json")))
    bench = json.load(open(os.path.join(d, "bench.json")))
    med = {}
    for b in bench["benchmarks"]:
        if b.get("aggregate_name") != "median":
            continue
        name = re.sub(r"/iterations:\d+", "", b["run_name"])
        med[name] = b
    cmds = meta["commands"]
    L = []
    L.append("# Performance")
    L.append("")
    L.append("Measured by `bench/run_bench.sh` (see the end of this page for every command).")
    L.append("")
    L.append("- date: %s" % meta["date"])
    L.append("- machine: %s, `nproc` = %s, %s" % (meta["cpu"], meta["nproc"], meta["kernel"]))
    L.append(
        "- load average before / after the run: %s / %s" % (meta["load_before"], meta["load_after"])
    )
    L.append(
        "- compiler: %s; build type %s (`%s`)"
        % (meta["compiler"], meta["build_type"], meta["cxx_flags"])
    )
    L.append("- source: commit %s%s" % (meta["commit"], meta["dirty"]))
    L.append("")
    L.append(
        "**The machine is shared and noisy** (2 cores, other builds and test runs going on "
        "at the same time). Every figure is the median of several repetitions from one run "
        "of the script; ratios are taken between medians of the same run. Wall time "
        "includes the time the process waited for a core, CPU time does not; where they "
        "differ a lot the machine was busy, and CPU time is the better measure of the code. "
        "The callgrind instruction counts at the end do not depend on load."
    )
    L.append("")

    L.append("## Controller::step per mode (ns per step, median of %s repetitions)" % meta["reps"])
    L.append("")
    L.append(
        "Inputs replayed from a closed-loop run of scenario 3 (140 s, dt = 1 ms) in the "
        "same mode: `trajectory` = every step of the run, in order, %s whole passes per "
        "repetition (the onsets, recoveries, network updates and sensitivity-ODE phases of "
        "the run all happen inside the timed loop; the replay is checked to reproduce the "
        "closed loop's u bit for bit first); `in_phase` = only the steps of the longest "
        "adaptation phase (in learning modes each integrates S_dot = Pi S), the worst "
        "steady cost." % meta["passes"]
    )
    L.append("")
    L.append(
        "| mode | region | wall [ns/step] | CPU [ns/step] | aim | verdict "
        "| onsets / learned per pass | steps in a phase |"
    )
    L.append("|---|---|---:|---:|---:|---|---|---:|")
    for region in ("trajectory", "in_phase"):
        for m in MODES:
            b = med.get("ControllerStep/%s/%s" % (m, region))
            if not b:
                continue
            wall = to_ns(b["real_time"], b["time_unit"])
            cpu = to_ns(b["cpu_time"], b["time_unit"])
            aim = AIM_STEP[m]
            if region == "trajectory":
                ev = "%d / %d" % (b.get("onsets/pass", 0), b.get("learned/pass", 0))
                ph = "%.1f %%" % b.get("in_phase_%", 0)
            else:
                ev = "-"
                ph = "%d (from t = %.3f s)" % (b.get("phase_steps", 0), b.get("phase_t0_s", 0))
            L.append(
                "| %s | %s | %.0f | %.0f | < %.0f | %s | %s | %s |"
                % (m, region, wall, cpu, aim, verdict(cpu, wall, aim), ev, ph)
            )
    b = med.get("PlantStep/rk4")
    if b:
        L.append("")
        L.append(
            "For comparison, one RK4 step of the plant (`PlantStep/rk4`, what the closed "
            "loop adds per sample): wall %.0f ns, CPU %.0f ns."
            % (to_ns(b["real_time"], b["time_unit"]), to_ns(b["cpu_time"], b["time_unit"]))
        )
    L.append("")

    L.append("## Full scenario 3 per mode (140 s at dt = 1 ms, 140 000 samples, ClosedLoop::run)")
    L.append("")
    L.append("| mode | wall [ms/run] | CPU [ms/run] | CPU per sample [ns] | aim | verdict |")
    L.append("|---|---:|---:|---:|---:|---|")
    for m in MODES:
        b = med.get("ClosedLoop/scenario3/%s" % m)
        if not b:
            continue
        wall = to_ns(b["real_time"], b["time_unit"]) / 1e6
        cpu = to_ns(b["cpu_time"], b["time_unit"]) / 1e6
        L.append(
            "| %s | %.1f | %.1f | %.0f | < 100 | %s |"
            % (m, wall, cpu, b.get("per_step", float("nan")) * 1e9, verdict(cpu, wall, 100.0))
        )
    L.append("")

    tl = json.load(open(os.path.join(d, "timeloop.json")))
    hf_path = os.path.join(d, "hyperfine.json")
    hf = json.load(open(hf_path)) if os.path.exists(hf_path) else None
    L.append("## C++ CLI against the Python/numpy prototype (scenario 1, rac, same work)")
    L.append("")
    L.append(
        "`bench/prototype_rac.py` runs the same equations, dt, integrators and per-sample "
        "order; its per-window peak |e| agrees with the CLI's to %s rad (IAE to %s rad s), "
        "events %s."
        % (
            meta.get("xcheck_peak", "?"),
            meta.get("xcheck_iae", "?"),
            meta.get("xcheck_events", "?"),
        )
    )
    L.append("")
    L.append(
        "| measure | CLI (median) | prototype (median) | ratio prototype / CLI | aim | verdict |"
    )
    L.append("|---|---:|---:|---:|---:|---|")
    rows = []
    if hf:
        c, p = hf["results"][0], hf["results"][1]
        rows.append(
            (
                "process wall time, hyperfine (%d / %d runs)" % (len(c["times"]), len(p["times"])),
                c["median"],
                p["median"],
                True,
            )
        )
    for key, label in (
        ("wall", "process wall time, interleaved loop"),
        ("cpu", "process CPU time (user + sys), interleaved loop"),
        ("inproc", "in-process `wall_time_s` (design + run, no start-up/YAML)"),
    ):
        rows.append(
            (
                "%s (%d runs each)" % (label, tl["reps"]),
                median([r[key] for r in tl["cli"]]),
                median([r[key] for r in tl["py"]]),
                True,
            )
        )
    for label, c, p, _ in rows:
        ratio = p / c
        L.append(
            "| %s | %.4f s | %.3f s | %.0fx | >= 100x | %s |"
            % (label, c, p, ratio, "met" if ratio >= 100 else "**missed**")
        )
    L.append("")
    L.append(
        "The process figures include start-up: for the CLI the dynamic loader, YAML files "
        "and design (a few ms), for the prototype the interpreter and the numpy/scipy/yaml "
        "imports (a few hundred ms); the in-process figure is the simulation alone."
    )
    L.append("")

    cg_path = os.path.join(d, "callgrind.json")
    if os.path.exists(cg_path):
        cg = json.load(open(cg_path))
        steps = meta.get("cg_steps", 140000)
        L.append("## Instructions per sample (callgrind, scenario 3 through the CLI; noise-free)")
        L.append("")
        L.append("Inclusive instruction counts divided by the %d samples of scenario 3." % steps)
        L.append("")
        L.append(
            "| mode | Controller::step | of which SensitivityTracker::accumulate | Plant::step "
            "| ClosedLoop::run | whole process |"
        )
        L.append("|---|---:|---:|---:|---:|---:|")
        for m in MODES:
            if m not in cg:
                continue
            g = cg[m]

            def f(k, g=g, steps=steps):
                return ("%.0f" % (g[k] / steps)) if k in g else "-"

            L.append(
                "| %s | %s | %s | %s | %s | %s |"
                % (
                    m,
                    f("controller_step"),
                    f("sensitivity_accumulate"),
                    f("plant_step"),
                    f("closed_loop_run"),
                    f("total"),
                )
            )
        L.append("")
        L.append(
            "(The sensitivity ODE runs only during phases, so its per-sample average is "
            "diluted by the quiet steps; see the `in_phase` rows above for its cost per "
            "in-phase step.)"
        )
        L.append("")
        g = cg.get("rac", {})
        if "plant_step" in g and "closed_loop_run" in g and "controller_step" in g:

            def share(k, g=g):
                return 100.0 * g[k] / g["closed_loop_run"]

            text = (
                "Where the time of a batch run goes (rac): the plant's RK4 step is %.0f %% of "
                "ClosedLoop::run's instructions, the controller %.0f %%, the rest (metrics, "
                "scenario look-up, copies of the step output) %.0f %%."
                % (
                    share("plant_step"),
                    share("controller_step"),
                    100.0 - share("plant_step") - share("controller_step"),
                )
            )
            if g.get("eigen_gemv"):
                text += (
                    " %.0f %% of ClosedLoop::run's instructions are spent inside Eigen's "
                    "general matrix-vector kernel (`general_matrix_vector_product`), to "
                    "which the small dynamic-size products (`A * x` in the plant, "
                    "`Phi_r * x_r` in the reference model) dispatch." % share("eigen_gemv")
                )
            text += (
                " Listings: `%s/callgrind.<mode>.txt` (inclusive), "
                "`callgrind_annotate %s/callgrind.rac.out` (exclusive)."
                % (meta["res"], meta["res"])
            )
            L.append(text)
            L.append("")
    L.append(
        "Note: Debian's libbenchmark prints \"Library was built as DEBUG\"; that concerns "
        "the harness itself (its timer loop), not the code under test, which is built "
        "Release (`-O3 -DNDEBUG`)."
    )
    L.append("")

    L.append("## Commands")
    L.append("")
    for k, v in cmds:
        L.append("- %s:" % k)
        L.append("")
        L.append("  ```")
        L.append("  %s" % v)
        L.append("  ```")
    L.append("")
    text = "\n".join(L)
    with open(args["--out"], "w") as f:
        f.write(text)
    print(text)


if __name__ == "__main__":
    cmd, rest = sys.argv[1], sys.argv[2:]
    {"timeloop": timeloop, "callgrind": callgrind, "report": report}[cmd](rest)
