"""preadaptive_mrac.analysis.metrics: switches, the running integral, baseline choice and the
comparison against the baseline (hand-computed values)."""

import unittest

import numpy as np

import pkg_path  # noqa: F401
from preadaptive_mrac.analysis import metrics, runs


def window(index, t_start, peak, iae):
    return {
        'index': index,
        't_start': t_start,
        'kind': 'switch',
        'theta_scale': 1.0,
        'peak_abs_e': peak,
        'iae': iae,
        'recovery_time': None,
    }


def run_metrics(label, mode, wins, peak, iae):
    return {
        'label': label,
        'mode': mode,
        'windows': wins,
        'whole_run': {'peak_abs_e': peak, 'iae': iae, 'max_abs_u': 0.3},
    }


class TestSwitches(unittest.TestCase):
    def test_time_is_the_first_sample_of_the_new_theta(self):
        t = np.arange(6) * 0.5
        theta = np.array([[1.0] * 3] * 3 + [[2.0] * 3] * 3)
        ts, before, after = metrics.find_switches(t, theta)
        np.testing.assert_allclose(ts, [1.5])
        np.testing.assert_allclose(before, [[1, 1, 1]])
        np.testing.assert_allclose(after, [[2, 2, 2]])

    def test_no_switch_for_constant_or_one_sample(self):
        self.assertEqual(len(metrics.find_switches([0, 1], [[1, 1, 1], [1, 1, 1]])[0]), 0)
        self.assertEqual(len(metrics.find_switches([0], [[1, 1, 1]])[0]), 0)

    def test_cumulative_trapezoid(self):
        t = np.array([0.0, 1.0, 3.0])
        y = np.array([1.0, 1.0, 3.0])
        np.testing.assert_allclose(metrics._cum_trapz(y, t), [0.0, 1.0, 5.0])


class TestCompare(unittest.TestCase):
    def setUp(self):
        self.rac = run_metrics(
            'R', 'rac', [window(0, 0.0, 0.2, 1.0), window(1, 10.0, 0.4, 2.0)], 0.4, 3.0
        )
        self.pa = run_metrics(
            'P',
            'pa_learn',
            [window(0, 0.0, 0.2, 1.0), window(1, 10.02, 0.1, 1.0), window(2, 30.0, 0.1, 1.0)],
            0.2,
            2.0,
        )

    def test_baseline_is_the_rac_run_or_the_named_one(self):
        self.assertEqual(metrics.choose_baseline([self.pa, self.rac]), 'R')
        self.assertEqual(metrics.choose_baseline([self.pa, self.rac], 'P'), 'P')
        self.assertIsNone(metrics.choose_baseline([self.pa]))
        with self.assertRaises(runs.InputError) as cm:
            metrics.choose_baseline([self.pa], 'X')
        self.assertIn("no run labelled 'X'", str(cm.exception))

    def test_reductions_per_paired_window(self):
        c = metrics.compare([self.rac, self.pa], 'R')
        self.assertEqual(c['baseline'], 'R')
        (row,) = c['runs']
        self.assertEqual(row['label'], 'P')
        by_index = {w['index']: w for w in row['windows']}
        self.assertAlmostEqual(by_index[1]['peak_reduction_pct'], 75.0)
        self.assertAlmostEqual(by_index[1]['iae_reduction_pct'], 50.0)
        self.assertEqual(by_index[1]['baseline_index'], 1)
        self.assertAlmostEqual(by_index[0]['peak_reduction_pct'], 0.0)
        self.assertNotIn(2, by_index)
        self.assertEqual(row['unmatched_windows'], [2])
        self.assertAlmostEqual(row['whole_run']['peak_reduction_pct'], 50.0)

    def test_no_baseline_no_comparison(self):
        self.assertIsNone(metrics.compare([self.pa], None))
        self.assertIsNone(metrics._pct(0.0, 1.0))


if __name__ == '__main__':
    unittest.main()
