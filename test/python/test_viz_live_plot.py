"""preadaptive_mrac.viz.live_plot: rqt_plot's TOPIC/FIELD syntax and field resolution, on
stand-in messages (no master, no window)."""

import contextlib
import io
import sys
import unittest
from unittest import mock

import pkg_path  # noqa: F401
from preadaptive_mrac.viz.live_plot import (
    SpecError,
    absolute_spec,
    main,
    parse_spec,
    resolve,
    split_fields,
    window_title,
)


class Msg:
    """A message as genpy makes them: fields in __slots__."""

    def __init__(self, _type, **fields):
        self.__slots__ = list(fields)
        self._type = _type
        for k, v in fields.items():
            setattr(self, k, v)


TOPICS = ['/plant/state', '/controller/status', '/controller/status_extra']


class TestWindowTitle(unittest.TestCase):
    def test_two_windows_differ(self):
        # scenario.launch's plot and a user's rosrun live_plot beside it
        a = window_title('/conditions_plot', 'elevator commanded / applied [rad]', ['x'])
        b = window_title('/live_plot_123_456', '', ['plant/state/alpha', 'plant/state/q'])
        self.assertNotEqual(a, b)
        self.assertEqual(a, 'elevator commanded / applied [rad] (/conditions_plot)')
        self.assertEqual(b, 'plant/state/alpha plant/state/q (/live_plot_123_456)')


class TestSpec(unittest.TestCase):
    def test_split_fields(self):
        self.assertEqual(split_fields('x[1]'), [('x', [1])])
        self.assertEqual(split_fields('header/stamp'), [('header', []), ('stamp', [])])
        with self.assertRaises(SpecError):
            split_fields('1x')

    def test_longest_topic_prefix_and_alternatives(self):
        self.assertEqual(parse_spec('/plant/state/alpha', TOPICS), ('/plant/state', ['alpha']))
        self.assertEqual(
            parse_spec('/controller/status_extra/e', TOPICS), ('/controller/status_extra', ['e'])
        )
        self.assertEqual(
            parse_spec('/controller/status/theta_hat_0:theta_hat_1', TOPICS),
            ('/controller/status', ['theta_hat_0', 'theta_hat_1']),
        )
        self.assertEqual(
            parse_spec('/plant/state/header/stamp:seq', TOPICS),
            ('/plant/state', ['header/stamp', 'header/seq']),
        )

    def test_not_yet_published_and_malformed(self):
        self.assertIsNone(parse_spec('/other/topic/x', TOPICS))
        for bad in ['plant/state/alpha', '/plant/state/', '/plant//state/alpha', '/plant/state/a:']:
            with self.assertRaises(SpecError, msg=bad):
                parse_spec(bad, TOPICS)
        with self.assertRaisesRegex(SpecError, 'a topic, not a field'):
            parse_spec('/plant/state', TOPICS)

    def test_relative_spec_in_the_node_namespace(self):
        self.assertEqual(absolute_spec('plant/state/alpha', '/'), '/plant/state/alpha')
        self.assertEqual(absolute_spec('plant/state/alpha', '/run_a/'), '/run_a/plant/state/alpha')
        self.assertEqual(absolute_spec('plant/state/x[1]', '/a/b'), '/a/b/plant/state/x[1]')
        self.assertEqual(absolute_spec('/plant/state/alpha', '/run_a/'), '/plant/state/alpha')


class TestResolve(unittest.TestCase):
    def setUp(self):
        self.msg = Msg('preadaptive_mrac/PlantState', alpha=0.1, x=[0.0, 0.1, 0.2], step=3, ok=True)

    def test_numbers_arrays_and_elements(self):
        self.assertEqual(resolve(self.msg, split_fields('alpha'), 'alpha', '/s'), [('', 0.1)])
        self.assertEqual(resolve(self.msg, split_fields('step'), 'step', '/s'), [('', 3.0)])
        self.assertEqual(resolve(self.msg, split_fields('ok'), 'ok', '/s'), [('', 1.0)])
        self.assertEqual(resolve(self.msg, split_fields('x[2]'), 'x[2]', '/s'), [('', 0.2)])
        self.assertEqual(
            resolve(self.msg, split_fields('x'), 'x', '/s'),
            [('[0]', 0.0), ('[1]', 0.1), ('[2]', 0.2)],
        )

    def test_errors_name_the_field(self):
        with self.assertRaisesRegex(SpecError, 'has no field nope .*alpha, x, step, ok'):
            resolve(self.msg, split_fields('nope'), 'nope', '/s')
        with self.assertRaisesRegex(SpecError, 'index 5 outside x'):
            resolve(self.msg, split_fields('x[5]'), 'x[5]', '/s')
        with self.assertRaisesRegex(SpecError, 'alpha is not an array'):
            resolve(self.msg, split_fields('alpha[0]'), 'alpha[0]', '/s')


class TestCommandLine(unittest.TestCase):
    def test_roslaunch_arguments_left_out(self):
        # scenario.launch plot:=true starts live_plot as a node: roslaunch appends __name:= and
        # __log:=. They must not be refused; the real error (--window 0) is the one reported.
        argv = ['live_plot', 'plant/state/alpha', '--window', '0', '__name:=p', '__log:=/tmp/p.log']
        err = io.StringIO()
        with mock.patch.object(sys, 'argv', argv), contextlib.redirect_stderr(err):
            with self.assertRaises(SystemExit) as e:
                main()
        self.assertEqual(e.exception.code, 2)
        self.assertIn('--window: must be > 0', err.getvalue())
        self.assertNotIn('unrecognized arguments', err.getvalue())


if __name__ == '__main__':
    unittest.main()
