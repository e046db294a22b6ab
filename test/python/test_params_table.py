"""params/*.yaml (one declaration per parameter) against every place derived from
it: the shipped YAML's keys and values, the rows of docs/parameters.md, the dynamic_reconfigure
.cfg, the mutation study's optional keys; and the one list of modes (params/modes.yaml) against
every place that could keep its own list of them."""

import os
import re
import unittest

import yaml

import pkg_path
from preadaptive_mrac import modes as modes_table
from preadaptive_mrac import params_table
from preadaptive_mrac.studies import yaml_mutations

ROOT = pkg_path.ROOT


def read(rel):
    with open(os.path.join(ROOT, rel)) as f:
        return f.read()


def registered_modes():
    """The modes of params/modes.yaml, in order (the C++ registry's rows are generated from
    it: test_config's ModeRegistry test holds them to the registered parts)."""
    return list(modes_table.MODES)


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
        # (a key optional_unnoted without a default is not shipped: its absence is its meaning,
        # controller.model.A = the plant's)
        declared = {
            '%s.%s' % (self.prefix, r['key']): r.get('default')
            for r in self.rows
            if r['type'] != 'section'
            and not (r['presence'] == 'optional_unnoted' and 'default' not in r)
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
    """params/nodes.yaml's rows of the nodes with a generated struct, and of viz_markers (read
    through params_table.read_node_params): their defaults (the generated members', the
    Python node's) are the ones the docs show and lie in their ranges."""

    def setUp(self):
        self.table = params_table.load('nodes')
        readers = set(self.table['structs']) | {'viz_markers'}
        self.rows = [r for r in self.table['params'] if set(r['nodes']) & readers]
        self.required = [r for r in self.rows if r.get('presence') == 'required']

    def test_every_row_has_a_presence_and_the_optional_ones_a_default(self):
        self.assertGreaterEqual(len(self.rows), 45)
        for r in self.rows:
            self.assertIn(r.get('presence'), ('optional', 'optional_unnoted', 'required'))
            if r['presence'] != 'required':
                self.assertIn('default', r, r['key'])
        # a required key is a list read by hand (the generic reader has no required node key)
        self.assertEqual(sorted(r['key'] for r in self.required), ['state_topics', 'topics'])
        for r in self.required:
            self.assertEqual(r.get('read'), 'custom', r['key'])
            self.assertNotIn('default', r, r['key'])
            self.assertEqual(r['default_doc'], '**required**', r['key'])

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
            if r in self.required:
                continue
            first = r['default_doc'].split(' ')[0].strip('`')
            self.assertEqual(first, shown(r['default']), r['key'])

    def test_defaults_lie_in_their_range(self):
        for r in self.rows:
            if 'check' in r and r not in self.required:
                self.assertTrue(holds(r['check'], r['default']), r['key'])
            if 'choices' in r:
                self.assertIn(r['default'], r['choices'], r['key'])


class TestReadNodeParams(unittest.TestCase):
    """viz_markers' parameters through params_table.read_node_params: the rows' defaults, and
    every problem at once naming the key (before, its defaults were written in markers.py)."""

    def test_left_out_keys_take_the_rows_defaults(self):
        values, problems = params_table.read_node_params('viz_markers', {}, '/viz/')
        self.assertEqual(problems, [])
        rows = params_table.node_rows('viz_markers')
        self.assertEqual(values, {r['key']: r['default'] for r in rows})
        self.assertEqual((values['rate'], values['history_points']), (20.0, 400))

    def test_every_problem_at_once_naming_the_key(self):
        given = {'rate': 0, 'history': 'long', 'history_points': 1, 'publish_tf': 'yes'}
        given.update({'alpha_scale': float('nan'), 'body_frame': 'b'})
        values, problems = params_table.read_node_params('viz_markers', given, '/viz/')
        self.assertEqual(
            problems,
            [
                '/viz/rate: must be > 0, got 0',
                "/viz/history: expected a double, got 'long'",
                '/viz/history_points: must be >= 2, got 1',
                '/viz/alpha_scale: expected a finite number, got nan',
                "/viz/publish_tf: expected a bool, got 'yes'",
            ],
        )
        self.assertEqual(values['body_frame'], 'b')
        # an int where a double belongs is a number (a launch <param> without a type)
        values, problems = params_table.read_node_params('viz_markers', {'rate': 30}, '~')
        self.assertEqual((values['rate'], problems), (30.0, []))
        self.assertIsInstance(values['rate'], float)
        _, problems = params_table.read_node_params('viz_markers', {'history_points': 4.0}, '~')
        self.assertEqual(problems, ['~history_points: expected an int, got 4.0'])


class TestModeNames(unittest.TestCase):
    """No place keeps its own list of every mode: a line naming every mode, or every mode but
    one, as words (a list, a `|` alternation, a dict of them) fails in the sources, launch
    files, shipped YAML, messages, scripts and the Python package; those take the list from
    params/modes.yaml (or preadapt_sim --list-modes). A chosen few (a demo's defaults, a test's
    cases) are choices, not copies of the list. Docs (docs/, README.md) may list them."""

    FOLDERS = ('src', 'include', 'launch', 'config', 'msg', 'cfg', 'scripts', 'test', 'bench')
    SUFFIXES = ('.cpp', '.hpp', '.py', '.launch', '.yaml', '.msg', '.cfg', '.sh', '')

    def setUp(self):
        self.modes = registered_modes()
        self.word = re.compile(r'(?<![A-Za-z0-9_])(%s)(?![A-Za-z0-9_])' % '|'.join(self.modes))

    def test_table_order(self):
        # the reproduction's subject first, its baseline leading (reproduction/common.py)
        self.assertEqual(list(modes_table.PAPER_MODES), self.modes[:4])
        self.assertEqual(self.modes[0], 'rac')

    def lists_in(self, text):
        return [
            (n + 1, line)
            for n, line in enumerate(text.splitlines())
            if len(set(self.word.findall(line))) >= len(self.modes) - 1
        ]

    def test_no_hand_kept_mode_list(self):
        found = []
        for folder in self.FOLDERS:
            for dirpath, _, files in os.walk(os.path.join(ROOT, folder)):
                for f in files:
                    path = os.path.join(dirpath, f)
                    if os.path.splitext(f)[1] not in self.SUFFIXES or os.path.islink(path):
                        continue
                    try:
                        text = read(path)
                    except UnicodeDecodeError:
                        continue
                    rel = os.path.relpath(path, ROOT)
                    found += ['%s:%d: %s' % (rel, n, ln.strip()) for n, ln in self.lists_in(text)]
        self.assertEqual(found, [], 'mode lists kept by hand (take them from params/modes.yaml)')

    def test_the_check_finds_a_list(self):
        every = ', '.join('"%s"' % m for m in self.modes)
        self.assertEqual(len(self.lists_in('x = (%s)\nmode: pa  # rac' % every)), 1)
        self.assertEqual(len(self.lists_in(' | '.join(self.modes[1:]))), 1)
        self.assertEqual(self.lists_in(' | '.join(m + '_2' for m in self.modes)), [])

    def test_python_package_takes_the_table(self):
        from preadaptive_mrac.analysis import runs
        from preadaptive_mrac.bench import report
        from preadaptive_mrac.reproduction import common
        from preadaptive_mrac.studies import robust

        for name, lst in (('runs', runs.MODES), ('report', report.MODES), ('robust', robust.MODES)):
            self.assertEqual(list(lst), self.modes, name)
        self.assertEqual(list(common.MODES), self.modes[:4])

    def test_guess_mode(self):
        for m in self.modes:
            self.assertEqual(modes_table.guess_mode('scenario1_%s.csv' % m), m)
            self.assertEqual(modes_table.guess_mode('%s-run.bag' % m.replace('_', '-')), m)
        self.assertIsNone(modes_table.guess_mode('%s_vs_%s.csv' % (self.modes[0], self.modes[-1])))

    def test_mode_info_counts_truth_subscribers(self):
        import subprocess

        tool = os.path.join(ROOT, 'scripts', 'lib', 'mode_info')
        for row in modes_table.ROWS:
            out = subprocess.run(
                [tool, 'truth-subscribers', row['name'], '2'], capture_output=True, text=True
            )
            self.assertEqual(out.stdout.strip(), '3' if row['truth'] else '2', row['name'])
        out = subprocess.run([tool, 'truth-subscribers', 'no_such_mode', '1'], capture_output=True)
        self.assertEqual(out.stdout.strip(), b'1')


if __name__ == '__main__':
    unittest.main()
