#!/usr/bin/env python3
"""Realtime closed loop: no lost state, every state answered once and in order.

Subscribes to plant/state and controller/elevator_cmd (unbounded receive queues) while the
plant ticks on the wall clock, until `~states` consecutive states after the first answer seen
are in, then waits (bounded by `~timeout`, wall time) for their answers. Asserts:
  - the states arrive with consecutive step numbers (no loss, no reordering);
  - each of those states gets exactly one answer (a command that is not a staleness-timer
    command), the answers come in increasing step order, and each carries its state's time;
  - no answer is for a step the plant never published.
Nothing here measures a rate or a latency: under load the answers may come late, which is
allowed (the realtime plant holds the last command); losing or reordering one is not.
"""
import sys
import threading
import unittest

import rospy
import rostest
from rostest_util import subscribe_loop, wait_for

PKG = "preadaptive_mrac"


class RealtimeAnswersTest(unittest.TestCase):
    def setUp(self):
        self.want = int(rospy.get_param("~states", 3000))
        self.timeout = float(rospy.get_param("~timeout", 120.0))
        self.lock = threading.Lock()
        self.states = []  # (step, t) in arrival order
        self.answers = []  # (step, t) of answers (not stale-timer commands), in arrival order
        self.stale = 0
        # Commands first, so that the command connection is up before the plant starts (it
        # waits for this node's state subscription: state_watchers:=1).
        subscribe_loop(self)

    def on_state(self, msg):
        with self.lock:
            self.states.append((msg.step, msg.t))

    def on_cmd(self, msg):
        with self.lock:
            if msg.stale:
                self.stale += 1
            else:
                self.answers.append((msg.step, msg.t))

    def snapshot(self):
        with self.lock:
            return list(self.states), list(self.answers)

    def window(self):
        """Steps [first, first + want) from the first answered step on, or None yet."""
        states, answers = self.snapshot()
        if not answers:
            return None
        first = answers[0][0]
        return first, first + self.want

    def test_every_state_answered_in_order(self):
        def have_states():
            w = self.window()
            return w is not None and any(s >= w[1] - 1 for s, _ in self.snapshot()[0])

        wait_for(have_states, self.timeout, "%d states after the first answer" % self.want)
        first, end = self.window()

        def answered_through():
            return any(s >= end - 1 for s, _ in self.snapshot()[1])

        wait_for(answered_through, self.timeout, "the answer to step %d" % (end - 1))
        states, answers = self.snapshot()

        # No lost or reordered state: consecutive steps from the first one received.
        steps = [s for s, _ in states]
        gaps = [(a, b) for a, b in zip(steps, steps[1:]) if b != a + 1]
        self.assertEqual(gaps, [], "plant/state steps not consecutive (lost or reordered)")
        t_of = dict(states)

        # Answers: strictly increasing steps, each a published state, with that state's time.
        a_steps = [s for s, _ in answers]
        backwards = [(a, b) for a, b in zip(a_steps, a_steps[1:]) if b <= a]
        self.assertEqual(backwards, [], "answers out of order or repeated")
        unknown = [s for s in a_steps if s not in t_of and s >= steps[0]]
        self.assertEqual(unknown, [], "answers to steps the plant never published")
        wrong_t = [(s, t, t_of[s]) for s, t in answers if s in t_of and t != t_of[s]]
        self.assertEqual(wrong_t, [], "answer time differs from its state's time")

        # Every state of the window answered exactly once.
        in_window = [s for s in a_steps if first <= s < end]
        missing = sorted(set(range(first, end)) - set(in_window))
        self.assertEqual(missing[:20], [], "%d state(s) never answered" % len(missing))
        self.assertEqual(len(in_window), self.want)
        rospy.loginfo(
            "realtime_answers: %d states (steps %d..%d) answered in order; %d stale-timer "
            "command(s) meanwhile",
            self.want,
            first,
            end - 1,
            self.stale,
        )


if __name__ == "__main__":
    rospy.init_node("realtime_answers_check")
    rostest.rosrun(PKG, "realtime_answers", RealtimeAnswersTest, sys.argv)
