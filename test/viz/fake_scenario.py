#!/usr/bin/python3
"""Interim stand-in for the package's plant and controller nodes, for the rviz test when
the real scenario cannot be launched (package not built or not on ROS_PACKAGE_PATH).

Publishes, like plant_sim_node + mrac_controller_node in realtime mode, the fixture closed
loop of synthetic.py (mode pa, theta switches): plant/state, plant/truth,
controller/status, controller/elevator_cmd, controller/attention (message classes made
from msg/*.msg at run time) and tf world -> body (pitched by theta_pitch) -> velocity
(rotated by alpha), with the same conventions as src/ros/plant_sim_node.cpp. Stamps are
wall time, the `t` fields simulation time. Loops the run until shut down.

    fake_scenario.py [--speed 1.0] [--world world --body body --velocity velocity]
"""

import argparse
import math
import os
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import synthetic  # noqa: E402


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('--speed', type=float, default=1.0, help='simulation seconds per wall second')
    ap.add_argument('--world', default='world')
    ap.add_argument('--body', default='body')
    ap.add_argument('--velocity', default='velocity')
    ap.add_argument('--mode', default='pa')
    args = ap.parse_args([a for a in sys.argv[1:] if not a.startswith('__')])

    import rospy
    from geometry_msgs.msg import TransformStamped, Quaternion

    rospy.init_node('fake_scenario')
    classes = synthetic.load_msg_classes()
    sim = synthetic.simulate(args.mode)
    msgs = list(synthetic.make_messages(sim, classes))
    pubs = {}
    for rel, cls in (
        ('plant/state', 'PlantState'),
        ('plant/truth', 'PlantTruth'),
        ('controller/status', 'AdaptationStatus'),
        ('controller/elevator_cmd', 'ElevatorCommand'),
        ('controller/attention', 'AttentionEvent'),
    ):
        pubs[rel] = rospy.Publisher(rel, classes[cls], queue_size=1000)
    tfb = rospy.Publisher('/tf', synthetic.tf_message_class(), queue_size=100)

    def q_y(angle):
        return Quaternion(0.0, math.sin(0.5 * angle), 0.0, math.cos(0.5 * angle))

    rospy.loginfo(
        'fake_scenario: %d messages, %.1f s of simulation, looping' % (len(msgs), sim['t'][-1])
    )
    time.sleep(0.5)
    while not rospy.is_shutdown():
        wall0 = time.monotonic()
        for rel, msg, t in msgs:
            delay = wall0 + t / args.speed - time.monotonic()
            if delay > 0:
                time.sleep(delay)
            if rospy.is_shutdown():
                return
            now = rospy.Time.now()
            msg.header.stamp = now
            try:
                pubs[rel].publish(msg)
            except rospy.ROSException:
                return
            if rel == 'plant/state':
                tfs = []
                for parent, child, ang in (
                    (args.world, args.body, -msg.theta_pitch),
                    (args.body, args.velocity, msg.alpha),
                ):
                    tr = TransformStamped()
                    tr.header.stamp = now
                    tr.header.frame_id = parent
                    tr.child_frame_id = child
                    tr.transform.rotation = q_y(ang)
                    tfs.append(tr)
                tfb.publish(transforms=tfs)


if __name__ == '__main__':
    main()
