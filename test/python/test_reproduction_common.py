"""preadaptive_mrac.reproduction.common: the report's number formats, tables and event lookups."""

import unittest

import pkg_path  # noqa: F401
from preadaptive_mrac.reproduction import common


def run():
    return {
        'windows': [
            {'t_start': 0.0, 't_end': 5.0, 'theta': [1.0, 1.0, 1.0]},
            {'t_start': 5.0, 't_end': 20.0, 'theta': [2.0, 2.0, 2.0]},
        ],
        'events': [
            {'type': 'onset', 't': 5.0},
            {'type': 'ignored_onset', 't': 5.5},
            {'type': 'onset', 't': 5.2},
            {'type': 'recovered', 't': 6.0},
        ],
    }


class TestFormats(unittest.TestCase):
    def test_percent_and_mrad(self):
        self.assertEqual(common.fmt_pct(12.4), '+12%')
        self.assertEqual(common.fmt_pct(-3.6, signed=False), '-4%')
        self.assertEqual(common.fmt_pct(float('nan')), 'n/a')
        self.assertEqual(common.mrad(0.00123), '1.23')
        self.assertEqual(common.mrad(None), 'n/a')
        self.assertAlmostEqual(common.reduction(0.5, 2.0), 75.0)

    def test_md_table_escapes_pipes(self):
        t = common.md_table(['a', 'b|c'], [[1, 'x|y']])
        self.assertEqual(t, '| a | b\\|c |\n|---|---:|\n| 1 | x\\|y |\n')

    def test_seed_spec_and_block(self):
        self.assertEqual(common.seed_spec([1, 2, 3]), '1-3')
        self.assertEqual(common.seed_spec([1, 3]), '1,3')
        self.assertEqual(common.seed_spec([7]), '7')
        self.assertEqual(common.block('x', 'body'), '<!-- BEGIN x -->\nbody\n\n<!-- END x -->\n')

    def test_quick_grids_are_a_subset_of_the_keys(self):
        self.assertEqual(set(common.QUICK), set(common.GRIDS))


class TestEvents(unittest.TestCase):
    def test_first_onset_is_strictly_after_the_window_start(self):
        r = run()
        self.assertEqual(common.first_onset(r, 1)['t'], 5.2)
        self.assertEqual(common.first_onset(r, 0)['t'], 5.0)  # (t_start, t_end]
        self.assertEqual(common.recovery_after(r, 5.2)['t'], 6.0)
        self.assertIsNone(common.recovery_after(r, 6.0))
        self.assertEqual([e['t'] for e in common.ignored_in(r, 1)], [5.5])
        self.assertEqual(common.n_switch(r), 1)
        self.assertEqual(common.switch_label(r, 1), 't = 5 s (1 → 2)')


if __name__ == '__main__':
    unittest.main()
