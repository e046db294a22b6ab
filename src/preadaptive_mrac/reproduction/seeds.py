"""Sections (b) and (c): peaks after each switch and their distribution over seeds."""


import numpy as np
import matplotlib
import matplotlib.pyplot as plt
from matplotlib.lines import Line2D
from matplotlib.patches import Patch
from .common import (
    MODE_COLOR,
    PA_MODES,
    SCENARIOS,
    SETTING_TEXT,
    cscale,
    first_onset,
    fmt_pct,
    md_table,
    mrad,
    n_switch,
    quart,
    reduction,
    switch_label,
)


class PeakSeedSections:
    """Sections (b) peaks and (c) seeds."""

    # ---------------------------------------------------------------- (b) peaks
    def sec_peaks(self):
        out = ['## 2. Peak |e| per window\n']
        out.append(
            'Peak |e| = max |α − α_r| over each window (t_start, t_end] between θ switches, in '
            'mrad. rac does not depend on the seed; for the preadaptation modes the table gives '
            'seed 1 and the median over the %d seeds (seed = seed of the network\'s random '
            'initial weights, `controller.preadaptation.seed`).\n' % len(self.seeds)
        )
        for s in SCENARIOS:
            for setting in ('paper', 'alt'):
                runs, cmd = self.dataset(s, setting)
                bm = self.by_mode(runs)
                rac, spread = self.rac_ref(bm)
                out.append('### Scenario %d, %s\n' % (s, SETTING_TEXT[setting]))
                out.append('Regenerate: %s — data: `%s`\n' % (self.regen('peaks'), cmd))
                rows = []
                for w in range(len(rac['windows'])):
                    win = rac['windows'][w]
                    row = [
                        '%g–%g s (θ = %g)' % (win['t_start'], win['t_end'], cscale(rac, w)),
                        mrad(win['peak_abs_e']),
                    ]
                    for m in PA_MODES:
                        p = [bm[m][sd]['windows'][w]['peak_abs_e'] for sd in self.seeds]
                        row += [mrad(bm[m][1]['windows'][w]['peak_abs_e']), mrad(np.median(p))]
                    rows.append(row)
                hdr = ['window', 'rac']
                for m in PA_MODES:
                    hdr += ['%s seed 1' % m, '%s median' % m]
                out.append(md_table(hdr, rows))
                out.append(
                    '\n(rac: largest difference between seeds over all windows: %.1e rad.)\n'
                    % spread
                )
        return '\n'.join(out)

    # ---------------------------------------------------------------- (c) seeds
    def seed_stats(self, s, setting):
        runs, cmd = self.dataset(s, setting)
        bm = self.by_mode(runs)
        rac, _ = self.rac_ref(bm)
        st = {}
        for m in PA_MODES:
            for w in range(1, n_switch(rac) + 1):
                pr = rac['windows'][w]['peak_abs_e']
                p = np.array([bm[m][sd]['windows'][w]['peak_abs_e'] for sd in self.seeds])
                red = reduction(p, pr)
                det = sum(first_onset(bm[m][sd], w) is not None for sd in self.seeds)
                st[(m, w)] = dict(
                    peak=p,
                    red=red,
                    rac=pr,
                    det=det,
                    beat=int(np.sum(p < pr)),
                    ge50=int(np.sum(red >= 50.0)),
                )
        return st, rac, bm, cmd

    def sec_seeds(self):
        N = len(self.seeds)
        out = ['## 3. Distribution over the network\'s random initialisation (%d seeds)\n' % N]
        out.append(
            'Per switch and mode: in how many seeds an onset was detected after the switch; the '
            'peak |e| in the window after the switch (median [first quartile, third quartile], '
            'mrad; rac in the first column); the peak reduction against rac (positive = lower peak '
            'than rac, median [Q1, Q3]); how many seeds have a lower peak than rac, and how many '
            'reach the paper\'s ≥ 50 % reduction. Quartiles are numpy percentiles (linear '
            'interpolation). The figures show every seed: peak relative to rac on a log scale '
            '(1 = rac, 0.5 = the paper\'s claimed 50 % reduction).\n'
        )
        for s in SCENARIOS:
            for setting in ('paper', 'alt'):
                st, rac, bm, cmd = self.seed_stats(s, setting)
                out.append('### Scenario %d, %s\n' % (s, SETTING_TEXT[setting]))
                out.append('Regenerate: %s — data: `%s`\n' % (self.regen('seeds'), cmd))
                rows = []
                for w in range(1, n_switch(rac) + 1):
                    for m in PA_MODES:
                        d = st[(m, w)]
                        q1, med, q3 = quart(d['peak'])
                        r1, rm, r3 = quart(d['red'])
                        rows.append(
                            [
                                switch_label(rac, w) if m == 'pa' else '',
                                mrad(d['rac']) if m == 'pa' else '',
                                m,
                                '%d/%d' % (d['det'], N),
                                '%s [%s, %s]' % (mrad(med), mrad(q1), mrad(q3)),
                                '%s [%s, %s]' % (fmt_pct(rm), fmt_pct(r1), fmt_pct(r3)),
                                '%d/%d' % (d['beat'], N),
                                '%d/%d' % (d['ge50'], N),
                            ]
                        )
                out.append(
                    md_table(
                        [
                            'switch',
                            'rac peak',
                            'mode',
                            'onset det.',
                            'peak median [Q1, Q3]',
                            'reduction median [Q1, Q3]',
                            'beats rac',
                            '≥ 50 %',
                        ],
                        rows,
                        ['---', '---:', '---', '---:', '---:', '---:', '---:', '---:'],
                    )
                )
            out.append(self.seed_figure(s))
        return '\n'.join(out)

    def seed_figure(self, s):
        fig, axes = plt.subplots(2, 1, figsize=(13 if s == 3 else 10, 8), sharey=True)
        rng = np.random.default_rng(0)
        for ax, setting in zip(axes, ('paper', 'alt')):
            st, rac, _, _ = self.seed_stats(s, setting)
            ns = n_switch(rac)
            width = 0.25
            for i, m in enumerate(PA_MODES):
                data = [st[(m, w)]['peak'] / st[(m, w)]['rac'] for w in range(1, ns + 1)]
                pos = np.arange(1, ns + 1) + (i - 1) * width
                bp = ax.boxplot(
                    data,
                    positions=pos,
                    widths=width * 0.85,
                    patch_artist=True,
                    showfliers=False,
                    medianprops=dict(color='k'),
                )
                for b in bp['boxes']:
                    b.set_facecolor(MODE_COLOR[m])
                    b.set_alpha(0.35)
                for p, d in zip(pos, data):
                    ax.scatter(
                        p + rng.uniform(-0.07, 0.07, len(d)), d, s=7, color=MODE_COLOR[m], zorder=3
                    )
            ax.axhline(1.0, color='tab:blue', lw=1.2)
            ax.axhline(0.5, color='k', ls='--', lw=1.0)
            ax.set_yscale('log')
            ticks = [0.1, 0.2, 0.3, 0.5, 0.7, 1, 1.5, 2, 3, 5, 10]
            ax.yaxis.set_major_locator(matplotlib.ticker.FixedLocator(ticks))
            ax.yaxis.set_major_formatter(
                matplotlib.ticker.FixedFormatter(['%g' % t for t in ticks])
            )
            ax.yaxis.set_minor_locator(matplotlib.ticker.NullLocator())
            ax.set_xticks(np.arange(1, ns + 1))
            ax.set_xticklabels(
                [
                    '%g s\n%g→%g'
                    % (rac['windows'][w]['t_start'], cscale(rac, w - 1), cscale(rac, w))
                    for w in range(1, ns + 1)
                ]
            )
            ax.set_xlim(0.5, ns + 0.5)
            ax.set_ylabel('peak |e| / peak |e| of rac')
            ax.set_title(
                'Scenario %d, %s: %d seeds per box' % (s, SETTING_TEXT[setting], len(self.seeds))
            )
            ax.grid(axis='y', which='both', alpha=0.3)
        axes[-1].set_xlabel('switch time and θ scale change')
        handles = [Patch(facecolor=MODE_COLOR[m], alpha=0.5, label=m) for m in PA_MODES]
        handles += [
            Line2D([], [], color='tab:blue', label='rac (= 1)'),
            Line2D([], [], color='k', ls='--', label='paper\'s claim: 50 % lower peak'),
        ]
        axes[0].legend(handles=handles, loc='upper left', fontsize=8, ncol=2)
        fig.tight_layout()
        return '\nRegenerate: %s — data: the two sweeps of scenario %d above.\n\n' % (
            self.regen('seeds'),
            s,
        ) + self.fig(fig, 'seeds_s%d.png' % s)
