"""analyze_bag and dynamic_reconfigure: ParamChange messages (controller/param_change) are read
from a bag, listed in metrics.json and drawn as markers on the time plots."""
import json
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.join(HERE, '..', '..')
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(ROOT, 'src'))
import synthetic  # noqa: E402
from preadaptive_mrac import analysis as pa  # noqa: E402
from preadaptive_mrac.analysis import figure_style  # noqa: E402


def param_change_class():
    import genpy.dynamic
    import std_msgs.msg

    with open(os.path.join(synthetic.MSG_DIR, 'ParamChange.msg')) as f:
        text = f.read()
    full = text + '\n' + '=' * 80 + '\nMSG: std_msgs/Header\n' + std_msgs.msg.Header._full_text
    return genpy.dynamic.generate_dynamic('preadaptive_mrac/ParamChange', full)[
        'preadaptive_mrac/ParamChange'
    ]


class TestParamChange(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        import rosbag
        import rospy

        cls.dir = tempfile.mkdtemp(prefix='pmrac_param_change_test_')
        cls.sim = synthetic.simulate('pa', seed=1)
        # Same file name in two directories: the figures' titles (the run label) are equal.
        for sub in ('plain', 'changed'):
            os.makedirs(os.path.join(cls.dir, sub))
        cls.plain = synthetic.write_bag(os.path.join(cls.dir, 'plain', 'run.bag'), {'': cls.sim})
        cls.bag = os.path.join(cls.dir, 'changed', 'run.bag')
        shutil.copyfile(cls.plain, cls.bag)
        PC = param_change_class()
        with rosbag.Bag(cls.bag, 'a') as b:
            for step, name, old, new in (
                (6500, 'controller.attention.c_ed', 0.02, 0.015),
                (6500, 'controller.adaptation.gamma', 10.0, 20.0),
            ):
                m = PC()
                m.step, m.t, m.name, m.old_value, m.new_value = step, step * 0.001, name, old, new
                m.header.stamp = rospy.Time.from_sec(m.t)
                b.write('/controller/param_change', m, rospy.Time.from_sec(1000.0 + m.t))

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.dir, ignore_errors=True)

    def test_loaded(self):
        (run,) = pa.load_runs(self.bag)
        self.assertEqual(
            [(c['step'], c['name'], c['old_value'], c['new_value']) for c in run.param_changes],
            [
                (6500, 'controller.attention.c_ed', 0.02, 0.015),
                (6500, 'controller.adaptation.gamma', 10.0, 20.0),
            ],
        )
        self.assertAlmostEqual(run.param_changes[0]['t'], 6.5)
        (plain,) = pa.load_runs(self.plain)
        self.assertEqual(plain.param_changes, [])

    def test_markers_drawn(self):
        plt = figure_style._mpl()
        (run,) = pa.load_runs(self.bag)
        fig, ax = plt.subplots()
        lines = figure_style._param_change_lines(ax, run)
        self.assertEqual(len(lines), 1)  # one line for the two changes of one step
        self.assertEqual(list(lines[0].get_xdata()), [6.5, 6.5])
        texts = [t.get_text() for t in ax.texts]
        self.assertTrue(any('c_ed' in t and 'gamma' in t for t in texts), texts)
        plt.close(fig)

    def test_figures_and_metrics(self):
        out_a, out_b = os.path.join(self.dir, 'a'), os.path.join(self.dir, 'b')
        for bag, out in ((self.plain, out_a), (self.bag, out_b)):
            r = subprocess.run(
                [
                    '/usr/bin/python3',
                    os.path.join(ROOT, 'scripts', 'analyze_bag'),
                    bag,
                    '--out',
                    out,
                ],
                capture_output=True,
                text=True,
            )
            self.assertEqual(r.returncode, 0, r.stderr)
        with open(os.path.join(out_b, 'metrics.json')) as f:
            doc = json.load(f)
        self.assertEqual(len(doc['runs'][0]['param_changes']), 2)
        # The time plots differ only by the markers: the images must differ.
        for name in ('alpha_run.png', 'theta_hat_run.png', 'elevator_run.png'):
            with open(os.path.join(out_a, name), 'rb') as fa, open(
                os.path.join(out_b, name), 'rb'
            ) as fb:
                self.assertNotEqual(fa.read(), fb.read(), name)
        # ... and the figures without time axis are the same (the comparison can tell).
        with open(os.path.join(out_a, 'peak_per_window.png'), 'rb') as fa, open(
            os.path.join(out_b, 'peak_per_window.png'), 'rb'
        ) as fb:
            self.assertEqual(fa.read(), fb.read())


if __name__ == '__main__':
    unittest.main()
