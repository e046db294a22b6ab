"""preadaptive_mrac.analysis.loading and csv_runs: every input error names the file; a CSV of
the batch CLI with its --json summary beside it loads with events, mode and unique labels."""

import json
import os
import shutil
import tempfile
import unittest

import pkg_path  # noqa: F401
from preadaptive_mrac.analysis import csv_runs, loading, runs

HEADER = runs.CSV_HEADER


def write_csv(path, n=2001, dt=0.01, switch_at=10.0):
    with open(path, 'w') as f:
        f.write(HEADER + '\n')
        for i in range(n):
            t = i * dt
            c = 1.0 if t < switch_at else 2.0
            e = 0.01 if abs(t - switch_at) < 0.5 else 0.0
            row = [t, 0, 0.1 + e, 0, 0, 0.1, 0, e, 0, 0.2, 1, 1, 1, c, c, c, 0]
            f.write(','.join('%g' % v for v in row) + '\n')
    return path


class TestInputErrors(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix='pmrac_loading_')

    def tearDown(self):
        shutil.rmtree(self.dir)

    def expect(self, path, what):
        with self.assertRaises(runs.InputError) as cm:
            loading.load_runs(path)
        self.assertEqual(cm.exception.path, path)
        self.assertIn(what, str(cm.exception))

    def test_missing_directory_empty_and_fake_bag(self):
        self.expect(os.path.join(self.dir, 'nope.csv'), 'no such file')
        self.expect(self.dir, 'is a directory')
        empty = os.path.join(self.dir, 'empty.csv')
        open(empty, 'w').close()
        self.expect(empty, 'empty file (0 bytes)')
        fake = os.path.join(self.dir, 'fake.bag')
        with open(fake, 'w') as f:
            f.write('hello\n')
        self.expect(fake, 'not a ROS bag')

    def test_csv_without_the_columns(self):
        p = os.path.join(self.dir, 'other.csv')
        with open(p, 'w') as f:
            f.write('t,x1\n0,0\n')
        self.expect(p, 'missing columns xr1, e, u')

    def test_summary_json_last_line(self):
        p = os.path.join(self.dir, 'x.json')
        with open(p, 'w') as f:
            f.write('some log line\n{"mode": "rac"}\n')
        self.assertEqual(csv_runs._parse_summary_json(p), {'mode': 'rac'})
        with open(p, 'w') as f:
            f.write('no json here\n')
        with self.assertRaises(runs.InputError):
            csv_runs._parse_summary_json(p)


class TestCsvRuns(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.dir = tempfile.mkdtemp(prefix='pmrac_csv_')
        cls.rac = write_csv(os.path.join(cls.dir, 's1_rac.csv'))
        cls.pa = write_csv(os.path.join(cls.dir, 's1_pa_learn.csv'))
        with open(os.path.join(cls.dir, 's1_pa_learn.json'), 'w') as f:
            json.dump(
                {
                    'mode': 'pa_learn',
                    'dt': 0.01,
                    'episodes': 1,
                    'events': [{'type': 'onset', 't': 10.2}],
                },
                f,
            )

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.dir)

    def test_mode_and_events(self):
        (rac,) = loading.load_runs(self.rac)
        (pa,) = loading.load_runs(self.pa)
        self.assertEqual((rac.mode, pa.mode), ('rac', 'pa_learn'))
        self.assertEqual([e['type'] for e in pa.events], ['onset'])
        self.assertAlmostEqual(pa.events[0]['t'], 10.2)
        self.assertEqual(len(rac.t_e), 2001)

    def test_labels_unique_or_given(self):
        two = loading.load_inputs([self.rac, self.rac])
        self.assertEqual(len({r.label for r in two}), 2)
        named = loading.load_inputs([self.rac, self.pa], labels=['A', 'B'])
        self.assertEqual([r.label for r in named], ['A', 'B'])
        with self.assertRaises(runs.InputError) as cm:
            loading.load_inputs([self.rac], labels=['A', 'B'])
        self.assertIn('2 label(s) given for 1 run(s)', str(cm.exception))


if __name__ == '__main__':
    unittest.main()


class TestConditionColumns(unittest.TestCase):
    """A CSV of a plant with conditions carries the applied elevator and the gust;
    both are loaded and drawn (the elevator figure's applied line, a gust figure)."""

    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix='pmrac_conditions_')

    def tearDown(self):
        shutil.rmtree(self.dir)

    def write(self, gust):
        path = os.path.join(self.dir, 'cond_rac.csv')
        with open(path, 'w') as f:
            f.write(HEADER + ',u_applied,effectiveness,w_gust,plant_limited\n')
            for i in range(501):
                t = i * 0.01
                row = [t, 0, 0.1, 0, 0, 0.1, 0, 0, 0, 0.2, 1, 1, 1, 1, 1, 1, 0]
                row += [0.1 * (i > 5), 1, gust * ((i % 7) - 3), 0]
                f.write(','.join('%g' % v for v in row) + '\n')
        return path

    def test_applied_elevator_and_gust_loaded_and_drawn(self):
        from preadaptive_mrac.analysis import figures, metrics

        (run,) = loading.load_runs(self.write(gust=0.5))
        self.assertEqual(len(run.u_applied), 501)
        self.assertEqual(run.u_applied[6], 0.1)
        self.assertAlmostEqual(run.gust_w[0], -1.5)
        m = metrics.run_metrics(run)
        files = figures.write_figures(self.dir, [run], [m], None)
        self.assertIn(os.path.join(self.dir, 'gust_cond_rac.png'), files)
        for f in files:
            self.assertTrue(os.path.getsize(f) > 0, f)

    def test_still_air_has_no_gust_figure(self):
        (run,) = loading.load_runs(self.write(gust=0.0))
        self.assertIsNone(run.gust_w)
        self.assertIsNotNone(run.u_applied)

    def test_a_new_condition_column_is_loaded_and_drawn_by_name(self):
        """A condition the Python side has never heard of (here 'gust_alpha') comes
        in by its column name and gets a figure of its own; a constant one gets none."""
        from preadaptive_mrac.analysis import figures, metrics

        path = os.path.join(self.dir, 'new_rac.csv')
        with open(path, 'w') as f:
            f.write(HEADER + ',u_applied,effectiveness,w_gust,plant_limited,gust_alpha\n')
            for i in range(201):
                row = [i * 0.01, 0, 0.1, 0, 0, 0.1, 0, 0, 0, 0.2, 1, 1, 1, 1, 1, 1, 0]
                row += [0.1, 1, 0, 0, 0.001 * i]
                f.write(','.join('%g' % v for v in row) + '\n')
        (run,) = loading.load_runs(path)
        self.assertEqual(
            sorted(run.conditions),
            ['effectiveness', 'gust_alpha', 'plant_limited', 'u_applied', 'w_gust'],
        )
        self.assertAlmostEqual(run.conditions['gust_alpha'][1][100], 0.1)
        files = figures.write_figures(self.dir, [run], [metrics.run_metrics(run)], None)
        names = sorted(os.path.basename(p) for p in files if 'condition_' in p)
        self.assertEqual(names, ['condition_gust_alpha_new_rac.png'])

    def test_a_jsbsim_run_gets_the_flight_figure(self):
        """The engine's rows of the record (a JSBSim CSV: pitch, airspeed, altitude,
        flight_path after the fixed columns) load as conditions and are drawn together in
        flight_<run>.png, not one figure each; a linear run has no flight figure."""
        from preadaptive_mrac.analysis import figures, metrics

        path = os.path.join(self.dir, 'jsb_rac.csv')
        with open(path, 'w') as f:
            f.write(HEADER + ',pitch,airspeed,altitude,flight_path\n')
            for i in range(201):
                row = [i * 0.01, 0, 0.1, 0, 0, 0.1, 0, 0, 0, 0.2, 1, 1, 1, 1, 1, 1, 0]
                row += [0.0777 + 0.001 * i, 236.06 - 0.1 * i, 12192.0 + 0.5 * i, 0.001 * i]
                f.write(','.join('%g' % v for v in row) + '\n')
        (run,) = loading.load_runs(path)
        self.assertTrue(figures.has_flight(run))
        self.assertAlmostEqual(run.conditions['altitude'][1][200], 12292.0)
        files = figures.write_figures(self.dir, [run], [metrics.run_metrics(run)], None)
        names = sorted(os.path.basename(p) for p in files)
        self.assertIn('flight_jsb_rac.png', names)
        self.assertEqual([n for n in names if n.startswith('condition_')], [])
        self.assertFalse(figures.has_flight(loading.load_runs(write_csv(self.dir + '/l.csv'))[0]))


class TestEnvelopeExit(unittest.TestCase):
    """A run whose summary says it left the flight envelope is named at the top of
    the report (analyze_bag's text), with the time and the bound; a run inside is not."""

    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix='pmrac_envelope_')

    def tearDown(self):
        shutil.rmtree(self.dir)

    def test_the_report_starts_with_the_exit(self):
        from preadaptive_mrac.analysis import metrics, report

        lost, flew = os.path.join(self.dir, 'lost.csv'), os.path.join(self.dir, 'flew.csv')
        write_csv(lost)
        write_csv(flew)
        text = (
            't = 5.29 s (step 5290): |q| = 0.3526 rad/s > 0.35 rad/s '
            '(plant.envelope.max_pitch_rate)'
        )
        with open(os.path.join(self.dir, 'lost.json'), 'w') as f:
            json.dump({'mode': 'rac', 'envelope_exit': {'t': 5.29, 'text': text}}, f)
        with open(os.path.join(self.dir, 'flew.json'), 'w') as f:
            json.dump({'mode': 'rac', 'envelope_exit': None}, f)
        runs_ = loading.load_inputs([flew, lost])
        self.assertEqual([r.envelope_exit for r in runs_], [None, text])
        out = report.format_report([metrics.run_metrics(r) for r in runs_], None)
        self.assertEqual(out.splitlines()[0], '!! run lost LEFT THE FLIGHT ENVELOPE at ' + text)
        self.assertEqual(out.count('LEFT THE FLIGHT ENVELOPE'), 1)
