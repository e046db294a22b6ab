#!/usr/bin/env python3
"""Controller alone (no plant): the test publishes plant/state itself and asserts on what
mrac_controller_node publishes (controller/elevator_cmd, /diagnostics).

1. valid states -> normal answers (safe false);
2. NaN states -> answered with the safe command of the last valid state (u = -K x_last or 0),
   never a command derived from them; they do not refresh the staleness timer, so stale
   commands (stale true) appear within ~stale_timeout although states keep arriving;
   /diagnostics counts the rejections;
3. no states at all -> stale commands at the sample rate, value -K x_last (baseline_hold) or 0
   (zero); /diagnostics reports stale;
4. valid states again -> normal answers, diagnostics no longer stale.
Every wait is bounded; nothing sleeps to let things settle.
"""
import math
import sys
import threading
import time
import unittest

import rospy

from rostest_util import wait_for
import rostest
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
from preadaptive_mrac.msg import ElevatorCommand, PlantState

PKG = "preadaptive_mrac"
DT = 0.001
X_VALID = [0.001, 0.02, -0.004]


class StaleInputTest(unittest.TestCase):
    def setUp(self):
        self.policy = rospy.get_param("~policy", "baseline_hold")
        self.stale_timeout = rospy.get_param("~stale_timeout", 0.1)
        self.lock = threading.Lock()
        self.cmds = []  # (receipt monotonic time, msg)
        self.diag = []  # controller's DiagnosticStatus, in order
        self.cmd_sub = rospy.Subscriber(
            "controller/elevator_cmd",
            ElevatorCommand,
            self.on_cmd,
            queue_size=100000,
            tcp_nodelay=True,
        )
        self.diag_sub = rospy.Subscriber(
            "/diagnostics", DiagnosticArray, self.on_diag, queue_size=1000
        )
        self.pub = rospy.Publisher("plant/state", PlantState, queue_size=1000, tcp_nodelay=True)
        self.step = 0
        self.t_last_valid = None  # monotonic time the last finite state was sent

    def on_cmd(self, msg):
        with self.lock:
            self.cmds.append((time.monotonic(), msg))

    def on_diag(self, msg):
        for s in msg.status:
            if "mrac_controller" in s.name:
                with self.lock:
                    self.diag.append(s)

    def commands(self):
        with self.lock:
            return list(self.cmds)

    def last_diag(self):
        with self.lock:
            return self.diag[-1] if self.diag else None

    def diag_value(self, status, key):
        for kv in status.values:
            if kv.key == key:
                return kv.value
        return None

    def send(self, x):
        m = PlantState()
        m.header.stamp = rospy.Time.now()
        m.step = self.step
        m.t = self.step * DT
        m.dt = DT
        m.total_steps = 1000000
        m.x = x
        m.e_I, m.alpha, m.q = x[0], x[1], x[2]
        m.r = 0.0
        self.pub.publish(m)
        if all(math.isfinite(v) for v in x):
            self.t_last_valid = time.monotonic()
        self.step += 1

    def answers(self, steps, stale=False):
        return [m for _, m in self.commands() if m.step in steps and m.stale == stale]

    def test_nan_and_silence_give_safe_commands(self):
        # The controller subscribes to plant/state only once we listen to its commands.
        wait_for(lambda: self.pub.get_num_connections() >= 1, 60.0, "the controller to subscribe")

        # 1. Valid states at 200 Hz (gaps far below ~stale_timeout).
        valid_steps = set()
        sent = []
        for _ in range(40):
            valid_steps.add(self.step)
            self.send(X_VALID)
            sent.append(time.monotonic())
            time.sleep(0.005)  # pacing the publisher, not waiting for a condition
        max_gap = max(b - a for a, b in zip(sent, sent[1:]))
        wait_for(
            lambda: len(self.answers(valid_steps)) == len(valid_steps),
            10.0,
            "answers to the valid states",
        )
        normal = self.answers(valid_steps)
        self.assertTrue(all(not m.safe for m in normal))
        u_bl = normal[-1].u_baseline  # -K x_last
        self.assertTrue(abs(u_bl) > 1e-6, "x_last must give a non-zero baseline")
        expected = u_bl if self.policy == "baseline_hold" else 0.0
        if max_gap < 0.5 * self.stale_timeout:
            # (On a loaded machine this publisher itself can pause longer than the timeout;
            # then the controller is right to go stale and this check does not apply.)
            self.assertFalse(
                any(m.stale for _, m in self.commands()),
                "no stale command while valid states arrive",
            )
        else:
            sys.stderr.write("publisher paused %.3f s: stale check of phase 1 skipped\n" % max_gap)

        # 2. NaN states for 3 x the timeout: each answered safely; stale commands appear.
        t_nan = time.monotonic()
        nan_steps = set()
        while time.monotonic() - t_nan < 3.0 * self.stale_timeout:
            nan_steps.add(self.step)
            self.send(
                [float("nan"), 0.02, float("inf")] if self.step % 2 else [0.0, float("nan"), 0.0]
            )
            time.sleep(0.005)
        t_nan_end = time.monotonic()
        wait_for(
            lambda: len(self.answers(nan_steps)) == len(nan_steps),
            10.0,
            "answers to the NaN states",
        )
        for m in self.answers(nan_steps):
            self.assertTrue(m.safe, "a NaN state must not get an adaptive command")
            self.assertTrue(math.isfinite(m.u))
            self.assertAlmostEqual(m.u, expected, delta=1e-12)
        stale_during_nan = [
            (t, m) for t, m in self.commands() if m.stale and t_nan < t <= t_nan_end
        ]
        self.assertTrue(
            stale_during_nan, "NaN states must not refresh the timer: stale commands expected"
        )
        # Not before the timeout after the last valid state (a lower bound: load only delays).
        # How soon after it they come is speed, not asserted here.
        since_valid = stale_during_nan[0][0] - self.t_last_valid
        self.assertGreaterEqual(since_valid, self.stale_timeout - 0.005, "stale too early")
        wait_for(
            lambda: self.last_diag() is not None
            and int(self.diag_value(self.last_diag(), "states rejected") or 0) >= len(nan_steps),
            10.0,
            "/diagnostics to count the rejected states",
        )

        # 3. Silence: stale commands keep coming (one per sample period; how many per second
        # is speed and not asserted), in step order, value -K x_last or 0.
        t_stop = time.monotonic()
        n_before = len([1 for _, m in self.commands() if m.stale])

        def silence_stale():
            return [m for t, m in self.commands() if m.stale and t > t_stop + self.stale_timeout]

        wait_for(lambda: len(silence_stale()) >= 50, 20.0, "50 stale commands after silence")
        window = silence_stale()
        steps = [m.step for m in window]
        self.assertEqual(steps, sorted(steps))
        self.assertEqual(len(set(steps)), len(steps), "stale command steps increase")
        for m in window:
            self.assertTrue(m.safe and m.stale)
            self.assertAlmostEqual(m.u, expected, delta=1e-12)
            self.assertEqual(m.u_adaptive, 0.0)
        self.assertGreater(len([1 for _, m in self.commands() if m.stale]), n_before)
        wait_for(
            lambda: self.last_diag() is not None
            and self.diag_value(self.last_diag(), "stale") == "True"
            and self.last_diag().level == DiagnosticStatus.ERROR,
            10.0,
            "/diagnostics to report stale",
        )
        d = self.last_diag()
        self.assertGreater(float(self.diag_value(d, "stale time [s]")), self.stale_timeout)
        self.assertGreaterEqual(int(self.diag_value(d, "stale commands")), 1)

        # 4. Valid states again: normal answers, stale reported cleared.
        back_steps = set()
        for _ in range(20):
            back_steps.add(self.step)
            self.send(X_VALID)
            time.sleep(0.005)
        wait_for(
            lambda: len(self.answers(back_steps)) == len(back_steps), 10.0, "answers after recovery"
        )
        self.assertTrue(all(not m.safe for m in self.answers(back_steps)))
        wait_for(
            lambda: self.last_diag() is not None
            and self.diag_value(self.last_diag(), "stale") == "False",
            10.0,
            "/diagnostics to report recovery",
        )


if __name__ == "__main__":
    rospy.init_node("stale_input_check")
    rostest.rosrun(PKG, "stale_input", StaleInputTest, sys.argv)
