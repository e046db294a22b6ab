#!/usr/bin/env python3
"""Faults survived, realtime (wall clock), short scenario (test/ros/config/fault_scenario.yaml).
The test starts plant_sim_node and mrac_controller_node itself (rosrun; parameters set by
faults.test) so it can SIGKILL and restart them:

(b) plant killed mid-run -> the controller detects stale input within ~stale_timeout and
    publishes safe, stale-flagged commands (-K x_last) at its sample rate; /diagnostics says
    stale. Plant restarted -> the controller sees step 0 (reset, "plant restarts" counted)
    and answers with normal commands again.
(a) controller killed mid-run after a learning episode (weights saved) -> the plant holds trim
    (published elevator 0 after ~cmd_timeout); controller restarted with ~weights_in = the
    ~weights_out it saved -> it reports the same episode count (it continues from the weights it
    saved last), commands resume, and the plant runs the scenario to its end (exit code 0).
Every wait is bounded.
"""
import os
import sys
import time

import rospy

from rostest_util import NodeProcessTest, read_episodes, wait_for
import rostest
from diagnostic_msgs.msg import DiagnosticArray
from preadaptive_mrac.msg import AdaptationStatus, ElevatorCommand, PlantState

PKG = "preadaptive_mrac"


class FaultsTest(NodeProcessTest):
    def setUp(self):
        super().setUp()
        self.cmds, self.states, self.status, self.diag = [], [], [], []
        rospy.Subscriber(
            "controller/elevator_cmd",
            ElevatorCommand,
            lambda m: self.add(self.cmds, m),
            queue_size=100000,
            tcp_nodelay=True,
        )
        rospy.Subscriber(
            "plant/state",
            PlantState,
            lambda m: self.add(self.states, m),
            queue_size=100000,
            tcp_nodelay=True,
        )
        rospy.Subscriber(
            "controller/status",
            AdaptationStatus,
            lambda m: self.add(self.status, m),
            queue_size=100000,
        )
        rospy.Subscriber("/diagnostics", DiagnosticArray, self.on_diag, queue_size=1000)
        self.weights = rospy.get_param("/mrac_controller/weights_out")
        if os.path.exists(self.weights):
            os.remove(self.weights)

    def on_diag(self, msg):
        for s in msg.status:
            if "mrac_controller" in s.name:
                self.add(self.diag, s)

    @staticmethod
    def value(status, key):
        return next((kv.value for kv in status.values if kv.key == key), None)

    def test_controller_and_plant_restarts(self):
        ctl = self.start("mrac_controller_node", "mrac_controller")
        plant = self.start("plant_sim_node", "plant_sim")
        wait_for(lambda: len(self.after(self.cmds, 0)) > 500, 60.0, "the loop to run")

        # (b) plant killed: stale safe commands, then recovery after the restart.
        t_kill = self.kill(plant)
        wait_for(
            lambda: sum(1 for m in self.after(self.cmds, t_kill) if m.stale) > 100,
            10.0,
            "stale safe commands after the plant died",
        )
        stale = [m for m in self.after(self.cmds, t_kill) if m.stale]
        self.assertTrue(all(m.safe and m.u_adaptive == 0.0 for m in stale))
        self.assertEqual(len({m.u for m in stale}), 1, "one value: -K x_last held")
        wait_for(
            lambda: any(self.value(d, "stale") == "True" for d in self.after(self.diag, t_kill)),
            10.0,
            "/diagnostics to report stale",
        )
        t_restart = time.monotonic()
        plant = self.start("plant_sim_node", "plant_sim")
        wait_for(
            lambda: sum(1 for m in self.after(self.cmds, t_restart) if not m.safe) > 200,
            30.0,
            "normal commands after the plant restarted",
        )
        wait_for(
            lambda: any(
                self.value(d, "plant restarts") == "1" and self.value(d, "stale") == "False"
                for d in self.after(self.diag, t_restart)
            ),
            10.0,
            "/diagnostics to report the restart and recovery",
        )

        # (a) controller killed after a learning episode: trim, then resume from its weights.
        wait_for(
            lambda: any(s.episodes >= 1 for s in self.after(self.status, t_restart)),
            30.0,
            "a learning episode",
        )
        wait_for(
            lambda: os.path.exists(self.weights) and (read_episodes(self.weights) or 0) >= 1,
            10.0,
            "the weights saved after the episode",
        )
        t_kill = self.kill(ctl)
        saved = read_episodes(self.weights)
        wait_for(
            lambda: any(m.elevator == 0.0 for m in self.after(self.states, t_kill + 0.05)),
            10.0,
            "the plant to hold trim",
        )
        wait_for(
            lambda: len(self.after(self.states, t_kill + 0.2)) >= 50,
            10.0,
            "states while the controller is down",
        )
        tail = self.after(self.states, t_kill + 0.2)
        self.assertTrue(tail and all(m.elevator == 0.0 for m in tail[-20:]), "trim held")
        rospy.set_param("/mrac_controller/weights_in", self.weights)
        t_ctl = time.monotonic()
        ctl = self.start("mrac_controller_node", "mrac_controller")
        wait_for(
            lambda: len(self.after(self.status, t_ctl)) > 100,
            30.0,
            "the restarted controller to run",
        )
        self.assertGreaterEqual(
            self.after(self.status, t_ctl)[0].episodes,
            saved,
            "the restarted controller continues from the saved episodes",
        )
        wait_for(
            lambda: any(m.elevator != 0.0 for m in self.after(self.states, t_ctl)),
            10.0,
            "commands applied again",
        )

        # The restarted plant runs the scenario to its end.
        end = time.monotonic() + 60.0
        while plant.poll() is None and time.monotonic() < end:
            time.sleep(0.05)
        self.assertEqual(plant.poll(), 0, "the plant completes the scenario (exit 0)")
        last = self.after(self.states, 0)[-1]
        self.assertEqual(last.step + 1, last.total_steps)


if __name__ == "__main__":
    rospy.init_node("faults_check")
    rostest.rosrun(PKG, "faults", FaultsTest, sys.argv)
