"""The PNG figures: the paper's Figs. 2-4 and more."""

import os

import numpy as np
from .figure_style import (
    DECISION_STYLE,
    ONSET_COLOR,
    RECOVERY_COLOR,
    THETA_UNITS,
    _decision_markers,
    _event_lines,
    _first_reset,
    _is_paper_reset,
    _legend,
    _mpl,
    _safe,
    _save,
    _switch_lines,
    _xlim,
    _ylim_to_xlim,
)
from .report import _fmt, _theta_text
from .runs import MODE_TEXT


def plot_alpha(plt, run, m, path, c_e, xlim=None):
    fig, (ax, ax2) = plt.subplots(
        2, 1, sharex=True, figsize=(11, 6.4), gridspec_kw={'height_ratios': [2.2, 1]}
    )
    ax.plot(run.t_alpha, run.alpha, color='tab:blue', lw=1.3, label=r'$\alpha$ (plant)', zorder=3)
    ax.plot(
        run.t_e,
        run.alpha_ref,
        color='tab:orange',
        lw=1.3,
        ls='--',
        label=r'$\alpha_{ref}$ (reference model)',
        zorder=3,
    )
    _switch_lines(ax, m)
    _event_lines(ax, run)
    ax.set_ylabel(r'angle of attack $\alpha$ [rad]')
    ax.set_title(
        "Response of $\\alpha$: run '%s', mode %s (%s)"
        % (run.label, run.mode, MODE_TEXT.get(run.mode, 'unknown mode'))
    )
    _legend(ax)
    _ylim_to_xlim(ax, [(run.t_alpha, run.alpha), (run.t_e, run.alpha_ref)], xlim)
    ax2.plot(run.t_e, run.e, color='tab:red', lw=1.0, label=r'$e=\alpha-\alpha_{ref}$', zorder=3)
    ax2.axhline(c_e, color='0.4', ls='--', lw=0.9, label=r'$\pm c_e$ = %.3g rad' % c_e)
    ax2.axhline(-c_e, color='0.4', ls='--', lw=0.9)
    _switch_lines(ax2, m, annotate=False)
    _event_lines(ax2, run, with_labels=False)
    ign = [
        ev
        for ev in run.events
        if ev['type'] in ('ignored_onset', 'ignored_recovery') and ev.get('e') is not None
    ]
    for kind, mk, col in (
        ('ignored_onset', 'x', ONSET_COLOR),
        ('ignored_recovery', 'x', RECOVERY_COLOR),
    ):
        pts = [(ev['t'], ev['e']) for ev in ign if ev['type'] == kind]
        if pts:
            ax2.plot(
                *zip(*pts),
                ls='none',
                marker=mk,
                ms=7,
                mew=1.8,
                color=col,
                zorder=4,
                label=kind.replace('_', ' ')
            )
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
    fig, (ax, ax2) = plt.subplots(
        2, 1, sharex=True, figsize=(11, 6.8), gridspec_kw={'height_ratios': [2.2, 1]}
    )
    ref_run = next((r for r in runs if r.label == baseline), runs[0])
    for r in runs:
        lab = "%s (%s)" % (r.label, 'RAC' if r.mode == 'rac' else r.mode)
        ax.plot(r.t_alpha, r.alpha, color=cols[r.label], lw=1.2, label=r'$\alpha$ ' + lab, zorder=3)
    ax.plot(
        ref_run.t_e,
        ref_run.alpha_ref,
        color='tab:orange',
        lw=1.2,
        ls='--',
        label=r'$\alpha_{ref}$',
        zorder=2,
    )
    mfocus = next(mm for mm in metrics if mm['label'] == focus.label)
    _switch_lines(ax, mfocus)
    _event_lines(ax, focus, with_labels=focus.label)
    ax.set_ylabel(r'angle of attack $\alpha$ [rad]')
    ax.set_title(
        r'Response of $\alpha$: '
        + ' vs '.join("'%s'" % r.label for r in runs)
        + "  (event lines: '%s')" % focus.label
    )
    _legend(ax)
    _ylim_to_xlim(ax, [(r.t_alpha, r.alpha) for r in runs], xlim)
    for r, mm in zip(runs, metrics):
        ax2.plot(r.t_e, np.abs(r.e), color=cols[r.label], lw=1.0, label='|e| ' + r.label, zorder=3)
        pk = [
            (w['t_peak'], w['peak_abs_e'])
            for w in mm['windows']
            if w['kind'] == 'switch' and w['t_peak'] is not None
        ]
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
            names.append(
                '%d: start\n' % w['index']
                + r'$\theta$=%s' % _theta_text(w['theta_scale'], w['theta'])
            )
        else:
            names.append(
                '%d: t=%.4g s\n' % (w['index'], w['t_start'])
                + r'$\theta$ %s$\to$%s'
                % (
                    _theta_text(w['theta_scale_before'], w['theta_before']),
                    _theta_text(w['theta_scale'], w['theta']),
                )
            )
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
                ax.annotate(
                    '%+.0f%%' % p,
                    xy=(xs[k], vals[k]),
                    xytext=(0, 2),
                    textcoords='offset points',
                    ha='center',
                    va='bottom',
                    fontsize=8,
                )
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
        ax.plot(
            run.t_e,
            run.theta_hat[:, i],
            color='tab:blue',
            lw=1.3,
            label=r'$\hat\theta_%d$ estimate' % i,
            zorder=3,
        )
        ax.plot(
            run.t_theta,
            run.theta[:, i],
            color='tab:red',
            lw=1.3,
            ls='--',
            label=r'$\theta_%d$ true' % i,
            zorder=2,
        )
        _switch_lines(ax, m, annotate=(i == 0))
        _event_lines(ax, run, with_labels=(i == 0))
        for ev in run.events:
            if _is_paper_reset(ev):
                ax.plot(
                    ev['t'],
                    ev['theta_hat_after'][i],
                    marker='o',
                    ms=5,
                    mfc='none',
                    color=ONSET_COLOR,
                    zorder=4,
                    label=r'reset to $\hat\theta_I$' if ev is _first_reset(run) else None,
                )
        # pa_robust: the estimate each decision set (or kept), the last of each verification
        # labelled with its identification residual against keeping's
        _decision_markers(
            ax,
            run,
            lambda ev, i=i: ev['theta_hat_after'][i]
            if ev.get('theta_hat_after') and len(ev['theta_hat_after']) > i
            else None,
            with_labels=(i == 0),
            annotate=(i == 0),
            xlim=xlim,
        )
        ax.set_ylabel(r'$\theta_%d$ %s' % (i, THETA_UNITS[i]))
        _legend(ax)
        _ylim_to_xlim(ax, [(run.t_e, run.theta_hat[:, i]), (run.t_theta, run.theta[:, i])], xlim)
    axes[0].set_title(
        r"Parameter estimate $\hat\theta$ and true $\theta$: run '%s' (mode %s)"
        % (run.label, run.mode)
    )
    axes[-1].set_xlabel('time $t$ [s]')
    _xlim(axes[-1], xlim)
    _save(fig, path)
    plt.close(fig)


def plot_elevator(plt, run, m, path, xlim=None):
    fig, ax = plt.subplots(figsize=(11, 4.8))
    ax.plot(run.t_u, run.u, color='tab:blue', lw=1.3, label=r'$u = u_{bl} + u_{ad}$', zorder=3)
    if run.u_bl is not None:
        ax.plot(
            run.t_u,
            run.u_bl,
            color='tab:gray',
            lw=1.0,
            ls='--',
            label=r'$u_{bl} = -Kx$ (baseline)',
            zorder=2,
        )
        ax.plot(
            run.t_u,
            run.u_ad,
            color='tab:purple',
            lw=1.0,
            ls='-.',
            label=r'$u_{ad} = -\hat\theta^T x$ (adaptive)',
            zorder=2,
        )
    _switch_lines(ax, m)
    _event_lines(ax, run)
    ax.set_ylabel(r'elevator command $u$ [rad]')
    ax.set_xlabel('time $t$ [s]')
    ax.set_title(
        "Elevator command: run '%s' (mode %s; from %s)" % (run.label, run.mode, run.u_source)
    )
    _legend(ax)
    ser = [(run.t_u, run.u)] + (
        [(run.t_u, run.u_bl), (run.t_u, run.u_ad)] if run.u_bl is not None else []
    )
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
    ax.plot(
        k,
        keep,
        color='0.25',
        lw=0.8,
        ls='--',
        marker='x',
        ms=5,
        zorder=3,
        label='score_keep: keeping the pre-switch estimate',
    )
    for kind, st in DECISION_STYLE.items():
        pts = [(kk, ev['score']) for kk, ev in zip(k, decs) if ev['decision'] == kind]
        if pts:
            ax.plot(
                *zip(*pts),
                ls='none',
                marker=st['marker'],
                ms=8,
                color=st['color'],
                zorder=4,
                label='score: %s' % kind
            )
    pos = [v for v in keep + [ev['score'] for ev in decs] if v is not None and v > 0]
    if pos:
        ax.set_yscale('log')
    starts = [i for i, ev in enumerate(decs) if ev['type'] == 'onset' or i == 0]
    for j, i0 in enumerate(starts):
        i1 = starts[j + 1] if j + 1 < len(starts) else len(decs)
        if i0 > 0:
            ax.axvline(i0 + 0.5, color=ONSET_COLOR, lw=1.0, zorder=1)
        last = decs[i1 - 1]
        ax.annotate(
            'onset %.3f s\n-> %s%s\n%s vs %s rad'
            % (
                decs[i0]['t'],
                last['decision'],
                ' #%d' % last['chosen'] if last['decision'] == 'memory' else '',
                _fmt(last['score'], '%.2g'),
                _fmt(last['score_keep'], '%.2g'),
            ),
            xy=(i0 + 0.6, 1.0),
            xycoords=('data', 'axes fraction'),
            xytext=(2, -3),
            textcoords='offset points',
            va='top',
            ha='left',
            fontsize=7.5,
            color='0.25',
        )
    ax.plot([], [], color=ONSET_COLOR, lw=1.0, label='a new verification (onset)')
    ax.set_xlim(0.5, len(decs) + 0.5)
    if pos:
        lo, hi = min(pos), max(pos)
        ax.set_ylim(lo / 3.0, hi * 30.0)  # room for the labels at the top
    ax.set_xlabel('decision # (onsets and DECISION events, in time order)')
    ax.set_ylabel('RMS identification residual [rad]')
    ax.set_title(
        "pa_robust verification: run '%s' (mode %s), %d decisions"
        % (run.label, run.mode, len(decs))
    )
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
        ax.plot(
            k,
            cost,
            color=cols[r.label],
            lw=1.0,
            marker='o',
            ms=6,
            label='%s (%s)' % (r.label, r.mode),
        )
        learned = [(kk, c) for kk, c, ev in zip(k, cost, rec) if ev.get('learned')]
        if learned:
            ax.plot(
                *zip(*learned),
                ls='none',
                marker='o',
                ms=9,
                mfc='none',
                mew=1.5,
                color='k',
                label='network updated (learned)'
            )
        for kk, c, ev in zip(k, cost, rec):
            ax.annotate(
                '%.4g s' % ev['t'],
                xy=(kk, c),
                xytext=(4, 4),
                textcoords='offset points',
                fontsize=7,
                color='0.3',
                annotation_clip=True,
            )
    if any_pts:
        _legend(ax)
        from matplotlib.ticker import MaxNLocator

        ax.xaxis.set_major_locator(MaxNLocator(integer=True, min_n_ticks=1))
        ax.set_xlim(0.5, max_k + 0.6)
        ax.set_ylim(0, ax.get_ylim()[1] * 1.08)
    else:
        ax.text(
            0.5,
            0.5,
            'no RECOVERED events with a cost E in these runs',
            transform=ax.transAxes,
            ha='center',
            va='center',
            fontsize=12,
            color='0.3',
        )
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
        for name, fn, args in (
            ('alpha_%s.png' % s, plot_alpha, (c_e, xlim)),
            ('theta_hat_%s.png' % s, plot_theta, (xlim,)),
            ('elevator_%s.png' % s, plot_elevator, (xlim,)),
        ):
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
