"""VizMarkers: the rviz MarkerArray (aircraft, velocity arrow, text, alpha history) and the
optional tf of a preadaptive_mrac run; see scripts/viz_markers for topics and parameters."""

import collections
import math
import threading
import time

import rospy
from geometry_msgs.msg import Point, Quaternion, TransformStamped, Vector3
from std_msgs.msg import ColorRGBA
from visualization_msgs.msg import Marker, MarkerArray
from .. import params_table
from .dynamic_msgs import DynamicSubscriber, EVENT_NAMES, tf_message_class


def _quat_y(angle):
    """Rotation about y by `angle` [rad] (REP 103: a nose-up pitch is a negative angle)."""
    return Quaternion(0.0, math.sin(0.5 * angle), 0.0, math.cos(0.5 * angle))


def _color(r, g, b, a=1.0):
    return ColorRGBA(r, g, b, a)


def flight_of(truth):
    """The flight outputs of a six-degree-of-freedom plant (plant.engine jsbsim) from a
    PlantTruth's conditions record: {pitch, airspeed, altitude, flight_path}, or None when the
    plant is the linear model (its record has no such rows)."""
    if truth is None:
        return None
    c = dict(zip(getattr(truth, 'condition_names', []), getattr(truth, 'conditions', [])))
    if not all(n in c for n in FLIGHT_ROWS):
        return None
    return {n: c[n] for n in FLIGHT_ROWS}


FLIGHT_ROWS = ('pitch', 'airspeed', 'altitude', 'flight_path')


def _t_of(msg):
    """Sample time of a message: its `t` field if the definition has one, else the stamp."""
    t = getattr(msg, 't', None)
    return float(t) if isinstance(t, float) else msg.header.stamp.to_sec()


class VizMarkers:
    def __init__(self):
        # Defaults and ranges from the one table (params/nodes.yaml's viz_markers rows).
        v, problems = params_table.read_node_params(
            'viz_markers', rospy.get_param('~', {}), rospy.resolve_name('~')
        )
        self.world, self.body, self.velocity = (
            v['world_frame'],
            v['body_frame'],
            v['velocity_frame'],
        )
        self.rate, self.history, self.history_points = v['rate'], v['history'], v['history_points']
        self.alpha_scale, self.publish_tf = v['alpha_scale'], v['publish_tf']
        # (the row's `non-empty`: no check of the table can say it)
        for key in ('world_frame', 'body_frame', 'velocity_frame'):
            if v[key] == '':
                problems.append('%s%s: must not be empty' % (rospy.resolve_name('~'), key))
        if problems:
            for p in problems:
                rospy.logfatal('viz_markers: %s' % p)
            raise SystemExit(2)

        self.lock = threading.Lock()
        self.state = None
        self.status = None
        self.truth = None
        self.altitude0 = None  # a JSBSim run's first altitude (the text shows the change)
        self.last_event = None
        self.events = collections.deque(maxlen=200)
        self.hist = collections.deque()  # (t, alpha, alpha_ref)
        self.alpha_ref = None
        self.tf_pub = None
        if self.publish_tf:
            self.tf_cls = tf_message_class()
            # relative, like the plant's: /tf at the top level, the run's own in a namespace
            self.tf_pub = rospy.Publisher('tf', self.tf_cls, queue_size=100)
        self.pub = rospy.Publisher('aircraft_markers', MarkerArray, queue_size=2)
        self.subs = [
            DynamicSubscriber('plant/state', self.on_state, 200),
            DynamicSubscriber('controller/status', self.on_status, 200),
            DynamicSubscriber('controller/attention', self.on_attention, 100),
            DynamicSubscriber('plant/truth', self.on_truth, 10),
        ]
        self.n_published = 0
        self._last_tf_step = None

    # ---------------------------------------------------------------- callbacks
    def on_state(self, msg):
        t = _t_of(msg)
        with self.lock:
            if self.hist and t < self.hist[-1][0] - 1e-9:
                # time went back: a new run (or a bag looped); start the history afresh
                self.hist.clear()
                self.altitude0 = None
                self.events.clear()
                self.last_event = None
            self.state = msg
            min_dt = self.history / self.history_points
            if not self.hist or t - self.hist[-1][0] >= min_dt:
                self.hist.append((t, msg.alpha, self.alpha_ref))
            while self.hist and self.hist[0][0] < t - self.history:
                self.hist.popleft()
        if self.tf_pub is not None:
            self._send_tf(msg)

    def on_status(self, msg):
        with self.lock:
            self.status = msg
            self.alpha_ref = msg.alpha_ref

    def on_attention(self, msg):
        name = msg.type_name or (EVENT_NAMES[msg.type] if msg.type < len(EVENT_NAMES) else '?')
        ev = {
            'type': name,
            't': _t_of(msg),
            'e': msg.e,
            'e_dot': msg.e_dot_est,
            'reset': bool(msg.reset),
            'cost': msg.cost,
            'learned': bool(msg.learned),
            # pa_robust's verification (absent from older message definitions)
            'decision': getattr(msg, 'decision', '') or '',
            'score': getattr(msg, 'score', 0.0),
            'score_keep': getattr(msg, 'score_keep', 0.0),
        }
        with self.lock:
            self.last_event = ev
            self.events.append(ev)

    def on_truth(self, msg):
        with self.lock:
            self.truth = msg

    def _send_tf(self, msg):
        stamp = msg.header.stamp
        if self._last_tf_step is not None and msg.step == self._last_tf_step:
            return
        self._last_tf_step = msg.step
        tfs = []
        # The velocity vector lies alpha below the nose; on a JSBSim run the whole angle of
        # attack, pitch attitude - flight path angle (PlantState.theta_pitch is then JSBSim's
        # pitch attitude).
        with self.lock:
            fl = flight_of(self.truth)
        alpha = fl['pitch'] - fl['flight_path'] if fl is not None else msg.alpha
        for parent, child, angle in (
            (self.world, self.body, -msg.theta_pitch),
            (self.body, self.velocity, alpha),
        ):
            tr = TransformStamped()
            tr.header.stamp = stamp
            tr.header.frame_id = parent
            tr.child_frame_id = child
            tr.transform.rotation = _quat_y(angle)
            tfs.append(tr)
        self.tf_pub.publish(self.tf_cls(transforms=tfs))

    # ---------------------------------------------------------------- markers
    def _marker(self, ns, mid, mtype, frame, frame_locked=False):
        m = Marker()
        m.header.frame_id = frame
        m.header.stamp = rospy.Time(0)  # latest transform
        m.ns = ns
        m.id = mid
        m.type = mtype
        m.action = Marker.ADD
        m.pose.orientation.w = 1.0
        m.frame_locked = frame_locked
        m.lifetime = rospy.Duration(0)
        return m

    def aircraft(self, elevator):
        out = []
        grey = _color(0.82, 0.84, 0.88)
        blue = _color(0.45, 0.62, 0.85)
        m = self._marker('aircraft', 0, Marker.CYLINDER, self.body, True)
        m.pose.orientation = _quat_y(0.5 * math.pi)  # cylinder axis z -> body x
        m.scale = Vector3(0.55, 0.55, 4.6)
        m.color = grey
        out.append(m)
        m = self._marker('aircraft', 1, Marker.SPHERE, self.body, True)
        m.pose.position = Point(2.3, 0.0, 0.0)
        m.scale = Vector3(1.1, 0.55, 0.55)
        m.color = grey
        out.append(m)
        m = self._marker('aircraft', 2, Marker.CUBE, self.body, True)
        m.pose.position = Point(0.2, 0.0, -0.1)
        m.scale = Vector3(1.3, 6.4, 0.09)
        m.color = blue
        out.append(m)
        m = self._marker('aircraft', 3, Marker.CUBE, self.body, True)  # horizontal tail
        m.pose.position = Point(-2.05, 0.0, 0.15)
        m.scale = Vector3(0.5, 2.2, 0.07)
        m.color = blue
        out.append(m)
        m = self._marker('aircraft', 4, Marker.CUBE, self.body, True)  # fin
        m.pose.position = Point(-2.0, 0.0, 0.75)
        m.scale = Vector3(0.8, 0.07, 1.1)
        m.color = blue
        out.append(m)
        # Elevator: a plate hinged at the tail's trailing edge, trailing edge down for u > 0
        # (positive u gives a nose-down moment: B = [0, -0.02, -1.16]).
        d = max(-0.6, min(0.6, elevator))
        hinge_x, half = -2.3, 0.2
        m = self._marker('aircraft', 5, Marker.CUBE, self.body, True)
        m.pose.position = Point(hinge_x - half * math.cos(d), 0.0, 0.15 - half * math.sin(d))
        m.pose.orientation = _quat_y(d)
        m.scale = Vector3(2 * half, 2.2, 0.05)
        m.color = _color(0.95, 0.85, 0.3)
        out.append(m)
        return out

    def velocity_arrow(self):
        m = self._marker('velocity', 0, Marker.ARROW, self.velocity, True)
        m.points = [Point(0.0, 0.0, 0.0), Point(4.8, 0.0, 0.0)]
        m.scale = Vector3(0.09, 0.24, 0.45)
        m.color = _color(0.2, 0.95, 0.95)
        return [m]

    def texts(self, state, status, truth, ev):
        lines = []
        t = _t_of(state) if state is not None else None
        mode = status.mode if status is not None else '?'
        eps = status.episodes if status is not None else 0
        lines.append(
            (
                ('t = %.3f s, mode %s, episodes %d' % (t, mode, eps))
                if t is not None
                else 'waiting for plant/state ...',
                _color(1, 1, 1),
            )
        )
        # a run that left the flight envelope says so, in red, under the time
        if truth is not None and getattr(truth, 'envelope_exit', ''):
            text = 'LEFT THE FLIGHT ENVELOPE at ' + truth.envelope_exit
            lines.append((text, _color(1, 0.2, 0.2)))
        if state is not None:
            lines.append(
                (
                    'alpha = %+.5f rad (%+.2f deg)' % (state.alpha, math.degrees(state.alpha)),
                    _color(1.0, 0.9, 0.3),
                )
            )
        # a JSBSim run's attitude, airspeed and altitude (the linear model has none)
        fl = flight_of(truth)
        if fl is not None:
            lines.append(
                (
                    'pitch %+.2f deg, flight path %+.2f deg'
                    % (math.degrees(fl['pitch']), math.degrees(fl['flight_path'])),
                    _color(0.85, 0.6, 1.0),
                )
            )
            if self.altitude0 is None:
                self.altitude0 = fl['altitude']
            lines.append(
                (
                    'airspeed %.1f m/s, altitude %.0f m (%+.1f m)'
                    % (fl['airspeed'], fl['altitude'], fl['altitude'] - self.altitude0),
                    _color(0.5, 1.0, 0.7),
                )
            )
        if status is not None:
            lines.append(
                (
                    'alpha_ref = %+.5f rad, e = %+.5f rad' % (status.alpha_ref, status.e),
                    _color(0.8, 0.8, 0.8),
                )
            )
            th = list(status.theta_hat) or [
                status.theta_hat_0,
                status.theta_hat_1,
                status.theta_hat_2,
            ]
            txt = 'theta_hat = [' + ', '.join('%+.3f' % v for v in th) + ']'
            if truth is not None and len(truth.theta):
                tv = list(truth.theta)
                same = all(abs(v - tv[0]) < 1e-12 for v in tv)
                txt += (
                    (', theta = %g x ones' % tv[0])
                    if same
                    else (', theta = [' + ', '.join('%+.3f' % v for v in tv) + ']')
                )
            lines.append((txt, _color(0.6, 0.85, 1.0)))
        if ev is None:
            lines.append(('last event: none yet', _color(0.7, 0.7, 0.7)))
        else:
            extra = ''
            if ev['type'] == 'onset' and ev['reset']:
                extra = ', reset'
            if ev['type'] == 'recovered':
                extra = ', E = %.3g rad s%s' % (ev['cost'], ', learned' if ev['learned'] else '')
            if ev.get('decision'):
                extra += ', %s: %.2g vs keep %.2g rad' % (
                    ev['decision'],
                    ev['score'],
                    ev['score_keep'],
                )
            col = {'onset': _color(0.3, 1.0, 0.3), 'recovered': _color(1, 1, 1)}.get(
                ev['type'], _color(0.75, 0.75, 0.55)
            )
            lines.append(
                (
                    'last event: %s at %.3f s (e = %+.4f rad%s)'
                    % (ev['type'].upper(), ev['t'], ev['e'], extra),
                    col,
                )
            )
        out = []
        for i, (txt, col) in enumerate(lines):
            m = self._marker('text', i, Marker.TEXT_VIEW_FACING, self.world)
            m.pose.position = Point(0.5, 0.0, 6.0 - 0.5 * i)
            m.scale.z = 0.36
            m.color = col
            m.text = txt
            out.append(m)
        for i in range(len(lines), 9):  # keep ids stable: remove lines no longer shown
            m = self._marker('text', i, Marker.TEXT_VIEW_FACING, self.world)
            m.action = Marker.DELETE
            out.append(m)
        return out

    def history_plot(self, hist, events, now):
        z0, x_left, width = -4.2, -5.0, 10.0
        k = self.alpha_scale

        def xz(t, a):
            return Point(
                x_left + width * (t - (now - self.history)) / self.history, 0.0, z0 + k * a
            )

        out = []
        axis = self._marker('alpha_history', 0, Marker.LINE_LIST, self.world)
        axis.scale.x = 0.03
        axis.color = _color(0.6, 0.6, 0.6, 0.8)
        axis.points = [
            Point(x_left, 0, z0),
            Point(x_left + width, 0, z0),
            Point(x_left, 0, z0),
            Point(x_left, 0, z0 + k * 0.15),
        ]
        for i in range(int(self.history) + 1):  # 1 s ticks
            x = x_left + width * i / self.history
            axis.points += [Point(x, 0, z0 - 0.12), Point(x, 0, z0)]
        out.append(axis)
        a = self._marker('alpha_history', 1, Marker.LINE_STRIP, self.world)
        a.scale.x = 0.06
        a.color = _color(1.0, 0.9, 0.3)
        a.points = [xz(t, al) for t, al, _ in hist]
        r = self._marker('alpha_history', 2, Marker.LINE_STRIP, self.world)
        r.scale.x = 0.04
        r.color = _color(0.75, 0.75, 0.75, 0.9)
        r.points = [xz(t, ar) for t, _, ar in hist if ar is not None]
        ticks = self._marker('alpha_history', 3, Marker.LINE_LIST, self.world)
        ticks.scale.x = 0.05
        ticks.color = _color(1, 1, 1)
        for ev in events:
            if ev['type'] not in ('onset', 'recovered') or ev['t'] < now - self.history:
                continue
            col = _color(0.3, 1.0, 0.3) if ev['type'] == 'onset' else _color(1, 1, 1)
            x = xz(ev['t'], 0.0).x
            ticks.points += [Point(x, 0, z0), Point(x, 0, z0 + k * 0.15)]
            ticks.colors += [col, col]
        label = self._marker('alpha_history', 4, Marker.TEXT_VIEW_FACING, self.world)
        label.pose.position = Point(x_left + 0.5 * width, 0.0, z0 - 0.6)
        label.scale.z = 0.32
        label.color = _color(0.85, 0.85, 0.85)
        label.text = 'alpha (yellow), alpha_ref (grey), last %g s' % self.history
        # LINE_STRIPs need >= 2 points; an empty one would be an rviz error
        for mk in (a, r, ticks):
            if len(mk.points) < 2:
                mk.action = Marker.DELETE
                mk.points = []
                mk.colors = []
        out += [a, r, ticks, label]
        return out

    def build(self):
        with self.lock:
            state, status, truth, ev = self.state, self.status, self.truth, self.last_event
            hist = list(self.hist)
            events = list(self.events)
        arr = MarkerArray()
        arr.markers += self.aircraft(state.elevator if state is not None else 0.0)
        arr.markers += self.velocity_arrow()
        arr.markers += self.texts(state, status, truth, ev)
        now = _t_of(state) if state is not None else 0.0
        arr.markers += self.history_plot(hist, events, now)
        return arr

    def spin(self, stop):
        """Publish until stop() is true or rospy shuts down."""
        period = 1.0 / self.rate
        rospy.loginfo(
            'viz_markers: publishing %s at %g Hz (frames %s, %s, %s)%s'
            % (
                self.pub.resolved_name,
                self.rate,
                self.world,
                self.body,
                self.velocity,
                '; publishing tf from plant/state' if self.publish_tf else '',
            )
        )
        # Wall-clock loop: in lockstep /clock stops at the end of a run, the view must not.
        while not stop() and not rospy.is_shutdown():
            start = time.monotonic()
            try:
                self.pub.publish(self.build())
            except rospy.ROSException:  # shutting down
                break
            self.n_published += 1
            deadline = start + period
            while not stop() and time.monotonic() < deadline:
                time.sleep(min(0.02, max(0.0, deadline - time.monotonic())))
