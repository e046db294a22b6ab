#!/usr/bin/env python3
"""bag_recorder_node's ~accept_from: a stray node's states on the recorded topic never reach
the bag; the accepted publisher's (this test node, /recorder_guard) all do, in order."""
import glob
import os
import signal
import sys
import threading
import time
import unittest

import rosbag
import rospy

from rostest_util import signal_node, wait_for
import rostest
from preadaptive_mrac.msg import PlantState, RecorderProgress

PKG = "preadaptive_mrac"
N = 200
STRAY_STEP = 1 << 40


class RecorderGuardTest(unittest.TestCase):
    def test_stray_states_never_reach_the_bag(self):
        bag_dir = rospy.get_param("~bag_dir")
        lock = threading.Lock()
        progress = {"step": -1}
        stray_seen = threading.Event()

        def on_progress(m):
            with lock:
                if m.step < STRAY_STEP:
                    progress["step"] = max(progress["step"], m.step)

        def on_state(m):
            if m.step == STRAY_STEP:
                stray_seen.set()

        rospy.Subscriber("/bag_recorder/progress", RecorderProgress, on_progress, queue_size=1000)
        rospy.Subscriber("/plant/state", PlantState, on_state, queue_size=10)
        pub = rospy.Publisher("/plant/state", PlantState, queue_size=N)
        # The stray runs and reaches subscribers (so it reaches the recorder too) before the run.
        wait_for(stray_seen.is_set, 60.0, "the stray node's states")
        wait_for(lambda: pub.get_num_connections() >= 2, 60.0, "the recorder to subscribe")
        for k in range(N):
            m = PlantState(step=k, t=k * 0.001, dt=0.001, total_steps=N, x=[0.0, 1e-3 * k, 0.0])
            m.header.stamp = rospy.Time(1.0 + k * 0.001)
            pub.publish(m)
            if k % 50 == 49:
                time.sleep(0.01)  # pacing the publisher, not waiting for a condition
        wait_for(lambda: progress["step"] >= N - 1, 60.0, "the recorder to write every state")
        time.sleep(0.5)  # more stray states arrive meanwhile (500 Hz)
        signal_node("/bag_recorder", signal.SIGINT, 30.0, "the recorder to close its bag")

        bags = glob.glob(os.path.join(bag_dir, "*.bag"))
        self.assertEqual(len(bags), 1, "one closed bag: %s" % os.listdir(bag_dir))
        with rosbag.Bag(bags[0]) as b:
            steps = [m.step for _, m, _ in b.read_messages(topics=["/plant/state"])]
        stray = sum(1 for s in steps if s == STRAY_STEP)
        self.assertEqual(stray, 0, "%d stray state(s) written to the bag" % stray)
        self.assertEqual(steps, list(range(N)), "the accepted states, in order")
        sys.stderr.write("bag: %d states, none of the stray's\n" % len(steps))


if __name__ == "__main__":
    rospy.init_node("recorder_guard")
    rostest.rosrun(PKG, "recorder_guard", RecorderGuardTest, sys.argv)
