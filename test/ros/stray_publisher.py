#!/usr/bin/env python3
"""A stray node for test/ros/stray_publisher.test: publishes, until shut down, on the closed
loop's own topics what a misconfigured second plant or controller might.

~kind: command -> controller/elevator_cmd, u = ~u, step = 2^~step_log2 (far ahead of the
       plant, so a realtime plant that took it would hold it against every later answer);
       state   -> plant/state, a finite state at that step (a controller that took it would
       answer it and then see the real plant's next state as a restart).
~rate: messages per second (wall clock).
Started by stray_publisher_check.py with its own node name (__name:=...), which is the caller
id the guarded nodes see.
"""
import rospy
from preadaptive_mrac.msg import ElevatorCommand, PlantState


def main():
    rospy.init_node("stray_publisher")
    kind = rospy.get_param("~kind")
    step = 1 << int(rospy.get_param("~step_log2"))  # (XML-RPC ints are 32 bits)
    rate = rospy.Rate(float(rospy.get_param("~rate", 500.0)))
    if kind == "command":
        pub = rospy.Publisher("controller/elevator_cmd", ElevatorCommand, queue_size=100)
        msg = ElevatorCommand(step=step, t=step * 0.001, u=float(rospy.get_param("~u")))
        msg.u_baseline = msg.u
    elif kind == "state":
        pub = rospy.Publisher("plant/state", PlantState, queue_size=100)
        msg = PlantState(step=step, t=step * 0.001, dt=0.001, total_steps=step + 1)
        msg.x = [0.0, 0.3, 0.0]
        msg.e_I, msg.alpha, msg.q = msg.x
        msg.r = 0.1
    else:
        raise SystemExit("~kind must be command or state, got %r" % kind)
    while not rospy.is_shutdown():
        msg.header.stamp = rospy.Time.now()
        pub.publish(msg)
        try:
            rate.sleep()
        except rospy.ROSInterruptException:
            break


if __name__ == "__main__":
    main()
