#!/usr/bin/python3
"""Test fixtures for the analysis and rviz tests: a small closed loop and writers for
bags and CSV files in the formats the package's nodes and batch CLI produce.

This is NOT the package's controller (that is the C++ core). It is an independent,
deliberately simple implementation of docs/spec.md's plant, LQR baseline, MRAC law, dirty
derivative and attention function, plus a fixed random "preadaptation" reset (mode pa,
no learning) and, in mode pa_robust, made-up verification decisions (every kind, with
scores) on onsets and as DECISION events after them, so that the tests get data with the
real structure (theta switches, onsets, recoveries, resets, decisions) without needing
the C++ build. Everything the analysis must
find (switch times, peaks, event counts) is recomputed by the tests from the arrays
returned here, never typed in.
"""

import csv
import json
import math
import os
import shutil

import numpy as np
import scipy.linalg

PKG_DIR = os.path.abspath(os.path.join(os.path.dirname(__file__), '..', '..'))
MSG_DIR = os.path.join(PKG_DIR, 'msg')

# docs/spec.md plant
A = np.array([[0.0, 1.0, 0.0], [0.0, -0.32, 0.86], [0.0, -0.93, -0.43]])
B = np.array([0.0, -0.02, -1.16])
B1R = np.array([-1.0, 0.0, 0.0])

EVENT_NAMES = {0: 'onset', 1: 'recovered', 2: 'ignored_onset', 3: 'ignored_recovery', 4: 'decision'}
DECISION_KINDS = ('keep', 'fit', 'memory', 'network')  # AttentionEvent.decision_code 1..4
NO_DECISION = {
    'decision': '',
    'decision_code': 0,
    'chosen': -1,
    'candidates': 0,
    'score': 0.0,
    'score_keep': 0.0,
}
# The AttentionEvent fields added with pa_robust: a bag recorded before has none of them.
DECISION_MSG_LINES = (
    'DECISION',
    'decision',
    'decision_code',
    'chosen',
    'candidates',
    'score',
    'score_keep',
)


def legacy_attention_text(text):
    """AttentionEvent.msg as it was before pa_robust: without the DECISION type and the
    decision fields (what an old bag stores)."""
    keep = []
    for line in text.splitlines():
        words = line.split('#')[0].replace('=', ' ').split()
        if len(words) >= 2 and (words[1] in DECISION_MSG_LINES or words[1].startswith('DECISION_')):
            continue
        keep.append(line)
    return '\n'.join(keep) + '\n'


def load_msg_classes(msg_dir=MSG_DIR, legacy_attention=False):
    """Message classes generated at run time from msg/*.msg (no build needed); with
    legacy_attention, AttentionEvent without the pa_robust fields (an old bag's)."""
    import genpy.dynamic
    import std_msgs.msg

    classes = {}
    sep = '\n' + '=' * 80 + '\n'
    for name in (
        'PlantState',
        'PlantTruth',
        'ElevatorCommand',
        'AttentionEvent',
        'AdaptationStatus',
    ):
        with open(os.path.join(msg_dir, name + '.msg')) as f:
            text = f.read()
        if legacy_attention and name == 'AttentionEvent':
            text = legacy_attention_text(text)
        full = text + sep + 'MSG: std_msgs/Header\n' + std_msgs.msg.Header._full_text
        core = 'preadaptive_mrac/' + name
        classes[name] = genpy.dynamic.generate_dynamic(core, full)[core]
    return classes


def tf_message_class():
    """tf2_msgs/TFMessage from geometry_msgs' definition (no python3-tf2-ros needed)."""
    import genpy.dynamic
    from geometry_msgs.msg import TransformStamped

    full = (
        'geometry_msgs/TransformStamped[] transforms\n'
        + '=' * 80
        + '\nMSG: geometry_msgs/TransformStamped\n'
        + TransformStamped._full_text
    )
    return genpy.dynamic.generate_dynamic('tf2_msgs/TFMessage', full)['tf2_msgs/TFMessage']


def theta_schedule(switches, scales):
    """scales[i] holds until switches[i] (exclusive); scales[-1] after the last switch."""
    assert len(scales) == len(switches) + 1

    def theta(t):
        for s, c in zip(switches, scales):
            if t < s - 1e-12:
                return c
        return scales[-1]

    return theta


def simulate(
    mode='rac',
    switches=(3.0, 10.0, 17.0),
    scales=(0.1, 4.0, 10.0, 1.0),
    t_end=24.0,
    dt=0.002,
    r=0.1,
    gamma=10.0,
    c_e=0.005,
    c_ed=0.02,
    tau=0.01,
    seed=1,
    init_scale=1.0,
    decimate=5,
    decision_every=5,
    decision_count=3,
):
    """Run the fixture closed loop. Returns a dict of arrays sampled every `decimate`
    steps (t, x, xr, e, e_dot, u, u_bl, u_ad, theta_hat, theta, phase, theta_pitch) and
    the list of attention events (every step is evaluated, so no event is lost by the
    decimation).

    Mode pa_robust (a stand-in, not the core's algorithm): an onset resets like pa and
    carries the decision network; then `decision_count` DECISION events follow, one every
    `decision_every` steps while no attention event happens, cycling through keep, fit
    and memory, each but keep moving theta_hat half way to the true theta; score_keep is
    |e| + 0.01 and score a fraction of it (equal for keep)."""
    K = scipy.linalg.solve_continuous_are(A, B.reshape(3, 1), np.eye(3), np.eye(1))
    K = (B.reshape(1, 3) @ K).ravel()  # R = 1: K = B^T P_care
    Ar = A - np.outer(B, K)
    P = scipy.linalg.solve_continuous_lyapunov(Ar.T, -np.eye(3))
    PB = P @ B
    rng = np.random.default_rng(seed)
    V = rng.uniform(-init_scale, init_scale, (2, 3))
    W = rng.uniform(-init_scale, init_scale, (3, 3))
    th_fn = theta_schedule(list(switches), list(scales))

    x = np.zeros(3)
    xr = np.zeros(3)
    th_hat = np.zeros(3)
    e_prev = 0.0
    e_dot = 0.0
    s_prev = -c_e
    phase = False
    phase_cost = 0.0
    episodes = 0
    theta_pitch = x[1]
    decisions_made = 0  # DECISION events so far
    decisions_due = []  # steps of the pending DECISION events
    n = int(round(t_end / dt))
    out = {
        k: []
        for k in (
            't',
            'x',
            'xr',
            'e',
            'e_dot',
            'u',
            'u_bl',
            'u_ad',
            'theta_hat',
            'theta',
            'phase',
            'theta_pitch',
            'step',
        )
    }
    events = []
    for k in range(n + 1):
        t = k * dt
        c = th_fn(t)
        theta = c * np.ones(3)
        e = x[1] - xr[1]
        if k > 0:
            e_dot += (dt / (tau + dt)) * ((e - e_prev) / dt - e_dot)
        e_prev = e
        s = abs(e) - c_e
        ev = None
        if s_prev < 0.0 <= s and abs(e_dot) > c_ed:
            ev = 2 if phase else 0
        elif s_prev > 0.0 >= s and abs(e_dot) < c_ed:
            ev = 1 if phase else 3
        s_prev = s
        if ev is None and decisions_due and decisions_due[0] <= k:
            decisions_due.pop(0)
            ev = 4
        if ev is not None:
            before = th_hat.copy()
            reset = False
            cost = 0.0
            dec = dict(NO_DECISION)
            if ev == 0:
                phase = True
                phase_cost = 0.0
                if mode != 'rac':
                    z = np.array([e, abs(e_dot)])
                    sig = 1.0 / (1.0 + np.exp(-(V.T @ z)))
                    th_hat = W.T @ sig
                    reset = True
                if mode == 'pa_robust':
                    decisions_due = [k + decision_every * (j + 1) for j in range(decision_count)]
            elif ev == 1:
                phase = False
                cost = phase_cost
                decisions_due = []
            if mode == 'pa_robust' and ev in (0, 4):
                kind = 'network' if ev == 0 else ('keep', 'fit', 'memory')[decisions_made % 3]
                if ev == 4:
                    decisions_made += 1
                    if kind != 'keep':
                        th_hat = 0.5 * (th_hat + theta)
                        reset = True
                score_keep = abs(e) + 0.01
                dec = {
                    'decision': kind,
                    'decision_code': DECISION_KINDS.index(kind) + 1,
                    'chosen': decisions_made % 2 if kind == 'memory' else -1,
                    'candidates': 2 + decisions_made % 4,
                    'score': score_keep if kind == 'keep' else score_keep / (2.0 + decisions_made),
                    'score_keep': score_keep,
                }
            d = {
                'type': ev,
                'type_name': EVENT_NAMES[ev],
                't': t,
                'step': k,
                'e': e,
                'e_dot_est': e_dot,
                'theta_hat_before': before,
                'theta_hat_after': th_hat.copy(),
                'reset': reset,
                'cost': cost,
                'grad': [],
                'learned': False,
                'episodes': episodes,
            }
            d.update(dec)
            events.append(d)
        u_bl = -K @ x
        u_ad = -th_hat @ x
        u = u_bl + u_ad
        if k % decimate == 0:
            for key, val in (
                ('t', t),
                ('x', x.copy()),
                ('xr', xr.copy()),
                ('e', e),
                ('e_dot', e_dot),
                ('u', u),
                ('u_bl', u_bl),
                ('u_ad', u_ad),
                ('theta_hat', th_hat.copy()),
                ('theta', theta),
                ('phase', int(phase)),
                ('theta_pitch', theta_pitch),
                ('step', k),
            ):
                out[key].append(val)
        if k == n:
            break

        # RK4 over [t, t+dt] of (x, xr, th_hat), theta and u's structure held.
        def f(xx, xxr, thh):
            uu = -K @ xx - thh @ xx
            dx = A @ xx + B * (theta @ xx + uu) + B1R * r
            dxr = Ar @ xxr + B1R * r
            dth = gamma * xx * ((xx - xxr) @ PB)
            return dx, dxr, dth

        k1 = f(x, xr, th_hat)
        k2 = f(x + 0.5 * dt * k1[0], xr + 0.5 * dt * k1[1], th_hat + 0.5 * dt * k1[2])
        k3 = f(x + 0.5 * dt * k2[0], xr + 0.5 * dt * k2[1], th_hat + 0.5 * dt * k2[2])
        k4 = f(x + dt * k3[0], xr + dt * k3[1], th_hat + dt * k3[2])
        x = x + dt / 6.0 * (k1[0] + 2 * k2[0] + 2 * k3[0] + k4[0])
        xr = xr + dt / 6.0 * (k1[1] + 2 * k2[1] + 2 * k3[1] + k4[1])
        th_hat = th_hat + dt / 6.0 * (k1[2] + 2 * k2[2] + 2 * k3[2] + k4[2])
        theta_pitch = x[1]  # the plant node: a level flight path, the nose at alpha
        if phase:
            phase_cost += abs(e) * dt
    res = {k: np.array(v) for k, v in out.items()}
    res['events'] = events
    res['mode'] = mode
    res['dt'] = dt
    res['total_steps'] = n + 1
    res['switches'] = list(switches)
    res['scales'] = list(scales)
    return res


def _set_opt(msg, **fields):
    """Set fields that the current msg/*.msg define (t, dt, total_steps were added later)."""
    for k, v in fields.items():
        if k in msg.__slots__:
            setattr(msg, k, v)


def make_messages(sim, classes):
    """Yield (relative topic, message, t) in time order for a simulation result."""
    import rospy

    PlantState = classes['PlantState']
    PlantTruth = classes['PlantTruth']
    Elevator = classes['ElevatorCommand']
    Attention = classes['AttentionEvent']
    Status = classes['AdaptationStatus']
    ev_iter = iter(sim['events'])
    next_ev = next(ev_iter, None)
    for i, t in enumerate(sim['t']):
        stamp = rospy.Time.from_sec(float(t))
        step = int(sim['step'][i])
        while next_ev is not None and next_ev['t'] <= t + 1e-12:
            ev = next_ev
            m = Attention()
            m.header.stamp = rospy.Time.from_sec(ev['t'])
            m.type = ev['type']
            m.type_name = ev['type_name']
            m.step = ev['step']
            _set_opt(m, t=float(ev['t']))
            m.e = ev['e']
            m.e_dot_est = ev['e_dot_est']
            m.theta_hat_before = list(ev['theta_hat_before'])
            m.theta_hat_after = list(ev['theta_hat_after'])
            m.reset = ev['reset']
            m.cost = ev['cost']
            m.grad = list(ev['grad'])
            m.learned = ev['learned']
            m.episodes = ev['episodes']
            # the pa_robust fields (not in a legacy AttentionEvent class)
            _set_opt(m, **{k: ev.get(k, v) for k, v in NO_DECISION.items()})
            yield 'controller/attention', m, ev['t']
            next_ev = next(ev_iter, None)
        x = sim['x'][i]
        ps = PlantState()
        ps.header.stamp = stamp
        ps.header.frame_id = 'body'
        ps.step = step
        _set_opt(ps, t=float(t), dt=float(sim['dt']), total_steps=int(sim['total_steps']))
        ps.x = list(x)
        ps.e_I, ps.alpha, ps.q = float(x[0]), float(x[1]), float(x[2])
        ps.theta_pitch = float(sim['theta_pitch'][i])
        ps.r = 0.1
        ps.elevator = float(sim['u'][i - 1]) if i > 0 else 0.0
        yield 'plant/state', ps, t
        tr = PlantTruth()
        tr.header.stamp = stamp
        tr.step = step
        tr.theta = list(sim['theta'][i])
        tr.theta_scale = float(sim['theta'][i][0])
        # a run that left the flight envelope at sample sim['envelope_step']
        if i >= sim.get('envelope_step', len(sim['t'])):
            _set_opt(
                tr,
                envelope_bound=sim['envelope_bound'],
                envelope_exit_t=float(sim['t'][sim['envelope_step']]),
                envelope_exit=sim['envelope_text'],
            )
        yield 'plant/truth', tr, t
        st = Status()
        st.header.stamp = stamp
        st.step = step
        _set_opt(st, t=float(t))
        st.x_ref = list(sim['xr'][i])
        st.alpha_ref = float(sim['xr'][i][1])
        st.e = float(sim['e'][i])
        st.e_dot_est = float(sim['e_dot'][i])
        th = sim['theta_hat'][i]
        st.theta_hat = list(th)
        st.theta_hat_0, st.theta_hat_1, st.theta_hat_2 = (float(v) for v in th)
        st.phase_active = bool(sim['phase'][i])
        st.mode = sim['mode']
        st.episodes = 0
        yield 'controller/status', st, t
        el = Elevator()
        el.header.stamp = stamp
        el.step = step
        _set_opt(el, t=float(t))
        el.u = float(sim['u'][i])
        el.u_baseline = float(sim['u_bl'][i])
        el.u_adaptive = float(sim['u_ad'][i])
        yield 'controller/elevator_cmd', el, t


def write_bag(path, runs, classes=None, skip_topics=(), t0_wall=1000.0):
    """Write a bag. runs: {namespace: sim}; namespace '' for a single-run bag, 'rac'/'pa'
    for a compare bag. Topics in skip_topics (relative, e.g. 'plant/truth') are left out.
    Messages are written in time order, with bag time = t0_wall + sim time."""
    import rosbag
    import rospy

    classes = classes or load_msg_classes()
    streams = []
    for ns, sim in runs.items():
        prefix = '/' + ns + '/' if ns else '/'
        for rel, msg, t in make_messages(sim, classes):
            if rel in skip_topics:
                continue
            streams.append((t, prefix + rel, msg))
    streams.sort(key=lambda s: s[0])
    with rosbag.Bag(path, 'w') as bag:
        for t, topic, msg in streams:
            bag.write(topic, msg, rospy.Time.from_sec(t0_wall + t))
    return path


def write_unindexed_bag(path, sim, classes=None):
    """What a killed `rosbag record` leaves: chunks on disk, no index (header index_pos
    = 0). Written by copying the file while the writer is still open."""
    import rosbag
    import rospy

    classes = classes or load_msg_classes()
    tmp = path + '.writing'
    bag = rosbag.Bag(tmp, 'w', chunk_threshold=4096)
    for rel, msg, t in make_messages(sim, classes):
        bag.write('/' + rel, msg, rospy.Time.from_sec(1000.0 + t))
    bag._file.flush()
    shutil.copyfile(tmp, path)
    bag.close()
    os.remove(tmp)
    return path


CSV_HEADER = [
    't',
    'x0',
    'x1',
    'x2',
    'xr0',
    'xr1',
    'xr2',
    'e',
    'e_dot_est',
    'u',
    'theta_hat0',
    'theta_hat1',
    'theta_hat2',
    'theta_true0',
    'theta_true1',
    'theta_true2',
    'phase',
]


def write_csv(path, sim, json_path=None, windows=True):
    """The batch CLI's CSV; with json_path, also its `--json` summary line (events)."""
    with open(path, 'w', newline='') as f:
        w = csv.writer(f)
        w.writerow(CSV_HEADER)
        for i, t in enumerate(sim['t']):
            row = [
                t,
                *sim['x'][i],
                *sim['xr'][i],
                sim['e'][i],
                sim['e_dot'][i],
                sim['u'][i],
                *sim['theta_hat'][i],
                *sim['theta'][i],
                sim['phase'][i],
            ]
            w.writerow(['%.9g' % v for v in row])
    if json_path:
        evs = []
        for ev in sim['events']:
            d = {'type': ev['type_name'], 't': ev['t'], 'e': ev['e'], 'e_dot': ev['e_dot_est']}
            if ev['type'] == 0:
                d['reset'] = bool(ev['reset'])
                if ev['reset']:
                    d['theta_hat_reset'] = list(ev['theta_hat_after'])
            if ev.get('decision'):  # as src/io/setup.cpp prints pa_robust's decisions
                for k in ('decision', 'chosen', 'candidates', 'score', 'score_keep'):
                    d[k] = ev[k]
                d['theta_hat_after'] = list(ev['theta_hat_after'])
            if ev['type'] == 1:
                d['cost'] = ev['cost']
            evs.append(d)
        summary = {'mode': sim['mode'], 'events': evs}
        with open(json_path, 'w') as f:
            f.write('some log line the CLI printed before the summary\n')
            f.write(json.dumps(summary) + '\n')
    return path


def reference_metrics(sim):
    """Per-window peak |e| and event counts computed straight from the arrays, for the
    tests to compare the analysis against."""
    t = sim['t']
    e = np.abs(sim['e'])
    bounds = [t[0]] + list(sim['switches']) + [t[-1]]
    wins = []
    for i in range(len(bounds) - 1):
        lo, hi = bounds[i], bounds[i + 1]
        last = i == len(bounds) - 2
        m = (t >= lo - 1e-9) & ((t <= hi + 1e-9) if last else (t < hi - 1e-9))
        ev_in = [
            ev
            for ev in sim['events']
            if ev['t'] >= lo - 1e-9 and (ev['t'] <= hi + 1e-9 if last else ev['t'] < hi - 1e-9)
        ]
        rec = [ev['t'] for ev in ev_in if ev['type'] == 1]
        wins.append(
            {
                't_start': lo,
                't_end': hi,
                'peak': float(e[m].max()),
                'onsets': sum(1 for ev in ev_in if ev['type'] == 0),
                'recoveries': len(rec),
                'decisions': sum(1 for ev in ev_in if ev.get('decision')),
                'recovery_time': (rec[0] - lo) if rec else None,
            }
        )
    return wins


if __name__ == '__main__':
    import sys

    s = simulate(sys.argv[1] if len(sys.argv) > 1 else 'rac')
    for ev in s['events']:
        print(
            '%-17s t=%.3f e=%+.4f e_dot=%+.4f'
            % (ev['type_name'], ev['t'], ev['e'], ev['e_dot_est'])
        )
    for w in reference_metrics(s):
        print(w)
    print('max |u|', np.abs(s['u']).max(), 'max|e|', np.abs(s['e']).max())
    _ = math
