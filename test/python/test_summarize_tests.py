"""scripts/summarize_tests: the closing count, and for a failed case the last lines of its
message, so that the tail of a test log (all a CI page may show) says why it failed."""

import os
import subprocess
import tempfile
import unittest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

FAILING = """<testsuite>
<testcase classname="Realtime" name="test_in_order"><failure message="AssertionError">Traceback
  File "check.py", line 9, in test_in_order
AssertionError: Lists differ: [(5, 7)] != []

plant/state steps not consecutive (lost or reordered)
</failure></testcase>
<testcase classname="Realtime" name="test_other"/>
<testcase classname="Gtest" name="Skipped" status="notrun"/>
</testsuite>
"""


def summarize(files):
    with tempfile.TemporaryDirectory() as d:
        for name, text in files.items():
            os.makedirs(os.path.dirname(os.path.join(d, name)), exist_ok=True)
            with open(os.path.join(d, name), 'w') as f:
                f.write(text)
        r = subprocess.run(
            ['/usr/bin/python3', os.path.join(ROOT, 'scripts', 'summarize_tests'), d],
            capture_output=True,
            text=True,
        )
    return r.returncode, r.stdout.splitlines()


class SummarizeTestsTest(unittest.TestCase):
    def test_failure_prints_its_message_before_the_count(self):
        rc, lines = summarize({'a/rosunit-x.xml': FAILING})
        self.assertEqual(rc, 1)
        self.assertEqual(lines[0], 'FAILED  Realtime.test_in_order (rosunit-x.xml)')
        detail = [line for line in lines if line.startswith('    | ')]
        self.assertIn('    | AssertionError: Lists differ: [(5, 7)] != []', detail)
        self.assertEqual(detail[-1], '    | plant/state steps not consecutive (lost or reordered)')
        self.assertLessEqual(len(detail), 6)
        self.assertIn('SKIPPED Gtest.Skipped (rosunit-x.xml)', lines)
        self.assertEqual(lines[-1], '1 passed, 1 failed, 1 skipped')

    def test_all_passed_exits_0_and_no_case_is_a_failure(self):
        ok = '<testsuite><testcase classname="A" name="b"/></testsuite>'
        self.assertEqual(summarize({'ok.xml': ok}), (0, ['1 passed, 0 failed, 0 skipped']))
        rc, lines = summarize({'ok.xml': ok, 'empty.xml': '<testsuite/>'})
        self.assertEqual(rc, 1)
        self.assertIn('FAILED  empty.xml: no test case ran', lines)


if __name__ == '__main__':
    unittest.main()
