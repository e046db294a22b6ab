"""Reading runs from ROS bags (single-run or compare.launch). Needs Debian's python3-rosbag."""

import os
import struct

import numpy as np

from . import bag_chunks
from .runs import (
    EVENT_TYPES,
    InputError,
    REQUIRED,
    Run,
    TOPICS,
    WHY,
    _gust_from_conditions,
    _msg_decision,
    _rebase_epoch,
)


def _is_bag(path):
    with open(path, 'rb') as f:
        return f.read(13) == b'#ROSBAG V2.0\n'


def _stamp_times(stamps, bag_times):
    """Header stamps as float seconds; bag receive times if every stamp is zero."""
    s = np.asarray(stamps, dtype=float)
    if s.size and not np.any(s):
        return np.asarray(bag_times, dtype=float), True
    return s, False


def _index_pos(path):
    """The file header's index_pos (0: the recorder never wrote the index), or None when the
    file header itself cannot be read."""
    try:
        with open(path, 'rb') as f:
            f.seek(13)
            (hlen,) = struct.unpack('<I', f.read(4))
            if hlen > 4096:
                return None
            header = f.read(hlen)
        pos = 0
        while pos + 4 <= len(header):
            (flen,) = struct.unpack_from('<I', header, pos)
            field = header[pos + 4 : pos + 4 + flen]
            pos += 4 + flen
            name, _, value = field.partition(b'=')
            if name == b'index_pos' and len(value) == 8:
                return struct.unpack('<Q', value)[0]
    except (OSError, struct.error):
        return None
    return None


def _corrupt(path, what):
    return InputError(
        path,
        'corrupt bag (damaged file: %s); `rosbag reindex %s` may recover the messages before '
        'the damage' % (what, path),
    )


def _open_bag(rosbag, path, skip_index):
    try:
        return rosbag.Bag(path, 'r', skip_index=skip_index)
    except rosbag.ROSBagUnindexedException:
        # rosbag says "unindexed" for any failure while reading the index: only a bag whose
        # header has no index position was left open by its recorder.
        pos = _index_pos(path)
        if pos is None:
            raise _corrupt(path, 'its file header cannot be read')
        if pos != 0:
            raise _corrupt(path, 'its index at byte %d cannot be read' % pos)
        raise InputError(
            path,
            'unindexed bag (the recorder did not close it: %s); run '
            '`rosbag reindex %s` and analyse it again'
            % (
                'still being recorded or killed'
                if path.endswith('.active')
                else 'killed or crashed',
                path,
            ),
        )
    except (rosbag.ROSBagException, OSError, ValueError) as ex:
        raise InputError(path, 'cannot read the bag: %s' % ex)
    except Exception as ex:  # a damaged record rosbag does not name (struct.error & co.)
        raise _corrupt(path, '%s: %s' % (type(ex).__name__, ex))


def _load_bag(path):
    try:
        import rosbag
    except ImportError:
        raise InputError(
            path,
            'reading bags needs ROS\' rosbag module: run with /usr/bin/python3 '
            '(Debian package python3-rosbag)',
        )
    # The chunk reader (bag_chunks.py) reads the index itself: rosbag opens the bag without it,
    # and again with it (read_messages) for any bag the chunk reader does not handle.
    bag = _open_bag(rosbag, path, True)
    try:
        fast = bag_chunks.ChunkReader(bag)
    except Exception:  # not a bag for it (bag_chunks.Unsupported) or one it misreads: rosbag's
        fast = None  # own reading gives the answer or the error it always gave
    if fast is None:
        bag.close()
        bag = _open_bag(rosbag, path, False)
    try:
        return _read_bag(bag, path, fast, lambda: _open_bag(rosbag, path, False))
    except InputError:
        raise
    except Exception as ex:  # a record that cannot be read: a bit flip, a cut, ...
        raise _corrupt(path, 'a record cannot be read: %s: %s' % (type(ex).__name__, ex))
    finally:
        bag.close()


def _read_messages(bag, topics):
    """{topic: [(message, bag time [s])]} through rosbag's read_messages."""
    out = {}
    for topic, msg, bt in bag.read_messages(topics=topics):
        out.setdefault(topic, []).append((msg, bt.to_sec()))
    return out


def _read_topics(bag, topics, fast, reopen):
    if fast is not None:
        try:
            return fast.read(topics)
        except Exception:  # as above: read_messages answers, or raises what it raises
            full = reopen()
            try:
                return _read_messages(full, topics)
            finally:
                full.close()
    return _read_messages(bag, topics)


def _read_bag(bag, path, fast=None, reopen=None):
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
        raise InputError(
            path,
            'no preadaptive_mrac run in the bag: expected topics %s; the '
            'bag has %s' % (', '.join('/' + TOPICS[k][0] for k in REQUIRED), found),
        )
    missing = []
    for ns in runs_ns:
        for k in REQUIRED:
            if k not in groups[ns]:
                missing.append('%s/%s (%s, for %s)' % (ns, TOPICS[k][0], TOPICS[k][1], WHY[k]))
    if missing:
        raise InputError(
            path, 'missing topic%s %s' % ('s' if len(missing) > 1 else '', '; '.join(missing))
        )
    topic_to = {}
    for ns in runs_ns:
        for k, tp in groups[ns].items():
            topic_to[tp] = (ns, k)
    acc = {ns: {k: [] for k in TOPICS} for ns in runs_ns}
    for topic, pairs in _read_topics(bag, list(topic_to), fast, reopen).items():
        ns, k = topic_to[topic]
        acc[ns][k].extend(pairs)
    runs = []
    stem = os.path.basename(path)
    for suffix in ('.active', '.bag'):
        if stem.endswith(suffix):
            stem = stem[: -len(suffix)]
    for ns in runs_ns:
        label = ns.strip('/').replace('/', '_') or stem
        run = Run(label, path, ns)
        _fill_from_bag(run, acc[ns], path)
        _flag_non_finite(run)
        if '.incomplete.' in os.path.basename(path):
            run.notes.append(
                'WARNING: incomplete recording (the recorder named it so: the run stopped '
                'early or messages were lost); metrics cover only what was recorded'
            )
        runs.append(run)
    runs.sort(key=lambda r: (r.mode != 'rac', r.namespace))  # regular adaptive control first
    return runs


def _flag_non_finite(run):
    """A WARNING note for each recorded series holding NaN or infinite values: the metrics of
    such a run (printed '-', null in metrics.json) are not numbers."""
    ns = run.namespace
    series = (
        ('%s/controller/status e' % ns, run.e),
        ('%s/controller/status theta_hat' % ns, run.theta_hat),
        ('%s/plant/state alpha' % ns, run.alpha),
        ('%s/plant/truth theta' % ns, run.theta),
        (run.u_source + ' u', run.u),
    )
    for name, v in series:
        v = np.asarray(v, dtype=float)
        bad = ~np.isfinite(v)
        if bad.any():
            run.notes.append(
                'WARNING: %d non-finite value(s) (NaN or inf) in %s: metrics that use them '
                'are not numbers' % (int(bad.sum()), name)
            )


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
    run.theta_hat = np.array(
        [
            list(m.theta_hat)
            if len(m.theta_hat) == 3
            else [m.theta_hat_0, m.theta_hat_1, m.theta_hat_2]
            for m, _ in st
        ],
        dtype=float,
    )
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

    # PlantState.elevator is what the plant applied over [t - dt, t]; shown beside
    # the command when the plant says what it was commanded (bags recorded before the field
    # existed have no elevator_command) and the two differ (delay, lag or limits on).
    if ps and hasattr(ps[0][0], 'elevator_command') and dt:
        applied = np.array([m.elevator for m, _ in ps], dtype=float)
        commanded = np.array([m.elevator_command for m, _ in ps], dtype=float)
        if np.any(applied != commanded):
            run.t_applied, run.u_applied = run.t_alpha[1:] - dt, applied[1:]
    # The plant's conditions record by name (PlantTruth.conditions): values of the
    # previous step are moved to the step they belong to. Bags recorded before the record
    # existed have gust_w alone.
    if tr and getattr(tr[0][0], 'condition_names', None):
        names = list(tr[0][0].condition_names)
        prev = list(tr[0][0].condition_of_previous_step)
        vals = np.array([list(m.conditions) for m, _ in tr], dtype=float)
        for i, name in enumerate(names):
            if i < len(prev) and prev[i] and dt:
                run.conditions[name] = (run.t_theta[1:] - dt, vals[1:, i])
            else:
                run.conditions[name] = (run.t_theta, vals[:, i])
        _gust_from_conditions(run)
    elif tr and hasattr(tr[0][0], 'gust_w'):
        gust = np.array([m.gust_w for m, _ in tr], dtype=float)
        if np.any(gust != 0.0):
            run.t_gust, run.gust_w = run.t_theta, gust

    # the plant's first exit from the flight envelope (bags before it have no field)
    for m, _ in tr:
        if getattr(m, 'envelope_exit', ''):
            run.envelope_exit = m.envelope_exit
            break

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
        tname = (
            m.type_name
            if m.type_name in EVENT_TYPES
            else (EVENT_TYPES[m.type] if m.type < len(EVENT_TYPES) else 'type%d' % m.type)
        )
        ev = {
            'type': tname,
            't': float(t),
            'e': m.e,
            'e_dot': m.e_dot_est,
            'theta_hat_before': list(m.theta_hat_before) or None,
            'theta_hat_after': list(m.theta_hat_after) or None,
            'reset': bool(m.reset),
            'cost': m.cost if tname == 'recovered' else None,
            'grad': list(m.grad) or None,
            'learned': bool(m.learned),
            'episodes': int(m.episodes),
        }
        ev.update(_msg_decision(m))
        run.events.append(ev)
        run.episodes = max(run.episodes or 0, int(m.episodes))
    if not acc['attention']:
        run.notes.append('no %s/controller/attention messages: no attention events' % ns)
    for m, _ in acc.get('param_change', []):
        run.param_changes.append(
            {
                't': float(m.t),
                'step': int(m.step),
                'name': m.name,
                'old_value': m.old_value,
                'new_value': m.new_value,
            }
        )
        run.notes.append(
            '%s: %.6g -> %.6g at t = %.6g s (step %d)'
            % (m.name, m.old_value, m.new_value, m.t, m.step)
        )
    _rebase_epoch(run)
