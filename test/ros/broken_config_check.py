#!/usr/bin/python3
"""rostest node: plant_sim_node and mrac_controller_node given broken parameters exit with
code 2, name each offending key by its fully resolved name on stderr, and never publish.

Each case loads YAML (package config plus a per-case file from test/ros/config) into a fresh
namespace, starts the node there as a subprocess, feeds it plant states the way a plant would,
and watches the node's output topic. A valid configuration is run the same way as a control:
it must answer with commands, so the watching itself is shown to work.
"""
import os
import signal
import subprocess
import sys
import time
import unittest

import rosgraph
import rospkg
import rospy
import rostest
import yaml
from roslib.packages import find_node

from preadaptive_mrac.msg import ElevatorCommand, PlantState

PKG = 'preadaptive_mrac'
PKG_DIR = rospkg.RosPack().get_path(PKG)
TEST_CONFIG = os.path.join(PKG_DIR, 'test', 'ros', 'config')
EXIT_CONFIG_ERROR = 2
NODE_TIMEOUT_S = 30.0


def load_yaml(path):
    with open(path) as f:
        return yaml.safe_load(f)


def merged(*docs):
    """Merge YAML documents (maps merge recursively, later keys win)."""
    out = {}

    def merge(dst, src):
        for k, v in src.items():
            if isinstance(v, dict) and isinstance(dst.get(k), dict):
                merge(dst[k], v)
            else:
                dst[k] = v

    for d in docs:
        merge(out, d)
    return out


def package_config(name):
    return load_yaml(os.path.join(PKG_DIR, 'config', name))


def broken_config(name):
    return load_yaml(os.path.join(TEST_CONFIG, name))


def fake_state(k, nan_at=None):
    m = PlantState()
    m.header.stamp = rospy.Time(0, 1) if k == 0 else rospy.Time.from_sec(k * 0.001)
    m.step = k
    m.t = k * 0.001
    m.dt = 0.001
    m.total_steps = 1000000
    m.x = [0.0, float('nan'), 0.0] if k == nan_at else [0.0, 0.001 * k, 0.0]
    m.r = 0.1
    return m


class BrokenConfigTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('broken_config_test')

    def run_node(
        self,
        node_type,
        node_name,
        ns,
        params,
        out_topic,
        out_type,
        stop_on_message=False,
        feed_states=True,
        nan=None,
        stop_when=None,
    ):
        """Start a node in `ns` with `params` as its private namespace, feed it plant states
        (a controller; a plant needs no input) and collect what it publishes on `out_topic`
        until it exits (or, with stop_on_message, until it publishes; then it is interrupted).
        Returns (exit code, stdout + stderr, messages)."""
        private = ns + '/' + node_name
        rospy.set_param(private, params)
        got = []
        sub = rospy.Subscriber(ns + '/' + out_topic, out_type, got.append, tcp_nodelay=True)
        states = (
            rospy.Publisher(ns + '/plant/state', PlantState, queue_size=100)
            if feed_states
            else None
        )
        exe = find_node(PKG, node_type)
        self.assertTrue(exe, 'cannot find %s' % node_type)
        proc = subprocess.Popen(
            [exe[0], '__name:=' + node_name, '__ns:=' + ns],
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            universal_newlines=True,
        )
        deadline = time.time() + NODE_TIMEOUT_S
        k = 0
        try:
            while time.time() < deadline and proc.poll() is None:
                if stop_on_message and got and (stop_when is None or stop_when(got)):
                    break
                # A fake plant at ~200 Hz: a controller that wrongly started would answer.
                if nan is not None and got and 'step' not in nan:
                    nan['step'] = k + 3
                if states is not None:
                    states.publish(fake_state(k, nan.get('step') if nan is not None else None))
                k += 1
                time.sleep(0.005)
            if proc.poll() is None and stop_on_message:
                proc.send_signal(signal.SIGINT)
            out, err = proc.communicate(timeout=NODE_TIMEOUT_S)
        finally:
            if proc.poll() is None:
                proc.kill()
                proc.communicate()
            sub.unregister()
            if states is not None:
                states.unregister()
            rospy.delete_param(private)
        return proc.returncode, out + err, got

    def published_topics(self):
        state = rosgraph.Master('/broken_config_test').getSystemState()
        return [t for t, _ in state[0]]

    def assert_refused(self, node_type, node_name, ns, params, out_topic, out_type, keys):
        rc, text, got = self.run_node(
            node_type,
            node_name,
            ns,
            params,
            out_topic,
            out_type,
            feed_states=(out_topic != 'plant/state'),
        )
        self.assertEqual(
            rc,
            EXIT_CONFIG_ERROR,
            'exit code %s, expected %d; output:\n%s' % (rc, EXIT_CONFIG_ERROR, text),
        )
        for key in keys:
            self.assertIn(key, text, 'the message does not name %s; output:\n%s' % (key, text))
        self.assertEqual(got, [], 'published %d message(s) on %s' % (len(got), out_topic))
        self.assertNotIn(ns + '/' + out_topic, self.published_topics())

    # --- controller

    def controller_params(self, plant=None, controller=None):
        return merged(
            plant or package_config('plant/b747.yaml'),
            controller or package_config('controller/default.yaml'),
        )

    def test_valid_controller_answers(self):
        """Control: the same harness with a valid YAML gets commands and exit code 0."""
        rc, text, got = self.run_node(
            'mrac_controller_node',
            'mrac_controller',
            '/valid_ctl',
            self.controller_params(),
            'controller/elevator_cmd',
            ElevatorCommand,
            stop_on_message=True,
        )
        self.assertTrue(got, 'no command from a valid controller; output:\n' + text)
        self.assertIsInstance(got[0], ElevatorCommand)
        self.assertEqual(rc, 0, 'exit code %s after SIGINT; output:\n%s' % (rc, text))

    def test_missing_key(self):
        ns = '/broken_missing'
        self.assert_refused(
            'mrac_controller_node',
            'mrac_controller',
            ns,
            self.controller_params(controller=broken_config('broken_missing_key.yaml')),
            'controller/elevator_cmd',
            ElevatorCommand,
            [ns + '/mrac_controller/controller/adaptation/gamma', 'missing'],
        )

    def test_wrong_type(self):
        ns = '/broken_type'
        self.assert_refused(
            'mrac_controller_node',
            'mrac_controller',
            ns,
            self.controller_params(controller=broken_config('broken_wrong_type.yaml')),
            'controller/elevator_cmd',
            ElevatorCommand,
            [ns + '/mrac_controller/controller/lqr/R', 'expected a number'],
        )

    def test_not_stabilizable(self):
        ns = '/broken_stab'
        self.assert_refused(
            'mrac_controller_node',
            'mrac_controller',
            ns,
            self.controller_params(plant=broken_config('broken_not_stabilizable.yaml')),
            'controller/elevator_cmd',
            ElevatorCommand,
            [ns + '/mrac_controller/plant/A', 'not_stabilizable'],
        )

    def test_several_problems_at_once(self):
        ns = '/broken_many'
        params = self.controller_params(controller=broken_config('broken_missing_key.yaml'))
        params['controller']['lqr']['R'] = 'one'
        params['weights_in'] = '/nonexistent/weights.yaml'
        self.assert_refused(
            'mrac_controller_node',
            'mrac_controller',
            ns,
            params,
            'controller/elevator_cmd',
            ElevatorCommand,
            [
                ns + '/mrac_controller/controller/adaptation/gamma',
                ns + '/mrac_controller/controller/lqr/R',
                ns + '/mrac_controller/weights_in',
            ],
        )

    # --- plant

    def test_valid_plant_publishes(self):
        """Control: a valid plant publishes its first state and exits 0 on SIGINT."""
        params = merged(
            package_config('plant/b747.yaml'), package_config('scenarios/scenario1.yaml')
        )
        rc, text, got = self.run_node(
            'plant_sim_node',
            'plant_sim',
            '/valid_plant',
            params,
            'plant/state',
            PlantState,
            stop_on_message=True,
            feed_states=False,
        )
        self.assertTrue(got, 'no state from a valid plant; output:\n' + text)
        self.assertEqual(got[0].step, 0)
        self.assertEqual(rc, 0, 'exit code %s after SIGINT; output:\n%s' % (rc, text))

    def test_nan_state_gets_the_safe_command(self):
        """A state with a NaN is answered with the safe (baseline-hold) command, flagged, and
        the controller goes on answering the next states with the adaptive law."""
        nan = {}
        rc, text, got = self.run_node(
            'mrac_controller_node',
            'mrac_controller',
            '/nan_ctl',
            self.controller_params(),
            'controller/elevator_cmd',
            ElevatorCommand,
            stop_on_message=True,
            nan=nan,
            stop_when=lambda g: 'step' in nan and any(c.step > nan['step'] + 1 for c in g),
        )
        self.assertIn('step', nan, 'no answer at all; output:\n' + text)
        nan_at = nan['step']
        by_step = {c.step: c for c in got}
        self.assertIn(nan_at, by_step, 'no answer to the NaN state; output:\n' + text)
        self.assertTrue(by_step[nan_at].safe)
        self.assertFalse(any(c.safe for c in got if c.step != nan_at))
        self.assertTrue(all(c.u == c.u for c in got), 'a command is NaN')
        self.assertIn(nan_at + 1, by_step)
        self.assertIn('x[1] is nan', text)
        self.assertEqual(rc, 0, 'exit code %s after SIGINT; output:\n%s' % (rc, text))

    def test_broken_plant_node(self):
        ns = '/broken_plant'
        params = merged(
            package_config('plant/b747.yaml'),
            package_config('scenarios/scenario1.yaml'),
            broken_config('broken_plant_node.yaml'),
        )
        self.assert_refused(
            'plant_sim_node',
            'plant_sim',
            ns,
            params,
            'plant/state',
            PlantState,
            [ns + '/plant_sim/clock', ns + '/plant_sim/dt'],
        )

    def test_broken_plant_conditions(self):
        """Negative delay and time constant, sigma_w < 0, an effectiveness out of
        (0, 2] and a schedule going backwards: refused at once, each key named."""
        ns = '/broken_conditions'
        params = merged(
            package_config('plant/b747.yaml'), package_config('scenarios/scenario1.yaml')
        )
        params['plant']['actuator']['delay'] = -0.01
        params['plant']['actuator']['time_constant'] = -1.0
        params['plant']['turbulence']['sigma_w'] = -1.0
        params['scenario']['effectiveness'] = [
            {'until': 30.0, 'value': 2.5},
            {'until': 20.0, 'value': 1.0},
            {'until': 60.0, 'value': 1.0},
        ]
        p = ns + '/plant_sim/'
        self.assert_refused(
            'plant_sim_node',
            'plant_sim',
            ns,
            params,
            'plant/state',
            PlantState,
            [
                p + 'plant/actuator/delay',
                p + 'plant/actuator/time_constant',
                p + 'plant/turbulence/sigma_w',
                p + 'scenario/effectiveness/0/value',
                p + 'scenario/effectiveness/1/until',
            ],
        )


if __name__ == '__main__':
    rostest.rosrun(PKG, 'broken_config', BrokenConfigTest, sys.argv)
