"""Robust-preadaptation study (scripts/robust_study): the unseen scenario family with and without
sensor noise -> table.md, ratios.png, timeseries.png. With --condition (repeatable: the
preadapt_family flags of one plant condition, e.g. "--mismatch 0.3 --delay 0:0.04"): one family
per condition at the first noise level, and table.md holds one row per condition and mode with
the largest whole-run peak |e| of any run from runs.jsonl (docs/research/mismatch.md,
docs/research/robust.md)."""

import argparse
import json
import math
import os
import shlex
import subprocess
import sys
import tempfile

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from .. import modes  # noqa: E402
from ..paths import package_root, tool_dir  # noqa: E402
from . import family_noise_seed  # noqa: E402

ROOT = package_root()
MODES = list(modes.MODES)
COLORS = modes.MODE_COLOUR
DECISION_STYLE = {
    "keep": ("o", "0.5"),
    "fit": ("s", "tab:green"),
    "memory": ("*", "tab:blue"),
    "network": ("^", "tab:orange"),
}


def tool(name):
    path = os.path.join(tool_dir(), name)
    if not os.path.exists(path):
        sys.exit("robust_study: %s not found; build first (README)" % path)
    return path


def family(seed, count, noise, out_dir=None, extra=(), modes=None):
    cmd = [
        tool("preadapt_family"),
        "--seed",
        str(seed),
        "--count",
        str(count),
        "--noise",
        repr(noise),
        "--modes",
        ",".join(modes or MODES),
        "--json",
    ] + list(extra)
    if out_dir:
        cmd += ["--out-dir", out_dir]
    text = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout
    rows = {}
    for line in text.splitlines():
        if line.startswith("{"):
            row = json.loads(line)
            rows[row["mode"]] = row
    return text, rows


def summary_cells(r):
    """A mode's family summary as table cells: better and halved [%], median and worst peak
    ratio, worst IAE ratio, scenarios with IAE > +5 %."""
    return (
        100 * r["frac_better"],
        100 * r["frac_halved"],
        r["median_ratio"],
        r["worst_ratio"],
        r["worst_iae_ratio"],
        r["iae_over_5pct"],
    )


def table(rows_by_noise, seed, count):
    out = []
    for noise, rows in rows_by_noise:
        out.append(
            "Family seed %d, %d scenarios, noise %g rad (rad/s) on alpha and q; "
            "%d repeated-switch windows.\n" % (seed, count, noise, rows["rac"]["windows"])
        )
        out.append(
            "| mode | better than rac | halved | median ratio | worst ratio | "
            "worst IAE ratio | scenarios IAE > +5 % | worst max\\|u\\| / rac | "
            "worst max\\|u\\| / oracle |"
        )
        out.append("|---|---|---|---|---|---|---|---|---|")
        for m in MODES:
            r = rows[m]
            out.append(
                "| %s | %.1f %% | %.1f %% | %.3f | %.3f | %.3f | %d | %.2f | %.2f |"
                % ((m,) + summary_cells(r) + (r["worst_u_rac"], r["worst_u_oracle"]))
            )
        out.append("")
    return "\n".join(out)


def max_peaks(runs_jsonl):
    """mode -> the largest whole-run peak |e| of any of its runs (inf for a run whose peak is not
    a finite number: a lost run) and the number of such runs."""
    peak, lost = {}, {}
    with open(runs_jsonl) as f:
        for line in f:
            r = json.loads(line)
            p = r["peak_abs_e"]
            ok = all(isinstance(v, (int, float)) and math.isfinite(v) for v in (p, r["iae"]))
            peak[r["mode"]] = max(peak.get(r["mode"], 0.0), p if ok else math.inf)
            lost[r["mode"]] = lost.get(r["mode"], 0) + (not ok)
    return peak, lost


def condition_rows(seed, count, noise, condition, modes, tmp):
    """One family under `condition` (preadapt_family flags): its command, the summary rows by
    mode, and the max peak and lost runs by mode."""
    extra = shlex.split(condition)
    out_dir = os.path.join(tmp, "family")
    _, rows = family(seed, count, noise, out_dir, extra, modes)
    peak, lost = max_peaks(os.path.join(out_dir, "runs.jsonl"))
    return rows, peak, lost


def condition_table(results, seed, count, noise, modes):
    """results: [(condition, rows, peak, lost)] -> Markdown, one row per condition and mode."""
    out = [
        "Family seed %d, %d scenarios, noise %g rad (rad/s) on alpha and q; %d repeated-switch "
        "windows per family:\n" % (seed, count, noise, results[0][1]["rac"]["windows"]),
        "    preadapt_family --seed %d --count %d --noise %g --modes %s --json --out-dir D "
        "<condition>\n" % (seed, count, noise, ",".join(modes)),
        "| condition | mode | better | halved | median | worst | worst IAE ratio | "
        "IAE > +5 % | max peak [rad] | lost runs |",
        "|---|---|---|---|---|---|---|---|---|---|",
    ]
    for condition, rows, peak, lost in results:
        for m in modes:
            if m == "rac":
                continue
            r = rows[m]
            out.append(
                "| `%s` | %s | %.1f %% | %.1f %% | %.3f | %.3g | %.3g | %d | %.3g | %d |"
                % ((condition or "(none)", m) + summary_cells(r) + (peak[m], lost[m]))
            )
        out.append(
            "| `%s` | rac | | | | | | | %.3g | %d |"
            % (condition or "(none)", peak["rac"], lost["rac"])
        )
    return "\n".join(out) + "\n"


def ratio_figure(rows_by_noise, path):
    fig, axes = plt.subplots(
        1, len(rows_by_noise), figsize=(6 * len(rows_by_noise), 4.6), sharey=True
    )
    axes = np.atleast_1d(axes)
    modes = [m for m in MODES if m != "rac"]
    for ax, (noise, rows) in zip(axes, rows_by_noise):
        data = [np.log10(np.maximum(rows[m]["ratios"], 1e-6)) for m in modes]
        parts = ax.violinplot(data, showmedians=True, widths=0.8)
        for body, m in zip(parts["bodies"], modes):
            body.set_facecolor(COLORS[m])
            body.set_alpha(0.5)
        ax.axhline(0.0, color="k", lw=1)
        ax.axhline(np.log10(0.5), color="k", lw=0.8, ls=":")
        ax.set_xticks(range(1, len(modes) + 1))
        ax.set_xticklabels(modes, rotation=20)
        ax.set_title("noise %g on alpha and q" % noise if noise else "clean")
        ax.grid(alpha=0.3)
    axes[0].set_ylabel("log10(peak |e| / peak |e| of rac)\nper repeated-switch window")
    fig.suptitle(
        "Peak error after a switch back into a known regime, ratio to rac "
        "(below 0: better; dotted: halved)"
    )
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def timeseries_figure(scenario_yaml, noise, noise_seed, path):
    sets = (
        [
            "--set",
            "plant.noise.std=[0,%r,%r]" % (noise, noise),
            "--set",
            "plant.noise.seed=%d" % noise_seed,
        ]
        if noise
        else []
    )
    runs = {}
    with tempfile.TemporaryDirectory() as tmp:
        for mode in ("rac", "pa_robust"):
            csv = os.path.join(tmp, mode + ".csv")
            out = subprocess.run(
                [
                    tool("preadapt_sim"),
                    "--scenario",
                    scenario_yaml,
                    "--mode",
                    mode,
                    "--json",
                    "--csv",
                    csv,
                ]
                + sets,
                check=True,
                capture_output=True,
                text=True,
            ).stdout
            summary = json.loads(out.strip().splitlines()[-1])
            data = np.genfromtxt(csv, delimiter=",", names=True)
            runs[mode] = (summary, data)
    summary, d = runs["pa_robust"]
    _, drac = runs["rac"]
    fig, ax = plt.subplots(
        3, 1, figsize=(11, 9), sharex=True, gridspec_kw={"height_ratios": [1.2, 1.2, 1]}
    )
    ax[0].plot(drac["t"], drac["e"] * 1e3, color=COLORS["rac"], lw=0.8, label="rac")
    ax[0].plot(d["t"], d["e"] * 1e3, color=COLORS["pa_robust"], lw=0.8, label="pa_robust")
    for w in summary["windows"][1:]:
        for a in ax:
            a.axvline(w["t_start"], color="k", lw=0.5, ls=":")
    ax[0].set_ylabel("e = alpha - alpha_r [mrad]")
    ax[0].legend(loc="upper right")
    for i in range(3):
        ax[1].plot(d["t"], d["theta_true%d" % i], color="C%d" % i, lw=1.5, alpha=0.35)
        ax[1].plot(
            d["t"],
            d["theta_hat%d" % i],
            color="C%d" % i,
            lw=0.9,
            label="theta_hat[%d] (faint: true)" % i,
        )
    ax[1].set_ylabel("theta")
    ax[1].legend(loc="upper right", fontsize=8)
    seen = set()
    for e in summary["events"]:
        if "decision" not in e:
            if e["type"] == "onset":
                ax[2].axvline(e["t"], color="tab:red", lw=0.6, alpha=0.5)
            continue
        marker, color = DECISION_STYLE.get(e["decision"], ("x", "k"))
        label = e["decision"] if e["decision"] not in seen else None
        seen.add(e["decision"])
        ax[2].semilogy(e["t"], max(e["score"], 1e-5), marker, color=color, ms=6, label=label)
        ax[2].semilogy(e["t"], max(e["score_keep"], 1e-5), "_", color="k", ms=8)
    ax[2].set_ylabel("RMS identification\nresidual [rad]")
    ax[2].set_xlabel("t [s]")
    ax[2].legend(loc="upper right", fontsize=8, title="decision (-: keeping)", title_fontsize=8)
    ax[0].set_title(
        "%s, noise %g: onsets (red), decisions and their scores against keeping "
        "the pre-switch estimate" % (os.path.basename(scenario_yaml), noise)
    )
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main(description=None, argv=None):
    """scripts/robust_study: parse the options and run."""
    p = argparse.ArgumentParser(description=(description or "").split("\n")[0])
    p.add_argument("--seed", type=int, default=20261123)
    p.add_argument("--count", type=int, default=40)
    p.add_argument("--noise", default="0,1e-4")
    p.add_argument("--scenario-index", type=int, default=0)
    p.add_argument("--out", default=os.path.join(ROOT, "docs", "figures", "robust"))
    p.add_argument(
        "--condition",
        action="append",
        default=[],
        help="preadapt_family flags of one plant condition (repeatable): one family each, "
        "table.md with max peaks, no figures",
    )
    p.add_argument("--modes", default=",".join(MODES))
    a = p.parse_args(argv)
    os.makedirs(a.out, exist_ok=True)
    if a.condition:
        modes = ["rac"] + [m for m in a.modes.split(",") if m != "rac"]
        noise = float(a.noise.split(",")[0])
        results = []
        for condition in a.condition:
            with tempfile.TemporaryDirectory() as tmp:
                rows, peak, lost = condition_rows(a.seed, a.count, noise, condition, modes, tmp)
            results.append((condition, rows, peak, lost))
        text = condition_table(results, a.seed, a.count, noise, modes)
        with open(os.path.join(a.out, "table.md"), "w") as f:
            f.write(text)
        print(text)
        print("robust_study: table.md in %s" % a.out)
        return 0
    rows_by_noise = []
    with tempfile.TemporaryDirectory() as tmp:
        for noise in [float(x) for x in a.noise.split(",")]:
            text, rows = family(a.seed, a.count, noise, tmp if noise else None)
            for line in text.splitlines():
                if not line.startswith("{"):
                    print(line)
            rows_by_noise.append((noise, rows))
        with open(os.path.join(a.out, "table.md"), "w") as f:
            f.write(table(rows_by_noise, a.seed, a.count))
        ratio_figure(rows_by_noise, os.path.join(a.out, "ratios.png"))
        noisy = [n for n, _ in rows_by_noise if n > 0]
        noise = noisy[0] if noisy else 0.0
        scen = os.path.join(tmp, "scenario_%d.yaml" % a.scenario_index)
        if not os.path.exists(scen):
            subprocess.run(
                [
                    tool("preadapt_family"),
                    "--seed",
                    str(a.seed),
                    "--count",
                    str(a.scenario_index + 1),
                    "--modes",
                    "rac",
                    "--out-dir",
                    tmp,
                ],
                check=True,
                capture_output=True,
            )
        timeseries_figure(
            scen,
            noise,
            family_noise_seed(a.seed, a.scenario_index),
            os.path.join(a.out, "timeseries.png"),
        )
    print("robust_study: table.md, ratios.png, timeseries.png in %s" % a.out)
