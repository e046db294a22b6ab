#!/usr/bin/python3
"""Tests of scripts/analyze_bag and the preadaptive_mrac.analysis package on synthetic bags and
CSVs.

Run:  /usr/bin/python3 -m unittest discover -s test/viz -p 'test_*.py' -v

The bags and CSVs are written by synthetic.py (an independent Python closed loop, message
classes generated from msg/*.msg); expected values are recomputed from the arrays, or are
analytic for the hand-made CSV. The CLI is run as a user would (subprocess, exit codes,
stderr) and its metrics.json/.csv and figures are read back.
"""

import csv
import io
import json
import os
import shutil
import subprocess
import sys
import tempfile
import types
import unittest

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
PKG = os.path.abspath(os.path.join(HERE, '..', '..'))
SCRIPTS = os.path.join(PKG, 'scripts')
CLI = os.path.join(SCRIPTS, 'analyze_bag')
sys.path.insert(0, HERE)
sys.path.insert(
    0, os.path.join(PKG, 'src')
)  # the package of this source tree, not an installed one

import synthetic  # noqa: E402
from preadaptive_mrac import analysis as pa  # noqa: E402
from preadaptive_mrac.analysis import figure_style  # noqa: E402
from preadaptive_mrac.analysis import runs as run_records  # noqa: E402

PY = '/usr/bin/python3' if os.path.exists('/usr/bin/python3') else sys.executable


def run_cli(*args):
    p = subprocess.run(
        [PY, CLI] + [str(a) for a in args],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        universal_newlines=True,
        timeout=300,
    )
    return p.returncode, p.stdout, p.stderr


def is_png(path):
    with open(path, 'rb') as f:
        return f.read(8) == b'\x89PNG\r\n\x1a\n'


class Fixtures:
    """Simulations and files shared by the tests (made once)."""

    dir = None

    @classmethod
    def make(cls):
        if cls.dir:
            return cls
        cls.dir = tempfile.mkdtemp(prefix='pmrac_analysis_test_')
        cls.classes = synthetic.load_msg_classes()
        cls.rac = synthetic.simulate('rac')
        cls.pa = synthetic.simulate('pa', seed=1)
        d = cls.dir
        cls.compare_bag = synthetic.write_bag(
            os.path.join(d, 'compare.bag'), {'rac': cls.rac, 'pa': cls.pa}, cls.classes
        )
        cls.rac_bag = synthetic.write_bag(
            os.path.join(d, 'rac_run.bag'), {'': cls.rac}, cls.classes
        )
        cls.pa_bag = synthetic.write_bag(os.path.join(d, 'pa_run.bag'), {'': cls.pa}, cls.classes)
        cls.rac_csv = synthetic.write_csv(
            os.path.join(d, 'out_rac.csv'), cls.rac, os.path.join(d, 'out_rac.json')
        )
        cls.pa_csv = synthetic.write_csv(os.path.join(d, 'scenario_pa.csv'), cls.pa)
        # pa_robust: decisions on onsets and as DECISION events
        cls.robust = synthetic.simulate('pa_robust', seed=1)
        cls.robust_bag = synthetic.write_bag(
            os.path.join(d, 'compare_robust.bag'), {'rac': cls.rac, 'pa': cls.robust}, cls.classes
        )
        cls.robust_csv = synthetic.write_csv(
            os.path.join(d, 's1_pa_robust.csv'), cls.robust, os.path.join(d, 's1_pa_robust.json')
        )
        # a bag recorded before AttentionEvent had the decision fields
        cls.legacy_classes = synthetic.load_msg_classes(legacy_attention=True)
        cls.legacy_bag = synthetic.write_bag(
            os.path.join(d, 'legacy_pa.bag'), {'': cls.pa}, cls.legacy_classes
        )
        return cls


def tearDownModule():
    if Fixtures.dir and not os.environ.get('PMRAC_KEEP_TEST_FILES'):
        shutil.rmtree(Fixtures.dir, ignore_errors=True)


class TestEnvelopeExitBag(unittest.TestCase):
    """A bag whose truth says the plant left the flight envelope: analyze_bag's
    report names the run, the time and the bound before anything else; a bag inside does not."""

    def test_report_starts_with_the_exit(self):
        f = Fixtures.make()
        sim = dict(f.rac)
        sim['envelope_step'] = 1500
        sim['envelope_bound'] = 'alpha'
        sim['envelope_text'] = (
            't = %g s (step 1500): |alpha| = 0.3 rad > 0.2618 rad (plant.envelope.max_alpha)'
            % sim['t'][1500]
        )
        bag = synthetic.write_bag(os.path.join(f.dir, 'lost.bag'), {'': sim}, f.classes)
        rc, out, err = run_cli(bag, '--out', os.path.join(f.dir, 'out_lost'))
        self.assertEqual(rc, 0, err)
        self.assertEqual(
            out.splitlines()[0], '!! run lost LEFT THE FLIGHT ENVELOPE at ' + sim['envelope_text']
        )
        rc, out, err = run_cli(f.rac_bag, '--out', os.path.join(f.dir, 'out_inside'))
        self.assertEqual(rc, 0, err)
        self.assertNotIn('FLIGHT ENVELOPE', out)


class TestCompareBag(unittest.TestCase):
    """A compare.launch-style bag: /rac/... and /pa/... in one file."""

    @classmethod
    def setUpClass(cls):
        cls.f = Fixtures.make()
        cls.out = os.path.join(cls.f.dir, 'out_compare')
        cls.rc, cls.stdout, cls.stderr = run_cli(cls.f.compare_bag, '--out', cls.out)
        with open(os.path.join(cls.out, 'metrics.json')) as fh:
            cls.doc = json.load(fh)
        cls.runs = {r['label']: r for r in cls.doc['runs']}

    def test_exit_and_runs(self):
        self.assertEqual(self.rc, 0, self.stderr)
        self.assertEqual(sorted(self.runs), ['pa', 'rac'])
        self.assertEqual(self.runs['rac']['mode'], 'rac')
        self.assertEqual(self.runs['pa']['mode'], 'pa')
        self.assertEqual(self.runs['pa']['namespace'], '/pa')

    def test_switches_from_truth(self):
        for label, sim in (('rac', self.f.rac), ('pa', self.f.pa)):
            got = [s['t'] for s in self.runs[label]['switches']]
            np.testing.assert_allclose(got, sim['switches'], atol=1e-9)
            scales = [w['theta_scale'] for w in self.runs[label]['windows']]
            np.testing.assert_allclose(scales, sim['scales'])

    def test_window_metrics_match_the_data(self):
        for label, sim in (('rac', self.f.rac), ('pa', self.f.pa)):
            ref = synthetic.reference_metrics(sim)
            wins = self.runs[label]['windows']
            self.assertEqual(len(wins), len(ref))
            for w, r in zip(wins, ref):
                self.assertAlmostEqual(w['t_start'], r['t_start'], places=9)
                self.assertAlmostEqual(w['peak_abs_e'], r['peak'], places=12)
                self.assertEqual(w['onsets'], r['onsets'], (label, w['index']))
                self.assertEqual(w['recoveries'], r['recoveries'], (label, w['index']))
                if r['recovery_time'] is None:
                    self.assertIsNone(w['recovery_time'])
                else:
                    self.assertAlmostEqual(w['recovery_time'], r['recovery_time'], places=9)
            # windows partition the run: their integrals add up to the whole-run IAE
            t, ae = sim['t'], np.abs(sim['e'])
            iae = float(np.sum(0.5 * (ae[1:] + ae[:-1]) * np.diff(t)))
            whole = self.runs[label]['whole_run']
            self.assertAlmostEqual(whole['iae'], iae, places=10)
            self.assertAlmostEqual(sum(w['iae'] for w in wins), iae, places=10)
            self.assertAlmostEqual(whole['max_abs_u'], float(np.max(np.abs(sim['u']))), places=12)
            self.assertAlmostEqual(whole['peak_abs_e'], float(ae.max()), places=12)
            n = {k: sum(1 for ev in sim['events'] if ev['type_name'] == k) for k in pa.EVENT_TYPES}
            self.assertEqual(whole['onsets'], n['onset'])
            self.assertEqual(whole['recoveries'], n['recovered'])
            self.assertEqual(whole['ignored_recoveries'], n['ignored_recovery'])
            self.assertEqual(whole['ignored_onsets'], n['ignored_onset'])

    def test_comparison_against_rac(self):
        comp = self.doc['comparison']
        self.assertEqual(comp['baseline'], 'rac')
        rows = comp['runs'][0]['windows']
        ref_rac = synthetic.reference_metrics(self.f.rac)
        ref_pa = synthetic.reference_metrics(self.f.pa)
        self.assertEqual(len(rows), len(ref_rac))
        for row, rr, rp in zip(rows, ref_rac, ref_pa):
            want = 100.0 * (rr['peak'] - rp['peak']) / rr['peak']
            self.assertAlmostEqual(row['peak_reduction_pct'], want, places=8)
        # the fixture's pa run is worse after the first switch and better after the last
        self.assertLess(rows[1]['peak_reduction_pct'], 0.0)
        self.assertGreater(rows[3]['peak_reduction_pct'], 50.0)
        self.assertIn("comparison against 'rac'", self.stdout)
        self.assertIn('%+.1f%%' % rows[3]['peak_reduction_pct'], self.stdout)

    def test_files_written(self):
        names = set(os.listdir(self.out))
        # no pa_robust run, no decisions figure
        self.assertFalse([n for n in names if n.startswith('decisions_')])
        for n in (
            'metrics.json',
            'metrics.csv',
            'alpha_rac.png',
            'alpha_pa.png',
            'theta_hat_rac.png',
            'theta_hat_pa.png',
            'elevator_rac.png',
            'elevator_pa.png',
            'alpha_compare.png',
            'peak_per_window.png',
            'cost_per_episode.png',
        ):
            self.assertIn(n, names)
            if n.endswith('.png'):
                p = os.path.join(self.out, n)
                self.assertTrue(is_png(p), n)
                self.assertGreater(os.path.getsize(p), 20000, n)
        with open(os.path.join(self.out, 'metrics.csv')) as fh:
            rows = list(csv.DictReader(fh))
        self.assertEqual(len(rows), 2 * (4 + 1))
        pa_w3 = [r for r in rows if r['label'] == 'pa' and r['window'] == '3'][0]
        self.assertEqual(pa_w3['baseline'], 'rac')
        self.assertAlmostEqual(
            float(pa_w3['peak_reduction_pct']),
            self.doc['comparison']['runs'][0]['windows'][3]['peak_reduction_pct'],
            places=5,
        )

    def test_alpha_figure_has_event_lines(self):
        """The alpha figure draws one green line per onset and one black per recovery."""
        import matplotlib

        matplotlib.use('Agg')
        runs = pa.load_runs(self.f.compare_bag)
        run = [r for r in runs if r.label == 'pa'][0]
        m = pa.run_metrics(run)
        plt = figure_style._mpl()
        captured = {}
        orig = plt.subplots

        def spy(*a, **k):
            fig, axes = orig(*a, **k)
            captured['axes'] = axes
            return fig, axes

        plt.subplots = spy
        try:
            pa.plot_alpha(plt, run, m, os.path.join(self.f.dir, 'spy.png'), 0.005)
        finally:
            plt.subplots = orig
        ax = captured['axes'][0]
        xs = {'green': [], 'black': []}
        for line in ax.get_lines():
            x = line.get_xdata()
            if len(x) == 2 and x[0] == x[1]:
                c = matplotlib.colors.to_hex(line.get_color())
                if c == matplotlib.colors.to_hex(pa.ONSET_COLOR):
                    xs['green'].append(x[0])
                elif c == '#000000':
                    xs['black'].append(x[0])
        on = [ev['t'] for ev in self.f.pa['events'] if ev['type_name'] == 'onset']
        rec = [ev['t'] for ev in self.f.pa['events'] if ev['type_name'] == 'recovered']
        np.testing.assert_allclose(sorted(xs['green']), on)
        np.testing.assert_allclose(sorted(xs['black']), rec)


def decision_events(sim):
    return [ev for ev in sim['events'] if ev.get('decision')]


class TestDecisions(unittest.TestCase):
    """pa_robust's verification decisions: read from bags (AttentionEvent fields) and the
    CLI's JSON, listed in metrics.json and the report, drawn on the time plots; bags
    recorded before the fields existed still load."""

    @classmethod
    def setUpClass(cls):
        cls.f = Fixtures.make()
        cls.out = os.path.join(cls.f.dir, 'out_robust')
        cls.rc, cls.stdout, cls.stderr = run_cli(cls.f.robust_bag, '--out', cls.out)
        with open(os.path.join(cls.out, 'metrics.json')) as fh:
            cls.doc = json.load(fh)
        cls.runs = {r['label']: r for r in cls.doc['runs']}

    def assertDecisionsEqual(self, got, sim):
        want = decision_events(sim)
        self.assertGreaterEqual(len(want), 8)
        self.assertEqual({ev['decision'] for ev in want}, set(pa.DECISIONS))
        self.assertEqual(len(got), len(want))
        for g, w in zip(got, want):
            self.assertAlmostEqual(g['t'], w['t'], places=9)
            self.assertEqual(g['type'], w['type_name'])
            self.assertEqual(g['decision'], w['decision'])
            self.assertEqual(g['chosen'], w['chosen'])
            self.assertEqual(g['candidates'], w['candidates'])
            self.assertAlmostEqual(g['score'], w['score'], places=14)
            self.assertAlmostEqual(g['score_keep'], w['score_keep'], places=14)
            np.testing.assert_allclose(g['theta_hat_after'], w['theta_hat_after'], atol=1e-12)

    def test_decisions_in_metrics_json(self):
        self.assertEqual(self.rc, 0, self.stderr)
        self.assertEqual(self.runs['pa']['mode'], 'pa_robust')
        r = self.runs['pa']
        self.assertDecisionsEqual(r['decisions'], self.f.robust)
        want = decision_events(self.f.robust)
        w = r['whole_run']
        self.assertEqual(w['decisions'], len(want))
        self.assertEqual(
            w['decision_events'], sum(1 for ev in self.f.robust['events'] if ev['type'] == 4)
        )
        self.assertEqual(
            w['decisions_by_kind'],
            {k: sum(1 for ev in want if ev['decision'] == k) for k in pa.DECISIONS},
        )
        ref = synthetic.reference_metrics(self.f.robust)
        self.assertEqual(
            [win['decisions'] for win in r['windows']], [rw['decisions'] for rw in ref]
        )
        # every event, DECISION ones included, with its fields; none on the others
        self.assertEqual(
            [e['type'] for e in r['events']], [e['type_name'] for e in self.f.robust['events']]
        )
        for e, ev in zip(r['events'], self.f.robust['events']):
            self.assertEqual(e['decision'], ev['decision'] or None)
        # the rac run of the same bag has none
        self.assertEqual(self.runs['rac']['decisions'], [])
        self.assertEqual(self.runs['rac']['whole_run']['decisions'], 0)
        with open(os.path.join(self.out, 'metrics.csv')) as fh:
            rows = list(csv.DictReader(fh))
        alls = {row['label']: row for row in rows if row['window'] == 'all'}
        self.assertEqual(int(alls['pa']['decisions']), len(want))
        self.assertEqual(int(alls['rac']['decisions']), 0)

    def test_decisions_from_the_cli_json(self):
        run = pa.load_runs(self.f.robust_csv)[0]
        self.assertEqual(run.mode, 'pa_robust')
        self.assertDecisionsEqual(pa.run_metrics(run)['decisions'], self.f.robust)
        # a DECISION that keeps does not move theta_hat; the others do
        for ev in run.events:
            if ev['type'] == 'decision':
                self.assertEqual(ev['reset'], ev['decision'] != 'keep')

    def test_report_lists_the_decisions(self):
        want = decision_events(self.f.robust)
        self.assertIn(
            'decisions (pa_robust verification): %d, %d of them DECISION events'
            % (len(want), sum(1 for ev in want if ev['type'] == 4)),
            self.stdout,
        )
        # the last decision of each verification (from each onset)
        finals = pa.final_decisions([{'type': ev['type_name'], 't': ev['t']} for ev in want])
        self.assertEqual(len(finals), sum(1 for ev in want if ev['type'] == 0))
        for d in finals:
            ev = [e for e in want if e['t'] == d['t']][0]
            self.assertIn('t = %.3f s: %s' % (ev['t'], ev['decision']), self.stdout)
            self.assertIn(
                'residual %.3g rad against %.3g rad keeping' % (ev['score'], ev['score_keep']),
                self.stdout,
            )

    def test_decisions_figure_written(self):
        p = os.path.join(self.out, 'decisions_pa.png')
        self.assertTrue(os.path.exists(p), sorted(os.listdir(self.out)))
        self.assertTrue(is_png(p))
        self.assertGreater(os.path.getsize(p), 20000)
        self.assertFalse(os.path.exists(os.path.join(self.out, 'decisions_rac.png')))

    def _spy(self, fn, *args):
        """Call a plot function, returning its axes (matplotlib objects, not pixels)."""
        import matplotlib

        matplotlib.use('Agg')
        plt = figure_style._mpl()
        captured = {}
        orig = plt.subplots

        def spy(*a, **k):
            fig, axes = orig(*a, **k)
            captured['axes'] = axes
            return fig, axes

        plt.subplots = spy
        try:
            fn(plt, *args)
        finally:
            plt.subplots = orig
        return captured['axes']

    def _markers(self, ax):
        """{decision kind: [(x, y), ...]} of the decision markers drawn on ax."""
        import matplotlib

        out = {}
        for line in ax.get_lines():
            for kind, st in pa.DECISION_STYLE.items():
                if (
                    line.get_linestyle() == 'None'
                    and line.get_marker() == st['marker']
                    and matplotlib.colors.to_hex(line.get_color())
                    == matplotlib.colors.to_hex(st['color'])
                ):
                    out.setdefault(kind, []).extend(zip(line.get_xdata(), line.get_ydata()))
        return out

    def test_time_plots_draw_decisions(self):
        run = [r for r in pa.load_runs(self.f.robust_bag) if r.label == 'pa'][0]
        m = pa.run_metrics(run)
        want = decision_events(self.f.robust)
        # theta_hat figure: a marker per decision at the estimate it set, in every component
        axes = self._spy(pa.plot_theta, run, m, os.path.join(self.f.dir, 'spy_theta.png'))
        for i, ax in enumerate(axes):
            got = self._markers(ax)
            for kind in pa.DECISIONS:
                pts = sorted(got.get(kind, []))
                exp = [(ev['t'], ev['theta_hat_after'][i]) for ev in want if ev['decision'] == kind]
                np.testing.assert_allclose(pts, exp, atol=1e-12, err_msg='%s %d' % (kind, i))
        # ... labelled with score against keeping's at the last decision of each verification
        texts = [a.get_text() for a in axes[0].texts if ' vs keep ' in a.get_text()]
        finals = pa.final_decisions([dict(ev, type=ev['type_name']) for ev in want])
        self.assertEqual(len(texts), len(finals))
        for d in finals:
            self.assertIn(figure_style._decision_text(d), texts)
        self.assertTrue(
            any(a.get_text().startswith('memory #') for a in axes[0].texts)
            or all(d['decision'] != 'memory' for d in finals)
        )
        # the error panel of the alpha figure: the same decisions at their e
        ax2 = self._spy(pa.plot_alpha, run, m, os.path.join(self.f.dir, 'spy_a.png'), 0.005)[1]
        got = self._markers(ax2)
        for kind in pa.DECISIONS:
            np.testing.assert_allclose(
                sorted(got.get(kind, [])),
                [(ev['t'], ev['e']) for ev in want if ev['decision'] == kind],
                atol=1e-12,
            )
        # the decisions figure: score and score_keep per decision
        ax = self._spy(pa.plot_decisions, run, os.path.join(self.f.dir, 'spy_d.png'))
        got = self._markers(ax)
        for kind in pa.DECISIONS:
            ks = [k + 1 for k, ev in enumerate(want) if ev['decision'] == kind]
            np.testing.assert_allclose(
                sorted(got.get(kind, [])), [(k, want[k - 1]['score']) for k in ks], rtol=1e-12
            )

    def test_message_fields_and_codes(self):
        """decision_code alone (an empty decision string) and the DECISION type code."""
        m = types.SimpleNamespace(
            decision='', decision_code=3, chosen=2, candidates=5, score=0.001, score_keep=0.1
        )
        self.assertEqual(
            run_records._msg_decision(m),
            {'decision': 'memory', 'chosen': 2, 'candidates': 5, 'score': 0.001, 'score_keep': 0.1},
        )
        m.decision_code = 0
        self.assertIsNone(run_records._msg_decision(m)['decision'])
        cls = self.f.classes['AttentionEvent']
        self.assertEqual(cls.DECISION, 4)
        self.assertEqual(pa.EVENT_TYPES[cls.DECISION], 'decision')
        self.assertEqual(
            [
                pa.DECISIONS[c - 1]
                for c in (
                    cls.DECISION_KEEP,
                    cls.DECISION_FIT,
                    cls.DECISION_MEMORY,
                    cls.DECISION_NETWORK,
                )
            ],
            list(pa.DECISIONS),
        )
        self.assertEqual(cls.DECISION_NONE, 0)

    def test_old_bag_without_decision_fields(self):
        self.assertNotIn('decision', self.f.legacy_classes['AttentionEvent'].__slots__)
        self.assertIn('decision', self.f.classes['AttentionEvent'].__slots__)
        out = os.path.join(self.f.dir, 'out_legacy')
        rc, so, se = run_cli(self.f.legacy_bag, '--out', out)
        self.assertEqual(rc, 0, se)
        with open(os.path.join(out, 'metrics.json')) as fh:
            old = json.load(fh)['runs'][0]
        self.assertEqual(len(old['events']), len(self.f.pa['events']))
        self.assertTrue(all(e['decision'] is None for e in old['events']))
        self.assertEqual(old['decisions'], [])
        self.assertEqual(old['whole_run']['decisions'], 0)
        # the same metrics as the bag of the same run with today's message
        new = pa.run_metrics(pa.load_runs(self.f.pa_bag)[0])
        for wo, wn in zip(old['windows'], new['windows']):
            self.assertEqual(wo['peak_abs_e'], wn['peak_abs_e'])
            self.assertEqual(wo['onsets'], wn['onsets'])
        self.assertFalse([n for n in os.listdir(out) if n.startswith('decisions_')])


class TestCsvInputs(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.f = Fixtures.make()

    def test_csv_with_json_and_csv_with_phase_only(self):
        out = os.path.join(self.f.dir, 'out_csv')
        rc, so, se = run_cli(self.f.rac_csv, self.f.pa_csv, '--out', out)
        self.assertEqual(rc, 0, se)
        with open(os.path.join(out, 'metrics.json')) as fh:
            doc = json.load(fh)
        runs = {r['label']: r for r in doc['runs']}
        self.assertEqual(set(runs), {'out_rac', 'scenario_pa'})
        # events and mode from out_rac.json (all four types)
        r = runs['out_rac']
        self.assertEqual(r['mode'], 'rac')
        self.assertEqual(len(r['events']), len(self.f.rac['events']))
        self.assertEqual(
            [e['type'] for e in r['events']], [e['type_name'] for e in self.f.rac['events']]
        )
        # phase column only: onsets/recoveries at the samples where phase changes
        p = runs['scenario_pa']
        self.assertEqual(p['mode'], 'pa')  # from the file name
        ph = self.f.pa['phase']
        t = self.f.pa['t']
        on = t[1:][(ph[1:] == 1) & (ph[:-1] == 0)]
        rec = t[1:][(ph[1:] == 0) & (ph[:-1] == 1)]
        np.testing.assert_allclose([e['t'] for e in p['events'] if e['type'] == 'onset'], on)
        np.testing.assert_allclose([e['t'] for e in p['events'] if e['type'] == 'recovered'], rec)
        self.assertTrue(any('phase column' in n for n in p['notes']))
        self.assertEqual(doc['comparison']['baseline'], 'out_rac')

    def test_bag_and_csv_of_the_same_run_agree(self):
        bag = pa.run_metrics(pa.load_runs(self.f.rac_bag)[0])
        csvm = pa.run_metrics(pa.load_runs(self.f.rac_csv)[0])
        for wb, wc in zip(bag['windows'], csvm['windows']):
            # the CSV holds values printed with 9 significant digits
            self.assertAlmostEqual(wb['peak_abs_e'], wc['peak_abs_e'], delta=1e-9)
            self.assertAlmostEqual(wb['iae'], wc['iae'], delta=1e-8)
            self.assertEqual(wb['onsets'], wc['onsets'])
            self.assertEqual(wb['recoveries'], wc['recoveries'])

    def test_analytic_metrics(self):
        """A hand-made CSV with known answers: e is a triangle after each switch."""
        d = os.path.join(self.f.dir, 'analytic')
        os.makedirs(d, exist_ok=True)
        path = os.path.join(d, 'tri.csv')
        t = np.round(np.arange(0, 10.0 + 1e-9, 0.01), 10)
        theta = np.where(t < 4.0, 0.5, np.where(t < 7.0, 2.0, 3.0))
        e = np.zeros_like(t)
        # window 1 (4..7 s): triangle of height 0.02 peaking at 5 s, base 4..6 s
        m = (t >= 4) & (t <= 6)
        e[m] = 0.02 * (1 - np.abs(t[m] - 5.0))
        # window 2 (7..10 s): negative triangle of height 0.01 peaking at 8 s, base 7.5..8.5
        m = (t >= 7.5) & (t <= 8.5)
        e[m] = -0.01 * (1 - 2 * np.abs(t[m] - 8.0))
        u = np.where(t > 5, -0.3, 0.1)
        phase = ((t >= 4.2) & (t < 5.9)).astype(int)
        with open(path, 'w') as fh:
            fh.write(','.join(synthetic.CSV_HEADER) + '\n')
            for i in range(len(t)):
                row = [
                    t[i],
                    0,
                    0.1 + e[i],
                    0,
                    0,
                    0.1,
                    0,
                    e[i],
                    0,
                    u[i],
                    0,
                    0,
                    0,
                    theta[i],
                    theta[i],
                    theta[i],
                    phase[i],
                ]
                fh.write(','.join(repr(float(v)) for v in row) + '\n')
        m = pa.run_metrics(pa.load_runs(path)[0])
        self.assertEqual([s['t'] for s in m['switches']], [4.0, 7.0])
        w0, w1, w2 = m['windows']
        self.assertEqual((w0['theta_scale'], w1['theta_scale'], w2['theta_scale']), (0.5, 2.0, 3.0))
        self.assertEqual(w1['theta_scale_before'], 0.5)
        self.assertAlmostEqual(w0['peak_abs_e'], 0.0)
        self.assertAlmostEqual(w1['peak_abs_e'], 0.02, places=12)
        self.assertAlmostEqual(w1['t_peak'], 5.0, places=9)
        self.assertAlmostEqual(w1['iae'], 0.02, places=9)  # area 0.5 * 2 s * 0.02
        self.assertAlmostEqual(w2['peak_abs_e'], 0.01, places=12)
        self.assertAlmostEqual(w2['t_peak'], 8.0, places=9)
        self.assertAlmostEqual(w2['iae'], 0.005, places=9)  # 0.5 * 1 s * 0.01
        self.assertAlmostEqual(m['whole_run']['iae'], 0.025, places=9)
        self.assertAlmostEqual(m['whole_run']['max_abs_u'], 0.3)
        self.assertAlmostEqual(w1['onset_delay'], 0.2, places=9)
        self.assertAlmostEqual(w1['recovery_time'], 1.9, places=9)
        self.assertEqual((w1['onsets'], w1['recoveries'], w2['onsets']), (1, 1, 0))
        self.assertIsNone(w2['recovery_time'])


class TestErrors(unittest.TestCase):
    """Bad inputs: exit 2, one line on stderr naming the file and the problem."""

    @classmethod
    def setUpClass(cls):
        cls.f = Fixtures.make()
        cls.d = os.path.join(cls.f.dir, 'errors')
        os.makedirs(cls.d, exist_ok=True)

    def assertInputError(self, path, *fragments, extra=()):
        rc, so, se = run_cli(path, '--out', os.path.join(self.d, 'o'), *extra)
        self.assertEqual(rc, 2, 'stdout: %s\nstderr: %s' % (so, se))
        lines = [ln for ln in se.splitlines() if ln.strip()]
        self.assertEqual(len(lines), 1, se)
        self.assertIn(os.path.basename(path) if not extra else '', lines[0])
        for frag in fragments:
            self.assertIn(frag, lines[0])
        self.assertNotIn('Traceback', se)
        return lines[0]

    def test_missing_file(self):
        self.assertInputError(os.path.join(self.d, 'nope.bag'), 'no such file')

    def test_zero_byte_file(self):
        p = os.path.join(self.d, 'zero.bag')
        open(p, 'w').close()
        self.assertInputError(p, 'empty file')

    def test_bag_without_messages(self):
        import rosbag

        p = os.path.join(self.d, 'nomsgs.bag')
        with rosbag.Bag(p, 'w'):
            pass
        self.assertInputError(p, 'empty bag')

    def test_bag_without_expected_topics(self):
        import rosbag
        import rospy
        from std_msgs.msg import String

        p = os.path.join(self.d, 'chatter.bag')
        with rosbag.Bag(p, 'w') as b:
            b.write('/chatter', String('hello'), rospy.Time(1))
        self.assertInputError(p, 'no preadaptive_mrac run', '/plant/state', '/chatter')

    def test_bag_missing_truth(self):
        p = synthetic.write_bag(
            os.path.join(self.d, 'notruth.bag'),
            {'': self.f.rac},
            self.f.classes,
            skip_topics=('plant/truth',),
        )
        line = self.assertInputError(p, 'missing topic', '/plant/truth')
        self.assertNotIn('/controller/status', line)

    def test_compare_bag_missing_one_status(self):
        import rosbag

        p = os.path.join(self.d, 'half.bag')
        with rosbag.Bag(self.f.compare_bag) as src, rosbag.Bag(p, 'w') as dst:
            for topic, msg, t in src.read_messages(raw=True):
                if topic != '/pa/controller/status':
                    dst.write(topic, msg, t, raw=True)
        self.assertInputError(p, '/pa/controller/status')

    def test_unindexed_active_bag_then_reindex(self):
        p = os.path.join(self.d, 'rec.bag.active')
        synthetic.write_unindexed_bag(p, self.f.pa, self.f.classes)
        self.assertInputError(p, 'unindexed', 'rosbag reindex %s' % p)
        # what the message tells the user to do makes the file readable
        if shutil.which('rosbag'):
            subprocess.run(
                ['rosbag', 'reindex', p],
                check=True,
                stdout=subprocess.DEVNULL,
                stderr=subprocess.DEVNULL,
                timeout=120,
            )
        else:
            import rosbag

            with rosbag.Bag(p, 'a', allow_unindexed=True) as b:
                for _ in b.reindex():
                    pass
        rc, so, se = run_cli(p, '--out', os.path.join(self.d, 'reindexed'), '--no-figures')
        self.assertEqual(rc, 0, se)
        self.assertIn('== run rec (', so)

    def test_not_a_bag(self):
        p = os.path.join(self.d, 'text.bag')
        with open(p, 'w') as fh:
            fh.write('not a bag\n')
        self.assertInputError(p, 'not a ROS bag')

    def test_csv_missing_columns(self):
        p = os.path.join(self.d, 'cols.csv')
        with open(p, 'w') as fh:
            fh.write('t,x1,e\n0,0,0\n')
        self.assertInputError(p, 'missing columns', 'xr1', 'theta_true0')

    def test_csv_header_only(self):
        p = os.path.join(self.d, 'hdr.csv')
        with open(p, 'w') as fh:
            fh.write(','.join(synthetic.CSV_HEADER) + '\n')
        self.assertInputError(p, 'no data rows')

    def test_labels_count_and_unknown_baseline(self):
        rc, so, se = run_cli(
            self.f.compare_bag,
            '--labels',
            'only_one',
            '--no-figures',
            '--out',
            os.path.join(self.d, 'o'),
        )
        self.assertEqual(rc, 2)
        self.assertIn('1 label(s) given for 2 run(s)', se)
        rc, so, se = run_cli(
            self.f.compare_bag,
            '--baseline',
            'zzz',
            '--no-figures',
            '--out',
            os.path.join(self.d, 'o'),
        )
        self.assertEqual(rc, 2)
        self.assertIn("no run labelled 'zzz'", se)


class TestLabelsAndBaseline(unittest.TestCase):
    def test_two_single_run_bags(self):
        f = Fixtures.make()
        out = os.path.join(f.dir, 'out_labels')
        rc, so, se = run_cli(
            f.pa_bag,
            f.rac_bag,
            '--labels',
            'PA',
            'RAC',
            '--baseline',
            'PA',
            '--out',
            out,
            '--no-figures',
        )
        self.assertEqual(rc, 0, se)
        with open(os.path.join(out, 'metrics.json')) as fh:
            doc = json.load(fh)
        self.assertEqual([r['label'] for r in doc['runs']], ['PA', 'RAC'])
        self.assertEqual(doc['comparison']['baseline'], 'PA')
        self.assertEqual([c['label'] for c in doc['comparison']['runs']], ['RAC'])
        self.assertFalse([n for n in os.listdir(out) if n.endswith('.png')])


class TestVizMarkersOffline(unittest.TestCase):
    """preadaptive_mrac.viz (scripts/viz_markers) without a master: message decoding and marker
    geometry."""

    @classmethod
    def setUpClass(cls):
        from preadaptive_mrac.viz import markers

        cls.vm = markers
        cls.classes = synthetic.load_msg_classes()

    def _viz(self):
        v = self.vm.VizMarkers.__new__(self.vm.VizMarkers)
        v.world, v.body, v.velocity = 'world', 'body', 'velocity'
        v.history, v.history_points, v.alpha_scale = 10.0, 400, 20.0
        import threading
        import collections

        v.lock = threading.Lock()
        v.state = v.status = v.truth = v.last_event = None
        v.events = collections.deque(maxlen=200)
        v.hist = collections.deque()
        v.alpha_ref = None
        v.tf_pub = None
        return v

    def test_text_shows_the_envelope_exit(self):
        """The rviz text names a run that left the flight envelope, in red."""
        v = self._viz()
        truth = self.classes['PlantTruth']()
        truth.theta = [1.0, 1.0, 1.0]
        inside = [m.text for m in v.texts(None, None, truth, None) if m.action == m.ADD]
        self.assertFalse(any('FLIGHT ENVELOPE' in t for t in inside), inside)
        truth.envelope_exit = 't = 0.503 s (step 503): |q| = 1.17 rad/s > 0.35 rad/s'
        out = [m for m in v.texts(None, None, truth, None) if m.action == m.ADD]
        self.assertEqual(out[1].text, 'LEFT THE FLIGHT ENVELOPE at ' + truth.envelope_exit)
        self.assertEqual((out[1].color.r, out[1].color.g), (1.0, 0.2))

    def test_dynamic_subscriber_decodes_wire_bytes(self):
        cls = self.classes['PlantState']
        m = cls()
        m.step = 42
        m.alpha = 0.123
        m.theta_pitch = 0.2
        if 't' in m.__slots__:
            m.t = 0.042
        buf = io.BytesIO()
        m.serialize(buf)
        raw = types.SimpleNamespace(
            _buff=buf.getvalue(),
            _connection_header={
                'type': cls._type,
                'md5sum': cls._md5sum,
                'message_definition': cls._full_text,
            },
        )
        got = []
        sub = self.vm.DynamicSubscriber.__new__(self.vm.DynamicSubscriber)
        sub._callback, sub._classes = got.append, {}
        sub._on_raw(raw)
        sub._on_raw(raw)  # second time from the class cache
        self.assertEqual(len(got), 2)
        self.assertEqual(got[0].step, 42)
        self.assertAlmostEqual(got[0].alpha, 0.123)
        self.assertEqual(len(sub._classes), 1)

    def _raw(self, name, **fields):
        cls = self.classes[name]
        m = cls()
        for k, v in fields.items():
            if k in m.__slots__:
                setattr(m, k, v)
        buf = io.BytesIO()
        m.serialize(buf)
        return types.SimpleNamespace(
            _buff=buf.getvalue(),
            _connection_header={
                'type': cls._type,
                'md5sum': cls._md5sum,
                'message_definition': cls._full_text,
            },
        )

    def test_concurrent_decoding(self):
        """rospy calls each subscription's callback in its own thread; classes generated at
        the same time must all work (genpy's generator is not thread-safe)."""
        import threading
        import time
        import genpy.generate_struct as gs

        # Widen the race window as a loaded machine does: yield the CPU whenever the
        # generator records a struct pattern in its module-level list.
        orig_add = gs.add_pattern

        def slow_add(p):
            time.sleep(0.0005)
            orig_add(p)

        gs.add_pattern = slow_add
        self.addCleanup(setattr, gs, 'add_pattern', orig_add)
        raws = [
            self._raw('PlantState', step=7, t=0.007, alpha=0.1),
            self._raw('AdaptationStatus', step=7, t=0.007, e=0.002, mode='pa'),
            self._raw('AttentionEvent', step=7, t=0.007, type_name='onset'),
            self._raw('ElevatorCommand', step=7, t=0.007, u=-0.3),
        ]
        errors, decoded = [], []
        for _ in range(3):
            barrier = threading.Barrier(8)

            def work(raw):
                sub = self.vm.DynamicSubscriber.__new__(self.vm.DynamicSubscriber)
                sub._callback, sub._classes = decoded.append, {}
                barrier.wait()
                try:
                    sub._on_raw(raw)
                except Exception as ex:  # noqa: BLE001 - any failure counts
                    errors.append(repr(ex))

            threads = [threading.Thread(target=work, args=(raws[i % 4],)) for i in range(8)]
            for th in threads:
                th.start()
            for th in threads:
                th.join()
        self.assertEqual(errors, [])
        self.assertEqual(len(decoded), 24)
        self.assertTrue(all(m.step == 7 for m in decoded))

    def test_markers_from_a_run(self):
        v = self._viz()
        for rel, msg, t in synthetic.make_messages(self.f_sim(), self.classes):
            {
                'plant/state': v.on_state,
                'controller/status': v.on_status,
                'controller/attention': v.on_attention,
                'plant/truth': v.on_truth,
                'controller/elevator_cmd': lambda m: None,
            }[rel](msg)
        arr = v.build()
        by = {(m.ns, m.id): m for m in arr.markers}
        self.assertEqual(by[('aircraft', 0)].header.frame_id, 'body')
        self.assertTrue(by[('aircraft', 0)].frame_locked)
        self.assertEqual(by[('velocity', 0)].header.frame_id, 'velocity')
        texts = [m.text for m in arr.markers if m.ns == 'text' and m.action == m.ADD]
        sim = self.f_sim()
        self.assertTrue(texts[0].startswith('t = %.3f s' % sim['t'][-1]), texts[0])
        self.assertIn('alpha = %+.5f rad' % sim['x'][-1][1], texts[1])
        self.assertIn('theta = %g x ones' % sim['theta'][-1][0], texts[3])
        last = sim['events'][-1]
        self.assertIn('last event: %s at %.3f s' % (last['type_name'].upper(), last['t']), texts[4])
        strip = by[('alpha_history', 1)]
        self.assertEqual(strip.type, strip.LINE_STRIP)
        self.assertGreater(len(strip.points), 100)
        # newest point at the right end, height = z0 + alpha_scale * alpha
        self.assertAlmostEqual(strip.points[-1].x, 5.0, delta=0.3)
        self.assertAlmostEqual(strip.points[-1].z, -4.2 + 20.0 * v.hist[-1][1], places=9)
        # every quaternion is normalised (rviz warns otherwise)
        for m in arr.markers:
            q = m.pose.orientation
            self.assertAlmostEqual(q.x**2 + q.y**2 + q.z**2 + q.w**2, 1.0, places=9)

    def test_last_event_text_shows_a_decision(self):
        v = self._viz()
        sim = synthetic.simulate('pa_robust', t_end=12.0)
        last = [ev for ev in sim['events'] if ev['t'] <= 10.325][-1]
        self.assertEqual(last['type_name'], 'decision')
        for rel, msg, t in synthetic.make_messages(sim, self.classes):
            if t > 10.325:
                break
            {
                'plant/state': v.on_state,
                'controller/status': v.on_status,
                'controller/attention': v.on_attention,
                'plant/truth': v.on_truth,
                'controller/elevator_cmd': lambda m: None,
            }[rel](msg)
        texts = [m.text for m in v.build().markers if m.ns == 'text' and m.action == m.ADD]
        self.assertIn('last event: DECISION at %.3f s' % last['t'], texts[4])
        self.assertIn(
            '%s: %.2g vs keep %.2g rad' % (last['decision'], last['score'], last['score_keep']),
            texts[4],
        )

    def test_elevator_plate_trailing_edge_down_for_positive_u(self):
        v = self._viz()
        plate = [m for m in v.aircraft(0.2) if m.id == 5][0]
        self.assertLess(plate.pose.position.z, 0.15)  # hinge height 0.15 m
        plate = [m for m in v.aircraft(-0.2) if m.id == 5][0]
        self.assertGreater(plate.pose.position.z, 0.15)

    _sim = None

    def f_sim(self):
        if TestVizMarkersOffline._sim is None:
            TestVizMarkersOffline._sim = synthetic.simulate('pa', t_end=12.0)
        return TestVizMarkersOffline._sim


if __name__ == '__main__':
    unittest.main()
