"""preadaptive_mrac.bench.report: docs/performance.md from a results directory (synthetic
results with hand-computed medians, ratios and verdicts), and the hand-written sections of an
existing page carried over."""

import json
import os
import shutil
import tempfile
import unittest

import pkg_path  # noqa: F401
from preadaptive_mrac.bench import report

META_ENV = {
    'META_DATE': '2026-11-23 12:00 UTC',
    'META_CPU': 'AMD EPYC',
    'META_NPROC': '2',
    'META_KERNEL': 'Linux 6',
    'META_LOAD_BEFORE': '1.0 1.0 1.0',
    'META_LOAD_AFTER': '2.0 2.0 2.0',
    'META_COMPILER': 'c++ 12',
    'META_FLAGS': '-O3 -DNDEBUG',
    'META_COMMIT': 'abc1234',
    'META_DIRTY': '',
    'META_REPS': '10',
    'META_CMDS': 'build|cmake --build x\nall of the above|bench/run_bench.sh\n',
}


def gbench(name, real_ms, cpu_ms, **counters):
    b = {
        'run_name': name,
        'aggregate_name': 'median',
        'real_time': real_ms,
        'cpu_time': cpu_ms,
        'time_unit': 'ms',
    }
    b.update(counters)
    return b


def runs(walls, cpus, inprocs):
    return [{'wall': w, 'cpu': c, 'inproc': i} for w, c, i in zip(walls, cpus, inprocs)]


def results():
    meta = report.meta_from_env(META_ENV, 'build_bench/bench_results', {})
    bench = {
        'benchmarks': [
            gbench('ClosedLoop/scenario3/rac', 9.0, 8.0, per_step=8.0e-3 / 140000),
            gbench('ClosedLoop/scenario3/pa_robust', 25.0, 15.0, per_step=15e-3 / 140000),
            gbench('ClosedLoop/scenario3/oracle', 30.0, 22.0, per_step=22e-3 / 140000),
            gbench(
                'ControllerStep/rac/trajectory/iterations:420000',
                50e-6,
                40e-6,
                **{'onsets/pass': 6, 'learned/pass': 0, 'in_phase_%': 28.0}
            ),
            gbench(
                'ControllerStep/pa_robust/trajectory/iterations:420000',
                90e-6,
                80e-6,
                **{'onsets/pass': 32, 'learned/pass': 10, 'in_phase_%': 9.3}
            ),
            dict(gbench('ClosedLoop/scenario3/pa', 1.0, 1.0), aggregate_name='mean'),
        ]
    }
    timeloop = {
        'cmds': [['sim'], ['proto'], ['base_sim']],
        'reps': 3,
        'a': runs([0.010, 0.012, 0.011], [0.008, 0.009, 0.010], [0.004, 0.005, 0.006]),
        'b': runs([6.0, 6.6, 6.3], [5.9, 6.5, 6.2], [5.5, 5.6, 5.7]),
        'c': runs([0.03] * 3, [0.02] * 3, [0.01] * 3),
    }
    hyperfine = {
        'results': [
            {'median': 0.02, 'times': [0.02] * 5},
            {'median': 6.0, 'times': [6] * 5},
            {'median': 0.04, 'times': [0.04] * 5},
        ]
    }
    baseline = {
        'commit': 'base123',
        'build_dir': '/b',
        'reps': 3,
        'load': '1 / 2',
        'identical': {'rac': True, 'pa_robust': False},
        'modes': {
            'rac': {
                'reps': 3,
                'a': runs([0.02] * 3, [0.010] * 3, [0.005] * 3),
                'b': runs([0.04] * 3, [0.020] * 3, [0.015] * 3),
            },
            'pa_robust': {
                'reps': 3,
                'a': runs([0.05] * 3, [0.030] * 3, [0.020] * 3),
                'b': runs([0.09] * 3, [0.060] * 3, [0.050] * 3),
            },
        },
    }
    callgrind = {
        'rac': {
            'total': 140000 * 800,
            'closed_loop_run': 140000 * 700,
            'controller_step': 140000 * 300,
            'plant_step': 140000 * 200,
        }
    }
    callgrind_base = {'rac': {'total': 140000 * 2000}}
    return {
        'meta': meta,
        'bench': bench,
        'timeloop': timeloop,
        'hyperfine': hyperfine,
        'callgrind': callgrind,
        'baseline': baseline,
        'callgrind_base': callgrind_base,
    }


def row(text, start):
    lines = [ln for ln in text.splitlines() if ln.startswith(start)]
    assert len(lines) == 1, (start, lines)
    return [c.strip() for c in lines[0].strip('|').split('|')]


class TestVerdicts(unittest.TestCase):
    def test_verdict(self):
        self.assertEqual(report.verdict(10, 15, 20), 'met')
        self.assertEqual(
            report.verdict(10, 25, 20), 'met on CPU time, **missed on wall time** (load)'
        )
        self.assertEqual(report.verdict(25, 25, 20), '**missed**')
        self.assertEqual(report.verdict(600, 550, 500, higher_is_better=True), 'met')


class TestRender(unittest.TestCase):
    def setUp(self):
        self.text = report.render(results())

    def test_scenario3_against_20_ms(self):
        self.assertEqual(
            row(self.text, '| rac | 9.0 |'), ['rac', '9.0', '8.0', '57', '< 20', 'met']
        )
        self.assertEqual(
            row(self.text, '| pa_robust | 25.0 |')[-1],
            'met on CPU time, **missed on wall time** (load)',
        )
        self.assertEqual(row(self.text, '| oracle | 30.0 |')[-1], '**missed**')
        self.assertNotIn('| pa | 1.0 |', self.text)  # only medians are reported

    def test_controller_step_without_an_aim(self):
        r = row(self.text, '| pa_robust | trajectory |')
        self.assertEqual(r[4:6], ['-', 'no aim set'])
        self.assertEqual(r[6], '32 / 10')
        self.assertEqual(row(self.text, '| rac | trajectory |')[4:6], ['< 1000', 'met'])

    def test_prototype_ratios_against_500x(self):
        # hyperfine: 6.0 / 0.02 = 300x; loop wall: 6.3 / 0.011 = 573x; CPU 6.2 / 0.009 = 689x;
        # in-process 5.6 / 0.005 = 1120x.
        self.assertEqual(
            row(self.text, '| process wall time, hyperfine')[3:], ['300x', '>= 500x', '**missed**']
        )
        self.assertEqual(
            row(self.text, '| process wall time, interleaved')[3:], ['573x', '>= 500x', 'met']
        )
        self.assertEqual(row(self.text, '| process CPU time')[3], '689x')
        self.assertEqual(row(self.text, '| in-process')[3], '1120x')

    def test_prototype_against_the_baseline_build_too(self):
        # The third command: hyperfine 6.0 / 0.04 = 150x; loop wall 6.3 / 0.03 = 210x.
        prefix = '| baseline build (commit base123): '
        self.assertEqual(row(self.text, prefix + 'process wall time, hyperfine')[3], '150x')
        self.assertEqual(row(self.text, prefix + 'process wall time, interleaved')[3], '210x')
        self.assertEqual(row(self.text, prefix + 'process CPU time')[3], '310x')
        no_base = results()
        no_base['baseline'] = None
        self.assertNotIn('baseline build (commit', report.render(no_base))

    def test_baseline_table(self):
        self.assertEqual(
            row(self.text, '| rac | yes |'),
            ['rac', 'yes', '15.0', '5.0', '3.00x', '20.0', '10.0', '2.00x', '2000', '800', '2.50x'],
        )
        r = row(self.text, '| pa_robust | **no** |')
        self.assertEqual(r[2:5], ['50.0', '20.0', '2.50x'])
        self.assertEqual(r[8:], ['-', '-', '-'])  # no instruction counts for it
        self.assertIn('Baseline: commit base123', self.text)

    def test_instructions_and_commands(self):
        self.assertEqual(row(self.text, '| rac | 300 |'), ['rac', '300', '-', '200', '700', '800'])
        self.assertIn("the plant's RK4 step is 29 %", self.text)
        self.assertIn('  bench/run_bench.sh', self.text)


class TestMedians(unittest.TestCase):
    def test_one_repetition_has_no_aggregates(self):
        one = {'benchmarks': [{'run_name': 'ClosedLoop/scenario3/rac', 'run_type': 'iteration'}]}
        self.assertEqual(list(report.benchmark_medians(one)), ['ClosedLoop/scenario3/rac'])
        med = report.benchmark_medians(results()['bench'])
        self.assertEqual(med['ClosedLoop/scenario3/rac']['cpu_time'], 8.0)
        self.assertIn('ControllerStep/rac/trajectory', med)


class TestWrite(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix='pmrac_report_')
        for name, data in results().items():
            with open(os.path.join(self.dir, name + '.json'), 'w') as f:
                json.dump(data, f)

    def tearDown(self):
        shutil.rmtree(self.dir)

    def test_hand_written_sections_are_kept_and_old_tables_replaced(self):
        out = os.path.join(self.dir, 'performance.md')
        with open(out, 'w') as f:
            f.write(
                '# Performance\n\nold header\n\n## Full scenario 3 per mode (old)\n\n| old |\n\n'
                '## Through ROS: lockstep\n\nmeasured by hand\n\n| a | b |\n\n'
                '## Commands\n\n- old\n'
            )
        text = report.write(self.dir, out)
        with open(out) as f:
            self.assertEqual(f.read(), text)
        self.assertNotIn('old header', text)
        self.assertNotIn('| old |', text)
        self.assertNotIn('- old\n', text)
        self.assertTrue(
            text.endswith('## Through ROS: lockstep\n\nmeasured by hand\n\n| a | b |\n')
        )
        self.assertEqual(text.count('## Commands'), 1)
        # Written again, the page stays the same.
        self.assertEqual(report.write(self.dir, out), text)

    def test_a_new_page(self):
        out = os.path.join(self.dir, 'new.md')
        text = report.write(self.dir, out)
        self.assertTrue(text.startswith('# Performance\n'))
        self.assertNotIn('Through ROS', text)


class TestMeta(unittest.TestCase):
    def test_crosscheck_and_meta(self):
        x = report.prototype_crosscheck(
            'table\n{"vs_cli": {"max_abs_diff_peak_abs_e": 4.5e-14, "max_abs_diff_iae": 8.3e-13, '
            '"same_events": true}}\n'
        )
        meta = report.meta_from_env(META_ENV, 'res', x)
        self.assertEqual(meta['xcheck_peak'], '4.5e-14')
        self.assertEqual(meta['xcheck_events'], 'identical')
        self.assertEqual(meta['commands'][1], ['all of the above', 'bench/run_bench.sh'])
        self.assertEqual(report.meta_from_env(META_ENV, 'res', {})['xcheck_iae'], '?')


if __name__ == '__main__':
    unittest.main()
