"""live_plot: scrolling plot of message fields, with rqt_plot's topic/field syntax.

    scripts/live_plot /controller/status/e /plant/state/alpha /controller/status/alpha_ref
    scripts/live_plot /plant/state/x[1] /controller/status/theta_hat_0:theta_hat_1:theta_hat_2
    scripts/live_plot /controller/elevator_cmd/u --window 30
    scripts/live_plot /plant/state/alpha --headless --duration 20 --save alpha.png

Each argument is TOPIC/FIELD as in rqt_plot (not packaged in Debian 12):
  /plant/state/alpha           a field (the topic is the longest published topic that is a
                               prefix; nested fields with '/': /plant/state/header/stamp)
  /plant/state/x[1]            one element of an array field
  /controller/status/e:e_dot_est   several fields of one topic (one line each)
  /controller/status/theta_hat an array without an index: one line per element
A TOPIC without a leading '/' is relative, resolved in the node's namespace as any ROS name
(plant/state/alpha is /run_a/plant/state/alpha for a live_plot started in run_a).
The x axis is the message's header stamp (simulation time in lockstep, wall time in
realtime), or the time of receipt for messages without a header, in seconds from the first
sample; the window shows the last --window seconds and scrolls.

Options: --window S (10), --rate HZ redraws per second (10), --duration S stop after S
seconds of wall time (default: until Ctrl-C, the window is closed or the master goes), --save
PNG write the figure there at the end, --headless no window (matplotlib Agg; use with --save),
--wait S give up when a topic is not published after S seconds (default: wait, with a warning
after 5 s), --title TEXT.

At the end it prints one line per line plotted: "live_plot: SPEC: N points". Exit codes: 0;
2 a malformed argument or a field the topic's messages do not have or that is not a number
(one line naming it and listing the fields there are); 1 a topic not published within --wait.
Messages are deserialised from the definition their publisher sends (rospy.AnyMsg + genpy),
so any topic of any package can be plotted without its Python messages.
"""

import argparse
import collections
import re
import signal
import sys
import threading
import time

_SPEC_RE = re.compile(r'^(/[A-Za-z0-9_~/\[\]:]*)$')
_PART_RE = re.compile(r'^([A-Za-z_][A-Za-z0-9_]*)((?:\[[0-9]+\])*)$')


class SpecError(Exception):
    pass


def split_fields(rest):
    """'x[1]' -> [('x', [1])]; 'header/stamp' -> [('header', []), ('stamp', [])]."""
    path = []
    for part in rest.split('/'):
        m = _PART_RE.match(part)
        if not m:
            raise SpecError("'%s' is not a field name (letters, digits, _ and [index])" % part)
        path.append((m.group(1), [int(i) for i in re.findall(r'\[([0-9]+)\]', m.group(2))]))
    return path


def parse_spec(spec, topics):
    """rqt_plot syntax against the published topic names: returns (topic, [field path text,
    ...]). Raises SpecError for a malformed spec; returns None when no topic matches yet."""
    if not _SPEC_RE.match(spec) or spec.endswith('/') or '//' in spec:
        raise SpecError('%s: expected /TOPIC/FIELD, e.g. /plant/state/alpha' % spec)
    best = None
    for t in topics:
        if spec.startswith(t.rstrip('/') + '/') and (best is None or len(t) > len(best)):
            best = t.rstrip('/')
    if best is None:
        if spec in topics:
            raise SpecError('%s: a topic, not a field of it; e.g. %s/FIELD' % (spec, spec))
        return None
    rest = spec[len(best) + 1 :]
    # rqt_plot's "topic/field1:field2": alternatives share the path before the last '/'.
    head, _, last = rest.rpartition('/')
    fields = [(head + '/' + f) if head else f for f in last.split(':')]
    for f in fields:
        if not f:
            raise SpecError('%s: an empty field in a:b' % spec)
        split_fields(f)
    return best, fields


def absolute_spec(spec, namespace):
    """A relative spec ('plant/state/alpha') joined to the node's namespace ('/run_a/'), as
    rospy resolves a relative topic name; an absolute one as it is."""
    if spec.startswith('/'):
        return spec
    return '/' + (namespace.strip('/') + '/' if namespace.strip('/') else '') + spec


def field_names(msg):
    return list(getattr(msg, '__slots__', []))


def resolve(msg, path, text, topic):
    """The value at `path` in `msg`, as a list of (label suffix, float)."""
    v = msg
    for name, idx in path:
        if not hasattr(v, '__slots__') or name not in v.__slots__:
            raise SpecError(
                '%s/%s: %s has no field %s (its fields: %s)'
                % (
                    topic,
                    text,
                    getattr(v, '_type', type(v).__name__),
                    name,
                    ', '.join(field_names(v)) or 'none',
                )
            )
        v = getattr(v, name)
        for i in idx:
            if not isinstance(v, (list, tuple, bytes)):
                raise SpecError('%s/%s: %s is not an array' % (topic, text, name))
            if i >= len(v):
                raise SpecError(
                    '%s/%s: index %d outside %s (length %d)' % (topic, text, i, name, len(v))
                )
            v = v[i]
    if hasattr(v, 'to_sec'):  # rospy Time / Duration
        return [('', v.to_sec())]
    if isinstance(v, bool) or isinstance(v, (int, float)):
        return [('', float(v))]
    if isinstance(v, (list, tuple)) and all(isinstance(x, (int, float)) for x in v):
        return [('[%d]' % i, float(x)) for i, x in enumerate(v)]
    raise SpecError(
        '%s/%s: not a number but %s; give a field of it (its fields: %s)'
        % (topic, text, getattr(v, '_type', type(v).__name__), ', '.join(field_names(v)))
    )


class Series:
    """The samples of one plotted line, trimmed to what the window can show."""

    def __init__(self, label):
        self.label = label
        self.t = collections.deque()
        self.v = collections.deque()
        self.count = 0


class TopicFeed:
    """One subscription (dynamic_msgs.DynamicSubscriber: rospy.AnyMsg + a class generated from
    the connection header) and the lines it feeds."""

    def __init__(self, subscriber_class, topic, fields, plot):
        self.topic = topic
        self.fields = [(f, split_fields(f)) for f in fields]
        self.plot = plot
        self.sub = subscriber_class(topic, self.on_msg, 200, warn_label=None)

    def on_msg(self, msg):
        h = getattr(msg, 'header', None)
        stamp = h.stamp.to_sec() if h is not None and hasattr(h, 'stamp') else 0.0
        t = stamp if stamp > 0.0 else time.time()
        try:
            values = [(text, resolve(msg, path, text, self.topic)) for text, path in self.fields]
        except SpecError as e:
            self.plot.fail(str(e))
            return
        self.plot.add(self.topic, t, values)


class Plot:
    def __init__(self, args):
        self.args = args
        self.lock = threading.Lock()
        self.series = collections.OrderedDict()
        self.t0 = None
        self.t_last = None
        self.error = None

    def fail(self, text):
        with self.lock:
            if self.error is None:
                self.error = text

    def add(self, topic, t, values):
        keep = self.args.window * 1.5
        with self.lock:
            if self.t0 is None:
                self.t0 = t
            x = t - self.t0
            self.t_last = x if self.t_last is None else max(self.t_last, x)
            for text, items in values:
                for suffix, v in items:
                    label = '%s/%s%s' % (topic, text, suffix)
                    s = self.series.get(label)
                    if s is None:
                        s = self.series[label] = Series(label)
                    s.t.append(x)
                    s.v.append(v)
                    s.count += 1
                    while s.t and s.t[0] < x - keep:
                        s.t.popleft()
                        s.v.popleft()


def window_title(node_name, title, specs):
    """The window's title: what it plots and which node draws it, so two windows differ (the
    default, matplotlib's "Figure 1", is the same for every process)."""
    return '%s (%s)' % (title or ' '.join(specs), node_name)


def main(description=__doc__):
    ap = argparse.ArgumentParser(
        prog='live_plot',
        description=description.split('\n\n')[0],
        formatter_class=argparse.RawDescriptionHelpFormatter,
        epilog='\n'.join(description.split('\n')[1:]),
    )
    ap.add_argument('specs', nargs='+', metavar='[/]TOPIC/FIELD')
    ap.add_argument('--window', type=float, default=10.0)
    ap.add_argument('--rate', type=float, default=10.0)
    ap.add_argument('--duration', type=float, default=0.0)
    ap.add_argument('--save', default='')
    ap.add_argument('--headless', action='store_true')
    ap.add_argument('--wait', type=float, default=0.0)
    ap.add_argument('--title', default='')
    # roslaunch (plot:=true) appends __name:= and __log:= (and any remapping): left out, as
    # rospy.myargv does.
    args = ap.parse_args([a for a in sys.argv[1:] if ':=' not in a])
    for name in ('window', 'rate'):
        value = getattr(args, name)
        if not value > 0:
            ap.exit(2, 'live_plot: error: --%s: must be > 0, got %s\n' % (name, value))
    for name in ('duration', 'wait'):
        value = getattr(args, name)
        if not value >= 0:
            ap.exit(2, 'live_plot: error: --%s: must be >= 0, got %s\n' % (name, value))
    if args.headless and not args.save:
        ap.exit(2, 'live_plot: error: --headless draws no window: give --save PNG\n')
    # Syntax first (no master needed), so a typo is refused at once.
    try:
        for s in args.specs:
            parse_spec(absolute_spec(s, '/'), [])
    except SpecError as e:
        ap.exit(2, 'live_plot: error: %s\n' % e)

    import matplotlib

    if args.headless:
        matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    import rosgraph
    import rospy

    from preadaptive_mrac.viz.dynamic_msgs import DynamicSubscriber

    rospy.init_node('live_plot', anonymous=True, disable_signals=True)
    stop = threading.Event()
    signal.signal(signal.SIGINT, lambda *_: stop.set())
    signal.signal(signal.SIGTERM, lambda *_: stop.set())
    plot = Plot(args)
    master = rosgraph.Master(rospy.get_name())
    # Relative specs follow the node's namespace, so a launch file included in a user's
    # <group ns> plots its own run (scenario.launch plot:=true).
    pending = [absolute_spec(s, rospy.get_namespace()) for s in args.specs]
    feeds = {}
    start = time.monotonic()
    warned = False

    fig, ax = plt.subplots(figsize=(9, 5))
    ax.set_xlabel('t [s] (from the first sample)')
    ax.grid(True, alpha=0.3)
    if args.title:
        ax.set_title(args.title)
    fig.canvas.manager.set_window_title(window_title(rospy.get_name(), args.title, args.specs))
    lines = {}
    if not args.headless:
        plt.show(block=False)
    period = 1.0 / args.rate
    rc = 0
    while not stop.is_set() and not rospy.is_shutdown():
        now = time.monotonic()
        if pending:
            try:
                topics = [t for t, _ in master.getPublishedTopics('/')]
            except Exception:  # the master went away
                topics = []
            for spec in list(pending):
                try:
                    found = parse_spec(spec, topics)
                except SpecError as e:
                    plot.fail(str(e))
                    break
                if found is None:
                    continue
                topic, fields = found
                if topic in feeds:  # one subscription per topic
                    feeds[topic].fields += [(f, split_fields(f)) for f in fields]
                else:
                    feeds[topic] = TopicFeed(DynamicSubscriber, topic, fields, plot)
                pending.remove(spec)
            if pending and now - start > 5.0 and not warned:
                print(
                    'live_plot: waiting for %s (no published topic is a prefix yet)'
                    % ', '.join(pending),
                    file=sys.stderr,
                )
                warned = True
            if pending and args.wait > 0 and now - start > args.wait:
                print(
                    'live_plot: error: %s: no published topic is a prefix of it after %g s'
                    % (', '.join(pending), args.wait),
                    file=sys.stderr,
                )
                rc = 1
                break
        with plot.lock:
            if plot.error:
                break
            snapshot = [(s.label, list(s.t), list(s.v)) for s in plot.series.values()]
            t_last = plot.t_last
        for label, ts, vs in snapshot:
            if label not in lines:
                (lines[label],) = ax.plot([], [], label=label, linewidth=1.5)
                ax.legend(loc='upper left', fontsize='small')
            lines[label].set_data(ts, vs)
        if t_last is not None:
            ax.set_xlim(max(0.0, t_last - args.window), max(t_last, args.window))
            lo = [min(v) for _, ts, v in snapshot if v]
            hi = [max(v) for _, ts, v in snapshot if v]
            if lo:
                pad = 0.05 * (max(hi) - min(lo)) or 1e-3
                ax.set_ylim(min(lo) - pad, max(hi) + pad)
        if args.headless:
            time.sleep(period)
        else:
            if not plt.fignum_exists(fig.number):
                break  # window closed
            fig.canvas.draw_idle()
            plt.pause(period)
        if args.duration > 0 and time.monotonic() - start >= args.duration:
            break
    if plot.error:
        print('live_plot: error: %s' % plot.error, file=sys.stderr)
        rc = 2
    if args.save and rc != 2:
        fig.savefig(args.save, dpi=100)
        print('live_plot: saved %s' % args.save)
    with plot.lock:
        for s in plot.series.values():
            print('live_plot: %s: %d points' % (s.label, s.count))
    rospy.signal_shutdown('done')
    sys.exit(rc)
