"""How much each mode reacts to a switch back into a known regime, against the error it was
already carrying (docs/notebook.md, "pa_robust: Lambda per regime", (e)).

A family's repeated-switch windows rate a mode by its peak |e| in the window over rac's. This
study re-runs a family's scenarios (a `preadapt_family --out-dir D`: its runs.jsonl and scenario
files, noise seeds `seed * 1000003 + scenario` as the family draws them) with preadapt_sim,
reads |e| from each run's CSV, and puts beside every window each mode's standing error: the
largest |e| in the `pre` seconds before the switch. A mode whose peak after the switch is hardly
above that did not react to the switch; a window ratio against such a baseline says as much
about the baseline as about the mode.
"""

import csv
import json
import os
import statistics
import subprocess
import tempfile
from concurrent.futures import ThreadPoolExecutor

from ..paths import tool_dir
from . import family_noise_seed


def repeated_windows(windows):
    """Indices of the windows whose theta was seen in an earlier window (not the first)."""
    seen, out = [], []
    for k, w in enumerate(windows):
        if k > 0 and w['theta'] in seen:
            out.append(k)
        seen.append(w['theta'])
    return out


def standing_error(t, abs_e, t_switch, pre):
    """The largest |e| over [t_switch - pre, t_switch), or 0.0 when no sample is there."""
    return max((e for tt, e in zip(t, abs_e) if t_switch - pre <= tt < t_switch), default=0.0)


def window_rows(windows_by_mode, series_by_mode, pre=1.0, base='rac'):
    """One row per repeated-switch window of a scenario: per mode (standing error before the
    switch, peak in the window); and each mode's window ratio to `base`."""
    rows = []
    for k in repeated_windows(windows_by_mode[base]):
        ts = windows_by_mode[base][k]['t_start']
        row = {'window': k, 't_switch': ts, 'modes': {}}
        for m, wins in windows_by_mode.items():
            t, abs_e = series_by_mode[m]
            row['modes'][m] = {
                'before': standing_error(t, abs_e, ts, pre),
                'peak': wins[k]['peak_abs_e'],
            }
        b = row['modes'][base]['peak']
        for m in row['modes']:
            p = row['modes'][m]['peak']
            row['modes'][m]['ratio'] = p / b if b > 0 else 1.0
        rows.append(row)
    return rows


def reaction(entry):
    """Peak after the switch over the standing error before it (inf when that is 0)."""
    return entry['peak'] / entry['before'] if entry['before'] > 0 else float('inf')


def summarize(rows, mode, base='rac'):
    """Windows where `mode` is worse than `base` against the others: counts, and the medians
    of base's reaction and peak, and of mode's peak."""

    def med(xs):
        return statistics.median(xs) if xs else None

    worse = [r for r in rows if r['modes'][mode]['ratio'] > 1.0]
    other = [r for r in rows if r['modes'][mode]['ratio'] <= 1.0]
    out = {'windows': len(rows), 'worse': len(worse)}
    for name, group in (('worse', worse), ('other', other)):
        out[name + '_base_reaction'] = med([reaction(r['modes'][base]) for r in group])
        out[name + '_base_peak'] = med([r['modes'][base]['peak'] for r in group])
        out[name + '_mode_peak'] = med([r['modes'][mode]['peak'] for r in group])
    return out


def read_abs_e(path):
    """Columns t and |e| of a preadapt_sim CSV."""
    t, abs_e = [], []
    with open(path) as f:
        for r in csv.DictReader(f):
            t.append(float(r['t']))
            abs_e.append(abs(float(r['e'])))
    return t, abs_e


def run_study(bin_dir, family_dir, seed, modes, noise=1e-4, pre=1.0, jobs=2):
    """Re-run every scenario of the family in `family_dir` for each mode; window_rows of all."""
    runs = {}
    with open(os.path.join(family_dir, 'runs.jsonl')) as f:
        for line in f:
            r = json.loads(line)
            runs.setdefault(r['scenario'], {})[r['mode']] = r
    missing = [m for m in modes if not all(m in by_mode for by_mode in runs.values())]
    if missing:
        raise ValueError(
            '%s: no run of mode(s) %s in every scenario (run preadapt_family with --modes %s)'
            % (family_dir, ', '.join(missing), ','.join(modes))
        )
    index = {}
    for sc in runs:
        name = os.path.basename(sc)
        index[sc] = int(name[len('scenario_') : -len('.yaml')])

    def one(task):
        sc, m, tmp = task
        csv_path = os.path.join(tmp, '%d_%s.csv' % (index[sc], m))
        cmd = [os.path.join(bin_dir, 'preadapt_sim'), '--scenario', sc, '--mode', m]
        for o in runs[sc][m].get('overrides', []):
            cmd += ['--set', o]
        cmd += ['--set', 'plant.noise.std=[0,%g,%g]' % (noise, noise)]
        cmd += ['--set', 'plant.noise.seed=%d' % family_noise_seed(seed, index[sc])]
        cmd += ['--csv', csv_path]
        subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
        series = read_abs_e(csv_path)
        os.remove(csv_path)
        return sc, m, series

    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        tasks = [(sc, m, tmp) for sc in sorted(runs, key=index.get) for m in modes]
        series = {}
        with ThreadPoolExecutor(max_workers=jobs) as ex:
            for sc, m, s in ex.map(one, tasks):
                series.setdefault(sc, {})[m] = s
    for sc in sorted(runs, key=index.get):
        wins = {m: runs[sc][m]['windows'] for m in modes}
        for row in window_rows(wins, series[sc], pre):
            row['scenario'] = index[sc]
            rows.append(row)
    return rows


def format_report(rows, mode, worst=10):
    """The `worst` windows by mode's ratio, then summarize()."""
    lines = [
        'scenario  switch [s]  ratio  rac before/peak [mrad]  rac reaction  '
        '%s before/peak [mrad]' % mode
    ]
    for r in sorted(rows, key=lambda r: -r['modes'][mode]['ratio'])[:worst]:
        b, p = r['modes']['rac'], r['modes'][mode]
        lines.append(
            '%8d %11.3f %6.2f %11.2f / %-8.2f %11.2f %12.2f / %.2f'
            % (
                r.get('scenario', -1),
                r['t_switch'],
                p['ratio'],
                1e3 * b['before'],
                1e3 * b['peak'],
                reaction(b),
                1e3 * p['before'],
                1e3 * p['peak'],
            )
        )
    s = summarize(rows, mode)

    def fmt(x, scale=1.0):
        return '-' if x is None else '%.2f' % (scale * x)

    lines.append(
        '%d windows, %d where %s is worse than rac; medians there / elsewhere: rac reaction '
        '(peak / before) %s / %s, rac peak %s / %s mrad, %s peak %s / %s mrad'
        % (
            s['windows'],
            s['worse'],
            mode,
            fmt(s['worse_base_reaction']),
            fmt(s['other_base_reaction']),
            fmt(s['worse_base_peak'], 1e3),
            fmt(s['other_base_peak'], 1e3),
            mode,
            fmt(s['worse_mode_peak'], 1e3),
            fmt(s['other_mode_peak'], 1e3),
        )
    )
    return '\n'.join(lines)


def main(argv=None, description=__doc__):
    import argparse

    ap = argparse.ArgumentParser(description=description)
    ap.add_argument('--dir', required=True, help='a preadapt_family --out-dir')
    ap.add_argument('--seed', type=int, required=True, help='the family seed it was run with')
    ap.add_argument('--noise', type=float, default=1e-4, help='its --noise')
    ap.add_argument('--mode', default='pa_robust', help='the mode to set against rac')
    ap.add_argument('--pre', type=float, default=1.0, help='seconds before a switch')
    ap.add_argument('--worst', type=int, default=10, help='windows listed')
    ap.add_argument('--jobs', type=int, default=2)
    args = ap.parse_args(argv)
    bin_dir = tool_dir()
    modes = ['rac'] if args.mode == 'rac' else ['rac', args.mode]
    try:
        rows = run_study(bin_dir, args.dir, args.seed, modes, args.noise, args.pre, args.jobs)
    except (OSError, ValueError) as e:
        print('switch_reaction_study: %s' % e)
        return 2
    print(
        'family %s (seed %d, noise %g): standing error = max |e| over the %g s before a switch'
        % (args.dir, args.seed, args.noise, args.pre)
    )
    print(format_report(rows, args.mode, args.worst))
    return 0
