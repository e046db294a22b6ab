"""Runs of the closed loop as the analysis sees them: topic and CSV layouts, Run, InputError,
and the decoding shared by the bag and CSV readers."""

import os

import numpy as np

from .. import modes as _modes
from ..modes import MODE_TEXT, MODES  # noqa: F401 (the package's names for them)


# AttentionEvent.type 0..4 by name; 'decision' is pa_robust's re-decision inside a phase.
EVENT_TYPES = ('onset', 'recovered', 'ignored_onset', 'ignored_recovery', 'decision')
# What a pa_robust verification chose (AttentionEvent.decision / decision_code 1..4).
DECISIONS = ('keep', 'fit', 'memory', 'network')
DECISION_FIELDS = ('decision', 'chosen', 'candidates', 'score', 'score_keep')

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
WHY = {
    'state': 'alpha',
    'status': 'alpha_ref, e and theta_hat',
    'truth': 'the true theta, whose switches define the windows',
}

CSV_HEADER = (
    't,x0,x1,x2,xr0,xr1,xr2,e,e_dot_est,u,theta_hat0,theta_hat1,theta_hat2,'
    'theta_true0,theta_true1,theta_true2,phase'
)
CSV_REQUIRED = (
    't',
    'x1',
    'xr1',
    'e',
    'u',
    'theta_hat0',
    'theta_hat1',
    'theta_hat2',
    'theta_true0',
    'theta_true1',
    'theta_true2',
)

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
      t_applied, u_applied                           elevator applied by the plant (after the
                                                     servo's delay, lag, limits), None without
      t_gust, gust_w                                 Dryden vertical gust [m/s], None without
      conditions                                     the plant's conditions record
                                                     (core/sim/plant_conditions.hpp) by name:
                                                     {name: (t, values)}, values over
                                                     [t, t + dt]; {} without conditions
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
        # what the elevator did and the gust (None: the source has no conditions)
        self.t_applied = self.u_applied = None
        self.t_gust = self.gust_w = None
        self.conditions = {}
        # the plant's first exit from the flight envelope, one line (None: stayed
        # inside, or the source does not say)
        self.envelope_exit = None
        self.summary = None  # the batch CLI's --json object, for a CSV input
        # dynamic_reconfigure changes (controller/param_change): dicts t, step, name,
        # old_value, new_value; drawn as markers on the time plots
        self.param_changes = []

    def describe(self):
        where = os.path.basename(self.source) + (' [%s]' % self.namespace if self.namespace else '')
        return "'%s' (mode %s) from %s" % (self.label, self.mode, where)


_guess_mode = _modes.guess_mode


def _gust_from_conditions(run):
    """The Dryden gust of the conditions record, when there is one and it is not still air."""
    if 'w_gust' in run.conditions:
        t, w = run.conditions['w_gust']
        if np.any(w != 0.0):
            run.t_gust, run.gust_w = t, w


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
    return {
        'decision': name,
        'chosen': int(getattr(m, 'chosen', -1)),
        'candidates': int(getattr(m, 'candidates', 0)),
        'score': float(getattr(m, 'score', 0.0)),
        'score_keep': float(getattr(m, 'score_keep', 0.0)),
    }


def _json_decision(ev):
    """The same from an event of the batch CLI's --json summary."""
    if not ev.get('decision'):
        return _no_decision()
    return {
        'decision': ev['decision'],
        'chosen': ev.get('chosen'),
        'candidates': ev.get('candidates'),
        'score': ev.get('score'),
        'score_keep': ev.get('score_keep'),
    }


def _rebase_epoch(run):
    t0 = float(run.t_e[0])
    if t0 > EPOCH_LIKE:
        for name in ('t_e', 't_alpha', 't_theta', 't_u'):
            v = getattr(run, name)
            if v is not None:
                setattr(run, name, v - t0)
        for ev in run.events:
            ev['t'] -= t0
        run.notes.append(
            'stamps are wall-clock times: time is measured from the first ' 'controller sample'
        )
