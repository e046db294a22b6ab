"""preadaptive_mrac.bench.timing: JSON lines, medians, one timed run and the interleaved loop,
on small Python commands standing in for the CLI and the prototype."""

import sys
import unittest

import pkg_path  # noqa: F401
from preadaptive_mrac.bench import timing


def py(code):
    return [sys.executable, '-c', code]


class TestHelpers(unittest.TestCase):
    def test_last_json_takes_the_last_object_line(self):
        text = 'a table\n{"wall_time_s": 1}\nmore\n{"wall_time_s": 2.5, "x": [1]}\n'
        self.assertEqual(timing.last_json(text), {'wall_time_s': 2.5, 'x': [1]})
        self.assertEqual(timing.last_json('no json here\n'), {})

    def test_median(self):
        self.assertEqual(timing.median([3.0, 1.0, 2.0]), 2.0)
        self.assertEqual(timing.median([1.0, 2.0]), 1.5)
        self.assertNotEqual(timing.median([]), timing.median([]))  # NaN


class TestRuns(unittest.TestCase):
    def test_run_once_reads_the_in_process_time(self):
        r = timing.run_once(py('print("x"); print(\'{"wall_time_s": 0.25}\')'))
        self.assertEqual(r['inproc'], 0.25)
        self.assertGreater(r['wall'], 0.0)
        self.assertGreaterEqual(r['cpu'], 0.0)
        self.assertIsNone(timing.run_once(py('print(1)'))['inproc'])

    def test_a_failing_command_raises_with_its_stderr(self):
        with self.assertRaises(timing.CommandFailed) as ctx:
            timing.run_once(py('import sys; sys.stderr.write("broken"); sys.exit(3)'))
        self.assertIn('(3)', str(ctx.exception))
        self.assertIn('broken', str(ctx.exception))

    def test_timeloop_interleaves_and_counts_each_command(self):
        lines = []
        a = py('print(\'{"wall_time_s": 0.001}\')')
        b = py('print(\'{"wall_time_s": 0.002}\')')
        c = py('print(\'{"wall_time_s": 0.003}\')')
        res = timing.timeloop([a, b, c], 2, log=lines.append)
        self.assertEqual(res['reps'], 2)
        self.assertEqual([len(res[k]) for k in 'abc'], [2, 2, 2])
        self.assertEqual(res['cmds'], [a, b, c])
        # A, B, C, A, B, C: the log shows the order.
        self.assertEqual([ln.split()[0] for ln in lines], ['a', 'b', 'c', 'a', 'b', 'c'])
        self.assertNotIn('json', res['a'][0])
        m = timing.medians(res, 'b')
        self.assertEqual(m['inproc'], 0.002)
        self.assertEqual(set(m), {'wall', 'cpu', 'inproc'})
        self.assertEqual(timing.medians(res, 'c')['inproc'], 0.003)

    def test_timeloop_needs_two_commands(self):
        with self.assertRaises(ValueError):
            timing.timeloop([py('pass')], 1)


if __name__ == '__main__':
    unittest.main()
