#!/usr/bin/env python3
"""A run that leaves the flight envelope (test/ros/envelope.test, either clock): the
truth and the log say it with the time and the bound; a state that is not finite ends the run.

Subscribes to plant/state, plant/truth, /diagnostics and /rosout; waits (bounded by
`~timeout`) for a truth that names an envelope exit and for the plant's states to stop, then
checks what each said.
"""
import math
import os
import signal
import sys
import threading
import time
import unittest

import rospy
import rostest
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
from rosgraph_msgs.msg import Log
from rostest_util import signal_node, subscribe_loop, wait_connected, wait_for

PKG = "preadaptive_mrac"


class EnvelopeTest(unittest.TestCase):
    def setUp(self):
        from preadaptive_mrac.msg import PlantTruth

        self.timeout = float(rospy.get_param("~timeout", 60.0))
        self.lock = threading.Lock()
        self.states = []  # (step, total_steps, all finite, arrival time)
        self.exits = []  # (step, bound, t, text) of truths that name an exit
        self.inside = []  # steps of truths that name none
        self.diag_errors = []
        self.log_errors = []
        # The truth and diagnostics first: the plant waits for the state subscription
        # (subscribe_loop) only, and the exit is on them for the few tens of ms the run has
        # left after it.
        self.log_sub = rospy.Subscriber("/rosout", Log, self.on_log, queue_size=1000)
        self.truth_sub = rospy.Subscriber("plant/truth", PlantTruth, self.on_truth)
        self.diag_sub = rospy.Subscriber("/diagnostics", DiagnosticArray, self.on_diag)
        # Connected before the plant can start: the exit lasts a few tens of ms of the run.
        for sub in (self.truth_sub, self.log_sub, self.diag_sub):
            wait_connected(sub, self.timeout, publisher_topic="plant/truth")
        subscribe_loop(self)

    def on_state(self, msg):
        with self.lock:
            finite = all(math.isfinite(v) for v in msg.x)
            self.states.append((msg.step, msg.total_steps, finite, time.monotonic()))

    def on_cmd(self, msg):
        pass

    def on_truth(self, msg):
        with self.lock:
            if msg.envelope_bound:
                self.exits.append(
                    (msg.step, msg.envelope_bound, msg.envelope_exit_t, msg.envelope_exit)
                )
            else:
                self.inside.append(msg.step)

    def on_diag(self, msg):
        for st in msg.status:
            if st.level == DiagnosticStatus.ERROR and "flight envelope" in st.message:
                with self.lock:
                    self.diag_errors.append(st.message)

    def on_log(self, msg):
        if msg.level == Log.ERROR and "left the flight envelope" in msg.msg:
            with self.lock:
                self.log_errors.append(msg.msg)

    def stopped(self):
        with self.lock:
            return bool(self.states) and not self.states[-1][2] and bool(self.exits)

    def test_exit_said_and_run_ended(self):
        wait_for(self.stopped, self.timeout, "a non-finite state after an envelope exit")
        time.sleep(1.0)  # the plant has ended: no state comes after the non-finite one
        with self.lock:
            states, exits, inside = list(self.states), list(self.exits), list(self.inside)
            diag, log = list(self.diag_errors), list(self.log_errors)
        last_step, total, finite, _ = states[-1]
        self.assertFalse(finite)
        self.assertLess(last_step + 1, total, "the run ended before its last step")
        self.assertTrue(all(s[2] for s in states[:-1]), "only the last state is not finite")
        step, bound, t, text = exits[0]
        self.assertIn(bound, ("alpha", "pitch_rate"))
        self.assertGreater(t, 0.5)
        self.assertLess(t, 1.5)
        self.assertIn("plant.envelope.max_", text)
        self.assertTrue(all(e[1:3] == (bound, t) for e in exits), "one exit, the first")
        self.assertTrue(all(s < step for s in inside), "no truth inside after the exit")
        wait_for(lambda: bool(self.log_errors), 5.0, "the plant's ERROR on /rosout")
        with self.lock:
            log = list(self.log_errors)
        self.assertEqual(len(log), 1, log)
        self.assertIn("t = ", log[0])
        # The plant's diagnostics say it too, at ERROR, with the time.
        wait_for(lambda: bool(self.diag_errors), 5.0, "the plant's ERROR on /diagnostics")
        with self.lock:
            diag = list(self.diag_errors)
        self.assertIn("t = ", diag[0])
        # The recorder, stopped, names the bag: a run that left the envelope (and stopped).
        import rosbag

        bag = rospy.get_param("~bag")
        signal_node("/bag_recorder", signal.SIGINT, 30.0, "the recorder to close its bag and exit")
        marked = bag[: -len(".bag")] + ".incomplete.envelope_exit.bag"
        self.assertTrue(
            os.path.exists(marked), "%s: %s" % (marked, os.listdir(os.path.dirname(bag)))
        )
        with rosbag.Bag(marked) as b:
            said = [m.envelope_bound for _, m, _ in b.read_messages(topics=["/plant/truth"])]
        self.assertIn(bound, said)
        rospy.loginfo(
            "envelope: %s; diagnostics ERRORs %d; %d states", text, len(diag), len(states)
        )


if __name__ == "__main__":
    rospy.init_node("envelope_check")
    rostest.rosrun(PKG, "envelope", EnvelopeTest, sys.argv)
