"""preadaptive_mrac.studies.yaml_mutations: leaves of the shipped YAML files, every mutation kind,
the seeded sample (no launch here; test/scripts/config_mutations.sh launches)."""

import math
import unittest

import pkg_path  # noqa: F401
from preadaptive_mrac.studies import yaml_mutations as cm


class TestLeaves(unittest.TestCase):
    def test_shapes(self):
        self.assertEqual(cm.shape(1.0), 'scalar')
        self.assertEqual(cm.shape([1, 2]), 'vector')
        self.assertEqual(cm.shape([[1, 2], [3, 4]]), 'matrix')
        self.assertIsNone(cm.shape([{'a': 1}]))
        self.assertIsNone(cm.shape([]))

    def test_leaves_walk_maps_and_lists_of_maps(self):
        doc = {'a': {'b': 1, 'v': [1, 2]}, 'segs': [{'until': 5, 'scale': 1}]}
        got = [(cm.dotted(p), s) for p, _, s in cm.leaves(doc)]
        self.assertEqual(
            got,
            [
                ('a.b', 'scalar'),
                ('a.v', 'vector'),
                ('segs.0.until', 'scalar'),
                ('segs.0.scale', 'scalar'),
            ],
        )


class TestMutate(unittest.TestCase):
    def setUp(self):
        self.doc = {'c': {'x': 1.0, 'name': 'rk4', 'v': [1.0, 2.0], 'm': [[1.0, 0.0], [0.0, 1.0]]}}

    def test_each_kind_and_the_original_untouched(self):
        self.assertNotIn('x', cm.mutate(self.doc, ('c', 'x'), 'drop', 'scalar')['c'])
        self.assertEqual(
            cm.mutate(self.doc, ('c', 'x'), 'type', 'scalar')['c']['x'], 'not_a_number'
        )
        self.assertEqual(cm.mutate(self.doc, ('c', 'name'), 'type', 'scalar')['c']['name'], 12345)
        self.assertTrue(math.isnan(cm.mutate(self.doc, ('c', 'v'), 'nan', 'vector')['c']['v'][0]))
        self.assertTrue(
            math.isnan(cm.mutate(self.doc, ('c', 'm'), 'nan', 'matrix')['c']['m'][0][0])
        )
        self.assertEqual(cm.mutate(self.doc, ('c', 'v'), 'size', 'vector')['c']['v'], [1.0])
        self.assertEqual(
            self.doc['c'], {'x': 1.0, 'name': 'rk4', 'v': [1.0, 2.0], 'm': [[1.0, 0.0], [0.0, 1.0]]}
        )


class TestShippedFiles(unittest.TestCase):
    def test_every_file_has_mutations_and_size_only_for_arrays(self):
        muts = cm.mutations()
        self.assertEqual({m[0] for m in muts}, set(cm.FILES))
        self.assertTrue(all(m[3] in ('vector', 'matrix') for m in muts if m[2] == 'size'))
        keys = {cm.dotted(m[1]) for m in muts}
        self.assertIn('controller.attention.c_e', keys)

    def test_sample_is_seeded_and_covers_every_file_and_kind(self):
        muts = cm.mutations()
        a, b = cm.pick(muts, 20, 7), cm.pick(muts, 20, 7)
        self.assertEqual(a, b)
        self.assertEqual(len(a), 20)
        strata = {(m[0], m[2]) for m in muts}
        self.assertTrue(strata <= {(m[0], m[2]) for m in a})


if __name__ == '__main__':
    unittest.main()
