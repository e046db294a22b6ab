#!/usr/bin/env python3
"""dynamic_reconfigure of mrac_controller_node, lockstep scenario 1, pa_learn (reconfigure.test).

The test publishes the plant's recorder progress (/gate/progress), so the lockstep plant stops
about 2000 steps past what the test has released: it holds the run near step 3000, before the
first switch (5 s). There it sends through the dynamic_reconfigure client
  - c_ed = -1 (refused by the core's validation: "must be in [1e-06, 10], got -1": the value asked,
    not one the server clamped it to), and hysteresis = 0.006 >= c_e (a rule no cfg range can
    express): both answered with the old values and `refusal` naming the key and the value
    asked (what dynparam and rqt_reconfigure show), and an ERROR naming them on /rosout;
  - gamma 1e308 with c_e 1e300, c_ed 1e-300, confirm_samples 2147483647 through scripts/tune:
    refused (beyond the YAML's ranges), the client exits 2 naming each key and value;
  - c_ed = 0.015 (the paper's 0.02 misses the switches at 5 s and 20 s; 0.015 sees them).
Then it releases the plant and, after the run, closes the recorder's bag once the recorder's
progress says it holds the last step of the states, commands and statuses, and checks:
  - one ParamChange (controller.attention.c_ed, 0.02 -> 0.015) stamped with a step s in
    (1000, 5000) and t = s dt, nothing from the refused requests;
  - the commands and theta_hat of every step equal, bit for bit, the CLI run with c_ed = 0.015
    from the start (the runs cannot differ before 5 s: |e| stays below c_e there, so c_ed is
    never consulted), and differ from the CLI run with the paper's 0.02 (onset at 5.4 s).
"""
import os
import subprocess
import sys
import tempfile
import threading
import time
import unittest

import dynamic_reconfigure.client
import rosbag
import rosgraph
import rosnode
import rospy
import rostest
from catkin.find_in_workspaces import find_in_workspaces
from rosgraph_msgs.msg import Log

from preadaptive_mrac.msg import AdaptationStatus, RecorderConnections, RecorderProgress
from rostest_util import wait_for

PKG = "preadaptive_mrac"
DT = 0.001
STEPS = 60000
# The topics the test counts, each complete in the bag before it is closed.
RECORDED = ("/plant/state", "/controller/elevator_cmd", "/controller/status")


def cli_csv(extra):
    exe = find_in_workspaces(["libexec"], project=PKG, path="preadapt_sim", first_match_only=True)
    assert exe, "preadapt_sim not found"
    fd, path = tempfile.mkstemp(suffix=".csv")
    os.close(fd)
    subprocess.run(
        [exe[0], "--scenario", "1", "--mode", "pa_learn", "--seed", "1", "--csv", path] + extra,
        check=True,
        stdout=subprocess.DEVNULL,
    )
    rows = {}
    with open(path) as f:
        head = f.readline().strip().split(",")
        iu, ith = head.index("u"), [head.index("theta_hat%d" % i) for i in range(3)]
        for k, line in enumerate(f):
            c = line.strip().split(",")
            rows[k] = (float(c[iu]), tuple(float(c[i]) for i in ith))
    os.remove(path)
    return rows


class ReconfigureTest(unittest.TestCase):
    def setUp(self):
        self.lock = threading.Lock()
        self.last_step = -1
        self.rosout = []
        # The controller waits for one status subscriber (the recorder, ~min_status_subscribers):
        # this test's own must not be the one it counts, or the recorder can connect after the
        # first statuses (fresh-clone CI: the bag held 56999 of 60000). So the recorder's
        # subscriptions first (its ~progress is advertised after them), then this test's.
        wait_for(
            lambda: any(
                t == "/recorder/progress"
                for t, _ in rosgraph.Master(rospy.get_name()).getSystemState()[0]
            ),
            60,
            "the recorder's subscriptions",
            poll=0.05,
        )
        time.sleep(1.0)
        rospy.Subscriber("controller/status", AdaptationStatus, self.on_status, queue_size=1000)
        rospy.Subscriber("/rosout", Log, self.on_log, queue_size=1000)
        self.gate = rospy.Publisher("/gate/progress", RecorderProgress, queue_size=10)
        # The gate's ~connections beside its ~progress: it records no topic, so the plant does
        # not wait for it to connect to the controller's commands.
        self.gate_connections = rospy.Publisher(
            "/gate/connections", RecorderConnections, queue_size=1, latch=True
        )
        self.gate_connections.publish(RecorderConnections(topics=[], publishers=[]))
        # From the start: the recorder may write the last steps before the run is followed.
        self.recorded = {}
        rospy.Subscriber("/recorder/progress", RecorderProgress, self.on_recorded, queue_size=1000)
        self.released = 1000

    def on_status(self, m):
        with self.lock:
            self.last_step = max(self.last_step, m.step)

    def on_recorded(self, m):
        with self.lock:
            self.recorded[m.topic] = max(self.recorded.get(m.topic, -1), m.step)

    def on_log(self, m):
        with self.lock:
            self.rosout.append(m)

    def open_gate(self, step):
        p = RecorderProgress()
        p.topic = "/plant/state"
        p.step = step
        p.total_steps = STEPS
        self.gate.publish(p)

    def logged(self, text):
        with self.lock:
            return any(text in m.msg for m in self.rosout if m.level >= Log.ERROR)

    def test_reconfigure(self):
        client = dynamic_reconfigure.client.Client("/mrac_controller/reconfigure", timeout=60)
        start = client.get_configuration(timeout=10)
        self.assertAlmostEqual(start["c_ed"], 0.02, places=15)  # the YAML's value, not the cfg's
        wait_for(lambda: self.gate.get_num_connections() > 0, 60, "the plant on /gate/progress")
        # Release 1000 steps; the plant stops ~2000 (~max_recorder_lag) later and waits.
        stop = None
        end = time.monotonic() + 60
        while time.monotonic() < end:
            self.open_gate(self.released)
            with self.lock:
                s = self.last_step
            if s >= 2900:
                time.sleep(0.3)
                with self.lock:
                    if self.last_step == s:
                        stop = s
                        break
            time.sleep(0.05)
        self.assertIsNotNone(stop, "the plant did not stop at the gate")
        self.assertLess(stop, 4000)

        got = client.update_configuration({"c_ed": -1.0})
        self.assertEqual(got["c_ed"], 0.02)
        refusal = "/mrac_controller/controller/attention/c_ed: must be in [1e-06, 10], got -1"
        self.assertIn(refusal, got["refusal"])
        wait_for(lambda: self.logged(refusal), 10, "the refusal of c_ed = -1 on /rosout")
        got = client.update_configuration({"hysteresis": 0.006})
        self.assertEqual(got["hysteresis"], 0.0)
        self.assertIn("/mrac_controller/controller/attention/hysteresis", got["refusal"])
        self.assertIn("got 0.006", got["refusal"])
        wait_for(
            lambda: self.logged("/mrac_controller/controller/attention/hysteresis"),
            10,
            "the refusal of hysteresis = 0.006 on /rosout",
        )
        # Values far outside the safe ranges (the YAML's), through the package's own client:
        # refused, exit 2, each key and value named; nothing changes (no ParamChange).
        tune = find_in_workspaces(["libexec"], project=PKG, path="tune", first_match_only=True)
        self.assertTrue(tune, "scripts/tune not found")
        for pairs, named in (
            (
                ["gamma=1e308", "c_e=1e300"],
                ["adaptation/gamma", "got 1e+308", "attention/c_e", "got 1e+300"],
            ),
            (["c_ed=1e-300"], ["attention/c_ed", "got 1e-300"]),
            (["confirm_samples=2147483647"], ["attention/confirm_samples", "got 2147483647"]),
        ):
            p = subprocess.run(
                [tune[0], "--timeout", "10"] + pairs,
                stderr=subprocess.PIPE,
                universal_newlines=True,
            )
            self.assertEqual(p.returncode, 2, p.stderr)
            for n in named:
                self.assertIn(n, p.stderr)
        got = client.update_configuration({"c_ed": 0.015})
        self.assertEqual(got["c_ed"], 0.015)
        self.assertEqual(got["refusal"], "")

        # Release the rest: follow the status, so the gate never holds the plant again.
        end = time.monotonic() + 300
        while time.monotonic() < end:
            with self.lock:
                s = self.last_step
            self.open_gate(max(s, self.released))
            if s >= STEPS - 1:
                break
            time.sleep(0.02)
        self.assertEqual(self.last_step, STEPS - 1)
        self.open_gate(STEPS - 1)

        # Close the bag: stop the recorder once it has written the last step of the states and
        # of the controller's commands and statuses. Those come on connections of their own,
        # from another node, and under load lag far behind the states (a bag closed at the
        # last state held 45480 of the 60000 commands and 25481 statuses).
        bag_path = rospy.get_param("~bag")

        def recorded():
            with self.lock:
                return all(self.recorded.get(t, -1) >= STEPS - 1 for t in RECORDED)

        try:
            wait_for(recorded, 120, "the recorder's last step of " + ", ".join(RECORDED))
        except AssertionError as e:
            with self.lock:
                raise AssertionError("%s; the recorder's last steps: %r" % (e, self.recorded))
        rosnode.kill_nodes(["/recorder"])
        wait_for(lambda: os.path.exists(bag_path), 60, "the closed bag " + bag_path)

        changes, cmds, ths = [], {}, {}
        with rosbag.Bag(bag_path) as bag:
            for topic, m, _ in bag.read_messages():
                if topic == "/controller/param_change":
                    changes.append(m)
                elif topic == "/controller/elevator_cmd" and not m.stale:
                    cmds[m.step] = m.u
                elif topic == "/controller/status":
                    ths[m.step] = tuple(m.theta_hat)
        self.assertEqual(len(changes), 1, [(c.name, c.step) for c in changes])
        c = changes[0]
        self.assertEqual(c.name, "controller.attention.c_ed")
        self.assertEqual((c.old_value, c.new_value), (0.02, 0.015))
        self.assertGreater(c.step, 1000)
        self.assertLess(c.step, 5000)
        self.assertEqual(c.t, c.step * DT)
        print("c_ed changed at step %d (t = %.3f s)" % (c.step, c.t))

        self.assertEqual(len(cmds), STEPS)
        self.assertEqual(len(ths), STEPS)
        new = cli_csv(["--set", "controller.attention.c_ed=0.015"])
        old = cli_csv([])
        # %.17g in the CSV round-trips doubles exactly: equality is bit for bit.
        bad = [k for k in range(STEPS) if (cmds[k], ths[k]) != new[k]]
        self.assertEqual(bad[:5], [], "%d steps differ from the CLI with c_ed = 0.015" % len(bad))
        differ = [k for k in range(STEPS) if (cmds[k], ths[k]) != old[k]]
        self.assertTrue(differ, "the change had no effect")
        self.assertGreater(differ[0], c.step)
        print(
            "%d steps equal the CLI with c_ed = 0.015; first difference from the paper's "
            "c_ed at step %d" % (STEPS, differ[0])
        )


if __name__ == "__main__":
    rospy.init_node("reconfigure_check")
    rostest.rosrun(PKG, "reconfigure", ReconfigureTest, sys.argv)
