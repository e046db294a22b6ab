"""Shared look of the figures: colours, event and switch lines, decision markers."""

import re
import warnings

import numpy as np
from .metrics import _scale_of
from .report import _fmt, final_decisions


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

    plt.rcParams.update(
        {
            'font.size': 11,
            'axes.titlesize': 12,
            'legend.fontsize': 9,
            'axes.grid': True,
            'grid.alpha': 0.3,
            'figure.dpi': 100,
        }
    )
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
            label = 'onset $E_u=1$' if ev['type'] == 'onset' else 'recovery $E_d=1$'
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
        lines.append(
            ax.axvline(
                t,
                color=PARAM_COLOR,
                ls='-.',
                lw=1.2,
                zorder=1,
                label='parameter change' if i == 0 and annotate else None,
            )
        )
        if annotate:
            txt = '\n'.join(
                '%s %.4g$\\to$%.4g' % (c['name'].split('.')[-1], c['old_value'], c['new_value'])
                for c in cs
            )
            ax.annotate(
                txt,
                xy=(t, 0.0),
                xycoords=('data', 'axes fraction'),
                xytext=(2, 2),
                textcoords='offset points',
                va='bottom',
                ha='left',
                fontsize=8,
                color=PARAM_COLOR,
                annotation_clip=True,
            )
    return lines


def _switch_lines(ax, m, annotate=True):
    for i, s in enumerate(m['switches']):
        ax.axvline(
            s['t'],
            color=SWITCH_COLOR,
            ls=':',
            lw=1.2,
            zorder=0,
            label=r'$\theta$ switch' if i == 0 and annotate else None,
        )
        if annotate:
            sc = _scale_of(s['theta_after'])
            txt = (r'$\theta$=%.3g' % sc) if sc is not None else r'$\theta$ switch'
            ax.annotate(
                txt,
                xy=(s['t'], 1.0),
                xycoords=('data', 'axes fraction'),
                xytext=(2, -2),
                textcoords='offset points',
                va='top',
                ha='left',
                fontsize=8,
                color='0.35',
                annotation_clip=True,
            )


def _legend(ax, **kw):
    """Legend outside the axes, on the right, so it never hides data."""
    h, lab = ax.get_legend_handles_labels()
    uniq = dict(zip(lab, h))
    if uniq:
        ax.legend(
            uniq.values(),
            uniq.keys(),
            loc='upper left',
            bbox_to_anchor=(1.005, 1.0),
            borderaxespad=0.0,
            **kw
        )


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


def _is_paper_reset(ev):
    """An onset that reset theta_hat to the network's theta_hat_I (pa modes; pa_robust's
    onsets carry a decision and are drawn as decisions)."""
    return (
        ev['type'] == 'onset'
        and ev.get('reset')
        and ev.get('theta_hat_after')
        and not ev.get('decision')
    )


def _first_reset(run):
    for ev in run.events:
        if _is_paper_reset(ev):
            return ev
    return None


def _decision_text(d):
    return '%s%s: %s vs keep %s rad' % (
        d['decision'],
        ' #%d' % d['chosen'] if d['decision'] == 'memory' else '',
        _fmt(d['score'], '%.2g'),
        _fmt(d['score_keep'], '%.2g'),
    )


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
            ax.plot(
                *zip(*pts),
                ls='none',
                marker=st['marker'],
                ms=7,
                mew=1.2,
                mfc='none',
                color=st['color'],
                zorder=5,
                label=('decision: %s' % kind) if with_labels else None
            )
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
            ax.annotate(
                _decision_text(d),
                xy=(d['t'], y),
                xytext=(6, 6 + lift),
                textcoords='offset points',
                fontsize=7.5,
                zorder=6,
                color=DECISION_STYLE[d['decision']]['color'],
                bbox={'boxstyle': 'round,pad=0.15', 'fc': 'white', 'ec': 'none', 'alpha': 0.75},
                annotation_clip=True,
            )
    return drawn
