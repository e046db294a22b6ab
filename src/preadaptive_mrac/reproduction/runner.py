"""Running the batch tools (preadapt_sweep, preadapt_sim) with caching, and the helpers
every section uses."""

import json
import os
import shlex
import subprocess
import sys
import tempfile
import threading
import time
import uuid
from concurrent.futures import ThreadPoolExecutor

import numpy as np
import matplotlib.pyplot as plt
from .common import DEFAULT_BIN, GRIDS, MODES, QUICK, ROOT, SETTINGS, fail, loadavg, seed_spec


class StudyBase:
    """Tools, caches and options of one study run; the sections are mixins on top."""

    def __init__(self, args):
        self.args = args
        self.bin_dir = args.bin_dir
        self.bin_abs = (
            args.bin_dir if os.path.isabs(args.bin_dir) else os.path.join(ROOT, args.bin_dir)
        )
        self.fig_dir = (
            args.fig_dir if os.path.isabs(args.fig_dir) else os.path.join(ROOT, args.fig_dir)
        )
        self.md_path = args.out if os.path.isabs(args.out) else os.path.join(ROOT, args.out)
        self.seeds = list(range(1, args.seeds + 1))
        self.heat_seeds = list(range(1, args.heat_seeds + 1))
        self.spread_seeds = list(range(1, args.spread_seeds + 1))
        self.jobs = args.jobs
        self.sweep_cache = {}
        self.sim_cache = {}
        self.n_runs = 0
        self.tmp = tempfile.mkdtemp(prefix='reproduction_study_')
        self.section_runs = 0
        self.lock = threading.Lock()
        self.load0 = loadavg()
        self.grid = dict(QUICK if args.quick else GRIDS)

    # ---------------------------------------------------------------- running the tools
    def tool(self, name):
        p = os.path.join(self.bin_abs, name)
        if not os.access(p, os.X_OK):
            sys.exit(
                'reproduction_study: %s not found or not executable (use --bin-dir; build with '
                'cmake -S . -B build_repro && cmake --build build_repro --target preadapt_sim '
                'preadapt_sweep)' % p
            )
        return p

    def shown(self, name, argv):
        return shlex.join([os.path.join(self.bin_dir, name)] + argv)

    def sweep(self, scenario, modes, seeds, sets=None, grid=None):
        """Runs preadapt_sweep; returns (runs, command string)."""
        argv = [
            '--scenario',
            str(scenario),
            '--modes',
            ','.join(modes),
            '--seeds',
            seed_spec(seeds),
        ]
        for k, v in sorted((sets or {}).items()):
            argv += ['--set', '%s=%s' % (k, v)]
        for k, vals in grid or []:
            argv += ['--grid', '%s=%s' % (k, ','.join(vals))]
        argv += ['--jobs', str(self.jobs)]
        key = tuple(argv)
        cmd = self.shown('preadapt_sweep', argv)
        if key in self.sweep_cache:
            return self.sweep_cache[key], cmd
        t0 = time.time()
        p = subprocess.run(
            [self.tool('preadapt_sweep')] + argv, cwd=ROOT, capture_output=True, text=True
        )
        if p.returncode != 0:
            fail(cmd, p)
        runs = [json.loads(line) for line in p.stdout.splitlines() if line.startswith('{')]
        expect = len(modes) * len(seeds)
        for _, vals in grid or []:
            expect *= len(vals)
        if len(runs) != expect:
            sys.exit(
                'reproduction_study: `%s` printed %d runs, expected %d' % (cmd, len(runs), expect)
            )
        self.n_runs += len(runs)
        self.section_runs += len(runs)
        print('  %5.1f s  %4d runs  %s' % (time.time() - t0, len(runs), cmd), flush=True)
        self.sweep_cache[key] = runs
        return runs, cmd

    def sim(self, scenario, mode, seed, sets=None, rows=None):
        """Runs preadapt_sim --csv --json; returns (columns dict, summary, command).

        rows = (t0, t1) loads only that time range of the CSV."""
        argv = ['--scenario', str(scenario), '--mode', mode, '--seed', str(seed)]
        for k, v in sorted((sets or {}).items()):
            argv += ['--set', '%s=%s' % (k, v)]
        key = (tuple(argv), rows)
        if key in self.sim_cache:
            return self.sim_cache[key]
        csv = os.path.join(self.tmp, 'run_%s.csv' % uuid.uuid4().hex)
        cmd = self.shown('preadapt_sim', argv + ['--csv', 'OUT.csv', '--json'])
        p = subprocess.run(
            [self.tool('preadapt_sim')] + argv + ['--csv', csv, '--json'],
            cwd=ROOT,
            capture_output=True,
            text=True,
        )
        if p.returncode != 0:
            fail(cmd, p)
        summary = json.loads(p.stdout.strip().splitlines()[-1])
        with open(csv) as f:
            header = f.readline().strip().split(',')
        want = ['t', 'x1', 'xr1', 'e', 'e_dot_est', 'phase']
        idx = [header.index(c) for c in want]
        kw = {}
        if rows is not None:
            dt = summary['dt']
            kw = {
                'skiprows': 1 + int(round(rows[0] / dt)),
                'max_rows': int(round((rows[1] - rows[0]) / dt)),
            }
        else:
            kw = {'skiprows': 1}
        data = np.loadtxt(csv, delimiter=',', usecols=idx, ndmin=2, **kw)
        os.remove(csv)
        cols = {c: data[:, i] for i, c in enumerate(want)}
        with self.lock:
            self.n_runs += 1
            self.section_runs += 1
            self.sim_cache[key] = (cols, summary, cmd)
        return self.sim_cache[key]

    def prefetch(self, specs):
        """Runs the given sims (scenario, mode, seed, sets, rows) --jobs at a time."""
        t0 = time.time()
        with ThreadPoolExecutor(max_workers=max(1, self.jobs)) as ex:
            list(ex.map(lambda sp: self.sim(*sp), specs))
        print('  %5.1f s  %4d preadapt_sim --csv runs' % (time.time() - t0, len(specs)), flush=True)

    def dataset(self, scenario, setting):
        """All four modes, every seed, one threshold setting."""
        return self.sweep(scenario, MODES, self.seeds, SETTINGS[setting])

    # ---------------------------------------------------------------- helpers on datasets
    @staticmethod
    def by_mode(runs):
        out = {}
        for r in runs:
            out.setdefault(r['mode'], {})[r['seed']] = r
        return out

    def rac_ref(self, bm):
        """rac's peaks; rac never resets theta_hat, so its runs must not depend on the seed."""
        racs = list(bm['rac'].values())
        p = np.array([[w['peak_abs_e'] for w in r['windows']] for r in racs])
        spread = float(np.max(p.max(axis=0) - p.min(axis=0)))
        return racs[0], spread

    def regen(self, section):
        extra = self.common_args()
        return '`%s`' % shlex.join(['scripts/reproduction_study', '--only', section] + extra)

    def common_args(self):
        a, extra = self.args, []
        if a.bin_dir != DEFAULT_BIN:
            extra += ['--bin-dir', a.bin_dir]
        if a.seeds != 40:
            extra += ['--seeds', str(a.seeds)]
        if a.heat_seeds != 20:
            extra += ['--heat-seeds', str(a.heat_seeds)]
        if a.spread_seeds != 40:
            extra += ['--spread-seeds', str(a.spread_seeds)]
        if a.jobs != 2:
            extra += ['--jobs', str(a.jobs)]
        if a.quick:
            extra += ['--quick']
        return extra

    def fig(self, fig, name):
        os.makedirs(self.fig_dir, exist_ok=True)
        path = os.path.join(self.fig_dir, name)
        fig.savefig(path, dpi=self.args.dpi)
        plt.close(fig)
        rel = os.path.relpath(path, os.path.dirname(self.md_path))
        return '![%s](%s)\n' % (name, rel)

    # ================================================================ sections
