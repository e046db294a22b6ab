"""preadaptive_mrac.reproduction.runner: the sweep's command line, the count check and the cache,
against a stand-in preadapt_sweep (a shell script that echoes its arguments as JSON lines)."""

import argparse
import os
import shutil
import stat
import tempfile
import unittest

import pkg_path  # noqa: F401
from preadaptive_mrac.reproduction import runner

FAKE_SWEEP = r'''#!/bin/sh
# One JSON line per requested run; N_RUNS overrides the count; the argv is logged.
echo "$@" >> "$(dirname "$0")/calls.log"
n=${N_RUNS:-2}
i=0
while [ $i -lt $n ]; do
  echo "{\"index\": $i, \"mode\": \"rac\", \"seed\": $((i + 1))}"
  i=$((i + 1))
done
'''


def args(bin_dir, quick=False):
    return argparse.Namespace(
        bin_dir=bin_dir,
        fig_dir='/tmp/unused_fig',
        out='/tmp/unused.md',
        seeds=2,
        heat_seeds=1,
        spread_seeds=2,
        jobs=1,
        dpi=50,
        quick=quick,
    )


class TestRunner(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix='pmrac_runner_')
        for name in ('preadapt_sweep', 'preadapt_sim'):
            p = os.path.join(self.dir, name)
            with open(p, 'w') as f:
                f.write(FAKE_SWEEP)
            os.chmod(p, os.stat(p).st_mode | stat.S_IXUSR)
        self.study = runner.StudyBase(args(self.dir))

    def tearDown(self):
        shutil.rmtree(self.study.tmp, ignore_errors=True)
        shutil.rmtree(self.dir)
        os.environ.pop('N_RUNS', None)

    def calls(self):
        with open(os.path.join(self.dir, 'calls.log')) as f:
            return f.read().splitlines()

    def test_command_line_and_cache(self):
        runs, cmd = self.study.sweep(1, ['rac'], [1, 2], {'b.key': '2', 'a.key': '1'})
        self.assertEqual([r['seed'] for r in runs], [1, 2])
        self.assertEqual(
            self.calls(),
            ['--scenario 1 --modes rac --seeds 1-2 --set a.key=1 --set b.key=2 --jobs 1'],
        )
        self.assertIn('preadapt_sweep --scenario 1', cmd)
        again, _ = self.study.sweep(1, ['rac'], [1, 2], {'a.key': '1', 'b.key': '2'})
        self.assertIs(again, runs)
        self.assertEqual(len(self.calls()), 1)
        self.assertEqual(self.study.n_runs, 2)

    def test_wrong_number_of_runs_stops_the_study(self):
        os.environ['N_RUNS'] = '1'
        with self.assertRaises(SystemExit) as cm:
            self.study.sweep(1, ['rac'], [1, 2])
        self.assertIn('printed 1 runs, expected 2', str(cm.exception))

    def test_missing_tool_is_named(self):
        os.remove(os.path.join(self.dir, 'preadapt_sweep'))
        with self.assertRaises(SystemExit) as cm:
            self.study.tool('preadapt_sweep')
        self.assertIn('preadapt_sweep not found', str(cm.exception))

    def test_quick_grids_belong_to_the_study(self):
        quick = runner.StudyBase(args(self.dir, quick=True))
        shutil.rmtree(quick.tmp)
        self.assertEqual(quick.grid['CED_BAND'], runner.QUICK['CED_BAND'])
        self.assertNotEqual(self.study.grid['CED_BAND'], quick.grid['CED_BAND'])
        self.assertEqual(
            self.study.common_args(),
            ['--bin-dir', self.dir, '--seeds', '2', '--heat-seeds', '1', '--spread-seeds', '2']
            + ['--jobs', '1'],
        )


if __name__ == '__main__':
    unittest.main()
