"""docs/spec.md metrics of a run and the comparison against a baseline."""

import math

import numpy as np
from .runs import DECISIONS, DECISION_FIELDS, InputError


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


# The steady part of a window: its last half (closed_loop.hpp EffortMetrics::kSteadyFraction).
STEADY_FRACTION = 0.5


def effort_series(run):
    """The elevator whose effort counts: (t, u, source), the applied elevator when the source
    records it (the plant's, after the servo's delay, lag and limits), else the command; (None,
    None, None) without either."""
    if run.u_applied is not None and len(run.u_applied):
        return np.asarray(run.t_applied, float), np.asarray(run.u_applied, float), 'applied'
    if run.u is not None and len(run.u):
        return np.asarray(run.t_u, float), np.asarray(run.u, float), 'command'
    return None, None, None


def effort(t, u, bounds, limits=None):
    """The elevator effort as the batch tools count it (closed_loop.hpp EffortMetrics): sample
    k holds u[k] over [t[k], t[k+1]]; its step is |u[k] - u[k-1]| (from 0 for the first).
    `bounds` are the window boundaries (windows [lo, hi), the last [lo, hi]); `limits` is
    (max_deflection [rad], max_rate [rad/s]) or None (then the times at the limits are None).
    Returns (whole-run dict, per-window list of dicts)."""
    t = np.asarray(t, float)
    u = np.asarray(u, float)
    n = len(t)
    dt = np.diff(t) if n > 1 else np.array([0.0])
    hold = np.append(dt, dt[-1]) if n > 1 else np.zeros(1)
    step = np.abs(np.diff(u, prepend=0.0))
    tol = 1e-9
    travel = rate = None
    if limits is not None:
        travel = np.abs(u) >= limits[0] * (1.0 - tol)
        rate = step >= limits[1] * np.append(hold[:1], dt[: n - 1]) * (1.0 - tol)
    whole = {
        'effort_source': None,
        'peak_abs_u': _f(np.max(np.abs(u))) if n else None,
        'time_at_travel_limit': _f(np.sum(hold[travel])) if travel is not None else None,
        'time_at_rate_limit': _f(np.sum(hold[rate])) if rate is not None else None,
        'steady_tv': 0.0,
        'steady_fraction': STEADY_FRACTION,
    }
    wins = []
    for i in range(len(bounds) - 1):
        lo, hi = bounds[i], bounds[i + 1]
        last = i == len(bounds) - 2
        m = (t >= lo) & ((t <= hi) if last else (t < hi))
        typical = float(np.median(hold[m])) if np.any(m) else 0.0
        steady = m & (t >= hi - STEADY_FRACTION * (hi - lo) - 0.5 * typical)
        idx = np.nonzero(steady)[0]
        tv = float(np.sum(np.abs(np.diff(u[idx])))) if len(idx) > 1 else 0.0
        at = None
        if travel is not None:
            at = _f(np.sum(hold[m & (travel | rate)]))
        wins.append({'time_at_limit': at, 'steady_tv': _f(tv)})
        whole['steady_tv'] += tv
    whole['steady_tv'] = _f(whole['steady_tv'])
    return whole, wins


def run_metrics(run, limits=None):
    """docs/spec.md metrics of one run: windows between switches of the true theta and the
    whole run, with the elevator's effort (`limits`: (max_deflection, max_rate) of the plant's
    elevator, for the time at each limit; default the run's own `actuator_limits` when its
    source says, else not computed). Returns a JSON-ready dict."""
    t = run.t_e
    ae = np.abs(run.e)
    cum = _cum_trapz(ae, t)
    sw_t, sw_before, sw_after = find_switches(run.t_theta, run.theta)
    t0, t1 = float(t[0]), float(t[-1])
    sw_keep = (sw_t > t0) & (sw_t < t1)
    sw_t, sw_before, sw_after = sw_t[sw_keep], sw_before[sw_keep], sw_after[sw_keep]
    bounds = [t0] + [float(s) for s in sw_t] + [t1]
    theta_at_start = (
        run.theta[np.searchsorted(run.t_theta, t0, side='right') - 1]
        if run.t_theta[0] <= t0
        else run.theta[0]
    )
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
        windows.append(
            {
                'index': i,
                'kind': 'switch' if i > 0 else 'start',
                't_start': lo,
                't_end': hi,
                'theta_before': [float(v) for v in sw_before[i - 1]] if i > 0 else None,
                'theta': [float(v) for v in th],
                'theta_scale_before': _scale_of(sw_before[i - 1]) if i > 0 else None,
                'theta_scale': _scale_of(th),
                'peak_abs_e': _f(peak),
                't_peak': _f(t_peak),
                'iae': _f(iae),
                'max_abs_u': _f(max_u),
                'recovery_time': _f(rec[0] - lo) if rec else None,
                'onset_delay': _f(ons[0] - lo) if ons else None,
                'onsets': len(ons),
                'recoveries': len(rec),
                'ignored_onsets': sum(1 for ev in evs if ev['type'] == 'ignored_onset'),
                'ignored_recoveries': sum(1 for ev in evs if ev['type'] == 'ignored_recovery'),
                'decisions': sum(1 for ev in evs if ev.get('decision')),
            }
        )
    te, ue, source = effort_series(run)
    if limits is None:
        limits = getattr(run, 'actuator_limits', None)
    if te is not None:
        eff, eff_win = effort(te, ue, bounds, limits)
        eff['effort_source'] = source
    else:
        eff, eff_win = None, [None] * len(windows)
    for w, e in zip(windows, eff_win):
        w['time_at_limit'] = e['time_at_limit'] if e else None
        w['steady_tv'] = e['steady_tv'] if e else None
    k = int(np.argmax(ae))
    costs = [ev for ev in run.events if ev['type'] == 'recovered' and ev.get('cost') is not None]
    decisions = decision_list(run)
    whole = {
        't_start': t0,
        't_end': t1,
        'duration': t1 - t0,
        'samples': int(len(t)),
        'iae': _f(cum[-1]),
        'peak_abs_e': _f(ae[k]),
        't_peak': _f(t[k]),
        'max_abs_u': _f(np.max(np.abs(run.u))) if run.u is not None and len(run.u) else None,
        'onsets': sum(1 for ev in run.events if ev['type'] == 'onset'),
        'recoveries': sum(1 for ev in run.events if ev['type'] == 'recovered'),
        'ignored_onsets': sum(1 for ev in run.events if ev['type'] == 'ignored_onset'),
        'ignored_recoveries': sum(1 for ev in run.events if ev['type'] == 'ignored_recovery'),
        'decision_events': sum(1 for ev in run.events if ev['type'] == 'decision'),
        'decisions': len(decisions),
        'decisions_by_kind': {
            k: sum(1 for d in decisions if d['decision'] == k) for k in DECISIONS
        },
        'episodes': run.episodes,
        'effort': eff,
        'costs': [_f(ev['cost']) for ev in costs],
    }
    return {
        'label': run.label,
        'source': run.source,
        'namespace': run.namespace,
        'mode': run.mode,
        'mode_from': run.mode_from,
        'u_source': run.u_source,
        'switches': [
            {
                't': float(s),
                'theta_before': [float(v) for v in b],
                'theta_after': [float(v) for v in a],
            }
            for s, b, a in zip(sw_t, sw_before, sw_after)
        ],
        'whole_run': whole,
        'windows': windows,
        'decisions': decisions,
        'events': [
            {
                k2: (
                    _f(v)
                    if isinstance(v, float)
                    else ([_f(x) for x in v] if isinstance(v, list) else v)
                )
                for k2, v in ev.items()
            }
            for ev in run.events
        ],
        'param_changes': [dict(c) for c in run.param_changes],
        'notes': list(run.notes),
        'envelope_exit': getattr(run, 'envelope_exit', None),
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
            raise InputError(
                '--baseline', "no run labelled '%s' (runs: %s)" % (baseline, ', '.join(labels))
            )
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
            rows.append(
                {
                    'index': w['index'],
                    'baseline_index': bw['index'],
                    't_start': w['t_start'],
                    'kind': w['kind'],
                    'theta_scale': w['theta_scale'],
                    'peak_baseline': bw['peak_abs_e'],
                    'peak': w['peak_abs_e'],
                    'peak_reduction_pct': _f(_pct(bw['peak_abs_e'], w['peak_abs_e'])),
                    'iae_baseline': bw['iae'],
                    'iae': w['iae'],
                    'iae_reduction_pct': _f(_pct(bw['iae'], w['iae'])),
                    'recovery_time_baseline': bw['recovery_time'],
                    'recovery_time': w['recovery_time'],
                }
            )
        bwr, wr = base['whole_run'], m['whole_run']
        out['runs'].append(
            {
                'label': m['label'],
                'mode': m['mode'],
                'windows': rows,
                'unmatched_windows': unmatched,
                'whole_run': {
                    'peak_reduction_pct': _f(_pct(bwr['peak_abs_e'], wr['peak_abs_e'])),
                    'iae_reduction_pct': _f(_pct(bwr['iae'], wr['iae'])),
                    'max_abs_u_baseline': bwr['max_abs_u'],
                    'max_abs_u': wr['max_abs_u'],
                },
            }
        )
    return out
