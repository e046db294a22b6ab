#!/usr/bin/env python3
"""JSBSim as the plant engine in ROS (test/ros/jsbsim.test).

case realtime: the run reaches its last step on the wall clock, the truth carries the
engine's flight outputs (pitch, airspeed, altitude, flight_path) from the trim on, the bag
holds the whole run, and the plant's JSBSim is gone once the run ended.
case killed (lockstep): the plant's JSBSim is SIGKILLed mid-run; the run ends before its last
step with one ERROR naming JSBSim, the stopped recorder names its bag .incomplete.bag, and no
JSBSim process of the plant is left.
"""
import os
import signal
import sys
import threading
import time
import unittest
import xmlrpc.client

import rospy
import rostest
from rosgraph_msgs.msg import Log
from rostest_util import signal_node, subscribe_loop, wait_for

PKG = "preadaptive_mrac"
FLIGHT = ("pitch", "airspeed", "altitude", "flight_path")


def node_pid(node):
    """The pid of a launched node's process (asked through the master and its own API)."""
    import rosgraph
    import rosnode

    caller = rospy.get_name()
    uri = rosnode.get_api_uri(rosgraph.Master(caller), node)
    return xmlrpc.client.ServerProxy(uri).getPid(caller)[2]


def jsbsim_children(ppid):
    """Pids of the live (not zombie) JSBSim processes whose parent is ppid."""
    out = []
    for d in os.listdir("/proc"):
        if not d.isdigit():
            continue
        try:
            with open("/proc/%s/stat" % d) as f:
                stat = f.read()
        except OSError:
            continue
        comm = stat[stat.index("(") + 1 : stat.rindex(")")]
        fields = stat[stat.rindex(")") + 2 :].split()
        if comm == "JSBSim" and int(fields[1]) == ppid and fields[0] != "Z":
            out.append(int(d))
    return out


class JsbsimTest(unittest.TestCase):
    def setUp(self):
        from preadaptive_mrac.msg import PlantTruth

        self.case = rospy.get_param("~case")
        self.timeout = float(rospy.get_param("~timeout", 60.0))
        self.lock = threading.Lock()
        self.states = []  # (step, total_steps)
        self.truths = []  # (step, {name: value})
        self.errors = []
        self.log_sub = rospy.Subscriber("/rosout", Log, self.on_log, queue_size=1000)
        self.truth_sub = rospy.Subscriber("plant/truth", PlantTruth, self.on_truth, queue_size=None)
        subscribe_loop(self)

    def on_state(self, msg):
        with self.lock:
            self.states.append((msg.step, msg.total_steps))

    def on_cmd(self, msg):
        pass

    def on_truth(self, msg):
        with self.lock:
            self.truths.append((msg.step, dict(zip(msg.condition_names, msg.conditions))))

    def on_log(self, msg):
        if msg.level >= Log.ERROR and "JSBSim" in msg.msg:
            with self.lock:
                self.errors.append(msg.msg)

    def last_step(self):
        with self.lock:
            return self.states[-1] if self.states else (-1, 0)

    def quiet_for(self, seconds):
        """Wait until no state has come for `seconds` (bounded by the timeout)."""
        end = time.monotonic() + self.timeout
        n, since = -1, time.monotonic()
        while time.monotonic() < end:
            with self.lock:
                if len(self.states) != n:
                    n, since = len(self.states), time.monotonic()
            if n > 0 and time.monotonic() - since > seconds:
                return
            time.sleep(0.05)
        raise AssertionError("states kept coming for %.0f s" % self.timeout)

    def test_jsbsim_run(self):
        wait_for(lambda: self.last_step()[0] >= 0, self.timeout, "the plant's first state")
        plant = node_pid(rospy.get_param("~plant_process"))
        children = jsbsim_children(plant)
        self.assertEqual(len(children), 1, "one JSBSim child of the plant's process %d" % plant)
        if self.case == "killed":
            wait_for(lambda: self.last_step()[0] >= 500, self.timeout, "step 500")
            os.kill(children[0], signal.SIGKILL)
        self.quiet_for(2.0)
        step, total = self.last_step()
        with self.lock:
            truths, errors = list(self.truths), list(self.errors)
        # What the linear model never had, on every truth, from the trim on (40,000 ft, Mach
        # 0.8: 236.06 m/s at 12,192 m, pitch = flight path angle + the trim's alpha 4.45 deg).
        self.assertTrue(truths)
        for k, c in truths:
            for name in FLIGHT:
                self.assertIn(name, c, "truth of step %d" % k)
        first = min(truths)[1]
        self.assertAlmostEqual(first["airspeed"], 236.06, delta=0.1)
        self.assertAlmostEqual(first["altitude"], 12192.0, delta=1.0)
        self.assertAlmostEqual(first["pitch"] - first["flight_path"], 0.0777, delta=0.001)
        later = max(truths)[1]
        self.assertNotEqual(later["altitude"], first["altitude"])
        bag = rospy.get_param("~bag")
        if self.case == "realtime":
            self.assertEqual(step + 1, total, "the run reached its last step")
            self.assertEqual(errors, [])
            wait_for(lambda: not jsbsim_children(plant), 10.0, "the plant's JSBSim to end")
            signal_node("/bag_recorder", signal.SIGINT, 30.0, "the recorder to close its bag")
            self.assertTrue(os.path.exists(bag), "%s: %s" % (bag, os.listdir(os.path.dirname(bag))))
            import rosbag

            with rosbag.Bag(bag) as b:
                steps = [m.step for _, m, _ in b.read_messages(topics=["/plant/state"])]
            self.assertEqual(sorted(set(steps)), list(range(total)), "the bag holds every state")
        else:
            self.assertLess(step + 1, total, "the run ended before its last step")
            self.assertGreaterEqual(step, 500)
            self.assertEqual(jsbsim_children(plant), [], "no JSBSim left")
            wait_for(lambda: bool(self.errors), 5.0, "the plant's ERROR on /rosout")
            with self.lock:
                errors = list(self.errors)
            self.assertEqual(len(errors), 1, errors)
            self.assertIn("the run ends at step", errors[0])
            self.assertIn("killed by signal 9", errors[0])
            signal_node("/bag_recorder", signal.SIGINT, 30.0, "the recorder to close its bag")
            marked = bag[: -len(".bag")] + ".incomplete.bag"
            self.assertTrue(
                os.path.exists(marked), "%s: %s" % (marked, os.listdir(os.path.dirname(bag)))
            )
        rospy.loginfo(
            "jsbsim %s: %d of %d states, last truth: %s; errors %s",
            self.case,
            step + 1,
            total,
            ", ".join("%s %.6g" % (n, later[n]) for n in FLIGHT),
            errors,
        )


if __name__ == "__main__":
    rospy.init_node("jsbsim_check")
    rostest.rosrun(PKG, "jsbsim", JsbsimTest, sys.argv)
