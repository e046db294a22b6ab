"""preadaptive_mrac.studies.config_mutation: how a launch's log is judged (no launch here;
test/scripts/config_mutations.sh launches)."""

import tempfile
import unittest

import pkg_path  # noqa: F401
from preadaptive_mrac.studies import config_mutation as cm


class TestDefaultsLine(unittest.TestCase):
    def test_the_start_up_line_must_name_the_dropped_key(self):
        rx = [r'/%s/controller/attention/hysteresis(?=[:\[\s]|$)' % n for n in ('mrac_controller',)]
        with tempfile.NamedTemporaryFile('w', suffix='.log') as f:
            f.write('[ INFO] [1.0]: optional keys filled with defaults: /plant_sim/dt = 0.001\n')
            f.write('[ INFO] mrac_controller: hysteresis 0 (not the line)\n')
            f.flush()
            self.assertFalse(cm.defaults_line_names(f.name, rx))
            f.write(
                '[ INFO] [1.1]: optional keys filled with defaults: /mrac_controller/stale_'
                'timeout = 0.05, /mrac_controller/controller/attention/hysteresis = 0\n'
            )
            f.flush()
            self.assertTrue(cm.defaults_line_names(f.name, rx))
        self.assertFalse(cm.defaults_line_names('/nonexistent/roslaunch.log', rx))


if __name__ == '__main__':
    unittest.main()
