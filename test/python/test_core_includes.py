"""scripts/core_includes on this tree: the core's includes run down only (docs/design.md)."""

import os
import shutil
import subprocess
import sys
import tempfile
import unittest

import pkg_path

SCRIPT = os.path.join(pkg_path.ROOT, 'scripts', 'core_includes')


class TestCoreIncludes(unittest.TestCase):
    def test_no_file_cycle_and_the_simulator_includes_no_controller(self):
        out = subprocess.run(
            [sys.executable, SCRIPT], capture_output=True, text=True, timeout=60, check=False
        )
        self.assertEqual(out.returncode, 0, out.stdout + out.stderr)
        self.assertIn('file cycles: none', out.stdout)
        self.assertNotRegex(out.stdout, r'(?m)^(sim|schema) +-> (control|robust)')
        self.assertNotRegex(out.stdout, r'(?m)-> jsbsim ')
        self.assertNotRegex(out.stdout, r'(?m)^(control(/\S+)?|robust) +-> controller ')
        self.assertNotRegex(out.stdout, r'(?m)^control(/\S+)? +-> robust ')
        self.assertNotRegex(out.stdout, r'(?m)^(control|robust) +-> control/')
        self.assertNotRegex(out.stdout, r'(?m)^(control(/\S+)?|robust|controller) +-> sim ')
        self.assertNotIn('apart: ', out.stdout)

    def run_on_copy_with(self, path, include):
        """The script on a copy of the core where `path` gains `include`."""
        with tempfile.TemporaryDirectory() as tmp:
            for part in ('src/core', 'include/preadaptive_mrac/core'):
                shutil.copytree(os.path.join(pkg_path.ROOT, part), os.path.join(tmp, part))
            with open(os.path.join(tmp, path), 'a') as f:
                f.write(f'#include "preadaptive_mrac/{include}"\n')
            return subprocess.run(
                [sys.executable, SCRIPT, '--root', tmp],
                capture_output=True,
                text=True,
                timeout=60,
                check=False,
            )

    def assert_each_fails(self, cases, marker):
        """Each (path, include) added alone makes the script fail and print `marker`."""
        for path, include in cases:
            out = self.run_on_copy_with(path, include)
            self.assertEqual(out.returncode, 1, path + ' -> ' + include + '\n' + out.stdout)
            self.assertIn(marker, out.stdout)

    def test_an_upward_include_fails(self):
        cases = (
            ('src/core/control/mrac/mrac_law.cpp', 'core/controller/controller_config.hpp'),
            ('src/core/control/network.cpp', 'core/robust/regime_memory.hpp'),
            ('src/core/control/attention.cpp', 'core/control/paper/paper_preadaptation.hpp'),
            ('src/core/control/l1/l1_law.cpp', 'core/control/mrac/mrac_law.hpp'),
            ('src/core/control/paper/paper_preadaptation.cpp', 'core/robust/chunk_sums.hpp'),
            ('src/core/robust/chunk_sums.cpp', 'core/control/oracle/oracle_preadaptation.hpp'),
            ('src/core/robust/robust_config.cpp', 'core/controller/mode_registry.hpp'),
        )
        self.assert_each_fails(cases, 'upward: ')

    def test_the_controller_including_the_simulator_fails(self):
        cases = (
            ('src/core/controller/controller.cpp', 'core/sim/plant.hpp'),
            ('src/core/robust/robust_config.cpp', 'params/plant_params.hpp'),
            ('include/preadaptive_mrac/core/control/mode_context.hpp', 'core/sim/scenario.hpp'),
        )
        self.assert_each_fails(cases, 'apart: ')


if __name__ == '__main__':
    unittest.main()
