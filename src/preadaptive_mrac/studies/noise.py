"""Sensor-noise study (scripts/noise_study): detections and false onsets of the attention
mechanism against the noise level, as a Markdown table."""

import argparse
import json
import os
import statistics
import subprocess

SWITCHES = [5.0, 20.0, 45.0]
WINDOW = 4.0
LEVELS = ["0", "1e-5", "3e-5", "1e-4", "3e-4", "1e-3"]
SETTINGS = [
    ("paper: c_ed 0.02, no debounce", ["controller.attention.c_ed=0.02"]),
    ("c_ed 0.015, no debounce", ["controller.attention.c_ed=0.015"]),
    (
        "c_ed 0.015, confirm 20, hysteresis 1 mrad",
        [
            "controller.attention.c_ed=0.015",
            "controller.attention.confirm_samples=20",
            "controller.attention.hysteresis=0.001",
        ],
    ),
]


def run(bin_dir, sets, seeds, jobs):
    cmd = [
        os.path.join(bin_dir, "preadapt_sweep"),
        "--scenario",
        "1",
        "--modes",
        "rac",
        "--jobs",
        str(jobs),
        "--grid",
        "plant.noise.std=" + ",".join("[0,%s,%s]" % (lv, lv) for lv in LEVELS),
        "--grid",
        "plant.noise.seed=" + ",".join(str(s) for s in range(1, seeds + 1)),
    ]
    for s in sets:
        cmd += ["--set", s]
    out = subprocess.run(cmd, check=True, stdout=subprocess.PIPE, text=True).stdout
    return cmd, [json.loads(line) for line in out.splitlines() if line.strip()]


def classify(run_json):
    detected, false = set(), 0
    for e in run_json["events"]:
        if e["type"] != "onset":
            continue
        hit = [s for s in SWITCHES if s <= e["t"] <= s + WINDOW]
        if hit:
            detected.add(hit[0])
        else:
            false += 1
    return len(detected), false


def main(description=None, argv=None):
    """scripts/noise_study: parse the options and run."""
    ap = argparse.ArgumentParser(
        description=description, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    ap.add_argument("--bin-dir", default="build/devel/lib/preadaptive_mrac")
    ap.add_argument("--seeds", type=int, default=10)
    ap.add_argument("--jobs", type=int, default=os.cpu_count() or 1)
    args = ap.parse_args(argv)
    print(
        "| attention setting | noise std on alpha, q | switches detected (of 3), median | "
        "false onsets per 60 s run: median [min, max] | ignored onsets, median |"
    )
    print("|---|---|---|---|---|")
    commands = []
    for label, sets in SETTINGS:
        cmd, runs = run(args.bin_dir, sets, args.seeds, args.jobs)
        commands.append(" ".join(cmd))
        by_level = {}
        for r in runs:
            lv = r["grid"]["plant.noise.std"]
            det, false = classify(r)
            ign = sum(1 for e in r["events"] if e["type"] == "ignored_onset")
            by_level.setdefault(lv, []).append((det, false, ign))
        for lv in LEVELS:
            rows = by_level["[0,%s,%s]" % (lv, lv)]
            dets = [d for d, _, _ in rows]
            fls = [f for _, f, _ in rows]
            igs = [i for _, _, i in rows]
            print(
                "| %s | %s rad, rad/s | %g | %g [%d, %d] | %g |"
                % (
                    label,
                    lv,
                    statistics.median(dets),
                    statistics.median(fls),
                    min(fls),
                    max(fls),
                    statistics.median(igs),
                )
            )
    print()
    print("Commands (one sweep per attention setting, %d noise seeds per cell):" % args.seeds)
    print()
    for c in commands:
        print("    " + c)
