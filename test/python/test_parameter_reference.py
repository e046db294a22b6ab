"""docs/parameters.md against the package: every key of the shipped YAML files and every key the
config readers and the nodes read has a row, and every row names a key that something reads."""

import glob
import os
import re
import unittest

import yaml

import pkg_path
from preadaptive_mrac import params_codegen, params_table

ROOT = pkg_path.ROOT
DOC = os.path.join(ROOT, 'docs', 'parameters.md')


def read(rel):
    with open(os.path.join(ROOT, rel)) as f:
        return f.read()


def table_rows():
    """(key, nodes) of each row: nodes is () for a config key, else the nodes named after it."""
    rows = []
    for line in read('docs/parameters.md').splitlines():
        m = re.match(r'^\| `([^`]+)`( \(([^)]*)\))? \|', line)
        if m and m.group(1) != 'name':
            nodes = tuple(n.strip() for n in m.group(3).split(',')) if m.group(3) else ()
            rows.append((m.group(1), nodes))
    return rows


def yaml_keys(node, path=''):
    """Dotted keys of every leaf and list of segments (not of the maps that only group keys);
    list entries as `[]`."""
    if isinstance(node, dict):
        for k, v in node.items():
            key = '%s.%s' % (path, k) if path else str(k)
            if not isinstance(v, dict):
                yield key
            yield from yaml_keys(v, key)
    elif isinstance(node, list) and node and all(isinstance(x, dict) for x in node):
        for x in node:
            yield from yaml_keys(x, path + '[]')


def function_body(text, name):
    i = text.index(name + '(const ParamValue& tree')
    j = text.find('\n}\n', i)
    return text[i:j]


def generated_node_keys():
    """node -> the keys of its struct generated from params/nodes.yaml (forEachKey)."""
    table = params_table.load_own('nodes')
    names = {name: node for node, name in table['structs'].items()}
    return {names[n]: {r['key'] for r in rows} for n, rows in params_codegen.structs(table)}


def node_keys():
    """Private parameters each node reads: for the C++ nodes the generated struct's keys when
    node_params.cpp's reader reads it (readNodeRows) and the keys it reads by hand; for
    viz_markers the table's rows when markers.py reads them through params_table."""
    keys = {}
    npc = read('src/ros/node_params.cpp')
    rx = r'(?:r\.get\w+\(|read(?:CallerList|TopicList|StringList)\(r, tree, )"(\w+)"'
    generated = generated_node_keys()
    for node, function in (
        ('plant_sim_node', 'readPlantNodeParams'),
        ('mrac_controller_node', 'readControllerNodeParams'),
        ('bag_recorder_node', 'readBagRecorderParams'),
        ('run_monitor_node', 'readRunMonitorParams'),
    ):
        body = function_body(npc, function)
        keys[node] = set(re.findall(rx, body))
        if 'readNodeRows(r, tree, &p' in body:
            keys[node] |= generated[node]
    markers = read('src/preadaptive_mrac/viz/markers.py')
    keys['viz_markers'] = set(re.findall(r"get_param\('~(\w+)'", markers))
    if "read_node_params(\n            'viz_markers'" in markers:
        keys['viz_markers'] |= {r['key'] for r in params_table.node_rows('viz_markers')}
    return keys


# A node's own read of one private key with the default written beside it (roscpp's
# pnh.param/getParam/param::get, rospy's get_param('~key')): the key's default and range would
# then be declared twice. Every node reads its whole private namespace once and takes the rest
# from params/nodes.yaml (node_params.cpp's readers, params_table.read_node_params).
HAND_READ = re.compile(
    r'\.param\s*<|\bparam\s*\(\s*"|getParam\s*\(\s*"|param::get\s*\(\s*"'
    r'|get_param\s*\(\s*[\'"]~\w'
)
HAND_READ_DIRS = ('src/ros', 'src/nodes', 'src/preadaptive_mrac/viz')


def hand_reads(text):
    """The lines of `text` that read one private key by hand (HAND_READ)."""
    return [ln.strip() for ln in text.splitlines() if HAND_READ.search(ln)]


def config_code_suffixes():
    """The dotted suffixes the config readers put after a section prefix (".lqr.Q", ".std")."""
    out = set()
    for rel in (
        'src/core/controller/controller.cpp',
        'src/core/controller/controller_config.cpp',
        'src/core/sim/plant.cpp',
        'src/core/sim/scenario.cpp',
    ):
        out |= set(re.findall(r'"\.([a-zA-Z_][\w.]*)"', read(rel)))
    # The fault keys, read from their table (Scenario::kFaultKeys: {"name", lo, hi, &field, ..}).
    out |= set(
        re.findall(
            r'\{"([a-z_]+)", -?[\d.]+, -?[\d.]+, &FaultSegment::', read('src/core/sim/scenario.cpp')
        )
    )
    # The scalars the plant and scenario read through the generic reader: the keys (and their
    # sections) of each struct generated from their tables that the reader reads.
    for component in ('plant', 'scenario'):
        text = read('src/core/sim/%s.cpp' % component)
        for name, rows in params_codegen.structs(params_table.load_own(component)):
            if 'static_cast<%s*>' % name not in text:
                continue
            for r in rows:
                parts = r['key'].split('.')
                out |= {'.'.join(parts[: i + 1]) for i in range(len(parts))}
    return out


class TestParameterReference(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.rows = table_rows()
        cls.config = {k for k, nodes in cls.rows if not nodes}
        cls.by_node = {}
        for k, nodes in cls.rows:
            for n in nodes:
                cls.by_node.setdefault(n, set()).add(k.lstrip('~'))

    def test_the_table_is_read(self):
        self.assertGreater(len(self.config), 60)
        self.assertIn('controller.attention.hysteresis', self.config)
        self.assertIn('dt', self.by_node['plant_sim_node'])

    def test_every_key_of_the_shipped_yaml_files_has_a_row(self):
        files = ['config/controller/default.yaml', 'config/plant/b747.yaml']
        files += sorted(
            os.path.relpath(p, ROOT) for p in glob.glob(os.path.join(ROOT, 'config/scenarios/*'))
        )
        self.assertGreaterEqual(len(files), 5)
        for rel in files:
            with open(os.path.join(ROOT, rel)) as f:
                doc = yaml.safe_load(f)
            missing = sorted(set(yaml_keys(doc)) - self.config)
            self.assertEqual(missing, [], '%s: keys missing from docs/parameters.md' % rel)

    def test_every_key_the_config_readers_read_has_a_row(self):
        flat = {k.replace('[]', '') for k in self.config}
        missing = sorted(
            s
            for s in config_code_suffixes()
            if not any(k.endswith('.' + s) or ('.' + s + '.') in k for k in flat)
        )
        self.assertEqual(missing, [], 'read by src/core but missing from docs/parameters.md')

    def test_every_node_parameter_has_a_row_and_every_row_is_read(self):
        for node, keys in node_keys().items():
            self.assertTrue(keys, 'no parameters found for %s (pattern out of date?)' % node)
            documented = self.by_node.get(node, set())
            self.assertEqual(sorted(keys - documented), [], '%s: undocumented' % node)
            self.assertEqual(sorted(documented - keys), [], '%s: documented, never read' % node)
        self.assertEqual(sorted(set(self.by_node) - set(node_keys())), [], 'unknown node')

    def test_no_node_reads_a_parameter_with_a_default_of_its_own(self):
        found = []
        for d in HAND_READ_DIRS:
            for dirpath, _, files in os.walk(os.path.join(ROOT, d)):
                for f in sorted(files):
                    if f.endswith(('.cpp', '.hpp', '.py')):
                        rel = os.path.relpath(os.path.join(dirpath, f), ROOT)
                        found += ['%s: %s' % (rel, ln) for ln in hand_reads(read(rel))]
        self.assertEqual(found, [], 'read by hand: declare the key in params/nodes.yaml')

    def test_hand_reads_are_found(self):
        planted = (
            'pnh.param<int>("progress_every", p.progress_every, 100);\n'
            '  ctx.pnh().getParam("state_topics", v);\n'
            'ros::param::get("~rate", r);\n'
            "        self.rate = float(rospy.get_param('~rate', 20.0))\n"
            '    nh.param("x", x, 1.0);\n'
        )
        self.assertEqual(len(hand_reads(planted)), 5)
        # the whole private namespace at once is how the nodes read
        whole = "rospy.get_param('~', {})\nros::param::get(pnh_.getNamespace(), v)\n"
        self.assertEqual(hand_reads(whole), [])

    def test_every_config_row_is_a_shipped_or_read_key(self):
        shipped = set()
        for p in glob.glob(os.path.join(ROOT, 'config', '*', '*.yaml')):
            with open(p) as f:
                shipped |= set(yaml_keys(yaml.safe_load(f)))
        suffixes = config_code_suffixes()
        stale = sorted(
            k
            for k in self.config - shipped
            if not any(k.replace('[]', '').endswith('.' + s) for s in suffixes)
            and k
            not in (
                'scenario.reference',
                'controller.robust',
                'controller.projection',
                'controller.model',
            )
        )
        self.assertEqual(stale, [], 'rows of docs/parameters.md that nothing reads or ships')


if __name__ == '__main__':
    unittest.main()
