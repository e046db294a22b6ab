"""scripts/install_deps --demo names what the package's own Python and the docs' commands need
at run time. A fresh Debian 12 after `scripts/run_demo` lacked rosrun (ros-core only recommends
rosbash, and install_deps installs without recommends) and geometry_msgs for Python (live_plot
and viz_markers died); the development machine had both, so nothing else caught it. The same
for the test set: a fresh Debian 12 after `scripts/test` lacked diagnostic_msgs for Python, and
8 rostests died at their first import (CI's machine had it)."""

import os
import re
import subprocess
import unittest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
# Message modules the demo set brings without naming them: apt installs them with these.
COMES_WITH = {
    'std_msgs': 'python3-rospy depends on python3-std-msgs',
    'rosgraph_msgs': 'python3-rospy depends on python3-rosgraph-msgs',
}


def demo_packages(*flags):
    out = subprocess.run(
        ['bash', os.path.join(ROOT, 'scripts', 'install_deps'), '--list', *flags],
        check=True,
        capture_output=True,
        text=True,
    ).stdout
    return set(out.split())


def python_files(*tops):
    """*.py files and executables whose first line names python, under each top folder."""
    files = []
    for top in tops:
        for d, _, names in os.walk(os.path.join(ROOT, top)):
            for n in names:
                path = os.path.join(d, n)
                if n.endswith('.py'):
                    files.append(path)
                elif os.access(path, os.X_OK):
                    with open(path, encoding='utf-8', errors='replace') as f:
                        if 'python' in f.readline():
                            files.append(path)
    return files


def imported_msg_modules(*tops):
    """The ROS message packages the Python files under tops import (default: what users run,
    src/preadaptive_mrac and scripts/, examples included)."""
    files = python_files(*(tops or ('src/preadaptive_mrac', 'scripts')))
    found = {}
    for path in files:
        with open(path, encoding='utf-8', errors='replace') as f:
            for line in f:
                m = re.match(r'\s*(?:from|import)\s+(\w+_msgs)\b', line)
                if m:
                    found.setdefault(m.group(1), os.path.relpath(path, ROOT))
    return found


def missing_debs(flag, modules):
    """(where, module, deb) for each imported message module whose python3-* package is not in
    `install_deps FLAG`."""
    pkgs = demo_packages(flag)
    out = []
    for module, where in sorted(modules.items()):
        deb = 'python3-' + module.replace('_', '-')
        if module not in COMES_WITH and deb not in pkgs:
            out.append('%s imports %s: %s is not in install_deps %s' % (where, module, deb, flag))
    return out


class TestDemoSet(unittest.TestCase):
    def test_rosrun_is_installed(self):
        # the README and every tutorial use rosrun; it is in rosbash
        self.assertIn('rosbash', demo_packages())

    def test_every_imported_message_package(self):
        modules = imported_msg_modules()
        self.assertIn('geometry_msgs', modules)  # the scan finds what it must
        self.assertEqual(missing_debs('--demo', modules), [])


class TestTestSet(unittest.TestCase):
    def test_every_message_package_the_tests_import(self):
        modules = imported_msg_modules('test', 'bench')
        self.assertIn('diagnostic_msgs', modules)  # the scan finds what it must
        self.assertEqual(missing_debs('--test', modules), [])


if __name__ == '__main__':
    unittest.main()
