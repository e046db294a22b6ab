"""Reading runs from the batch CLI's CSV files and their --json summaries."""

import csv
import json
import os
import re
import warnings

import numpy as np
from .runs import (
    _gust_from_conditions,
    CSV_HEADER,
    CSV_REQUIRED,
    EVENT_TYPES,
    InputError,
    Run,
    _guess_mode,
    _json_decision,
    _no_decision,
    _rebase_epoch,
)


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


# The columns preadapt_sim writes for every run (io/setup.cpp writeSeriesCsv); the others are
# the plant's conditions.
_FIXED_COLUMN = re.compile(
    r'^(t|(x|xr|theta_hat|theta_true)\d+|e|e_dot_est|u|phase|u_baseline|u_adaptive|r|saturated)$'
)


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
        raise InputError(
            path,
            'not a preadapt_sim CSV: missing column%s %s (preadapt_sim writes '
            'the header %s)' % ('s' if len(missing) > 1 else '', ', '.join(missing), CSV_HEADER),
        )
    try:
        with warnings.catch_warnings():
            warnings.simplefilter('ignore')  # numpy warns about an empty file; we say it below
            data = np.loadtxt(path, delimiter=',', skiprows=1, ndmin=2)
    except ValueError as ex:
        raise InputError(path, 'bad CSV data: %s' % ex)
    if data.shape[0] == 0:
        raise InputError(path, 'CSV has a header but no data rows')
    if data.shape[1] != len(header):
        raise InputError(
            path, 'CSV rows have %d fields, the header %d' % (data.shape[1], len(header))
        )
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
    # A run with plant conditions (docs/research/conditions.md) has one column per row of the
    # plant's conditions table (core/sim/plant_conditions.hpp) besides the fixed ones, values over
    # [t, t + dt] like u.
    for h in header:
        if not _FIXED_COLUMN.match(h):
            run.conditions[h] = (t, col[h])
    if 'u_applied' in run.conditions:
        run.t_applied, run.u_applied = run.conditions['u_applied']
    _gust_from_conditions(run)

    json_path = os.path.splitext(path)[0] + '.json'
    summary = None
    if os.path.exists(json_path):
        summary = _parse_summary_json(json_path)
    exit_ = summary.get('envelope_exit') if summary is not None else None
    if isinstance(exit_, dict) and exit_.get('text'):
        run.envelope_exit = exit_['text']
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
                'type': tname,
                't': float(ev['t']),
                'e': ev.get('e'),
                'e_dot': ev.get('e_dot'),
                'theta_hat_before': ev.get('theta_hat_before'),
                'theta_hat_after': after,
                'reset': reset,
                'cost': ev.get('cost') if tname == 'recovered' else None,
                'grad': ev.get('grad'),
                'learned': ev.get('learned'),
                'episodes': ev.get('episodes'),
            }
            d.update(dec)
            run.events.append(d)
        run.notes.append('events from %s' % os.path.basename(json_path))
    elif 'phase' in col:
        ph = col['phase'] > 0.5
        for i in np.nonzero(ph[1:] != ph[:-1])[0] + 1:
            d = {
                'type': 'onset' if ph[i] else 'recovered',
                't': float(t[i]),
                'e': float(run.e[i]),
                'e_dot': float(run.e_dot[i]) if run.e_dot is not None else None,
                'theta_hat_before': None,
                'theta_hat_after': None,
                'reset': None,
                'cost': None,
                'grad': None,
                'learned': None,
                'episodes': None,
            }
            d.update(_no_decision())
            run.events.append(d)
        run.notes.append(
            'events from the phase column (no %s): onsets and recoveries only, '
            'ignored events, decisions and costs unknown' % os.path.basename(json_path)
        )
    else:
        run.notes.append(
            'no %s and no phase column: no attention events' % os.path.basename(json_path)
        )
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
