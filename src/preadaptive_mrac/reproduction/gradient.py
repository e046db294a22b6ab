"""Section (e): exact against approximate gradient."""


import numpy as np
import matplotlib.pyplot as plt
from .common import SCENARIOS, SETTING_TEXT, md_table, mrad, n_switch, quart, switch_label


class GradientSection:
    """Section (e), gradient."""

    # ---------------------------------------------------------------- (e) gradient
    def sec_gradient(self):
        N = len(self.seeds)
        out = ['## 5. Approximate (Π̂, θ − θ̂ := 0) against exact gradient\n']
        out.append(
            'Paired by seed: the same initial network, pa_learn (approximate Jacobian, what the '
            'paper uses) against pa_learn_exact (the true θ in Π, which only a simulation knows). '
            'Per switch: median and quartiles of the difference of peak |e| (exact − approx, '
            'mrad; negative = exact better), in how many seeds the exact gradient gives the lower '
            'peak, and in how many both are identical (no learning episode had happened yet, so '
            'both networks are still the initial one). Last row per block: whole-run integral '
            'of |e|.\n'
        )
        for s in SCENARIOS:
            for setting in ('paper', 'alt'):
                runs, cmd = self.dataset(s, setting)
                bm = self.by_mode(runs)
                a, x = bm['pa_learn'], bm['pa_learn_exact']
                rac = bm['rac'][1]
                out.append('### Scenario %d, %s\n' % (s, SETTING_TEXT[setting]))
                out.append('Regenerate: %s — data: `%s`\n' % (self.regen('gradient'), cmd))
                rows = []
                for w in range(1, n_switch(rac) + 1):
                    pa_ = np.array([a[sd]['windows'][w]['peak_abs_e'] for sd in self.seeds])
                    px = np.array([x[sd]['windows'][w]['peak_abs_e'] for sd in self.seeds])
                    d = px - pa_
                    q1, m, q3 = quart(d)
                    same = int(np.sum(np.abs(d) < 1e-12))
                    rows.append(
                        [
                            switch_label(rac, w),
                            '%s [%s, %s]' % (mrad(m), mrad(q1), mrad(q3)),
                            '%d/%d' % (int(np.sum(d < -1e-12)), N),
                            '%d/%d' % (same, N),
                        ]
                    )
                ia = np.array([a[sd]['iae'] for sd in self.seeds])
                ix = np.array([x[sd]['iae'] for sd in self.seeds])
                d = ix - ia
                q1, m, q3 = quart(d)
                rows.append(
                    [
                        'whole run, ∫|e|dt [mrad·s]',
                        '%.2f [%.2f, %.2f]' % (1e3 * m, 1e3 * q1, 1e3 * q3),
                        '%d/%d' % (int(np.sum(d < -1e-12)), N),
                        '%d/%d' % (int(np.sum(np.abs(d) < 1e-12)), N),
                    ]
                )
                out.append(
                    md_table(
                        ['switch', 'exact − approx, median [Q1, Q3]', 'exact lower', 'identical'],
                        rows,
                    )
                )
        out.append('\nRegenerate: %s\n' % self.regen('gradient'))
        fig, axs = plt.subplots(2, 3, figsize=(15, 9.5))
        for j, s in enumerate(SCENARIOS):
            for i, setting in enumerate(('paper', 'alt')):
                ax = axs[i, j]
                runs, _ = self.dataset(s, setting)
                bm = self.by_mode(runs)
                rac = bm['rac'][1]
                ns = n_switch(rac)
                cmap = plt.get_cmap('viridis', ns)
                lo, hi = np.inf, 0
                for w in range(1, ns + 1):
                    pa_ = np.array(
                        [bm['pa_learn'][sd]['windows'][w]['peak_abs_e'] for sd in self.seeds]
                    )
                    px = np.array(
                        [bm['pa_learn_exact'][sd]['windows'][w]['peak_abs_e'] for sd in self.seeds]
                    )
                    ax.scatter(
                        1e3 * pa_,
                        1e3 * px,
                        s=10,
                        color=cmap(w - 1),
                        label='%g s' % rac['windows'][w]['t_start'],
                    )
                    lo, hi = min(lo, pa_.min(), px.min()), max(hi, pa_.max(), px.max())
                lim = (0, 1e3 * hi * 1.05)
                ax.plot(lim, lim, 'k--', lw=0.8)
                ax.set_xlim(lim)
                ax.set_ylim(lim)
                ax.set_aspect('equal')
                ax.set_xlabel('peak |e|, pa_learn (approx.) [mrad]')
                ax.set_ylabel('peak |e|, pa_learn_exact [mrad]')
                ax.set_title('Scenario %d, %s' % (s, SETTING_TEXT[setting]), fontsize=9)
                ax.legend(fontsize=7, title='switch', title_fontsize=7, ncol=2 if ns > 5 else 1)
                ax.grid(alpha=0.3)
        fig.suptitle(
            'Exact against approximate gradient, one point per seed and switch '
            '(below the diagonal = exact better)',
            fontsize=11,
        )
        fig.tight_layout()
        out.append(self.fig(fig, 'gradient_scatter.png'))
        return '\n'.join(out)
