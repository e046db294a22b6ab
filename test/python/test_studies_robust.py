"""preadaptive_mrac.studies.robust: the Markdown table of the family study."""

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


if __name__ == '__main__':
    unittest.main()
