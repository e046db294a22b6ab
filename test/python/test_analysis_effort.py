"""analyze_bag's elevator effort (preadaptive_mrac.analysis.metrics.effort, the report and
metrics.csv): peak |u| of the applied elevator, the time at the travel and rate limits and the
steady-flight total variation, counted as the batch tools count them (hand-computed values)."""

import os
import shutil
import subprocess
import sys
import tempfile
import unittest

import numpy as np

import pkg_path  # noqa: F401
from preadaptive_mrac.analysis import metrics, report, runs

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def limited_run():
    """Two windows of 1 s at dt 0.1 (switch at t = 1.0): up at the rate limit (0.1 per step at
    1 rad/s) to the travel 0.3, held; then a buzz of 0.01 between 0.3 and 0.29."""
    r = runs.Run('lim', 'synthetic')
    t = np.round(np.arange(20) * 0.1, 10)
    r.t_e = t
    r.e = np.zeros(20)
    r.t_theta = t
    r.theta = np.array([[1.0] * 3] * 10 + [[2.0] * 3] * 10)
    r.t_u = t
    r.u = np.full(20, 5.0)  # the command: far beyond the travel
    r.t_applied = t
    r.u_applied = np.array([0.1, 0.2] + [0.3] * 8 + [0.29, 0.3] * 5)
    return r


class TestEffort(unittest.TestCase):
    def test_applied_elevator_with_limits(self):
        m = metrics.run_metrics(limited_run(), limits=(0.3, 1.0))
        ef = m['whole_run']['effort']
        self.assertEqual(ef['effort_source'], 'applied')
        self.assertAlmostEqual(ef['peak_abs_u'], 0.3)
        # rate: 0 -> 0.1 -> 0.2 -> 0.3 (3 samples); travel: 8 + 5 samples of 0.1 s
        self.assertAlmostEqual(ef['time_at_rate_limit'], 0.3)
        self.assertAlmostEqual(ef['time_at_travel_limit'], 1.3)
        # window 1 = [1.0, 1.9]: steady from 1.9 - 0.45 - 0.05 = 1.4: samples 14..19, 5 steps
        w = m['windows']
        self.assertEqual(len(w), 2)
        self.assertAlmostEqual(w[1]['steady_tv'], 0.05)
        self.assertAlmostEqual(w[0]['steady_tv'], 0.0)
        self.assertAlmostEqual(ef['steady_tv'], 0.05)
        self.assertAlmostEqual(w[0]['time_at_limit'], 1.0)
        text = report.format_report([m], None)
        self.assertIn(
            'elevator effort (applied): peak |u| 0.3 rad, 1.3 s at the travel limit, 0.3 s at '
            'the rate limit, steady-flight total variation 0.05 rad (last 0.5 of each window)',
            text,
        )

    def test_without_limits_or_applied_elevator(self):
        r = limited_run()
        r.t_applied = r.u_applied = None
        ef = metrics.run_metrics(r)['whole_run']['effort']
        self.assertEqual(ef['effort_source'], 'command')
        self.assertEqual(ef['peak_abs_u'], 5.0)
        self.assertIsNone(ef['time_at_travel_limit'])
        self.assertEqual(ef['steady_tv'], 0.0)

    def test_csv_has_the_columns(self):
        d = tempfile.mkdtemp(prefix='pmrac_effort_')
        try:
            m = metrics.run_metrics(limited_run(), limits=(0.3, 1.0))
            m.update(source='synthetic', namespace='', mode='rac')
            report.write_tables(d, [m], None, {})
            with open(os.path.join(d, 'metrics.csv')) as f:
                rows = [line.rstrip('\n').split(',') for line in f]
            head = rows[0]
            last = dict(zip(head, rows[-1]))
            self.assertEqual(last['window'], 'all')
            self.assertAlmostEqual(float(last['steady_tv']), 0.05)
            self.assertAlmostEqual(float(dict(zip(head, rows[1]))['time_at_limit']), 1.0)
        finally:
            shutil.rmtree(d)

    def test_cli_refuses_bad_limits(self):
        p = subprocess.run(
            [
                sys.executable,
                os.path.join(ROOT, 'scripts', 'analyze_bag'),
                'x.csv',
                '--elevator-limits',
                '0.35',
                '-1',
            ],
            capture_output=True,
            text=True,
        )
        self.assertEqual(p.returncode, 2, p.stderr)
        self.assertIn('--elevator-limits: travel and rate must be > 0', p.stderr)


if __name__ == '__main__':
    unittest.main()
