"""preadaptive_mrac.analysis.runs: mode names from file names, decision decoding, epoch rebase."""

import types
import unittest

import numpy as np

import pkg_path  # noqa: F401
from preadaptive_mrac.analysis import runs


class TestGuessMode(unittest.TestCase):
    def test_each_mode_from_a_file_name(self):
        cases = {
            'scenario1_pa_learn.csv': 'pa_learn',
            'scenario1_pa_learn_exact.csv': 'pa_learn_exact',
            'x/s3-pa-robust.bag': 'pa_robust',
            's1_rac.csv': 'rac',
            'oracle_run.csv': 'oracle',
            'pa.csv': 'pa',
            'scenario1_l1.csv': 'l1',
        }
        for name, mode in cases.items():
            self.assertEqual(runs._guess_mode(name), mode, name)

    def test_none_or_two_modes_give_none(self):
        self.assertIsNone(runs._guess_mode('scenario1.csv'))
        self.assertIsNone(runs._guess_mode('rac_vs_pa_learn.csv'))
        self.assertIsNone(runs._guess_mode('l1_vs_rac.csv'))


class TestDecisions(unittest.TestCase):
    def test_message_with_a_code_only(self):
        m = types.SimpleNamespace(
            decision='', decision_code=3, chosen=1, candidates=4, score=0.5, score_keep=2.0
        )
        d = runs._msg_decision(m)
        self.assertEqual(d['decision'], 'memory')
        self.assertEqual((d['chosen'], d['candidates']), (1, 4))

    def test_old_message_without_fields_has_no_decision(self):
        self.assertEqual(runs._msg_decision(types.SimpleNamespace()), runs._no_decision())
        bad_code = types.SimpleNamespace(decision='', decision_code=9)
        self.assertIsNone(runs._msg_decision(bad_code)['decision'])

    def test_json_event(self):
        self.assertIsNone(runs._json_decision({'type': 'onset'})['decision'])
        d = runs._json_decision({'decision': 'fit', 'chosen': -1, 'score': 0.1})
        self.assertEqual((d['decision'], d['score'], d['score_keep']), ('fit', 0.1, None))


class TestRebaseEpoch(unittest.TestCase):
    def _run(self, t0):
        r = runs.Run('x', 'src')
        r.t_e = np.array([t0, t0 + 1.0])
        r.t_alpha = np.array([t0, t0 + 0.5])
        r.events = [{'t': t0 + 0.25}]
        return r

    def test_wall_clock_stamps_start_at_zero(self):
        r = self._run(1.7e9)
        runs._rebase_epoch(r)
        np.testing.assert_allclose(r.t_e, [0.0, 1.0])
        np.testing.assert_allclose(r.t_alpha, [0.0, 0.5])
        self.assertAlmostEqual(r.events[0]['t'], 0.25)
        self.assertTrue(any('wall-clock' in n for n in r.notes))

    def test_simulation_time_is_kept(self):
        r = self._run(3.0)
        runs._rebase_epoch(r)
        np.testing.assert_allclose(r.t_e, [3.0, 4.0])
        self.assertEqual(r.notes, [])


if __name__ == '__main__':
    unittest.main()
