"""preadaptive_mrac.studies.robust: the Markdown table of the family study."""

import json
import os
import tempfile
import unittest

import pkg_path  # noqa: F401
from preadaptive_mrac.studies import robust


def row(i):
    return {
        'windows': 80,
        'frac_better': 0.5 + 0.01 * i,
        'frac_halved': 0.25,
        'median_ratio': 0.5,
        'worst_ratio': 1.25,
        'worst_iae_ratio': 1.5,
        'iae_over_5pct': i,
        'worst_u_rac': 1.0,
        'worst_u_oracle': 2.0,
    }


class TestTable(unittest.TestCase):
    def test_one_block_per_noise_level_one_row_per_mode(self):
        rows = {m: row(i) for i, m in enumerate(robust.MODES)}
        text = robust.table([(0.0, rows), (1e-4, rows)], 4242, 40)
        self.assertEqual(text.count('Family seed 4242, 40 scenarios'), 2)
        self.assertIn('noise 0.0001 rad', text)
        self.assertIn('80 repeated-switch windows', text)
        self.assertIn('| rac | 50.0 % | 25.0 % | 0.500 | 1.250 | 1.500 | 0 | 1.00 | 2.00 |', text)
        self.assertEqual(sum(1 for ln in text.splitlines() if ln.startswith('| pa_robust |')), 2)

    def test_a_missing_mode_is_an_error(self):
        with self.assertRaises(KeyError):
            robust.table([(0.0, {'rac': row(0)})], 1, 1)


class TestConditionTable(unittest.TestCase):
    def test_max_peak_per_mode_and_a_lost_run_is_inf(self):
        lines = [
            {'mode': 'rac', 'peak_abs_e': 0.1, 'iae': 1.0},
            {'mode': 'rac', 'peak_abs_e': 0.12, 'iae': 1.0},
            {'mode': 'l1', 'peak_abs_e': 0.03, 'iae': 0.2},
            {'mode': 'l1', 'peak_abs_e': None, 'iae': None},  # NaN in the JSON: a lost run
            {'mode': 'rac', 'peak_abs_e': 0.05, 'iae': None},
        ]
        with tempfile.TemporaryDirectory() as tmp:
            path = os.path.join(tmp, 'runs.jsonl')
            with open(path, 'w') as f:
                f.write(''.join(json.dumps(x) + '\n' for x in lines))
            peak, lost = robust.max_peaks(path)
        self.assertEqual(peak['rac'], float('inf'))
        self.assertEqual(lost, {'rac': 1, 'l1': 1})
        self.assertEqual(peak['l1'], float('inf'))

    def test_one_row_per_condition_and_mode_with_the_command(self):
        rows = {m: row(i) for i, m in enumerate(robust.MODES)}
        peak = {m: 0.01 * (i + 1) for i, m in enumerate(robust.MODES)}
        lost = {m: 0 for m in robust.MODES}
        modes = ['rac', 'pa_robust']
        text = robust.condition_table(
            [('--mismatch 0.3', rows, peak, lost), ('', rows, peak, lost)], 4711, 40, 1e-4, modes
        )
        self.assertIn('preadapt_family --seed 4711 --count 40 --noise 0.0001', text)
        r = rows['pa_robust']
        want = '| `--mismatch 0.3` | pa_robust | %.1f %% |' % (100 * r['frac_better'])
        self.assertIn(want, text)
        self.assertIn('| `(none)` | rac | | | | | | | %.3g | 0 |' % peak['rac'], text)
        self.assertEqual(sum(1 for ln in text.splitlines() if ln.startswith('| `')), 4)


if __name__ == '__main__':
    unittest.main()
