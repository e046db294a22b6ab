#!/usr/bin/env python3
"""Realtime run to its end: after the plant's last state, no stale commands.

Subscribes to plant/state and controller/elevator_cmd, waits (bounded by `~timeout`) for the
state of the plant's last step (step + 1 == total_steps) and its answer, listens
`~listen_after` seconds more (20 times the controller's 0.05 s ~stale_timeout), then asserts
that no command came after that answer and that the commands answer the states one for one.
"""
import sys
import threading
import time
import unittest

import rospy
import rostest
from rostest_util import subscribe_loop, wait_for

PKG = "preadaptive_mrac"


class RealtimeEndTest(unittest.TestCase):
    def setUp(self):
        self.timeout = float(rospy.get_param("~timeout", 60.0))
        self.listen_after = float(rospy.get_param("~listen_after", 1.0))
        self.lock = threading.Lock()
        self.states = []  # steps
        self.last_step = None  # the plant's last step, once its state arrived
        self.cmds = []  # (step, stale, arrival index)
        subscribe_loop(self)

    def on_state(self, msg):
        with self.lock:
            self.states.append(msg.step)
            if msg.total_steps > 0 and msg.step + 1 == msg.total_steps:
                self.last_step = msg.step

    def on_cmd(self, msg):
        with self.lock:
            self.cmds.append((msg.step, msg.stale))

    def answered_last(self):
        with self.lock:
            return self.last_step is not None and any(
                s == self.last_step and not stale for s, stale in self.cmds
            )

    def test_no_command_after_the_last_answer(self):
        wait_for(self.answered_last, self.timeout, "the answer to the plant's last state")
        time.sleep(self.listen_after)
        with self.lock:
            cmds, states, last = list(self.cmds), list(self.states), self.last_step
        at = max(i for i, (s, stale) in enumerate(cmds) if s == last and not stale)
        after = cmds[at + 1 :]
        self.assertEqual(after[:10], [], "%d command(s) after the last state's answer" % len(after))
        answers = [s for s, stale in cmds if not stale]
        # The plant waits for this test's plant/state subscription only; the command
        # subscription to the controller may connect a few states later on a loaded machine,
        # so answers are compared from the first one heard (it must come early).
        first = min(answers)
        self.assertLess(first, 100, "the first answer heard is of step %d" % first)
        heard = [s for s in states if s >= first]
        self.assertEqual(sorted(set(answers)), sorted(set(heard)), "an answer per state")
        rospy.loginfo(
            "realtime_end: %d states, %d commands (%d stale during the run), none after step %d",
            len(states),
            len(cmds),
            sum(stale for _, stale in cmds),
            last,
        )


if __name__ == "__main__":
    rospy.init_node("realtime_end_check")
    rostest.rosrun(PKG, "realtime_end", RealtimeEndTest, sys.argv)
