"""The text report, metrics.json and metrics.csv."""

import csv
import json
import os


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
    # a run that lost the aircraft says so before anything else
    for m in metrics:
        if m.get('envelope_exit'):
            lines.append(
                "!! run %s LEFT THE FLIGHT ENVELOPE at %s" % (m['label'], m['envelope_exit'])
            )
    if lines:
        lines.append('')
    for m in metrics:
        w = m['whole_run']
        lines.append(
            '== run %s (%s, mode %s%s)'
            % (
                m['label'],
                os.path.basename(m['source']) + (' ' + m['namespace'] if m['namespace'] else ''),
                m['mode'],
                (' from ' + m['mode_from']) if m['mode_from'] else '',
            )
        )
        lines.append(
            '   t = %.3f .. %.3f s, %d controller samples, %d theta switch(es) at %s'
            % (
                w['t_start'],
                w['t_end'],
                w['samples'],
                len(m['switches']),
                ', '.join('%.3f s' % s['t'] for s in m['switches']) or '-',
            )
        )
        lines.append(
            '   whole run: integral |e| %s rad s, peak |e| %s rad (t = %s s), max |u| %s rad'
            % (
                _fmt(w['iae']),
                _fmt(w['peak_abs_e']),
                _fmt(w['t_peak'], '%.3f'),
                _fmt(w['max_abs_u']),
            )
        )
        ef = w.get('effort')
        if ef:
            lines.append(
                '   elevator effort (%s): peak |u| %s rad, %s s at the travel limit, %s s at '
                'the rate limit, steady-flight total variation %s rad (last %g of each window)'
                % (
                    ef['effort_source'],
                    _fmt(ef['peak_abs_u']),
                    _fmt(ef['time_at_travel_limit'], none='? (limits not given)'),
                    _fmt(ef['time_at_rate_limit'], none='?'),
                    _fmt(ef['steady_tv']),
                    ef['steady_fraction'],
                )
            )
        lines.append(
            '   events: %d onsets, %d recoveries, %d ignored onsets, %d ignored '
            'recoveries; learning episodes %s'
            % (
                w['onsets'],
                w['recoveries'],
                w['ignored_onsets'],
                w['ignored_recoveries'],
                _fmt(w['episodes'], '%d'),
            )
        )
        if w['decisions']:
            lines.append(
                '   decisions (pa_robust verification): %d, %d of them DECISION events; '
                '%s'
                % (
                    w['decisions'],
                    w['decision_events'],
                    ', '.join('%s %d' % (k, n) for k, n in w['decisions_by_kind'].items() if n),
                )
            )
            for d in final_decisions(m['decisions']):
                lines.append(
                    '     t = %.3f s: %s%s, residual %s rad against %s rad keeping '
                    '(%s candidates)'
                    % (
                        d['t'],
                        d['decision'],
                        ' #%d' % d['chosen'] if d['decision'] == 'memory' else '',
                        _fmt(d['score'], '%.3g'),
                        _fmt(d['score_keep'], '%.3g'),
                        _fmt(d['candidates'], '%d'),
                    )
                )
        for n in m['notes']:
            lines.append('   note: ' + n)
        lines.append(
            '   %3s %9s %9s %7s %11s %9s %12s %11s %6s %6s %5s'
            % (
                'win',
                't_start',
                't_end',
                'theta',
                'peak|e|',
                't_peak',
                'int|e|',
                'recovery',
                'onset',
                'recov',
                'ign',
            )
        )
        lines.append(
            '   %3s %9s %9s %7s %11s %9s %12s %11s %6s %6s %5s'
            % ('', '[s]', '[s]', '', '[rad]', '[s]', '[rad s]', '[s]', '', '', '')
        )
        for win in m['windows']:
            lines.append(
                '   %3d %9.3f %9.3f %7s %11s %9s %12s %11s %6d %6d %5d'
                % (
                    win['index'],
                    win['t_start'],
                    win['t_end'],
                    _theta_text(win['theta_scale'], win['theta']),
                    _fmt(win['peak_abs_e'], '%.5f'),
                    _fmt(win['t_peak'], '%.3f'),
                    _fmt(win['iae'], '%.6f'),
                    _fmt(win['recovery_time'], '%.3f'),
                    win['onsets'],
                    win['recoveries'],
                    win['ignored_onsets'] + win['ignored_recoveries'],
                )
            )
        lines.append('')
    if comparison is None:
        if len(metrics) > 1:
            lines.append(
                '== comparison: no regular adaptive control (rac) run among the inputs; '
                'name one with --baseline LABEL'
            )
        return '\n'.join(lines)
    lines.append(
        "== comparison against '%s' (mode %s): reduction in %% = 100 (baseline - run) / "
        "baseline, positive = smaller error than the baseline"
        % (comparison['baseline'], comparison['baseline_mode'])
    )
    for c in comparison['runs']:
        lines.append("   run '%s' (mode %s)" % (c['label'], c['mode']))
        lines.append(
            '   %3s %9s %7s %12s %12s %10s %12s %12s %10s'
            % (
                'win',
                't_start',
                'theta',
                'peak base',
                'peak run',
                'peak red.',
                'int base',
                'int run',
                'int red.',
            )
        )
        for r in c['windows']:
            lines.append(
                '   %3d %9.3f %7s %12s %12s %10s %12s %12s %10s'
                % (
                    r['index'],
                    r['t_start'],
                    _fmt(r['theta_scale'], '%.3g'),
                    _fmt(r['peak_baseline'], '%.5f'),
                    _fmt(r['peak'], '%.5f'),
                    _fmt(r['peak_reduction_pct'], '%+.1f%%'),
                    _fmt(r['iae_baseline'], '%.6f'),
                    _fmt(r['iae'], '%.6f'),
                    _fmt(r['iae_reduction_pct'], '%+.1f%%'),
                )
            )
        wr = c['whole_run']
        lines.append(
            '   whole run: peak |e| %s, integral |e| %s'
            % (_fmt(wr['peak_reduction_pct'], '%+.1f%%'), _fmt(wr['iae_reduction_pct'], '%+.1f%%'))
        )
        if c['unmatched_windows']:
            lines.append(
                '   note: window(s) %s have no baseline window starting at the same time'
                % ', '.join(str(i) for i in c['unmatched_windows'])
            )
    return '\n'.join(lines)


CSV_COLUMNS = [
    'label',
    'source',
    'namespace',
    'mode',
    'window',
    'kind',
    't_start',
    't_end',
    'theta_scale',
    'theta_scale_before',
    'peak_abs_e',
    't_peak',
    'iae',
    'max_abs_u',
    'time_at_limit',
    'steady_tv',
    'recovery_time',
    'onset_delay',
    'onsets',
    'recoveries',
    'ignored_onsets',
    'ignored_recoveries',
    'baseline',
    'peak_reduction_pct',
    'iae_reduction_pct',
    'decisions',
]


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
            whole.update(
                kind='whole_run',
                theta_scale=None,
                theta_scale_before=None,
                recovery_time=None,
                onset_delay=None,
                steady_tv=(whole.get('effort') or {}).get('steady_tv'),
            )
            rows.append(('all', whole))
            for idx, win in rows:
                r = red.get((m['label'], idx), {})
                base = (
                    comparison['baseline']
                    if comparison and m['label'] != comparison['baseline']
                    else None
                )
                vals = {
                    'label': m['label'],
                    'source': m['source'],
                    'namespace': m['namespace'],
                    'mode': m['mode'],
                    'window': idx,
                    'baseline': base,
                    'peak_reduction_pct': r.get('peak_reduction_pct'),
                    'iae_reduction_pct': r.get('iae_reduction_pct'),
                }
                for k in CSV_COLUMNS:
                    if k not in vals:
                        vals[k] = win.get(k)
                w.writerow([cell(vals[k]) for k in CSV_COLUMNS])
