"""preadaptive_mrac.analysis.report: number formatting and the settled decision of each phase."""

import unittest

import pkg_path  # noqa: F401
from preadaptive_mrac.analysis import report


class TestReport(unittest.TestCase):
    def test_fmt_and_theta_text(self):
        self.assertEqual(report._fmt(None), '-')
        self.assertEqual(report._fmt(0.123456), '0.1235')
        self.assertEqual(report._theta_text(2.0, None), '2')
        self.assertEqual(report._theta_text(None, [1.0, -0.5, 0.25]), '[1,-0.5,0.25]')
        self.assertEqual(report._theta_text(None, None), '-')

    def test_final_decision_of_each_verification(self):
        ds = [
            {'type': 'onset', 'decision': 'keep'},
            {'type': 'decision', 'decision': 'fit'},
            {'type': 'decision', 'decision': 'memory'},
            {'type': 'onset', 'decision': 'network'},
        ]
        self.assertEqual([d['decision'] for d in report.final_decisions(ds)], ['memory', 'network'])
        self.assertEqual(report.final_decisions([]), [])


if __name__ == '__main__':
    unittest.main()
