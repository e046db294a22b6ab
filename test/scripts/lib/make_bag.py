"""Write a small single-run bag of the package's topics (for the analysis tests).

    /usr/bin/python3 test/scripts/lib/make_bag.py OUT.bag [--nan-at STEP] [--steps N]

--nan-at STEP: the command and status of that step carry u = NaN and e = NaN (what one NaN
from `rostopic pub` puts into a recording). Needs the package's devel space sourced.
"""
import argparse
import math

import rosbag
import rospy
from preadaptive_mrac.msg import AdaptationStatus, ElevatorCommand, PlantState, PlantTruth


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('out')
    ap.add_argument('--steps', type=int, default=400)
    ap.add_argument('--nan-at', type=int, default=-1)
    a = ap.parse_args()
    dt = 0.01
    with rosbag.Bag(a.out, 'w', chunk_threshold=16 * 1024) as bag:
        for k in range(a.steps):
            t = k * dt
            stamp = rospy.Time(1.0 + t)
            alpha = 0.01 * math.sin(t)
            s = PlantState(step=k, t=t, dt=dt, total_steps=a.steps, x=[0.0, alpha, 0.0])
            s.header.stamp, s.alpha = stamp, alpha
            bag.write('/plant/state', s, stamp)
            tr = PlantTruth(step=k, theta=[0.0, 0.0, 0.0])
            tr.header.stamp = stamp
            bag.write('/plant/truth', tr, stamp)
            bad = k == a.nan_at
            st = AdaptationStatus(step=k, t=t, alpha_ref=alpha, mode='rac')
            st.header.stamp = stamp
            st.e = float('nan') if bad else 1e-4 * math.cos(t)
            st.theta_hat = [0.0, 0.0, 0.0]
            bag.write('/controller/status', st, stamp)
            c = ElevatorCommand(step=k, t=t, u=float('nan') if bad else -0.01 * alpha)
            c.header.stamp = stamp
            bag.write('/controller/elevator_cmd', c, stamp)


if __name__ == '__main__':
    main()
