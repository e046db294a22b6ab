"""Elevator effectiveness that changes with the regime: preadapt_family's
scenarios with a Lambda per regime, every mode against rac on the same plant and noise.

preadapt_family holds Lambda constant over a scenario; here each distinct theta of a scenario
(a regime) gets its own Lambda, drawn uniformly in [lo, hi] from a seed of its own, the first
segment (theta = 0.1 ones) Lambda 1. The metrics are docs/research/robust.md's: per repeated-switch
window the peak |e| ratio to rac; per scenario the IAE ratio; the largest peak |e| of any run.
"""

import json
import os
import random
import statistics
import subprocess
from concurrent.futures import ThreadPoolExecutor

import yaml

from ..paths import tool_dir


def with_regime_effectiveness(scenario, lo, hi, rng):
    """The scenario dict with an `effectiveness` schedule: one Lambda per distinct theta."""
    sc = scenario['scenario']
    lam, segs = {}, []
    for i, seg in enumerate(sc['theta']):
        key = tuple(seg['theta'])
        if key not in lam:
            lam[key] = 1.0 if i == 0 else rng.uniform(lo, hi)
        segs.append({'until': seg['until'], 'value': lam[key]})
    sc['effectiveness'] = segs
    return scenario


def repeated_ratios(run, base):
    """Peak |e| ratios to rac over the windows whose theta was seen in an earlier segment."""
    seen, out = [], []
    for k, (w, b) in enumerate(zip(run['windows'], base['windows'])):
        if k > 0 and w['theta'] in seen:
            out.append(w['peak_abs_e'] / b['peak_abs_e'] if b['peak_abs_e'] > 0 else 1.0)
        seen.append(w['theta'])
    return out


def summarize(runs, modes):
    """Per mode: better, halved, median, worst, worst IAE ratio, max peak, max|u| / oracle."""
    rows = {}
    for m in modes:
        ratios, iae, peak, u_or = [], [], 0.0, []
        for k, by_mode in sorted(runs.items()):
            r, base = by_mode[m], by_mode['rac']
            ratios += repeated_ratios(r, base)
            iae.append(r['iae'] / base['iae'])
            p = r['peak_abs_e']
            peak = max(peak, p if p is not None else float('inf'))
            if 'oracle' in by_mode:
                u_or.append(r['max_abs_u'] / by_mode['oracle']['max_abs_u'])
        rows[m] = {
            'windows': len(ratios),
            'better': sum(x < 1.0 for x in ratios) / len(ratios),
            'halved': sum(x <= 0.5 for x in ratios) / len(ratios),
            'median': statistics.median(ratios),
            'worst': max(ratios),
            'worst_iae': max(iae),
            'max_peak': peak,
            'worst_u_oracle': max(u_or) if u_or else None,
        }
    return rows


def run_study(bin_dir, seed, count, modes, lo=0.4, hi=1.0, noise=1e-4, out_dir='.', jobs=2):
    """Generate the family, add the Lambda schedules, run every mode; returns summarize()."""
    fam = os.path.join(out_dir, 'family')
    subprocess.run(
        [os.path.join(bin_dir, 'preadapt_family'), '--seed', str(seed), '--count', str(count)]
        # the study's own working folder: a re-run replaces it
        + ['--modes', 'rac', '--out-dir', fam, '--force', '--jobs', str(jobs)],
        check=True,
        stdout=subprocess.DEVNULL,
    )
    tasks = []
    for k in range(count):
        with open(os.path.join(fam, 'scenario_%d.yaml' % k)) as f:
            sc = yaml.safe_load(f)
        rng = random.Random('%d-%d' % (seed, k))
        path = os.path.join(out_dir, 'scenario_%d.yaml' % k)
        with open(path, 'w') as f:
            yaml.safe_dump(with_regime_effectiveness(sc, lo, hi, rng), f)
        for m in modes:
            tasks.append((k, m, path))

    def one(task):
        k, m, path = task
        cmd = [os.path.join(bin_dir, 'preadapt_sim'), '--scenario', path, '--mode', m, '--json']
        cmd += ['--set', 'plant.noise.std=[0,%g,%g]' % (noise, noise)]
        cmd += ['--set', 'plant.noise.seed=%d' % (seed * 1000 + k)]
        out = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout
        return k, m, json.loads(out.strip().splitlines()[-1])

    runs = {}
    with ThreadPoolExecutor(max_workers=jobs) as ex:
        for k, m, j in ex.map(one, tasks):
            runs.setdefault(k, {})[m] = j
    return summarize(runs, modes)


def format_rows(rows):
    lines = ['mode        windows  better  halved  median   worst  IAE:wst  max peak  u/oracle']
    for m, r in rows.items():
        u = '%8.2f' % r['worst_u_oracle'] if r['worst_u_oracle'] is not None else '       -'
        lines.append(
            '%-10s %8d %6.1f%% %6.1f%% %7.3f %7.3f %8.3f %9.4f %s'
            % (
                m,
                r['windows'],
                100 * r['better'],
                100 * r['halved'],
                r['median'],
                r['worst'],
                r['worst_iae'],
                r['max_peak'],
                u,
            )
        )
    return '\n'.join(lines)


def main(argv=None, description=__doc__):
    import argparse
    import tempfile

    ap = argparse.ArgumentParser(description=description)
    ap.add_argument('--seed', type=int, required=True, help='the family seed')
    ap.add_argument('--count', type=int, default=40)
    ap.add_argument('--modes', default='rac,pa_learn,pa_robust,oracle,l1')
    ap.add_argument('--lo', type=float, default=0.4, help='smallest Lambda of a regime')
    ap.add_argument('--hi', type=float, default=1.0, help='largest Lambda of a regime')
    ap.add_argument('--noise', type=float, default=1e-4, help='noise std on alpha and q')
    ap.add_argument('--jobs', type=int, default=2)
    args = ap.parse_args(argv)
    bin_dir = tool_dir()
    modes = args.modes.split(',')
    if 'rac' not in modes:
        modes.insert(0, 'rac')
    with tempfile.TemporaryDirectory() as out:
        rows = run_study(
            bin_dir, args.seed, args.count, modes, args.lo, args.hi, args.noise, out, args.jobs
        )
    print(
        'family seed %d, %d scenarios, Lambda per regime in [%g, %g], noise %g'
        % (args.seed, args.count, args.lo, args.hi, args.noise)
    )
    print(format_rows(rows))
    return 0
