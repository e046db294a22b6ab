"""preadaptive_mrac.studies.regime_effectiveness: the Lambda schedule and the window ratios."""

import random
import unittest

import pkg_path  # noqa: F401
from preadaptive_mrac.studies import regime_effectiveness as re_study


def scenario():
    t = [[0.1] * 3, [1.0, 2.0, 3.0], [2.0, 1.0, 0.5], [1.0, 2.0, 3.0], [2.0, 1.0, 0.5]]
    return {
        'scenario': {'theta': [{'until': 5.0 * (i + 1), 'theta': th} for i, th in enumerate(t)]}
    }


def run(peaks, thetas, iae=1.0):
    return {
        'windows': [{'theta': th, 'peak_abs_e': p} for p, th in zip(peaks, thetas)],
        'iae': iae,
        'peak_abs_e': max(peaks),
        'max_abs_u': 1.0,
    }


class TestRegimeEffectiveness(unittest.TestCase):
    def test_one_lambda_per_regime_the_first_segment_one(self):
        sc = re_study.with_regime_effectiveness(scenario(), 0.4, 1.0, random.Random(1))
        lam = [s['value'] for s in sc['scenario']['effectiveness']]
        self.assertEqual(lam[0], 1.0)
        self.assertEqual(lam[1], lam[3])  # the same regime, the same Lambda
        self.assertEqual(lam[2], lam[4])
        self.assertNotEqual(lam[1], lam[2])
        for v in lam[1:]:
            self.assertTrue(0.4 <= v <= 1.0)
        untils = [s['until'] for s in sc['scenario']['effectiveness']]
        self.assertEqual(untils, [s['until'] for s in sc['scenario']['theta']])

    def test_only_repeated_windows_count(self):
        th = [s['theta'] for s in scenario()['scenario']['theta']]
        base = run([1.0, 2.0, 2.0, 4.0, 8.0], th)
        mode = run([1.0, 1.0, 1.0, 1.0, 16.0], th)
        self.assertEqual(re_study.repeated_ratios(mode, base), [0.25, 2.0])
        rows = re_study.summarize({0: {'rac': base, 'm': mode}}, ['rac', 'm'])
        self.assertEqual(rows['m']['windows'], 2)
        self.assertEqual(rows['m']['better'], 0.5)
        self.assertEqual(rows['m']['worst'], 2.0)
        self.assertEqual(rows['rac']['median'], 1.0)


if __name__ == '__main__':
    unittest.main()
