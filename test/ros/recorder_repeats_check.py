#!/usr/bin/env python3
"""A lockstep plant's re-sent states are not recorded twice. The test node is the plant's
controller: it answers every state, except steps HELD, which it leaves unanswered until the
plant has published them a second time (after ~resend_interval); every other delivery is
answered, as the controller answers a repeat. Then it stops the recorder
(SIGINT) and reads the bag: plant/state, plant/truth and controller/elevator_cmd hold every
step exactly once, and the bag is complete (not .incomplete.bag). A held step's command is
published twice (the controller answers a re-sent state again). Without the recorder's
de-duplication, each held step would be in the bag twice."""
import collections
import os
import signal
import sys
import threading
import unittest

import rosbag
import rospy

from rostest_util import signal_node, wait_for
import rostest
from preadaptive_mrac.msg import ElevatorCommand, PlantState, RecorderProgress

PKG = "preadaptive_mrac"
HELD = (0, 7, 150, 151)  # step 0 and two neighbours: the first, an early and back-to-back
TOPICS = ("/plant/state", "/plant/truth", "/controller/elevator_cmd")


class RecorderRepeatsTest(unittest.TestCase):
    def test_resent_states_are_recorded_once(self):
        bag = rospy.get_param("~bag")
        lock = threading.Lock()
        seen = collections.Counter()
        progress = {}
        total = {"n": 0}
        pub = rospy.Publisher(
            "/controller/elevator_cmd", ElevatorCommand, queue_size=1000, tcp_nodelay=True
        )

        def on_state(msg):
            with lock:
                seen[msg.step] += 1
                total["n"] = msg.total_steps
                # As the controller does, a repeat is answered again (the first answer may
                # have gone before this node's command connection was up).
                if msg.step in HELD and seen[msg.step] == 1:
                    return
            c = ElevatorCommand()
            c.header.stamp = msg.header.stamp
            c.step = msg.step
            c.t = msg.t
            c.u = 0.0
            # A held step is answered twice (as the controller answers a re-sent state whose
            # first answer it believes lost): the second is the same command again.
            for _ in range(2 if msg.step in HELD else 1):
                pub.publish(c)

        def on_progress(m):
            with lock:
                progress[m.topic] = max(progress.get(m.topic, -1), m.step)

        rospy.Subscriber("/bag_recorder/progress", RecorderProgress, on_progress, queue_size=1000)
        # The plant starts once this node subscribes to its states: before that, both readers
        # of the commands (the plant and the recorder) must be connected, as the controller's
        # ~min_command_subscribers makes sure, or the first answers miss the bag.
        wait_for(
            lambda: pub.get_num_connections() >= 2,
            60.0,
            "the plant and the recorder to subscribe to the commands",
        )
        rospy.Subscriber("/plant/state", PlantState, on_state, queue_size=None, tcp_nodelay=True)

        def recorded_to_end():
            with lock:
                n = total["n"]
                return n > 0 and all(
                    progress.get(t, -1) >= n - 1
                    for t in ("/plant/state", "/controller/elevator_cmd")
                )

        wait_for(recorded_to_end, 90.0, "the recorder to write the plant's last state")
        with lock:
            n = total["n"]
            repeated = sorted(k for k, c in seen.items() if c > 1)
        self.assertTrue(
            set(HELD) <= set(repeated), "the plant re-sent the held states: %s" % repeated
        )

        signal_node("/bag_recorder", signal.SIGINT, 30.0, "the recorder to close its bag and exit")
        incomplete = bag[: -len(".bag")] + ".incomplete.bag"
        self.assertFalse(os.path.exists(incomplete), "the run reached its end: %s" % incomplete)
        self.assertTrue(os.path.exists(bag), "the recorder left %s" % bag)
        steps = collections.defaultdict(list)
        with rosbag.Bag(bag) as b:
            for topic, m, _ in b.read_messages(topics=TOPICS):
                steps[topic].append(m.step)
        for topic in TOPICS:
            self.assertEqual(
                steps[topic],
                list(range(n)),
                "%s: each of the %d steps once, in order (repeats: %s)"
                % (
                    topic,
                    n,
                    sorted(k for k, c in collections.Counter(steps[topic]).items() if c > 1),
                ),
            )
        sys.stderr.write(
            "held %s; bag: %s\n" % (HELD, ", ".join("%s %d" % (t, len(steps[t])) for t in TOPICS))
        )


if __name__ == "__main__":
    rospy.init_node("recorder_repeats_check")
    rostest.rosrun(PKG, "recorder_repeats", RecorderRepeatsTest, sys.argv)
