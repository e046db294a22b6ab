"""preadaptive_mrac.analysis figures: what a reader needs to read them is on the figure
: the meaning of the bar labels ("+97%") on the peak chart's axis, and on the
theta_hat figure that MRAC's estimate need not converge to the true theta."""

import types
import unittest

import matplotlib

matplotlib.use('Agg')
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import pkg_path  # noqa: F401,E402
from preadaptive_mrac.analysis import figure_style, figures, figures_compare  # noqa: E402
from preadaptive_mrac.analysis.runs import Run  # noqa: E402


class TestFigureTexts(unittest.TestCase):
    def setUp(self):
        # Keep the figures instead of writing PNGs.
        self.saved = []
        self.orig = (figure_style._save, figures._save, figures_compare._save)
        for mod in (figure_style, figures, figures_compare):
            mod._save = lambda fig, path: self.saved.append(fig)

    def tearDown(self):
        figure_style._save, figures._save, figures_compare._save = self.orig

    def test_peak_chart_says_what_its_bar_labels_mean(self):
        runs = [types.SimpleNamespace(label='rac', mode='rac')]
        runs.append(types.SimpleNamespace(label='pa', mode='pa_robust'))
        win = {'index': 1, 'kind': 'switch', 't_start': 5.0, 'theta_scale_before': 0.1}
        win.update(theta_scale=1.0, theta_before=None, theta=None)
        metrics = [
            {'label': 'rac', 'windows': [dict(win, peak_abs_e=0.02)]},
            {'label': 'pa', 'windows': [dict(win, peak_abs_e=0.0006)]},
        ]
        comparison = {
            'baseline': 'rac',
            'runs': [
                {'label': 'pa', 'windows': [{'baseline_index': 0, 'peak_reduction_pct': 97.0}]}
            ],
        }
        figures_compare.plot_peaks(plt, runs, metrics, comparison, 'rac', 'unused.png')
        ax = self.saved[-1].axes[0]
        self.assertIn('+97%', [t.get_text() for t in ax.texts])
        self.assertIn("100 (1 - peak / rac's peak) %", ax.get_xlabel())
        self.assertIn("+97% = a peak 97% below rac's", ax.get_xlabel())

    def test_theta_figure_says_the_estimate_need_not_converge(self):
        run = Run('rac', 'test.csv')
        run.mode = 'rac'
        run.t_e = run.t_theta = np.linspace(0.0, 2.0, 21)
        run.theta_hat = np.zeros((21, 3))
        run.theta = np.ones((21, 3))
        m = {'switches': [], 'windows': []}
        figures.plot_theta(plt, run, m, 'unused.png')
        title = self.saved[-1].axes[0].get_title()
        self.assertIn('need not converge', title)


if __name__ == '__main__':
    unittest.main()
