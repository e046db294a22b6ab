"""preadaptive_mrac.studies.switch_reaction: windows, standing errors, the summary."""

import json
import os
import tempfile
import unittest

import pkg_path  # noqa: F401
from preadaptive_mrac.studies import switch_reaction as sr

A, B = [1.0, 2.0, 3.0], [2.0, 1.0, 0.5]


def windows(peaks, thetas=(None, A, B, A, B)):
    th = [[0.1] * 3] + list(thetas[1:])
    return [
        {'t_start': 10.0 * k, 't_end': 10.0 * (k + 1), 'theta': t, 'peak_abs_e': p}
        for k, (p, t) in enumerate(zip(peaks, th))
    ]


def series(levels):
    """|e| at 10 Hz over 50 s: levels[k] in window k."""
    t = [0.1 * i for i in range(500)]
    return t, [levels[int(x // 10.0)] for x in t]


class TestSwitchReaction(unittest.TestCase):
    def test_repeated_windows_are_the_revisits(self):
        self.assertEqual(sr.repeated_windows(windows([1, 1, 1, 1, 1])), [3, 4])
        self.assertEqual(sr.repeated_windows(windows([1, 1, 1], (None, A, B))), [])

    def test_standing_error_is_the_largest_before_the_switch(self):
        t, e = series([0.1, 0.2, 0.3, 0.4, 0.5])
        self.assertAlmostEqual(sr.standing_error(t, e, 30.0, 1.0), 0.3)
        self.assertEqual(sr.standing_error(t, e, 0.0, 1.0), 0.0)

    def test_rows_ratios_and_summary(self):
        # rac carries 2 mrad before the switch into window 3 and peaks at 2 mrad (no reaction);
        # pa peaks at 4 there (ratio 2). Window 4: rac peaks at 30 from 1, pa at 3 (0.1).
        rac = windows([5e-3, 9e-3, 8e-3, 2e-3, 30e-3])
        pa = windows([5e-3, 9e-3, 8e-3, 4e-3, 3e-3])
        s = {'rac': series([1e-3, 1e-3, 2e-3, 1e-3, 1e-3]), 'pa': series([1e-3] * 5)}
        rows = sr.window_rows({'rac': rac, 'pa': pa}, s, pre=1.0)
        self.assertEqual([r['window'] for r in rows], [3, 4])
        self.assertAlmostEqual(rows[0]['modes']['pa']['ratio'], 2.0)
        self.assertAlmostEqual(rows[0]['modes']['rac']['before'], 2e-3)
        self.assertAlmostEqual(sr.reaction(rows[0]['modes']['rac']), 1.0)
        self.assertAlmostEqual(rows[1]['modes']['pa']['ratio'], 0.1)
        sm = sr.summarize(rows, 'pa')
        self.assertEqual((sm['windows'], sm['worse']), (2, 1))
        self.assertAlmostEqual(sm['worse_base_reaction'], 1.0)
        self.assertAlmostEqual(sm['other_base_reaction'], 30.0)
        self.assertAlmostEqual(sm['other_mode_peak'], 3e-3)
        report = sr.format_report(rows, 'pa')
        self.assertIn('2 windows, 1 where pa is worse than rac', report)

    def test_a_family_without_the_mode_is_refused_naming_it(self):
        with tempfile.TemporaryDirectory() as d:
            with open(os.path.join(d, 'runs.jsonl'), 'w') as f:
                f.write(json.dumps({'scenario': d + '/scenario_0.yaml', 'mode': 'rac'}) + '\n')
            with self.assertRaisesRegex(ValueError, 'pa_robust'):
                sr.run_study('/nonexistent', d, 1, ['rac', 'pa_robust'])
            self.assertEqual(sr.main(['--dir', d, '--seed', '1']), 2)


if __name__ == '__main__':
    unittest.main()
