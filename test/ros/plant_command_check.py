#!/usr/bin/env python3
"""plant_sim_node alone in realtime; the test node is its controller. Asserts on plant/state
and /diagnostics:
1. valid commands (u = U) answering each state -> the published `elevator` is U (the applied,
   i.e. lastApplied(), elevator) and the state is the measured one (noise on: the published
   alpha jitters from sample to sample);
2. NaN / Inf commands -> never applied (`elevator` stays finite), counted in /diagnostics;
   they do not count as fresh commands, so within ~cmd_timeout the plant holds trim (0);
3. valid commands again -> applied again;
4. silence -> trim within ~cmd_timeout, /diagnostics reports it.
Every wait is bounded.
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
U = 0.01


class PlantCommandTest(unittest.TestCase):
    def setUp(self):
        self.cmd_timeout = rospy.get_param("~cmd_timeout", 0.05)
        self.lock = threading.Lock()
        self.answer = None  # u to answer each state with, None = silent
        self.states = []  # (receipt monotonic time, msg)
        self.diag = []
        self.pub = rospy.Publisher(
            "controller/elevator_cmd", ElevatorCommand, queue_size=1000, tcp_nodelay=True
        )
        self.diag_sub = rospy.Subscriber(
            "/diagnostics", DiagnosticArray, self.on_diag, queue_size=1000
        )
        self.sub = rospy.Subscriber(
            "plant/state", PlantState, self.on_state, queue_size=100000, tcp_nodelay=True
        )

    def on_state(self, msg):
        with self.lock:
            self.states.append((time.monotonic(), msg))
            u = self.answer
        if u is not None:
            c = ElevatorCommand()
            c.header.stamp = msg.header.stamp
            c.step = msg.step
            c.t = msg.t
            c.u = u
            self.pub.publish(c)

    def on_diag(self, msg):
        for s in msg.status:
            if "plant_sim" in s.name:
                with self.lock:
                    self.diag.append(s)

    def set_answer(self, u):
        with self.lock:
            self.answer = u
        return time.monotonic()

    def states_after(self, t0):
        with self.lock:
            return [m for t, m in self.states if t > t0]

    def last_diag(self):
        with self.lock:
            return self.diag[-1] if self.diag else None

    @staticmethod
    def value(status, key):
        for kv in status.values:
            if kv.key == key:
                return kv.value
        return None

    def trim_reached(self, t0):
        # State k carries the elevator applied over step k-1; trim = several zeros in a row.
        s = self.states_after(t0)
        return len(s) > 5 and all(m.elevator == 0.0 for m in s[-5:])

    def test_rejects_nan_and_holds_trim(self):
        wait_for(lambda: self.pub.get_num_connections() >= 1, 60.0, "the plant to subscribe")
        wait_for(lambda: len(self.states_after(0.0)) > 0, 60.0, "the first state")

        # 1. Valid commands are applied.
        t1 = self.set_answer(U)
        wait_for(
            lambda: sum(1 for m in self.states_after(t1) if m.elevator == U) > 100,
            20.0,
            "the commanded elevator to be applied",
        )
        alpha = [m.alpha for m in self.states_after(t1)][:200]
        d2 = [alpha[i + 1] - 2 * alpha[i] + alpha[i - 1] for i in range(1, len(alpha) - 1)]
        rms = math.sqrt(sum(v * v for v in d2) / len(d2))
        self.assertGreater(rms, 1e-4, "published alpha must be the measured (noisy) one")

        # 2. NaN / Inf commands: never applied; trim within the timeout.
        t2 = self.set_answer(float("nan"))
        wait_for(lambda: self.trim_reached(t2), 10.0, "trim after NaN commands")
        s = self.states_after(t2)
        self.assertTrue(all(math.isfinite(m.elevator) for m in s))
        self.assertTrue(all(m.elevator in (U, 0.0) for m in s), "only U (held) or trim")
        first_zero = next(i for i, m in enumerate(s) if m.elevator == 0.0)
        # Once at trim, the plant stays there while only non-finite commands come. (How many
        # steps it takes to get there is wall-clock speed, not asserted.)
        self.assertTrue(all(m.elevator == 0.0 for m in s[first_zero:]), "trim held")
        self.set_answer(float("inf"))
        wait_for(
            lambda: self.last_diag() is not None
            and int(self.value(self.last_diag(), "commands rejected (non-finite)") or 0) > 10,
            10.0,
            "/diagnostics to count rejected commands",
        )

        # 3. Valid again.
        t3 = self.set_answer(U)
        wait_for(
            lambda: any(m.elevator == U for m in self.states_after(t3)),
            10.0,
            "commands to be applied again",
        )

        # 4. Silence: trim, reported.
        t4 = self.set_answer(None)
        wait_for(lambda: self.trim_reached(t4), 10.0, "trim after silence")
        wait_for(
            lambda: self.last_diag() is not None
            and self.value(self.last_diag(), "holding trim") == "True"
            and self.last_diag().level == DiagnosticStatus.ERROR
            and int(self.value(self.last_diag(), "trim episodes")) >= 2,
            10.0,
            "/diagnostics to report the second trim episode",
        )


if __name__ == "__main__":
    rospy.init_node("plant_command_check")
    rostest.rosrun(PKG, "plant_command", PlantCommandTest, sys.argv)
