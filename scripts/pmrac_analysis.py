"""Analysis of preadaptive_mrac runs: bags (single-run or compare.launch) and the batch
CLI's CSV files -> SPEC.md metrics, a comparison against regular adaptive control, PNG
figures (the paper's Figs. 2-4 and more), metrics.json and metrics.csv.

Used by scripts/analyze_bag; importable on its own (load_runs, run_metrics, compare,
write_figures, ...) by other tools, e.g. a sweep report. Needs /usr/bin/python3 with
Debian's python3-rosbag for bags (not for CSV files), numpy and matplotlib.
See docs/analysis.md.
"""

import csv
import json
import math
import os
import re
import sys
import warnings

import numpy as np

# AttentionEvent.type 0..4 by name; 'decision' is pa_robust's re-decision inside a phase.
EVENT_TYPES = ('onset', 'recovered', 'ignored_onset', 'ignored_recovery', 'decision')
# What a pa_robust verification chose (AttentionEvent.decision / decision_code 1..4).
DECISIONS = ('keep', 'fit', 'memory', 'network')
DECISION_FIELDS = ('decision', 'chosen', 'candidates', 'score', 'score_keep')
MODES = ('pa_learn_exact', 'pa_learn', 'pa_robust', 'oracle', 'pa', 'rac')
MODE_TEXT = {
    'rac': 'regular adaptive control',
    'pa': 'preadaptation, no learning',
    'pa_learn': 'preadaptation + learning (approx. gradient)',
    'pa_learn_exact': 'preadaptation + learning (exact gradient)',
    'pa_robust': 'robust preadaptation (residual trigger, regime memory, verification)',
    'oracle': 'oracle yardstick: theta_hat := true theta at each switch',
}

# Relative topic names and message type base names the nodes publish (msg/*.msg).
TOPICS = {
    'state': ('plant/state', 'PlantState'),
    'truth': ('plant/truth', 'PlantTruth'),
    'status': ('controller/status', 'AdaptationStatus'),
    'elevator': ('controller/elevator_cmd', 'ElevatorCommand'),
    'attention': ('controller/attention', 'AttentionEvent'),
    'param_change': ('controller/param_change', 'ParamChange'),  # dynamic_reconfigure
}
REQUIRED = ('state', 'status', 'truth')
WHY = {'state': 'alpha', 'status': 'alpha_ref, e and theta_hat',
       'truth': 'the true theta, whose switches define the windows'}

CSV_HEADER = ('t,x0,x1,x2,xr0,xr1,xr2,e,e_dot_est,u,theta_hat0,theta_hat1,theta_hat2,'
              'theta_true0,theta_true1,theta_true2,phase')
CSV_REQUIRED = ('t', 'x1', 'xr1', 'e', 'u', 'theta_hat0', 'theta_hat1', 'theta_hat2',
                'theta_true0', 'theta_true1', 'theta_true2')

# Time stamps larger than this are wall-clock (epoch) stamps, not simulation time.
EPOCH_LIKE = 1.0e6


class InputError(Exception):
    """A problem with an input file; str() is one line naming the file."""

    def __init__(self, path, what):
        super().__init__('%s: %s' % (path, what))
        self.path = path
        self.what = what


class Run:
    """One closed-loop run: time series and attention events.

    Time series (numpy arrays, time in seconds of simulation time):
      t_e, e, e_dot, alpha_ref, theta_hat (N x 3)   controller samples
      t_alpha, alpha                                 plant samples
      t_theta, theta (M x 3)                         true theta
      t_u, u, u_bl, u_ad (u_bl/u_ad may be None)     elevator command
    events: list of dicts with keys type (one of EVENT_TYPES), t, e, e_dot,
      theta_hat_before, theta_hat_after, reset, cost, grad, learned, episodes (None where
      the source does not say), and pa_robust's verification: decision (one of DECISIONS,
      None when the event carries none: every event of the other modes, and of bags
      recorded before the field existed), chosen, candidates, score, score_keep.
    """

    def __init__(self, label, source, namespace=''):
        self.label = label
        self.source = source
        self.namespace = namespace
        self.mode = 'unknown'
        self.mode_from = ''
        self.notes = []
        self.events = []
        self.episodes = None
        self.t_e = self.e = self.e_dot = self.alpha_ref = self.theta_hat = None
        self.t_alpha = self.alpha = None
        self.t_theta = self.theta = None
        self.t_u = self.u = self.u_bl = self.u_ad = None
        self.u_source = ''
        self.summary = None  # the batch CLI's --json object, for a CSV input
        # dynamic_reconfigure changes (controller/param_change): dicts t, step, name,
        # old_value, new_value; drawn as markers on the time plots
        self.param_changes = []

    def describe(self):
        where = os.path.basename(self.source) + (' [%s]' % self.namespace if self.namespace else '')
        return "'%s' (mode %s) from %s" % (self.label, self.mode, where)


# ----------------------------------------------------------------------------- loading

def _is_bag(path):
    with open(path, 'rb') as f:
        return f.read(13) == b'#ROSBAG V2.0\n'


def _guess_mode(name):
    """A mode named in a file name (scenario1_pa_learn.csv -> pa_learn); None if none or
    more than one is named."""
    s = os.path.splitext(os.path.basename(name))[0].lower().replace('-', '_')
    s = s.replace('pa_learn_exact', ' PALE ').replace('pa_learn', ' PAL ')
    s = s.replace('pa_robust', ' PAR ')
    toks = set(re.split(r'[^A-Za-z0-9]+', s))
    found = [m for tok, m in (('PALE', 'pa_learn_exact'), ('PAL', 'pa_learn'),
                              ('PAR', 'pa_robust'), ('oracle', 'oracle'), ('pa', 'pa'),
                              ('rac', 'rac')) if tok in toks]
    return found[0] if len(found) == 1 else None


def load_runs(path):
    """All runs in one file (a compare bag holds several). Raises InputError."""
    if not os.path.exists(path):
        raise InputError(path, 'no such file')
    if os.path.isdir(path):
        raise InputError(path, 'is a directory, not a bag or CSV file')
    size = os.path.getsize(path)
    if size == 0:
        raise InputError(path, 'empty file (0 bytes): nothing was recorded')
    if _is_bag(path):
        return _load_bag(path)
    if path.endswith('.bag') or path.endswith('.bag.active'):
        raise InputError(path, 'not a ROS bag (no "#ROSBAG V2.0" header)')
    return [_load_csv(path)]


def _stamp_times(stamps, bag_times):
    """Header stamps as float seconds; bag receive times if every stamp is zero."""
    s = np.asarray(stamps, dtype=float)
    if s.size and not np.any(s):
        return np.asarray(bag_times, dtype=float), True
    return s, False


def _load_bag(path):
    try:
        import rosbag
    except ImportError:
        raise InputError(path, 'reading bags needs ROS\' rosbag module: run with /usr/bin/python3 '
                         '(Debian package python3-rosbag)')
    try:
        bag = rosbag.Bag(path, 'r')
    except rosbag.ROSBagUnindexedException:
        raise InputError(path, 'unindexed bag (the recorder did not close it: %s); run '
                         '`rosbag reindex %s` and analyse it again' %
                         ('still being recorded or killed' if path.endswith('.active')
                          else 'killed or crashed', path))
    except (rosbag.ROSBagException, OSError, ValueError) as ex:
        raise InputError(path, 'cannot read the bag: %s' % ex)
    try:
        return _read_bag(bag, path)
    finally:
        bag.close()


def _read_bag(bag, path):
    if bag.get_message_count() == 0:
        raise InputError(path, 'empty bag: it holds no messages')
    info = bag.get_type_and_topic_info().topics
    groups = {}  # namespace -> {key: topic}
    for topic, tt in info.items():
        if tt.message_count == 0:
            continue
        base = tt.msg_type.split('/')[-1]
        parts = topic.rsplit('/', 2)
        ns = parts[0] if len(parts) == 3 else ''
        for key, (rel, typ) in TOPICS.items():
            if base == typ:
                g = groups.setdefault(ns, {})
                # prefer the expected name if a namespace has two topics of one type
                if key not in g or topic.endswith('/' + rel):
                    g[key] = topic
    runs_ns = sorted(ns for ns, g in groups.items() if 'state' in g or 'status' in g)
    if not runs_ns:
        found = ', '.join('%s (%s)' % (tp, info[tp].msg_type) for tp in sorted(info)) or 'none'
        raise InputError(path, 'no preadaptive_mrac run in the bag: expected topics %s; the '
                         'bag has %s' % (', '.join('/' + TOPICS[k][0] for k in REQUIRED), found))
    missing = []
    for ns in runs_ns:
        for k in REQUIRED:
            if k not in groups[ns]:
                missing.append('%s/%s (%s, for %s)' % (ns, TOPICS[k][0], TOPICS[k][1], WHY[k]))
    if missing:
        raise InputError(path, 'missing topic%s %s' % ('s' if len(missing) > 1 else '',
                                                      '; '.join(missing)))
    topic_to = {}
    for ns in runs_ns:
        for k, tp in groups[ns].items():
            topic_to[tp] = (ns, k)
    acc = {ns: {k: [] for k in TOPICS} for ns in runs_ns}
    for topic, msg, bt in bag.read_messages(topics=list(topic_to)):
        ns, k = topic_to[topic]
        acc[ns][k].append((msg, bt.to_sec()))
    runs = []
    stem = os.path.basename(path)
    for suffix in ('.active', '.bag'):
        if stem.endswith(suffix):
            stem = stem[:-len(suffix)]
    for ns in runs_ns:
        label = ns.strip('/').replace('/', '_') or stem
        run = Run(label, path, ns)
        _fill_from_bag(run, acc[ns], path)
        runs.append(run)
    runs.sort(key=lambda r: (r.mode != 'rac', r.namespace))  # regular adaptive control first
    return runs


def _msg_times(pairs, name, run, dt=None):
    """Sample times [s] of (msg, bag time) pairs: the message's `t` field (sample time,
    exact, in every mode), else step * dt (dt from plant/state), else the header stamp
    (simulation time in lockstep), else the bag time if every stamp is zero."""
    first = pairs[0][0]
    if hasattr(first, 't') and isinstance(getattr(first, 't'), float):
        return np.array([m.t for m, _ in pairs], dtype=float)
    if dt and hasattr(first, 'step'):
        return np.array([m.step for m, _ in pairs], dtype=float) * dt
    t, zero = _stamp_times([m.header.stamp.to_sec() for m, _ in pairs], [b for _, b in pairs])
    if zero:
        run.notes.append('%s has zero header stamps: bag times used' % name)
    return t


def _no_decision():
    return {k: None for k in DECISION_FIELDS}


def _msg_decision(m):
    """pa_robust's verification fields of an AttentionEvent; all None when it carries none
    (decision '' / DECISION_NONE) or was recorded before the fields existed."""
    name = getattr(m, 'decision', '') or ''
    if not name:
        code = int(getattr(m, 'decision_code', 0) or 0)
        name = DECISIONS[code - 1] if 1 <= code <= len(DECISIONS) else ''
    if not name:
        return _no_decision()
    return {'decision': name, 'chosen': int(getattr(m, 'chosen', -1)),
            'candidates': int(getattr(m, 'candidates', 0)),
            'score': float(getattr(m, 'score', 0.0)),
            'score_keep': float(getattr(m, 'score_keep', 0.0))}


def _json_decision(ev):
    """The same from an event of the batch CLI's --json summary."""
    if not ev.get('decision'):
        return _no_decision()
    return {'decision': ev['decision'], 'chosen': ev.get('chosen'),
            'candidates': ev.get('candidates'), 'score': ev.get('score'),
            'score_keep': ev.get('score_keep')}


def _fill_from_bag(run, acc, path):
    ns = run.namespace
    for k in REQUIRED:
        if not acc[k]:
            raise InputError(path, 'no messages on %s/%s' % (ns, TOPICS[k][0]))
    ps = acc['state']
    dt = getattr(ps[0][0], 'dt', None) or None
    st = acc['status']
    run.t_e = _msg_times(st, '%s/controller/status' % ns, run)
    run.e = np.array([m.e for m, _ in st], dtype=float)
    run.e_dot = np.array([m.e_dot_est for m, _ in st], dtype=float)
    run.alpha_ref = np.array([m.alpha_ref for m, _ in st], dtype=float)
    run.theta_hat = np.array([list(m.theta_hat) if len(m.theta_hat) == 3 else
                              [m.theta_hat_0, m.theta_hat_1, m.theta_hat_2] for m, _ in st],
                             dtype=float)
    modes = [m.mode for m, _ in st if m.mode]
    if modes:
        run.mode = max(set(modes), key=modes.count)
        run.mode_from = 'status'
    run.episodes = int(st[-1][0].episodes)

    run.t_alpha = _msg_times(ps, '%s/plant/state' % ns, run)
    run.alpha = np.array([m.alpha for m, _ in ps], dtype=float)

    tr = acc['truth']
    run.t_theta = _msg_times(tr, '%s/plant/truth' % ns, run, dt)
    th = []
    for m, _ in tr:
        v = list(m.theta)
        if len(v) != 3:
            v = [m.theta_scale] * 3
        th.append(v)
    run.theta = np.array(th, dtype=float)

    el = acc['elevator']
    if el:
        run.t_u = _msg_times(el, '%s/controller/elevator_cmd' % ns, run)
        run.u = np.array([m.u for m, _ in el], dtype=float)
        run.u_bl = np.array([m.u_baseline for m, _ in el], dtype=float)
        run.u_ad = np.array([m.u_adaptive for m, _ in el], dtype=float)
        run.u_source = '%s/controller/elevator_cmd' % ns
    else:
        run.t_u = run.t_alpha
        run.u = np.array([m.elevator for m, _ in ps], dtype=float)
        run.u_source = '%s/plant/state elevator' % ns
        run.notes.append('no %s/controller/elevator_cmd: u taken from plant/state.elevator' % ns)

    att = acc['attention']
    t_att = _msg_times(att, '%s/controller/attention' % ns, run) if att else []
    for (m, bt), t in zip(att, t_att):
        tname = m.type_name if m.type_name in EVENT_TYPES else (
            EVENT_TYPES[m.type] if m.type < len(EVENT_TYPES) else 'type%d' % m.type)
        ev = {
            'type': tname, 't': float(t), 'e': m.e, 'e_dot': m.e_dot_est,
            'theta_hat_before': list(m.theta_hat_before) or None,
            'theta_hat_after': list(m.theta_hat_after) or None,
            'reset': bool(m.reset), 'cost': m.cost if tname == 'recovered' else None,
            'grad': list(m.grad) or None, 'learned': bool(m.learned),
            'episodes': int(m.episodes)}
        ev.update(_msg_decision(m))
        run.events.append(ev)
        run.episodes = max(run.episodes or 0, int(m.episodes))
    if not acc['attention']:
        run.notes.append('no %s/controller/attention messages: no attention events' % ns)
    for m, _ in acc.get('param_change', []):
        run.param_changes.append({'t': float(m.t), 'step': int(m.step), 'name': m.name,
                                  'old_value': m.old_value, 'new_value': m.new_value})
        run.notes.append('%s: %.6g -> %.6g at t = %.6g s (step %d)' % (
            m.name, m.old_value, m.new_value, m.t, m.step))
    _rebase_epoch(run)


def _rebase_epoch(run):
    t0 = float(run.t_e[0])
    if t0 > EPOCH_LIKE:
        for name in ('t_e', 't_alpha', 't_theta', 't_u'):
            v = getattr(run, name)
            if v is not None:
                setattr(run, name, v - t0)
        for ev in run.events:
            ev['t'] -= t0
        run.notes.append('stamps are wall-clock times: time is measured from the first '
                         'controller sample')


def _parse_summary_json(path):
    """The batch CLI's `--json` output: the whole file, or its last line that is a JSON
    object (the CLI prints it on the last stdout line)."""
    with open(path) as f:
        text = f.read()
    try:
        obj = json.loads(text)
        if isinstance(obj, dict):
            return obj
    except ValueError:
        pass
    for line in reversed(text.splitlines()):
        line = line.strip()
        if line.startswith('{'):
            try:
                obj = json.loads(line)
                if isinstance(obj, dict):
                    return obj
            except ValueError:
                continue
    raise InputError(path, 'no JSON object in the file (expected the `--json` summary line)')


def _load_csv(path):
    with open(path, newline='') as f:
        reader = csv.reader(f)
        try:
            header = [h.strip() for h in next(reader)]
        except StopIteration:
            raise InputError(path, 'empty CSV file')
        except (UnicodeDecodeError, csv.Error) as ex:
            raise InputError(path, 'not a CSV file (%s)' % ex)
    missing = [c for c in CSV_REQUIRED if c not in header]
    if missing:
        raise InputError(path, 'not a preadapt_sim CSV: missing column%s %s (preadapt_sim writes '
                         'the header %s)' % ('s' if len(missing) > 1 else '', ', '.join(missing),
                                             CSV_HEADER))
    try:
        with warnings.catch_warnings():
            warnings.simplefilter('ignore')  # numpy warns about an empty file; we say it below
            data = np.loadtxt(path, delimiter=',', skiprows=1, ndmin=2)
    except ValueError as ex:
        raise InputError(path, 'bad CSV data: %s' % ex)
    if data.shape[0] == 0:
        raise InputError(path, 'CSV has a header but no data rows')
    if data.shape[1] != len(header):
        raise InputError(path, 'CSV rows have %d fields, the header %d' % (data.shape[1], len(header)))
    col = {h: data[:, i] for i, h in enumerate(header)}
    stem = os.path.splitext(os.path.basename(path))[0]
    run = Run(stem, path)
    t = col['t']
    run.t_e = run.t_alpha = run.t_theta = run.t_u = t
    run.e = col['e']
    run.e_dot = col.get('e_dot_est')
    run.alpha_ref = col['xr1']
    run.alpha = col['x1']
    run.theta_hat = np.column_stack([col['theta_hat%d' % i] for i in range(3)])
    run.theta = np.column_stack([col['theta_true%d' % i] for i in range(3)])
    run.u = col['u']
    run.u_source = 'CSV column u'
    if 'u_baseline' in col and 'u_adaptive' in col:
        run.u_bl, run.u_ad = col['u_baseline'], col['u_adaptive']

    json_path = os.path.splitext(path)[0] + '.json'
    summary = None
    if os.path.exists(json_path):
        summary = _parse_summary_json(json_path)
    if summary is not None and isinstance(summary.get('mode'), str):
        run.mode = summary['mode']
        run.mode_from = os.path.basename(json_path)
    if summary is not None and isinstance(summary.get('events'), list):
        for ev in summary['events']:
            tname = ev.get('type')
            if tname not in EVENT_TYPES or 't' not in ev:
                raise InputError(json_path, 'event without a known type or t: %s' % json.dumps(ev))
            after = ev.get('theta_hat_reset', ev.get('theta_hat_after'))
            dec = _json_decision(ev)
            if 'reset' in ev:
                reset = bool(ev['reset'])
            elif dec['decision'] is not None:  # a DECISION moves theta_hat unless it keeps
                reset = dec['decision'] != 'keep'
            else:
                reset = after is not None
            d = {
                'type': tname, 't': float(ev['t']), 'e': ev.get('e'), 'e_dot': ev.get('e_dot'),
                'theta_hat_before': ev.get('theta_hat_before'), 'theta_hat_after': after,
                'reset': reset,
                'cost': ev.get('cost') if tname == 'recovered' else None,
                'grad': ev.get('grad'), 'learned': ev.get('learned'),
                'episodes': ev.get('episodes')}
            d.update(dec)
            run.events.append(d)
        run.notes.append('events from %s' % os.path.basename(json_path))
    elif 'phase' in col:
        ph = col['phase'] > 0.5
        for i in np.nonzero(ph[1:] != ph[:-1])[0] + 1:
            d = {
                'type': 'onset' if ph[i] else 'recovered', 't': float(t[i]), 'e': float(run.e[i]),
                'e_dot': float(run.e_dot[i]) if run.e_dot is not None else None,
                'theta_hat_before': None, 'theta_hat_after': None, 'reset': None,
                'cost': None, 'grad': None, 'learned': None, 'episodes': None}
            d.update(_no_decision())
            run.events.append(d)
        run.notes.append('events from the phase column (no %s): onsets and recoveries only, '
                         'ignored events, decisions and costs unknown' %
                         os.path.basename(json_path))
    else:
        run.notes.append('no %s and no phase column: no attention events' %
                         os.path.basename(json_path))
    if run.mode == 'unknown':
        g = _guess_mode(stem)
        if g:
            run.mode = g
            run.mode_from = 'file name'
            run.notes.append('mode %s guessed from the file name' % g)
    run.events.sort(key=lambda ev: ev['t'])
    eps = [ev['episodes'] for ev in run.events if isinstance(ev.get('episodes'), (int, float))]
    if summary is not None and isinstance(summary.get('episodes'), (int, float)):
        eps.append(summary['episodes'])
    run.episodes = int(max(eps)) if eps else None
    run.summary = summary
    _rebase_epoch(run)
    return run


def load_inputs(paths, labels=None):
    """Runs of every input, labels made unique (or set from `labels`)."""
    runs = []
    for p in paths:
        runs.extend(load_runs(p))
    if labels:
        if len(labels) != len(runs):
            raise InputError(paths[0] if len(paths) == 1 else ', '.join(paths),
                             '%d label(s) given for %d run(s) (%s)' %
                             (len(labels), len(runs), ', '.join(r.describe() for r in runs)))
        for r, lab in zip(runs, labels):
            r.label = lab
    seen = {}
    for r in runs:
        if r.label in seen:
            seen[r.label] += 1
            r.label = '%s_%d' % (r.label, seen[r.label])
        else:
            seen[r.label] = 1
    return runs


# ----------------------------------------------------------------------------- metrics

def find_switches(t_theta, theta, rtol=1e-9):
    """Times at which the true theta changes: (times, theta before, theta after). A
    switch's time is the stamp of the first sample holding the new value."""
    theta = np.asarray(theta, dtype=float)
    if len(theta) < 2:
        return np.array([]), np.zeros((0, 3)), np.zeros((0, 3))
    d = np.abs(np.diff(theta, axis=0)).max(axis=1)
    scale = np.maximum(1.0, np.abs(theta).max(axis=1)[1:])
    idx = np.nonzero(d > rtol * scale)[0] + 1
    return np.asarray(t_theta)[idx], theta[idx - 1], theta[idx]


def _scale_of(v):
    v = np.asarray(v, dtype=float)
    return float(v[0]) if np.allclose(v, v[0], rtol=1e-9, atol=1e-12) else None


def _f(x):
    """JSON-safe float."""
    if x is None:
        return None
    x = float(x)
    return None if math.isnan(x) or math.isinf(x) else x


def _cum_trapz(y, t):
    out = np.zeros_like(t, dtype=float)
    if len(t) > 1:
        out[1:] = np.cumsum(0.5 * (y[1:] + y[:-1]) * np.diff(t))
    return out


def run_metrics(run):
    """SPEC.md metrics of one run: windows between switches of the true theta and the
    whole run. Returns a JSON-ready dict."""
    t = run.t_e
    ae = np.abs(run.e)
    cum = _cum_trapz(ae, t)
    sw_t, sw_before, sw_after = find_switches(run.t_theta, run.theta)
    t0, t1 = float(t[0]), float(t[-1])
    sw_keep = (sw_t > t0) & (sw_t < t1)
    sw_t, sw_before, sw_after = sw_t[sw_keep], sw_before[sw_keep], sw_after[sw_keep]
    bounds = [t0] + [float(s) for s in sw_t] + [t1]
    theta_at_start = run.theta[np.searchsorted(run.t_theta, t0, side='right') - 1] \
        if run.t_theta[0] <= t0 else run.theta[0]
    windows = []
    n_win = len(bounds) - 1
    for i in range(n_win):
        lo, hi = bounds[i], bounds[i + 1]
        last = i == n_win - 1

        def inside(tt, lo=lo, hi=hi, last=last):
            tt = np.asarray(tt)
            return (tt >= lo) & ((tt <= hi) if last else (tt < hi))
        m = inside(t)
        if np.any(m):
            k = int(np.argmax(np.where(m, ae, -1.0)))
            peak, t_peak = float(ae[k]), float(t[k])
        else:
            peak = t_peak = None
        iae = float(np.interp(hi, t, cum) - np.interp(lo, t, cum))
        mu = inside(run.t_u)
        max_u = float(np.max(np.abs(run.u[mu]))) if np.any(mu) else None
        evs = [ev for ev in run.events if inside(ev['t'])]
        rec = [ev['t'] for ev in evs if ev['type'] == 'recovered']
        ons = [ev['t'] for ev in evs if ev['type'] == 'onset']
        th = sw_after[i - 1] if i > 0 else theta_at_start
        windows.append({
            'index': i,
            'kind': 'switch' if i > 0 else 'start',
            't_start': lo, 't_end': hi,
            'theta_before': [float(v) for v in sw_before[i - 1]] if i > 0 else None,
            'theta': [float(v) for v in th],
            'theta_scale_before': _scale_of(sw_before[i - 1]) if i > 0 else None,
            'theta_scale': _scale_of(th),
            'peak_abs_e': _f(peak), 't_peak': _f(t_peak), 'iae': _f(iae),
            'max_abs_u': _f(max_u),
            'recovery_time': _f(rec[0] - lo) if rec else None,
            'onset_delay': _f(ons[0] - lo) if ons else None,
            'onsets': len(ons), 'recoveries': len(rec),
            'ignored_onsets': sum(1 for ev in evs if ev['type'] == 'ignored_onset'),
            'ignored_recoveries': sum(1 for ev in evs if ev['type'] == 'ignored_recovery'),
            'decisions': sum(1 for ev in evs if ev.get('decision')),
        })
    k = int(np.argmax(ae))
    costs = [ev for ev in run.events if ev['type'] == 'recovered' and ev.get('cost') is not None]
    decisions = decision_list(run)
    whole = {
        't_start': t0, 't_end': t1, 'duration': t1 - t0, 'samples': int(len(t)),
        'iae': _f(cum[-1]), 'peak_abs_e': _f(ae[k]), 't_peak': _f(t[k]),
        'max_abs_u': _f(np.max(np.abs(run.u))) if run.u is not None and len(run.u) else None,
        'onsets': sum(1 for ev in run.events if ev['type'] == 'onset'),
        'recoveries': sum(1 for ev in run.events if ev['type'] == 'recovered'),
        'ignored_onsets': sum(1 for ev in run.events if ev['type'] == 'ignored_onset'),
        'ignored_recoveries': sum(1 for ev in run.events if ev['type'] == 'ignored_recovery'),
        'decision_events': sum(1 for ev in run.events if ev['type'] == 'decision'),
        'decisions': len(decisions),
        'decisions_by_kind': {k: sum(1 for d in decisions if d['decision'] == k)
                              for k in DECISIONS},
        'episodes': run.episodes,
        'costs': [_f(ev['cost']) for ev in costs],
    }
    return {
        'label': run.label, 'source': run.source, 'namespace': run.namespace,
        'mode': run.mode, 'mode_from': run.mode_from, 'u_source': run.u_source,
        'switches': [{'t': float(s), 'theta_before': [float(v) for v in b],
                      'theta_after': [float(v) for v in a]}
                     for s, b, a in zip(sw_t, sw_before, sw_after)],
        'whole_run': whole, 'windows': windows, 'decisions': decisions,
        'events': [{k2: (_f(v) if isinstance(v, float) else
                         ([_f(x) for x in v] if isinstance(v, list) else v))
                    for k2, v in ev.items()} for ev in run.events],
        'param_changes': [dict(c) for c in run.param_changes],
        'notes': list(run.notes),
    }


def decision_list(run):
    """pa_robust's verification decisions of a run (onsets and DECISION events that carry
    one), in time order: dicts t, type, decision, chosen, candidates, score, score_keep,
    theta_hat_after. Empty for the other modes and for bags without the fields."""
    out = []
    for ev in run.events:
        if not ev.get('decision'):
            continue
        d = {'t': _f(ev['t']), 'type': ev['type']}
        for k in DECISION_FIELDS:
            v = ev.get(k)
            d[k] = _f(v) if isinstance(v, float) else v
        after = ev.get('theta_hat_after')
        d['theta_hat_after'] = [_f(x) for x in after] if after else None
        out.append(d)
    return out


def choose_baseline(metrics, baseline=None):
    """Label of the regular-adaptive-control run: `baseline` if given, else the first run
    whose mode is rac, else a run labelled rac; None if there is none."""
    labels = [m['label'] for m in metrics]
    if baseline is not None:
        if baseline not in labels:
            raise InputError('--baseline', "no run labelled '%s' (runs: %s)" %
                             (baseline, ', '.join(labels)))
        return baseline
    for m in metrics:
        if m['mode'] == 'rac':
            return m['label']
    for m in metrics:
        if m['label'] == 'rac':
            return m['label']
    return None


def _pct(base, val):
    if base is None or val is None or base <= 0:
        return None
    return 100.0 * (base - val) / base


def compare(metrics, baseline_label, tol=0.05):
    """Per-window peak |e| and integral |e| reduction (in %, positive = better than the
    baseline) of every other run against the baseline run. Windows are paired by their
    start time (within `tol` seconds)."""
    if baseline_label is None:
        return None
    base = next(m for m in metrics if m['label'] == baseline_label)
    out = {'baseline': baseline_label, 'baseline_mode': base['mode'], 'runs': []}
    for m in metrics:
        if m['label'] == baseline_label:
            continue
        rows, unmatched = [], []
        for w in m['windows']:
            bw = min(base['windows'], key=lambda b: abs(b['t_start'] - w['t_start']))
            if abs(bw['t_start'] - w['t_start']) > tol:
                unmatched.append(w['index'])
                continue
            rows.append({
                'index': w['index'], 'baseline_index': bw['index'], 't_start': w['t_start'],
                'kind': w['kind'], 'theta_scale': w['theta_scale'],
                'peak_baseline': bw['peak_abs_e'], 'peak': w['peak_abs_e'],
                'peak_reduction_pct': _f(_pct(bw['peak_abs_e'], w['peak_abs_e'])),
                'iae_baseline': bw['iae'], 'iae': w['iae'],
                'iae_reduction_pct': _f(_pct(bw['iae'], w['iae'])),
                'recovery_time_baseline': bw['recovery_time'],
                'recovery_time': w['recovery_time'],
            })
        bwr, wr = base['whole_run'], m['whole_run']
        out['runs'].append({
            'label': m['label'], 'mode': m['mode'], 'windows': rows,
            'unmatched_windows': unmatched,
            'whole_run': {
                'peak_reduction_pct': _f(_pct(bwr['peak_abs_e'], wr['peak_abs_e'])),
                'iae_reduction_pct': _f(_pct(bwr['iae'], wr['iae'])),
                'max_abs_u_baseline': bwr['max_abs_u'], 'max_abs_u': wr['max_abs_u']},
        })
    return out


# ----------------------------------------------------------------------------- text

def final_decisions(decisions):
    """The last decision of each verification (the decisions after one onset, up to the
    next onset): what the phase settled on."""
    out = []
    for d in decisions:
        if d['type'] == 'onset' or not out:
            out.append(d)
        else:
            out[-1] = d
    return out


def _fmt(v, spec='%.4g', none='-'):
    return none if v is None else spec % v


def _theta_text(scale, vec):
    if scale is not None:
        return _fmt(scale, '%.3g')
    return '[' + ','.join('%.2g' % v for v in vec) + ']' if vec is not None else '-'


def format_report(metrics, comparison):
    lines = []
    for m in metrics:
        w = m['whole_run']
        lines.append('== run %s (%s, mode %s%s)' % (
            m['label'], os.path.basename(m['source']) + (' ' + m['namespace'] if m['namespace'] else ''),
            m['mode'], (' from ' + m['mode_from']) if m['mode_from'] else ''))
        lines.append('   t = %.3f .. %.3f s, %d controller samples, %d theta switch(es) at %s' % (
            w['t_start'], w['t_end'], w['samples'], len(m['switches']),
            ', '.join('%.3f s' % s['t'] for s in m['switches']) or '-'))
        lines.append('   whole run: integral |e| %s rad s, peak |e| %s rad (t = %s s), max |u| %s rad'
                     % (_fmt(w['iae']), _fmt(w['peak_abs_e']), _fmt(w['t_peak'], '%.3f'),
                        _fmt(w['max_abs_u'])))
        lines.append('   events: %d onsets, %d recoveries, %d ignored onsets, %d ignored '
                     'recoveries; learning episodes %s' % (
                         w['onsets'], w['recoveries'], w['ignored_onsets'],
                         w['ignored_recoveries'], _fmt(w['episodes'], '%d')))
        if w['decisions']:
            lines.append('   decisions (pa_robust verification): %d, %d of them DECISION events; '
                         '%s' % (w['decisions'], w['decision_events'], ', '.join(
                             '%s %d' % (k, n) for k, n in w['decisions_by_kind'].items() if n)))
            for d in final_decisions(m['decisions']):
                lines.append('     t = %.3f s: %s%s, residual %s rad against %s rad keeping '
                             '(%s candidates)' % (
                                 d['t'], d['decision'],
                                 ' #%d' % d['chosen'] if d['decision'] == 'memory' else '',
                                 _fmt(d['score'], '%.3g'), _fmt(d['score_keep'], '%.3g'),
                                 _fmt(d['candidates'], '%d')))
        for n in m['notes']:
            lines.append('   note: ' + n)
        lines.append('   %3s %9s %9s %7s %11s %9s %12s %11s %6s %6s %5s' % (
            'win', 't_start', 't_end', 'theta', 'peak|e|', 't_peak', 'int|e|', 'recovery',
            'onset', 'recov', 'ign'))
        lines.append('   %3s %9s %9s %7s %11s %9s %12s %11s %6s %6s %5s' % (
            '', '[s]', '[s]', '', '[rad]', '[s]', '[rad s]', '[s]', '', '', ''))
        for win in m['windows']:
            lines.append('   %3d %9.3f %9.3f %7s %11s %9s %12s %11s %6d %6d %5d' % (
                win['index'], win['t_start'], win['t_end'],
                _theta_text(win['theta_scale'], win['theta']), _fmt(win['peak_abs_e'], '%.5f'),
                _fmt(win['t_peak'], '%.3f'), _fmt(win['iae'], '%.6f'),
                _fmt(win['recovery_time'], '%.3f'), win['onsets'], win['recoveries'],
                win['ignored_onsets'] + win['ignored_recoveries']))
        lines.append('')
    if comparison is None:
        if len(metrics) > 1:
            lines.append('== comparison: no regular adaptive control (rac) run among the inputs; '
                         'name one with --baseline LABEL')
        return '\n'.join(lines)
    lines.append("== comparison against '%s' (mode %s): reduction in %% = 100 (baseline - run) / "
                 "baseline, positive = smaller error than the baseline" %
                 (comparison['baseline'], comparison['baseline_mode']))
    for c in comparison['runs']:
        lines.append("   run '%s' (mode %s)" % (c['label'], c['mode']))
        lines.append('   %3s %9s %7s %12s %12s %10s %12s %12s %10s' % (
            'win', 't_start', 'theta', 'peak base', 'peak run', 'peak red.', 'int base',
            'int run', 'int red.'))
        for r in c['windows']:
            lines.append('   %3d %9.3f %7s %12s %12s %10s %12s %12s %10s' % (
                r['index'], r['t_start'], _fmt(r['theta_scale'], '%.3g'),
                _fmt(r['peak_baseline'], '%.5f'), _fmt(r['peak'], '%.5f'),
                _fmt(r['peak_reduction_pct'], '%+.1f%%'), _fmt(r['iae_baseline'], '%.6f'),
                _fmt(r['iae'], '%.6f'), _fmt(r['iae_reduction_pct'], '%+.1f%%')))
        wr = c['whole_run']
        lines.append('   whole run: peak |e| %s, integral |e| %s' % (
            _fmt(wr['peak_reduction_pct'], '%+.1f%%'), _fmt(wr['iae_reduction_pct'], '%+.1f%%')))
        if c['unmatched_windows']:
            lines.append('   note: window(s) %s have no baseline window starting at the same time'
                         % ', '.join(str(i) for i in c['unmatched_windows']))
    return '\n'.join(lines)


CSV_COLUMNS = ['label', 'source', 'namespace', 'mode', 'window', 'kind', 't_start', 't_end',
               'theta_scale', 'theta_scale_before', 'peak_abs_e', 't_peak', 'iae', 'max_abs_u',
               'recovery_time', 'onset_delay', 'onsets', 'recoveries', 'ignored_onsets',
               'ignored_recoveries', 'baseline', 'peak_reduction_pct', 'iae_reduction_pct',
               'decisions']


def write_tables(out_dir, metrics, comparison, settings):
    doc = {'settings': settings, 'runs': metrics, 'comparison': comparison}
    with open(os.path.join(out_dir, 'metrics.json'), 'w') as f:
        json.dump(doc, f, indent=1, allow_nan=False)
    red = {}
    if comparison:
        for c in comparison['runs']:
            for r in c['windows']:
                red[(c['label'], r['index'])] = r
            red[(c['label'], 'all')] = c['whole_run']
    with open(os.path.join(out_dir, 'metrics.csv'), 'w', newline='') as f:
        w = csv.writer(f)
        w.writerow(CSV_COLUMNS)

        def cell(v):
            if v is None:
                return ''
            if isinstance(v, float):
                return '%.9g' % v
            return v
        for m in metrics:
            rows = [(win['index'], win) for win in m['windows']]
            whole = dict(m['whole_run'])
            whole.update(kind='whole_run', theta_scale=None, theta_scale_before=None,
                         recovery_time=None, onset_delay=None)
            rows.append(('all', whole))
            for idx, win in rows:
                r = red.get((m['label'], idx), {})
                base = comparison['baseline'] if comparison and m['label'] != comparison['baseline'] else None
                vals = {'label': m['label'], 'source': m['source'], 'namespace': m['namespace'],
                        'mode': m['mode'], 'window': idx, 'baseline': base,
                        'peak_reduction_pct': r.get('peak_reduction_pct'),
                        'iae_reduction_pct': r.get('iae_reduction_pct')}
                for k in CSV_COLUMNS:
                    if k not in vals:
                        vals[k] = win.get(k)
                w.writerow([cell(vals[k]) for k in CSV_COLUMNS])


# ----------------------------------------------------------------------------- figures

ONSET_COLOR = 'tab:green'
RECOVERY_COLOR = 'black'
SWITCH_COLOR = '0.55'
THETA_UNITS = ('[1/s]', '[rad/rad]', '[s]')  # theta^T x enters u [rad]; x = [rad s, rad, rad/s]
# Marker per pa_robust decision kind (time plots and decisions_<label>.png).
DECISION_STYLE = {
    'keep': {'marker': 's', 'color': 'tab:gray'},
    'fit': {'marker': 'D', 'color': 'tab:purple'},
    'memory': {'marker': '^', 'color': 'tab:brown'},
    'network': {'marker': '*', 'color': 'tab:pink'},
}


def _mpl():
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    plt.rcParams.update({'font.size': 11, 'axes.titlesize': 12, 'legend.fontsize': 9,
                         'axes.grid': True, 'grid.alpha': 0.3, 'figure.dpi': 100})
    return plt


def _safe(label):
    return re.sub(r'[^A-Za-z0-9_.-]+', '_', label)


def _event_lines(ax, run, with_labels=True, lw=1.0):
    """Green vertical lines at onsets (E_u), black at recoveries (E_d); returns handles."""
    handles = []
    first = {'onset': True, 'recovered': True}
    for ev in run.events:
        if ev['type'] not in first:
            continue
        color = ONSET_COLOR if ev['type'] == 'onset' else RECOVERY_COLOR
        label = None
        if with_labels and first[ev['type']]:
            label = ('onset $E_u=1$' if ev['type'] == 'onset' else 'recovery $E_d=1$')
            if with_labels is not True:
                label += ' (%s)' % with_labels
            first[ev['type']] = False
        h = ax.axvline(ev['t'], color=color, lw=lw, alpha=0.85, zorder=1, label=label)
        if label:
            handles.append(h)
    return handles


PARAM_COLOR = 'tab:purple'


def _param_change_lines(ax, run, annotate=True):
    """Dash-dotted vertical lines at the steps dynamic_reconfigure changes took effect, with
    'key old -> new' beside them (changes of one step share a line); returns the lines."""
    by_t = {}
    for c in run.param_changes:
        by_t.setdefault(c['t'], []).append(c)
    lines = []
    for i, (t, cs) in enumerate(sorted(by_t.items())):
        lines.append(ax.axvline(t, color=PARAM_COLOR, ls='-.', lw=1.2, zorder=1,
                                label='parameter change' if i == 0 and annotate else None))
        if annotate:
            txt = '\n'.join('%s %.4g$\\to$%.4g' % (c['name'].split('.')[-1], c['old_value'],
                                                    c['new_value']) for c in cs)
            ax.annotate(txt, xy=(t, 0.0), xycoords=('data', 'axes fraction'), xytext=(2, 2),
                        textcoords='offset points', va='bottom', ha='left', fontsize=8,
                        color=PARAM_COLOR, annotation_clip=True)
    return lines


def _switch_lines(ax, m, annotate=True):
    for i, s in enumerate(m['switches']):
        ax.axvline(s['t'], color=SWITCH_COLOR, ls=':', lw=1.2, zorder=0,
                   label=r'$\theta$ switch' if i == 0 and annotate else None)
        if annotate:
            sc = _scale_of(s['theta_after'])
            txt = (r'$\theta$=%.3g' % sc) if sc is not None else r'$\theta$ switch'
            ax.annotate(txt, xy=(s['t'], 1.0), xycoords=('data', 'axes fraction'),
                        xytext=(2, -2), textcoords='offset points', va='top', ha='left',
                        fontsize=8, color='0.35', annotation_clip=True)


def _legend(ax, **kw):
    """Legend outside the axes, on the right, so it never hides data."""
    h, lab = ax.get_legend_handles_labels()
    uniq = dict(zip(lab, h))
    if uniq:
        ax.legend(uniq.values(), uniq.keys(), loc='upper left', bbox_to_anchor=(1.005, 1.0),
                  borderaxespad=0.0, **kw)


def _save(fig, path):
    with warnings.catch_warnings():
        # outside legends: tight_layout may give up; bbox_inches='tight' below fits them
        warnings.simplefilter('ignore', UserWarning)
        fig.tight_layout()
    fig.savefig(path, bbox_inches='tight', pad_inches=0.15)


def _xlim(ax, xlim):
    if xlim:
        ax.set_xlim(*xlim)


def _ylim_to_xlim(ax, series, xlim, pad=0.08):
    """Fit y limits to the data inside the x window (matplotlib uses all data)."""
    if not xlim:
        return
    lo, hi = np.inf, -np.inf
    for t, y in series:
        m = (t >= xlim[0]) & (t <= xlim[1])
        if np.any(m):
            lo, hi = min(lo, np.min(y[m])), max(hi, np.max(y[m]))
    if np.isfinite(lo) and hi > lo:
        d = (hi - lo) * pad
        ax.set_ylim(lo - d, hi + d)


def plot_alpha(plt, run, m, path, c_e, xlim=None):
    fig, (ax, ax2) = plt.subplots(2, 1, sharex=True, figsize=(11, 6.4),
                                  gridspec_kw={'height_ratios': [2.2, 1]})
    ax.plot(run.t_alpha, run.alpha, color='tab:blue', lw=1.3, label=r'$\alpha$ (plant)', zorder=3)
    ax.plot(run.t_e, run.alpha_ref, color='tab:orange', lw=1.3, ls='--',
            label=r'$\alpha_{ref}$ (reference model)', zorder=3)
    _switch_lines(ax, m)
    _event_lines(ax, run)
    _param_change_lines(ax, run)
    ax.set_ylabel(r'angle of attack $\alpha$ [rad]')
    ax.set_title("Response of $\\alpha$: run '%s', mode %s (%s)" % (
        run.label, run.mode, MODE_TEXT.get(run.mode, 'unknown mode')))
    _legend(ax)
    _ylim_to_xlim(ax, [(run.t_alpha, run.alpha), (run.t_e, run.alpha_ref)], xlim)
    ax2.plot(run.t_e, run.e, color='tab:red', lw=1.0, label=r'$e=\alpha-\alpha_{ref}$', zorder=3)
    ax2.axhline(c_e, color='0.4', ls='--', lw=0.9, label=r'$\pm c_e$ = %.3g rad' % c_e)
    ax2.axhline(-c_e, color='0.4', ls='--', lw=0.9)
    _switch_lines(ax2, m, annotate=False)
    _event_lines(ax2, run, with_labels=False)
    _param_change_lines(ax2, run, annotate=False)
    ign = [ev for ev in run.events if ev['type'] in ('ignored_onset', 'ignored_recovery')
           and ev.get('e') is not None]
    for kind, mk, col in (('ignored_onset', 'x', ONSET_COLOR), ('ignored_recovery', 'x', RECOVERY_COLOR)):
        pts = [(ev['t'], ev['e']) for ev in ign if ev['type'] == kind]
        if pts:
            ax2.plot(*zip(*pts), ls='none', marker=mk, ms=7, mew=1.8, color=col, zorder=4,
                     label=kind.replace('_', ' '))
    _decision_markers(ax2, run, lambda ev: ev.get('e'))
    ax2.set_ylabel('output error $e$ [rad]')
    ax2.set_xlabel('time $t$ [s]')
    _legend(ax2)
    _ylim_to_xlim(ax2, [(run.t_e, run.e), (np.array(xlim or [0, 0]), np.array([-c_e, c_e]))], xlim)
    _xlim(ax2, xlim)
    _save(fig, path)
    plt.close(fig)


def _run_colors(runs, baseline):
    palette = ['tab:blue', 'tab:purple', 'tab:cyan', 'tab:olive', 'tab:brown', 'tab:pink']
    cols, k = {}, 0
    for r in runs:
        if r.label == baseline:
            cols[r.label] = 'tab:red'
        else:
            cols[r.label] = palette[k % len(palette)]
            k += 1
    return cols


def plot_compare(plt, runs, metrics, baseline, path, xlim=None):
    cols = _run_colors(runs, baseline)
    focus = next((r for r in runs if r.label != baseline), runs[0])
    fig, (ax, ax2) = plt.subplots(2, 1, sharex=True, figsize=(11, 6.8),
                                  gridspec_kw={'height_ratios': [2.2, 1]})
    ref_run = next((r for r in runs if r.label == baseline), runs[0])
    for r in runs:
        lab = "%s (%s)" % (r.label, 'RAC' if r.mode == 'rac' else r.mode)
        ax.plot(r.t_alpha, r.alpha, color=cols[r.label], lw=1.2, label=r'$\alpha$ ' + lab, zorder=3)
    ax.plot(ref_run.t_e, ref_run.alpha_ref, color='tab:orange', lw=1.2, ls='--',
            label=r'$\alpha_{ref}$', zorder=2)
    mfocus = next(mm for mm in metrics if mm['label'] == focus.label)
    _switch_lines(ax, mfocus)
    _event_lines(ax, focus, with_labels=focus.label)
    ax.set_ylabel(r'angle of attack $\alpha$ [rad]')
    ax.set_title(r'Response of $\alpha$: ' + ' vs '.join("'%s'" % r.label for r in runs) +
                 "  (event lines: '%s')" % focus.label)
    _legend(ax)
    _ylim_to_xlim(ax, [(r.t_alpha, r.alpha) for r in runs], xlim)
    for r, mm in zip(runs, metrics):
        ax2.plot(r.t_e, np.abs(r.e), color=cols[r.label], lw=1.0, label='|e| ' + r.label, zorder=3)
        pk = [(w['t_peak'], w['peak_abs_e']) for w in mm['windows'] if w['kind'] == 'switch'
              and w['t_peak'] is not None]
        if pk:
            ax2.plot(*zip(*pk), ls='none', marker='v', ms=7, color=cols[r.label], zorder=4)
    _switch_lines(ax2, mfocus, annotate=False)
    _event_lines(ax2, focus, with_labels=False)
    ax2.set_ylabel('|e| [rad]')
    ax2.set_xlabel('time $t$ [s]')
    _ylim_to_xlim(ax2, [(r.t_e, np.abs(r.e)) for r in runs], xlim)
    ax2.set_ylim(bottom=0)
    _xlim(ax2, xlim)
    ax2.plot([], [], ls='none', marker='v', ms=7, color='0.4', label='peak |e| after a switch')
    _legend(ax2)
    _save(fig, path)
    plt.close(fig)


def plot_peaks(plt, runs, metrics, comparison, baseline, path):
    cols = _run_colors(runs, baseline)
    ref = next((mm for mm in metrics if mm['label'] == baseline), metrics[0])
    starts = [w['t_start'] for w in ref['windows']]
    names = []
    for w in ref['windows']:
        if w['kind'] == 'start':
            names.append('%d: start\n' % w['index'] + r'$\theta$=%s' % _theta_text(w['theta_scale'], w['theta']))
        else:
            names.append('%d: t=%.4g s\n' % (w['index'], w['t_start']) + r'$\theta$ %s$\to$%s' % (
                _theta_text(w['theta_scale_before'], w['theta_before']),
                _theta_text(w['theta_scale'], w['theta'])))
    red = {}
    if comparison:
        for c in comparison['runs']:
            for r in c['windows']:
                red[(c['label'], r['baseline_index'])] = r['peak_reduction_pct']
    n = len(runs)
    width = 0.8 / n
    fig, ax = plt.subplots(figsize=(max(8, 1.6 * len(starts) + 3), 5.2))
    x = np.arange(len(starts))
    top = 0.0
    for j, (r, mm) in enumerate(zip(runs, metrics)):
        vals = np.full(len(starts), np.nan)
        for w in mm['windows']:
            k = int(np.argmin([abs(s - w['t_start']) for s in starts]))
            if abs(starts[k] - w['t_start']) <= 0.05 and w['peak_abs_e'] is not None:
                vals[k] = w['peak_abs_e']
        xs = x - 0.4 + width * (j + 0.5)
        ax.bar(xs, vals, width * 0.92, color=cols[r.label], label='%s (%s)' % (r.label, r.mode))
        top = max(top, np.nanmax(vals) if np.any(np.isfinite(vals)) else 0.0)
        for k in range(len(starts)):
            p = red.get((r.label, k))
            if p is not None and np.isfinite(vals[k]):
                ax.annotate('%+.0f%%' % p, xy=(xs[k], vals[k]), xytext=(0, 2),
                            textcoords='offset points', ha='center', va='bottom', fontsize=8)
    ax.set_xticks(x)
    ax.set_xticklabels(names, fontsize=9)
    ax.set_ylim(0, top * 1.15 if top > 0 else 1)
    ax.set_ylabel('peak |e| in window [rad]')
    ax.set_xlabel('window (from the switch of the true $\\theta$ to the next)')
    ttl = 'Peak output error per window'
    if comparison:
        ttl += " (labels: reduction against '%s')" % comparison['baseline']
    ax.set_title(ttl)
    _legend(ax)
    _save(fig, path)
    plt.close(fig)


def plot_theta(plt, run, m, path, xlim=None):
    fig, axes = plt.subplots(3, 1, sharex=True, figsize=(11, 7.2))
    for i, ax in enumerate(axes):
        ax.plot(run.t_e, run.theta_hat[:, i], color='tab:blue', lw=1.3,
                label=r'$\hat\theta_%d$ estimate' % i, zorder=3)
        ax.plot(run.t_theta, run.theta[:, i], color='tab:red', lw=1.3, ls='--',
                label=r'$\theta_%d$ true' % i, zorder=2)
        _switch_lines(ax, m, annotate=(i == 0))
        _event_lines(ax, run, with_labels=(i == 0))
        _param_change_lines(ax, run, annotate=(i == 0))
        for ev in run.events:
            if _is_paper_reset(ev):
                ax.plot(ev['t'], ev['theta_hat_after'][i], marker='o', ms=5, mfc='none',
                        color=ONSET_COLOR, zorder=4,
                        label=r'reset to $\hat\theta_I$' if ev is _first_reset(run) else None)
        # pa_robust: the estimate each decision set (or kept), the last of each verification
        # labelled with its identification residual against keeping's
        _decision_markers(
            ax, run, lambda ev, i=i: ev['theta_hat_after'][i]
            if ev.get('theta_hat_after') and len(ev['theta_hat_after']) > i else None,
            with_labels=(i == 0), annotate=(i == 0), xlim=xlim)
        ax.set_ylabel(r'$\theta_%d$ %s' % (i, THETA_UNITS[i]))
        _legend(ax)
        _ylim_to_xlim(ax, [(run.t_e, run.theta_hat[:, i]), (run.t_theta, run.theta[:, i])], xlim)
    axes[0].set_title(r"Parameter estimate $\hat\theta$ and true $\theta$: run '%s' (mode %s)"
                      % (run.label, run.mode))
    axes[-1].set_xlabel('time $t$ [s]')
    _xlim(axes[-1], xlim)
    _save(fig, path)
    plt.close(fig)


def _is_paper_reset(ev):
    """An onset that reset theta_hat to the network's theta_hat_I (pa modes; pa_robust's
    onsets carry a decision and are drawn as decisions)."""
    return (ev['type'] == 'onset' and ev.get('reset') and ev.get('theta_hat_after')
            and not ev.get('decision'))


def _first_reset(run):
    for ev in run.events:
        if _is_paper_reset(ev):
            return ev
    return None


def _decision_text(d):
    return '%s%s: %s vs keep %s rad' % (
        d['decision'], ' #%d' % d['chosen'] if d['decision'] == 'memory' else '',
        _fmt(d['score'], '%.2g'), _fmt(d['score_keep'], '%.2g'))


def _decision_markers(ax, run, y_of, with_labels=True, annotate=False, xlim=None):
    """Markers at pa_robust's decisions (onsets and DECISION events): one style per kind
    (DECISION_STYLE), at height y_of(event) (None: not drawn). With `annotate`, the last
    decision of each verification is labelled with its score against keeping's."""
    drawn = []
    for kind, st in DECISION_STYLE.items():
        pts = []
        for ev in run.events:
            if ev.get('decision') != kind:
                continue
            y = y_of(ev)
            if y is not None:
                pts.append((ev['t'], y))
        if pts:
            ax.plot(*zip(*pts), ls='none', marker=st['marker'], ms=7, mew=1.2, mfc='none',
                    color=st['color'], zorder=5,
                    label=('decision: %s' % kind) if with_labels else None)
            drawn.append(kind)
    if annotate:
        evs = [ev for ev in run.events if ev.get('decision')]
        finals = final_decisions([dict(ev, _ev=ev) for ev in evs])
        span = (xlim[1] - xlim[0]) if xlim else float(run.t_e[-1] - run.t_e[0])
        last_t, lift = None, 0
        for d in finals:
            y = y_of(d['_ev'])
            if y is None or (xlim and not xlim[0] <= d['t'] <= xlim[1]):
                continue
            # verifications close together (a re-trigger right after a switch): stack labels
            lift = lift + 11 if last_t is not None and d['t'] - last_t < 0.15 * span else 0
            last_t = d['t']
            ax.annotate(_decision_text(d), xy=(d['t'], y), xytext=(6, 6 + lift),
                        textcoords='offset points', fontsize=7.5, zorder=6,
                        color=DECISION_STYLE[d['decision']]['color'],
                        bbox={'boxstyle': 'round,pad=0.15', 'fc': 'white', 'ec': 'none',
                              'alpha': 0.75}, annotation_clip=True)
    return drawn


def plot_elevator(plt, run, m, path, xlim=None):
    fig, ax = plt.subplots(figsize=(11, 4.8))
    ax.plot(run.t_u, run.u, color='tab:blue', lw=1.3, label=r'$u = u_{bl} + u_{ad}$', zorder=3)
    if run.u_bl is not None:
        ax.plot(run.t_u, run.u_bl, color='tab:gray', lw=1.0, ls='--',
                label=r'$u_{bl} = -Kx$ (baseline)', zorder=2)
        ax.plot(run.t_u, run.u_ad, color='tab:purple', lw=1.0, ls='-.',
                label=r'$u_{ad} = -\hat\theta^T x$ (adaptive)', zorder=2)
    _switch_lines(ax, m)
    _event_lines(ax, run)
    _param_change_lines(ax, run)
    ax.set_ylabel(r'elevator command $u$ [rad]')
    ax.set_xlabel('time $t$ [s]')
    ax.set_title("Elevator command: run '%s' (mode %s; from %s)" % (run.label, run.mode, run.u_source))
    _legend(ax)
    ser = [(run.t_u, run.u)] + ([(run.t_u, run.u_bl), (run.t_u, run.u_ad)] if run.u_bl is not None else [])
    _ylim_to_xlim(ax, ser, xlim)
    _xlim(ax, xlim)
    _save(fig, path)
    plt.close(fig)


def plot_decisions(plt, run, path):
    """pa_robust's verifications: the RMS identification residual of the estimate each
    decision set or kept (score, marker per kind) against keeping the pre-switch estimate
    (score_keep), decision by decision; the verifications (from each onset) are separated
    and labelled with their time and what they settled on."""
    decs = [ev for ev in run.events if ev.get('decision')]
    fig, ax = plt.subplots(figsize=(11, 4.8))
    k = np.arange(1, len(decs) + 1)
    keep = [ev['score_keep'] for ev in decs]
    ax.plot(k, keep, color='0.25', lw=0.8, ls='--', marker='x', ms=5, zorder=3,
            label='score_keep: keeping the pre-switch estimate')
    for kind, st in DECISION_STYLE.items():
        pts = [(kk, ev['score']) for kk, ev in zip(k, decs) if ev['decision'] == kind]
        if pts:
            ax.plot(*zip(*pts), ls='none', marker=st['marker'], ms=8, color=st['color'],
                    zorder=4, label='score: %s' % kind)
    pos = [v for v in keep + [ev['score'] for ev in decs] if v is not None and v > 0]
    if pos:
        ax.set_yscale('log')
    starts = [i for i, ev in enumerate(decs) if ev['type'] == 'onset' or i == 0]
    for j, i0 in enumerate(starts):
        i1 = starts[j + 1] if j + 1 < len(starts) else len(decs)
        if i0 > 0:
            ax.axvline(i0 + 0.5, color=ONSET_COLOR, lw=1.0, zorder=1)
        last = decs[i1 - 1]
        ax.annotate('onset %.3f s\n-> %s%s\n%s vs %s rad' % (
            decs[i0]['t'], last['decision'],
            ' #%d' % last['chosen'] if last['decision'] == 'memory' else '',
            _fmt(last['score'], '%.2g'), _fmt(last['score_keep'], '%.2g')),
            xy=(i0 + 0.6, 1.0), xycoords=('data', 'axes fraction'), xytext=(2, -3),
            textcoords='offset points', va='top', ha='left', fontsize=7.5, color='0.25')
    ax.plot([], [], color=ONSET_COLOR, lw=1.0, label='a new verification (onset)')
    ax.set_xlim(0.5, len(decs) + 0.5)
    if pos:
        lo, hi = min(pos), max(pos)
        ax.set_ylim(lo / 3.0, hi * 30.0)  # room for the labels at the top
    ax.set_xlabel('decision # (onsets and DECISION events, in time order)')
    ax.set_ylabel('RMS identification residual [rad]')
    ax.set_title("pa_robust verification: run '%s' (mode %s), %d decisions" % (
        run.label, run.mode, len(decs)))
    _legend(ax)
    _save(fig, path)
    plt.close(fig)


def plot_cost(plt, runs, baseline, path):
    cols = _run_colors(runs, baseline)
    fig, ax = plt.subplots(figsize=(9, 4.8))
    any_pts = False
    max_k = 1
    for r in runs:
        rec = [ev for ev in r.events if ev['type'] == 'recovered' and ev.get('cost') is not None]
        if not rec:
            continue
        any_pts = True
        max_k = max(max_k, len(rec))
        k = np.arange(1, len(rec) + 1)
        cost = [ev['cost'] for ev in rec]
        ax.plot(k, cost, color=cols[r.label], lw=1.0, marker='o', ms=6,
                label='%s (%s)' % (r.label, r.mode))
        learned = [(kk, c) for kk, c, ev in zip(k, cost, rec) if ev.get('learned')]
        if learned:
            ax.plot(*zip(*learned), ls='none', marker='o', ms=9, mfc='none', mew=1.5,
                    color='k', label='network updated (learned)')
        for kk, c, ev in zip(k, cost, rec):
            ax.annotate('%.4g s' % ev['t'], xy=(kk, c), xytext=(4, 4), textcoords='offset points',
                        fontsize=7, color='0.3', annotation_clip=True)
    if any_pts:
        _legend(ax)
        from matplotlib.ticker import MaxNLocator
        ax.xaxis.set_major_locator(MaxNLocator(integer=True, min_n_ticks=1))
        ax.set_xlim(0.5, max_k + 0.6)
        ax.set_ylim(0, ax.get_ylim()[1] * 1.08)
    else:
        ax.text(0.5, 0.5, 'no RECOVERED events with a cost E in these runs',
                transform=ax.transAxes, ha='center', va='center', fontsize=12, color='0.3')
        ax.set_ylim(bottom=0)
    ax.set_xlabel('adaptation phase (episode) # = k-th recovery event')
    ax.set_ylabel(r'cost $E=\int_{t_u}^{t_d}|e|\,dt$ [rad s]')
    ax.set_title('Cost of each adaptation phase (learning episode); labels: time of $E_d$')
    _save(fig, path)
    plt.close(fig)


def write_figures(out_dir, runs, metrics, comparison, c_e=0.005, xlim=None):
    """All PNG figures; returns their paths."""
    plt = _mpl()
    baseline = comparison['baseline'] if comparison else None
    files = []
    for r, m in zip(runs, metrics):
        s = _safe(r.label)
        for name, fn, args in (('alpha_%s.png' % s, plot_alpha, (c_e, xlim)),
                               ('theta_hat_%s.png' % s, plot_theta, (xlim,)),
                               ('elevator_%s.png' % s, plot_elevator, (xlim,))):
            p = os.path.join(out_dir, name)
            fn(plt, r, m, p, *args)
            files.append(p)
        if any(ev.get('decision') for ev in r.events):
            p = os.path.join(out_dir, 'decisions_%s.png' % s)
            plot_decisions(plt, r, p)
            files.append(p)
    if len(runs) > 1:
        p = os.path.join(out_dir, 'alpha_compare.png')
        order = sorted(range(len(runs)), key=lambda i: runs[i].label != baseline)
        plot_compare(plt, [runs[i] for i in order], [metrics[i] for i in order], baseline, p, xlim)
        files.append(p)
    p = os.path.join(out_dir, 'peak_per_window.png')
    plot_peaks(plt, runs, metrics, comparison, baseline, p)
    files.append(p)
    p = os.path.join(out_dir, 'cost_per_episode.png')
    plot_cost(plt, runs, baseline, p)
    files.append(p)
    return files


def analyze(paths, out_dir=None, labels=None, baseline=None, c_e=0.005, xlim=None,
            figures=True, stream=sys.stdout):
    """The whole pipeline; returns (metrics, comparison, files written)."""
    runs = load_inputs(paths, labels)
    metrics = [run_metrics(r) for r in runs]
    base = choose_baseline(metrics, baseline)
    comparison = compare(metrics, base) if len(metrics) > 1 else None
    if stream is not None:
        print(format_report(metrics, comparison), file=stream)
    files = []
    if out_dir:
        os.makedirs(out_dir, exist_ok=True)
        settings = {'inputs': [os.path.abspath(p) for p in paths], 'c_e': c_e,
                    'baseline': comparison['baseline'] if comparison else None,
                    'xlim': list(xlim) if xlim else None}
        write_tables(out_dir, metrics, comparison, settings)
        files = [os.path.join(out_dir, 'metrics.json'), os.path.join(out_dir, 'metrics.csv')]
        if figures:
            files += write_figures(out_dir, runs, metrics, comparison, c_e, xlim)
    return metrics, comparison, files
