#!/usr/bin/python3
"""Compare a lockstep bag with the batch CLI's CSV for the same scenario, mode, seed and dt.

    bag_vs_cli.py BAG CSV [--ns /rac]

Checks that every step 0..N-1 is in the bag exactly once on plant/state and
controller/status, and prints the largest differences of alpha (plant/state) and theta_hat
(controller/status) against the CSV. Exit code 1 when a step is missing or a difference
exceeds 1e-9; 2 when the bag lacks either topic (a namespaced bag without --ns: the message
names the namespaces found). Run with /usr/bin/python3: it needs the ROS python modules.
"""
import argparse
import csv
import sys

import rosbag


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('bag')
    ap.add_argument('csv')
    ap.add_argument('--ns', default='', help='namespace of the pair, e.g. /rac')
    ap.add_argument('--tol', type=float, default=1e-9)
    a = ap.parse_args()

    with open(a.csv) as f:
        rows = list(csv.DictReader(f))
    n = len(rows)
    alpha_cli = [float(r['x1']) for r in rows]
    th_cli = [[float(r['theta_hat%d' % i]) for i in range(3)] for r in rows]

    state_t, status_t = a.ns + '/plant/state', a.ns + '/controller/status'
    alpha = [None] * n
    th = [None] * n
    dup = 0
    with rosbag.Bag(a.bag) as bag:
        # Topics that are not in the bag at all are a wrong --ns (or bag), not missing steps.
        topics = sorted(bag.get_type_and_topic_info().topics)
        absent = [t for t in (state_t, status_t) if t not in topics]
        if absent:
            found = sorted(
                {t[: -len('/plant/state')] for t in topics if t.endswith('/plant/state')}
            )
            hint = ' (try %s)' % ', '.join('--ns ' + ns for ns in found if ns) if found else ''
            print(
                'bag_vs_cli: %s not in %s%s; its topics: %s'
                % (' and '.join(absent), a.bag, hint, ', '.join(topics) or 'none'),
                file=sys.stderr,
            )
            return 2
        for topic, msg, _ in bag.read_messages(topics=[state_t, status_t]):
            k = msg.step
            if k >= n:
                continue
            if topic == state_t:
                dup += alpha[k] is not None
                alpha[k] = msg.alpha
            else:
                dup += th[k] is not None
                th[k] = list(msg.theta_hat)
    missing_state = sum(v is None for v in alpha)
    missing_status = sum(v is None for v in th)
    ok = missing_state == 0 and missing_status == 0 and dup == 0
    d_alpha = max((abs(x - y) for x, y in zip(alpha, alpha_cli) if x is not None), default=0.0)
    d_th = max(
        (abs(p - q) for u, v in zip(th, th_cli) if u is not None for p, q in zip(u, v)), default=0.0
    )
    ok = ok and d_alpha <= a.tol and d_th <= a.tol
    print(
        'steps %d; missing state %d, status %d; duplicates %d; max |diff| alpha %.3g, '
        'theta_hat %.3g -> %s'
        % (n, missing_state, missing_status, dup, d_alpha, d_th, 'EQUAL' if ok else 'DIFFERENT')
    )
    return 0 if ok else 1


if __name__ == '__main__':
    sys.exit(main())
