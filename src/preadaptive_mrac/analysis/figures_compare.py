"""Figures over several runs: alpha of every run, peak |e| per window, cost per episode."""


import numpy as np
from .figure_style import _event_lines, _legend, _save, _switch_lines, _xlim, _ylim_to_xlim
from .report import _theta_text


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
    xlabel = 'window (from the switch of the true $\\theta$ to the next)'
    if comparison:
        # Say what a "+97%" over a bar is, where the reader looks for units: on the axis.
        b = comparison['baseline']
        xlabel += (
            "\nlabel over a bar: 100 (1 - peak / %s's peak) %%, the peak reduction against %s"
            "\n(+97%% = a peak 97%% below %s's; negative = above it)" % (b, b, b)
        )
    ax.set_xlabel(xlabel)
    ax.set_title('Peak output error per window')
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
