"""params/*.yaml (one declaration per parameter, issue 21) against every place derived from
it: the shipped YAML's keys and values, the rows of docs/parameters.md, the dynamic_reconfigure
.cfg, the mutation study's optional keys; and the one list of mode names (the registry in
src/core/mode_registry.cpp) against every place that names the modes."""

import os
import re
import unittest

import yaml

import pkg_path
from preadaptive_mrac import params_table
from preadaptive_mrac.studies import yaml_mutations

ROOT = pkg_path.ROOT


def read(rel):
    with open(os.path.join(ROOT, rel)) as f:
        return f.read()


def registered_modes():
    """The names of kModes in src/core/mode_registry.cpp, in order (what preadapt_sim
    --list-modes prints; read from the source so the test needs no build)."""
    src = read('src/core/mode_registry.cpp')
    body = src[src.index('kModes = {') :]
    return re.findall(r'^\s*\{"([a-z0-9_]+)",', body, re.M)


def leaves(node, path):
    if isinstance(node, dict):
        for k, v in node.items():
            yield from leaves(v, '%s.%s' % (path, k))
    else:
        yield path, node


class TestControllerTable(unittest.TestCase):
    def setUp(self):
        self.table = params_table.load('controller')
        self.rows = self.table['params']
        self.prefix = self.table['prefix']

    def test_the_shipped_yaml_has_exactly_the_table_keys_and_defaults(self):
        shipped = dict(
            leaves(
                yaml.safe_load(read('config/controller/default.yaml'))['controller'], 'controller'
            )
        )
        declared = {
            '%s.%s' % (self.prefix, r['key']): r.get('default')
            for r in self.rows
            if r['type'] != 'section'
        }
        self.assertEqual(sorted(shipped), sorted(declared))
        for key, value in shipped.items():
            self.assertEqual(value, declared[key], key)

    def test_docs_rows_are_the_tables(self):
        doc = {
            line.split('`')[1]: line
            for line in read('docs/parameters.md').splitlines()
            if line.startswith('| `%s.' % self.prefix) or line.startswith('| `%s` ' % self.prefix)
        }
        want = {
            '%s.%s'
            % (self.prefix, r['key']): params_table.docs_row(self.prefix, r, registered_modes())
            for r in self.rows
        }
        self.assertEqual(sorted(doc), sorted(want))
        for key, row in want.items():
            self.assertEqual(doc[key], row, key)

    def test_every_docs_row_is_a_table_row(self):
        """docs/parameters.md's table holds the rows of every table (controller with its parts,
        plant, scenario, nodes) in that order, and nothing else."""
        doc = [
            line
            for line in read('docs/parameters.md').splitlines()
            if line.startswith('| `') and not line.startswith('| `name`')
        ]
        want = params_table.docs_rows(registered_modes())
        self.assertEqual(len(doc), len(want))
        for got, row in zip(doc, want):
            self.assertEqual(got, row)

    def test_reconfigure_reads_the_table(self):
        cfg = read('cfg/ControllerTuning.cfg')
        self.assertIn('params_table.load("controller")', cfg)
        # no parameter of the table declared by hand beside it
        for r in params_table.tunables('controller'):
            self.assertNotIn('"%s"' % r['tunable'], cfg, r['tunable'])
        names = [r['tunable'] for r in params_table.tunables('controller')]
        self.assertEqual(len(names), len(set(names)))

    def test_generated_reconfigure_defaults_when_built(self):
        try:
            from preadaptive_mrac.cfg import ControllerTuningConfig as gen
        except ImportError:
            self.skipTest('the generated ControllerTuningConfig is not on the path (not built)')
        got = {p['name']: p['default'] for p in gen.config_description['parameters']}
        for g in gen.config_description['groups']:
            got.update({p['name']: p['default'] for p in g['parameters']})
        for r in params_table.tunables('controller'):
            self.assertEqual(got[r['tunable']], r['default'], r['tunable'])

    def test_mutation_study_drops_exactly_the_optional_keys(self):
        optional = set(params_table.optional_keys('controller'))
        self.assertIn('controller.attention.hysteresis', optional)
        for r in self.rows:
            key = '%s.%s' % (self.prefix, r['key'])
            if r['type'] == 'section' or key in ('controller.mode', 'controller.sample_time'):
                continue  # sections are not leaves; these two are set by the launch files
            runs = yaml_mutations.expected_runs('controller', key, 'drop')
            self.assertEqual(runs is not None, key in optional, key)

    def test_tunables_have_a_group_and_a_scalar_type(self):
        for r in params_table.tunables('controller'):
            self.assertIn(r['type'], ('double', 'int', 'bool'), r['key'])
            self.assertIn('group', r, r['key'])


def holds(check, v):
    lo, hi = check.get('min'), check.get('max')
    return (lo is None or (v > lo if check.get('min_open') else v >= lo)) and (
        hi is None or (v < hi if check.get('max_open') else v <= hi)
    )


class TestNodeTable(unittest.TestCase):
    """params/nodes.yaml's rows of the nodes with a generated struct: their defaults (the
    generated members') are the ones the docs show and lie in their ranges."""

    def setUp(self):
        self.table = params_table.load('nodes')
        self.rows = [
            r for r in self.table['params'] if set(r['nodes']) & set(self.table['structs'])
        ]

    def test_every_row_of_a_generated_node_is_optional_with_a_default(self):
        self.assertGreaterEqual(len(self.rows), 30)
        for r in self.rows:
            self.assertEqual(r.get('presence'), 'optional', r['key'])
            self.assertIn('default', r, r['key'])

    def test_docs_show_the_default(self):
        def shown(v):
            if isinstance(v, bool):
                return 'true' if v else 'false'
            if isinstance(v, str):
                return v or "''"
            if isinstance(v, list):
                return '[]' if not v else str(v)
            return params_table.number_text(v) if isinstance(v, float) else str(v)

        for r in self.rows:
            first = r['default_doc'].split(' ')[0].strip('`')
            self.assertEqual(first, shown(r['default']), r['key'])

    def test_defaults_lie_in_their_range(self):
        for r in self.rows:
            if 'check' in r:
                self.assertTrue(holds(r['check'], r['default']), r['key'])
            if 'choices' in r:
                self.assertIn(r['default'], r['choices'], r['key'])


class TestModeNames(unittest.TestCase):
    def setUp(self):
        self.modes = registered_modes()

    def test_registry_read(self):
        self.assertEqual(self.modes[:4], ['rac', 'pa', 'pa_learn', 'pa_learn_exact'])

    def test_comments_and_launch_docs_list_every_mode(self):
        bar = ' | '.join(self.modes)
        self.assertIn(
            'mode: pa_learn             # ' + bar + '\n', read('config/controller/default.yaml')
        )
        self.assertIn(
            'string mode                  # ' + bar + '\n', read('msg/AdaptationStatus.msg')
        )
        for launch in ('launch/closed_loop.launch', 'launch/scenario.launch'):
            self.assertIn('doc="' + bar + ' (', read(launch), launch)
        self.assertIn(
            'doc="mode of /pa: ' + ' | '.join(m for m in self.modes if m != 'rac') + ' (',
            read('launch/compare.launch'),
        )

    def test_python_lists_of_every_mode(self):
        from preadaptive_mrac.analysis import runs
        from preadaptive_mrac.bench import report
        from preadaptive_mrac.studies import robust

        for name, lst in (('runs', runs.MODES), ('report', report.MODES), ('robust', robust.MODES)):
            self.assertEqual(sorted(lst), sorted(self.modes), name)
        from preadaptive_mrac.reproduction import common

        self.assertEqual(list(common.MODES), self.modes[:4])  # the paper's four


if __name__ == '__main__':
    unittest.main()
