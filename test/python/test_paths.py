"""preadaptive_mrac.paths and the package layout (the package beside the generated messages)."""

import os
import unittest

import pkg_path

from preadaptive_mrac import paths


class TestPaths(unittest.TestCase):
    def test_package_root_is_the_source_tree(self):
        root = paths.package_root()
        self.assertEqual(os.path.realpath(root), os.path.realpath(pkg_path.ROOT))
        self.assertTrue(os.path.exists(os.path.join(root, 'package.xml')))
        self.assertTrue(os.path.exists(os.path.join(root, 'config', 'controller', 'default.yaml')))

    def test_generated_messages_import_beside_the_package(self):
        try:
            import genpy  # noqa: F401
        except ImportError:
            self.skipTest('genpy (ROS Python) is not installed')
        import preadaptive_mrac

        for d in preadaptive_mrac.__path__:
            if os.path.isdir(os.path.join(d, 'msg')):
                break
        else:
            self.skipTest('no built devel space on sys.path (source devel/setup.bash)')
        from preadaptive_mrac.msg import PlantState

        self.assertIn('alpha', PlantState.__slots__)


if __name__ == '__main__':
    unittest.main()
