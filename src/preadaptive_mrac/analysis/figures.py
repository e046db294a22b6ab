"""The PNG figures of one run (the paper's Figs. 2-4 and more), and write_figures() for all."""

import os

import numpy as np
from .figure_style import (
    DECISION_STYLE,
    ONSET_COLOR,
    RECOVERY_COLOR,
    THETA_UNITS,
    _decision_markers,
    _event_lines,
    _param_change_lines,
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
from .report import _fmt
from .runs import MODE_TEXT
from .figures_compare import plot_compare, plot_cost, plot_peaks


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
    _param_change_lines(ax, run)
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
    _param_change_lines(ax2, run, annotate=False)
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
        _param_change_lines(ax, run, annotate=(i == 0))
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
        + '\n'
        + r'MRAC drives the output error to zero, not $\hat\theta$ to $\theta$: without'
        + r' persistent excitation (e.g. a constant reference) $\hat\theta$ need not converge'
        + r' to $\theta$',
        fontsize=10,
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
    if run.u_applied is not None:
        ax.plot(
            run.t_applied,
            run.u_applied,
            color='tab:orange',
            lw=1.1,
            label='applied by the plant (after delay, lag, limits)',
            zorder=4,
        )
    _switch_lines(ax, m)
    _event_lines(ax, run)
    _param_change_lines(ax, run)
    ax.set_ylabel(r'elevator command $u$ [rad]')
    ax.set_xlabel('time $t$ [s]')
    ax.set_title(
        "Elevator command: run '%s' (mode %s; from %s)" % (run.label, run.mode, run.u_source)
    )
    _legend(ax)
    ser = [(run.t_u, run.u)] + (
        [(run.t_u, run.u_bl), (run.t_u, run.u_ad)] if run.u_bl is not None else []
    )
    if run.u_applied is not None:
        ser.append((run.t_applied, run.u_applied))
    _ylim_to_xlim(ax, ser, xlim)
    _xlim(ax, xlim)
    _save(fig, path)
    plt.close(fig)


# Conditions of the record (core/sim/plant_conditions.hpp) with a display of their own; every
# other condition a run has and that changes gets a figure of its own by name (plot_condition),
# so a new condition is drawn without an edit here.
CONDITIONS_SHOWN_ELSEWHERE = {
    'u_applied': 'the elevator figure',
    'w_gust': 'the gust figure',
    'effectiveness': 'the scenario schedule (not drawn)',
    'plant_limited': 'a flag (the saturation count, not drawn)',
    'pitch': 'the flight figure',
    'airspeed': 'the flight figure',
    'altitude': 'the flight figure',
    'flight_path': 'the flight figure',
}
# The flight outputs of a six-degree-of-freedom plant (plant.engine jsbsim, docs/jsbsim.md):
# rows of the conditions record only such a run has, drawn together by plot_flight.
FLIGHT_CONDITIONS = ('airspeed', 'altitude', 'pitch', 'flight_path')


def has_flight(run):
    """The run's plant was an engine that reports its flight (a JSBSim run)."""
    return all(n in run.conditions for n in FLIGHT_CONDITIONS)


def plot_flight(plt, run, m, path, xlim=None):
    """What the linear model never had, of a JSBSim run: true airspeed, altitude, and pitch
    attitude with the flight path angle (their difference is the angle of attack)."""
    fig, axes = plt.subplots(3, 1, sharex=True, figsize=(11, 7.6))
    t, v = run.conditions['airspeed']
    th, h = run.conditions['altitude']
    tp, pitch = run.conditions['pitch']
    tg, gamma = run.conditions['flight_path']
    panels = (
        (axes[0], [(t, v, 'tab:blue', '-', 'true airspeed')], 'airspeed [m/s]'),
        (axes[1], [(th, h, 'tab:brown', '-', 'altitude')], 'altitude [m]'),
        (
            axes[2],
            [
                (tp, np.degrees(pitch), 'tab:purple', '-', r'pitch attitude $\vartheta$'),
                (tg, np.degrees(gamma), 'tab:green', '--', r'flight path angle $\gamma$'),
            ],
            'angle [deg]',
        ),
    )
    for i, (ax, series, ylabel) in enumerate(panels):
        for ts, vs, col, ls, label in series:
            ax.plot(ts, vs, color=col, ls=ls, lw=1.2, label=label, zorder=3)
        _switch_lines(ax, m, annotate=(i == 0))
        _event_lines(ax, run, with_labels=(i == 0))
        ax.set_ylabel(ylabel)
        _legend(ax)
        _ylim_to_xlim(ax, [(ts, vs) for ts, vs, _, _, _ in series], xlim)
    axes[0].set_title(
        "Flight of the six-degree-of-freedom plant: run '%s' (mode %s)\nairspeed %.1f to "
        '%.1f m/s, altitude %.0f to %.0f m'
        % (run.label, run.mode, np.min(v), np.max(v), np.min(h), np.max(h))
    )
    axes[-1].set_xlabel('time $t$ [s]')
    _xlim(axes[-1], xlim)
    _save(fig, path)
    plt.close(fig)


def plot_condition(plt, run, m, name, path, xlim=None):
    """One condition of the plant's conditions record over time (name as in the CSV)."""
    t, v = run.conditions[name]
    fig, ax = plt.subplots(figsize=(10, 3.5))
    ax.plot(t, v, color='tab:green', lw=0.9, label=name)
    _switch_lines(ax, m)
    ax.set_ylabel(name)
    ax.set_xlabel('time $t$ [s]')
    ax.set_title("Plant condition %s: run '%s'" % (name, run.label))
    _legend(ax)
    _ylim_to_xlim(ax, [(t, v)], xlim)
    _xlim(ax, xlim)
    _save(fig, path)
    plt.close(fig)


def plot_gust(plt, run, m, path, xlim=None):
    """The Dryden vertical gust of a run with turbulence (docs/research/conditions.md)."""
    fig, ax = plt.subplots(figsize=(11, 3.8))
    ax.plot(run.t_gust, run.gust_w, color='tab:green', lw=0.9, label='$w_g$')
    _switch_lines(ax, m)
    ax.set_ylabel('vertical gust $w_g$ [m/s]')
    ax.set_xlabel('time $t$ [s]')
    ax.set_title(
        "Dryden vertical gust: run '%s' (std %.3g m/s)" % (run.label, float(np.std(run.gust_w)))
    )
    _legend(ax)
    _ylim_to_xlim(ax, [(run.t_gust, run.gust_w)], xlim)
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
            # Neighbouring verifications alternate between two rows, so their labels do not
            # run into each other when verifications are short.
            xytext=(2, -3 - 30 * (j % 2)),
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
        if r.gust_w is not None:
            p = os.path.join(out_dir, 'gust_%s.png' % s)
            plot_gust(plt, r, m, p, xlim)
            files.append(p)
        if has_flight(r):
            p = os.path.join(out_dir, 'flight_%s.png' % s)
            plot_flight(plt, r, m, p, xlim)
            files.append(p)
        for name, (_, v) in sorted(r.conditions.items()):
            if name in CONDITIONS_SHOWN_ELSEWHERE or len(v) == 0 or np.all(v == v[0]):
                continue
            p = os.path.join(out_dir, 'condition_%s_%s.png' % (_safe(name), s))
            plot_condition(plt, r, m, name, p, xlim)
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
