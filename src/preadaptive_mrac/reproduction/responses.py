"""Section (f) time responses and the every-seed figure, and the network section."""


import numpy as np
import matplotlib.pyplot as plt
from matplotlib.lines import Line2D
from .common import (
    K_CE,
    MODE_COLOR,
    PA_MODES,
    SCENARIOS,
    SETTINGS,
    SETTING_TEXT,
    SPREAD_ROWS,
    events,
    fmt_pct,
    md_table,
    reduction,
    switch_label,
)


class ResponseSections:
    """Section (f) responses and the network section."""

    # ---------------------------------------------------------------- (f) responses
    def sec_responses(self):
        out = ['## 6. Time responses (the paper\'s Figs. 2–4)\n']
        out.append(
            'α and α_ref = x_r[1] against time, seed 1 (fixed before looking at any result; its '
            'rank among the %d seeds is in the caption line), green vertical lines at onsets '
            '(E_u), black at recoveries (E_d) of the preadaptation run named in the panel title. '
            'The lower panels show e = α − α_ref with the ±c_e band.\n' % len(self.seeds)
        )
        specs = []
        for setting in ('paper', 'alt'):
            specs.append((1, setting, [('pa', (0, 60)), ('pa_learn', (0, 60))], None))
            specs.append((2, setting, [('pa_learn', (0, 140)), ('pa_learn', (70, 140))], None))
            specs.append(
                (
                    3,
                    setting,
                    [('pa_learn_exact', (0, 80)), ('pa_learn_exact', (65, 140))],
                    'pa_learn',
                )
            )
        need = []
        for s, setting, panels, extra in specs:
            for m in ['rac'] + [p[0] for p in panels] + ([extra] if extra else []):
                sp = (s, m, 1, SETTINGS[setting], None)
                if sp not in need:
                    need.append(sp)
        for setting in ('paper', 'alt'):
            need.append((1, 'rac', 1, SETTINGS[setting], SPREAD_ROWS))
            need += [
                (1, 'pa_learn', sd, SETTINGS[setting], SPREAD_ROWS) for sd in self.spread_seeds
            ]
        self.prefetch(need)
        for s, setting, panels, extra in specs:
            fig, cmds, cap = self.response_fig(s, setting, panels, extra)
            out.append('### Scenario %d, %s\n' % (s, SETTING_TEXT[setting]))
            out.append(
                'Regenerate: %s — data: %s\n'
                % (self.regen('responses'), ', '.join('`%s`' % c for c in cmds))
            )
            out.append(self.fig(fig, 'response_s%d_%s.png' % (s, setting)))
            out.append('\n' + cap + '\n')
        out.append(self.spread_fig())
        return '\n'.join(out)

    def rank_text(self, s, setting, mode, w):
        st, rac, _, _ = self.seed_stats(s, setting)
        red = st[(mode, w)]['red']
        r1 = red[self.seeds.index(1)]
        rank = int(np.sum(red > r1)) + 1
        return '%s at %s: seed 1 %s vs rac, rank %d of %d (1 = best; median %s)' % (
            mode,
            switch_label(rac, w),
            fmt_pct(r1),
            rank,
            len(red),
            fmt_pct(np.median(red)),
        )

    def response_fig(self, s, setting, panels, extra):
        sets = SETTINGS[setting]
        rac, rsum, rcmd = self.sim(s, 'rac', 1, sets)
        cmds = [rcmd.replace('OUT.csv', 'rac.csv')]
        fig, axs = plt.subplots(
            2,
            len(panels),
            figsize=(15, 8.5),
            sharex='col',
            gridspec_kw=dict(height_ratios=[2, 1.2]),
        )
        for j, (mode, (t0, t1)) in enumerate(panels):
            runs = [('rac', rac, rsum)]
            shown = [mode] if extra is None else [extra, mode]
            for m in shown:
                c, sm, cmd = self.sim(s, m, 1, sets)
                runs.append((m, c, sm))
                if cmd.replace('OUT.csv', m + '.csv') not in cmds:
                    cmds.append(cmd.replace('OUT.csv', m + '.csv'))
            ax, axe = axs[0, j], axs[1, j]
            for m, c, sm in runs:
                k = (c['t'] >= t0) & (c['t'] <= t1)
                lw = 1.6 if m == 'rac' else 1.2
                ax.plot(
                    c['t'][k],
                    c['x1'][k],
                    color=MODE_COLOR[m],
                    lw=lw,
                    label='α, %s' % m + ('' if m == 'rac' else ' (seed 1)'),
                )
                axe.plot(c['t'][k], 1e3 * c['e'][k], color=MODE_COLOR[m], lw=lw)
            k = (rac['t'] >= t0) & (rac['t'] <= t1)
            ax.plot(rac['t'][k], rac['xr1'][k], color='0.3', ls='--', lw=1.4, label='α_ref')
            c_e = float(sets.get(K_CE, 0.005))
            for y in (c_e, -c_e):
                axe.axhline(1e3 * y, color='0.5', ls=':', lw=1)
            ev_sum = runs[-1][2]
            for e in ev_sum['events']:
                if t0 <= e['t'] <= t1 and e['type'] in ('onset', 'recovered'):
                    col = 'tab:green' if e['type'] == 'onset' else 'k'
                    for a in (ax, axe):
                        a.axvline(e['t'], color=col, lw=0.9, alpha=0.8)
            for sw in rsum['windows'][1:]:
                if t0 <= sw['t_start'] <= t1:
                    ax.annotate(
                        ' θ→%g' % sw['theta'][0],
                        (sw['t_start'], 0.985),
                        xycoords=('data', 'axes fraction'),
                        fontsize=8,
                        ha='left',
                        va='top',
                        color='0.2',
                        bbox=dict(boxstyle='square,pad=0.1', fc='w', ec='none', alpha=0.8),
                    )
            ax.set_xlim(t0, t1)
            ax.set_ylabel('angle of attack α [rad]')
            axe.set_ylabel('e = α − α_ref [mrad]')
            axe.set_xlabel('time t [s]')
            ax.set_title(
                'Scenario %d, %s: rac vs %s; event lines of %s'
                % (s, setting, ' and '.join(shown), ev_sum['mode']),
                fontsize=9,
            )
            h, lab = ax.get_legend_handles_labels()
            h += [
                Line2D([], [], color='tab:green', lw=1, label='onset (E_u = 1)'),
                Line2D([], [], color='k', lw=1, label='recovery (E_d = 1)'),
            ]
            ax.legend(handles=h, fontsize=7, loc='lower right', ncol=2)
            ax.grid(alpha=0.3)
            axe.grid(alpha=0.3)
        fig.suptitle('Scenario %d, %s — seed 1' % (s, SETTING_TEXT[setting]), fontsize=11)
        fig.tight_layout()
        # caption: where seed 1 ranks at the last switch for the plotted modes
        ns = len(rsum['windows']) - 1
        cap = 'Seed 1\'s rank: ' + '; '.join(
            self.rank_text(s, setting, m, ns)
            for m in dict.fromkeys([p[0] for p in panels] + ([extra] if extra else []))
        )
        return fig, cmds, cap

    def spread_fig(self):
        out = ['### Every seed around the t = 45 s switch of scenario 1\n']
        t0, t1 = SPREAD_ROWS
        fig, axs = plt.subplots(1, 2, figsize=(15, 5.5), sharey=True)
        cmds = []
        for ax, setting in zip(axs, ('paper', 'alt')):
            sets = SETTINGS[setting]
            rc, rs, cmd = self.sim(1, 'rac', 1, sets, rows=SPREAD_ROWS)
            pr = rs['windows'][3]['peak_abs_e']
            n = {'b': 0, 'g': 0, 'r': 0}
            for sd in self.spread_seeds:
                c, sm, cmd = self.sim(1, 'pa_learn', sd, sets, rows=SPREAD_ROWS)
                red = reduction(sm['windows'][3]['peak_abs_e'], pr)
                col = 'tab:green' if red >= 50 else ('tab:red' if red < 0 else 'tab:gray')
                n['g' if red >= 50 else ('r' if red < 0 else 'b')] += 1
                ax.plot(c['t'], 1e3 * c['e'], color=col, lw=0.8, alpha=0.7)
            cmds.append(
                cmd.replace('--seed %d' % self.spread_seeds[-1], '--seed S').replace(
                    'OUT.csv', 'S.csv'
                )
            )
            ax.plot(rc['t'], 1e3 * rc['e'], color='tab:blue', lw=2.2)
            c_e = float(sets.get(K_CE, 0.005))
            for y in (c_e, -c_e):
                ax.axhline(1e3 * y, color='0.5', ls=':')
            ax.axvline(45.0, color='0.3', lw=0.8)
            ax.set_xlabel('time t [s]')
            ax.set_title(
                '%s: pa_learn, seeds 1–%d' % (SETTING_TEXT[setting], len(self.spread_seeds)),
                fontsize=10,
            )
            ax.grid(alpha=0.3)
            ax.legend(
                handles=[
                    Line2D([], [], color='tab:blue', lw=2.2, label='rac'),
                    Line2D(
                        [],
                        [],
                        color='tab:green',
                        label='pa_learn, ≥ 50 %% lower peak (%d seeds)' % n['g'],
                    ),
                    Line2D(
                        [],
                        [],
                        color='tab:gray',
                        label='pa_learn, 0–50 %% lower (%d seeds)' % n['b'],
                    ),
                    Line2D(
                        [],
                        [],
                        color='tab:red',
                        label='pa_learn, higher peak than rac (%d seeds)' % n['r'],
                    ),
                    Line2D([], [], color='0.5', ls=':', label='±c_e'),
                ],
                fontsize=8,
                loc='upper right',
            )
        axs[0].set_ylabel('e = α − α_ref [mrad]')
        fig.suptitle(
            'Scenario 1, the t = 45 s switch (θ 2 → 4): every seed of pa_learn against rac',
            fontsize=11,
        )
        fig.tight_layout()
        out.append(
            'Regenerate: %s — data (S = 1..%d): %s, and the same with `--mode rac --seed 1`\n'
            % (self.regen('responses'), len(self.spread_seeds), ', '.join('`%s`' % c for c in cmds))
        )
        out.append(self.fig(fig, 'spread_s1_45s.png'))
        return '\n'.join(out)

    # ---------------------------------------------------------------- network
    def sec_network(self):
        out = ['## 7. What the preadaptation network computes here\n']
        out.append(
            'θ̂_I = Wᵀσ(Vᵀz) with z = [e, |ê̇|] at the onset sample. At an onset |e| = c_e by '
            'construction and |ê̇| is a few hundredths, so Vᵀz ≈ 0, σ ≈ 0.5 and θ̂_I ≈ 0.5·Σ_j '
            'W[j,:] '
            'for *every* onset: the network is in effect one learned reset vector, whatever the '
            'direction or size of the jump. The tables measure this.\n'
        )
        runs, cmd = self.dataset(3, 'alt')
        bm = self.by_mode(runs)
        r = bm['pa'][1]
        out.append(
            '### pa (no learning), scenario 3, %s, seed 1: θ̂_I at every onset\n'
            % SETTING_TEXT['alt']
        )
        out.append('Regenerate: %s — data: `%s`\n' % (self.regen('network'), cmd))
        rows = []
        for e in events(r, 'onset'):
            rows.append(
                [
                    '%.3f' % e['t'],
                    '%+.4f' % e['e'],
                    '%.4f' % abs(e['e_dot']),
                    ', '.join('%+.4f' % v for v in e['theta_hat_reset']),
                ]
            )
        out.append(md_table(['onset t [s]', 'e [rad]', '|ê̇| [rad/s]', 'θ̂_I'], rows))
        # within-run vs across-seed ranges, all scenarios and settings, pa
        rows = []
        zmax_e = zmax_ed = 0.0
        cmds = []
        for s in SCENARIOS:
            for setting in ('paper', 'alt'):
                runs, cmd = self.dataset(s, setting)
                cmds.append(cmd)
                bm = self.by_mode(runs)
                within, first = [], []
                for sd in self.seeds:
                    th = np.array([e['theta_hat_reset'] for e in events(bm['pa'][sd], 'onset')])
                    if len(th) == 0:
                        continue
                    first.append(th[0])
                    if len(th) > 1:
                        within.append(np.max(th.max(axis=0) - th.min(axis=0)))
                for m in PA_MODES:
                    for sd in self.seeds:
                        for e in events(bm[m][sd], 'onset'):
                            zmax_e = max(zmax_e, abs(e['e']))
                            zmax_ed = max(zmax_ed, abs(e['e_dot']))
                first = np.array(first)
                across = (
                    np.max(first.max(axis=0) - first.min(axis=0))
                    if len(first) > 1
                    else float('nan')
                )
                rows.append(
                    [
                        'S%d, %s' % (s, setting),
                        '%.4f' % max(within) if within else 'n/a (≤ 1 onset)',
                        '%.3f' % across,
                    ]
                )
        out.append('\n### pa (no learning): spread of θ̂_I, all seeds\n')
        out.append('Regenerate: %s — data: the sweeps of section 3.\n' % self.regen('network'))
        out.append(
            md_table(
                [
                    'scenario, setting',
                    'largest range of θ̂_I over the onsets of one run',
                    'range of the first θ̂_I over seeds',
                ],
                rows,
            )
        )
        out.append(
            '\n(Range = max over the three components of max − min.) Largest |e| and |ê̇| '
            'at any onset in any of these runs: %.4f rad and %.4f rad/s.\n' % (zmax_e, zmax_ed)
        )
        return '\n'.join(out)
