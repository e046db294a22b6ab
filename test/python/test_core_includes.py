"""scripts/core_includes on this tree: the core's includes run down only (docs/design.md)."""

import os
import subprocess
import sys
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


if __name__ == '__main__':
    unittest.main()
