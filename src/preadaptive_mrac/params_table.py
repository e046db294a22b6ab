"""The one declaration of each parameter: params/<component>.yaml, one table per
component, and what is derived from it: the rows of docs/parameters.md, the dynamic_reconfigure
parameters (cfg/*.cfg read the table through this module's functions, copied into the .cfg's
own reading since the .cfg runs before the package is importable), the optional keys of the
mutation study. test/python/test_params_table.py fails when a derived place disagrees, and
test_config's ParamTable tests hold the C++ reading and validation against the same table.

A row: key (below the component's prefix), type, unit, presence (required | optional |
in_section | section | optional_unnoted: absent keeps the default without the start-up note),
default (the value of the shipped YAML and of the struct; the plant's parts: of the struct when
the section is left out), check (min, max, min_open, max_open: what the validation accepts, for
double and int), range (text, where no check can say it) or range_note (added after the
check's text), tunable (the dynamic_reconfigure name, with group) and doc (one line).
default_doc overrides the rendered default where a value cannot be shown (a matrix, a section).

For the generated C++ (params_codegen.py): the table's `struct` names the generated struct of
its values (the nodes' table: `structs`, node -> struct of the rows naming it; the plant's and
scenario's: a row's `struct`, one struct per name, of the rows naming it); a row's `field`
its member (default: the key's last part), `cpp_type` a member type other than the type's own
(with `choices`: the enum of them, generated with its parser; `enum_header`: the header that
declares it instead), `read: custom` a value the component's read() reads itself (a string
checked against the registry, a matrix or vector sized by the plant, a choice), and a section
row's `absent_note` what the start-up line says when the section is left out. A section row with
`table` is a part's own table (params/<table>.yaml, with `part_of` and its own `absent_note`:
pa_robust's, the L1 law's): load() expands its rows under the section's key, so every derived
place sees one list."""

import math
import os

import yaml

from .paths import package_root


def table_path(component):
    return os.path.join(package_root(), 'params', component + '.yaml')


def components():
    """Every parameter table's component name (params/*.yaml but the modes' table, which has
    rows of modes, not parameters: modes.py), sorted."""
    folder = os.path.join(package_root(), 'params')
    return sorted(
        f[: -len('.yaml')] for f in os.listdir(folder) if f.endswith('.yaml') and f != 'modes.yaml'
    )


def load_own(component):
    """The table as written: a section row with `table` is not expanded."""
    with open(table_path(component)) as f:
        return yaml.safe_load(f)


def load(component):
    """The table with every part's table expanded under its section row's key."""
    t = load_own(component)
    rows = []
    for row in t['params']:
        rows.append(row)
        if 'table' in row:
            for sub in load(row['table'])['params']:
                rows.append(dict(sub, key='%s.%s' % (row['key'], sub['key'])))
    return dict(t, params=rows)


def table_files(component):
    """The files a component's table is made of (its own and its parts'), for build rules."""
    files = [table_path(component)]
    for row in load_own(component)['params']:
        if 'table' in row:
            files += table_files(row['table'])
    return files


def number_text(v):
    """1e6 as the docs write it: '1e6', 10.0 as '10', 0.05 as '0.05'."""
    s = '%g' % v
    return s.replace('e+0', 'e').replace('e+', 'e')


def check_text(c, typ='double'):
    """The check as the docs write it; an int's bounds in full ('[0, 100000000]')."""
    lo, hi = c.get('min'), c.get('max')
    text = (lambda v: str(int(v))) if typ == 'int' else number_text
    if lo is not None and hi is not None:
        return '%s%s, %s%s' % (
            '(' if c.get('min_open') else '[',
            text(lo),
            text(hi),
            ')' if c.get('max_open') else ']',
        )
    if lo is not None:
        return '%s %s' % ('>' if c.get('min_open') else '>=', text(lo))
    return '%s %s' % ('<' if c.get('max_open') else '<=', text(hi))


def range_text(row, modes=None):
    if row.get('range') == '@modes':
        return ', '.join('`%s`' % m for m in modes)
    if 'choices' in row:
        return ', '.join('`%s`' % c for c in row['choices'])
    if 'check' in row:
        return check_text(row['check'], row['type']) + row.get('range_note', '')
    return row.get('range', '–')


def value_text(v, typ):
    if isinstance(v, bool):
        return '`%s`' % ('true' if v else 'false')
    if isinstance(v, str):
        return '`%s`' % v
    if typ == 'int':
        return str(v)
    return repr(float(v))


def default_text(row):
    if 'default_doc' in row:
        return row['default_doc']
    v = value_text(row['default'], row['type'])
    return {
        'required': '**required** (%s)',
        'optional': 'optional (%s)',
        'in_section': '**required** in the section (%s)',
        'optional_unnoted': 'optional (%s)',
    }[row['presence']] % v


def docs_name(prefix, row):
    """The name column: `plant.A`, or `~dt` (plant_sim_node) for a node's private key."""
    if prefix == '~':
        return '`~%s` (%s)' % (row['key'], ', '.join(row['nodes']))
    return '`%s.%s`' % (prefix, row['key'])


# The tables docs/parameters.md renders, in the order of its rows.
DOC_TABLES = ('controller', 'plant', 'scenario', 'nodes')


def docs_rows(modes=None):
    """Every row of docs/parameters.md's table, from the tables."""
    out = []
    for component in DOC_TABLES:
        t = load(component)
        out += [docs_row(t['prefix'], r, modes) for r in t['params']]
    return out


def docs_row(prefix, row, modes=None):
    """The row of docs/parameters.md."""
    return '| %s | %s | %s | %s | %s | %s |' % (
        docs_name(prefix, row),
        row['type'],
        row.get('unit', '–'),
        default_text(row),
        range_text(row, modes),
        row['doc'],
    )


def plain_doc(row):
    """The doc without its Markdown escape of | (a C++ string or comment would read it as an
    escape): for the .cfg's descriptions and the generated headers' comments."""
    return row['doc'].replace('\\|', '|')


def cfg_description(prefix, row):
    """The dynamic_reconfigure description: the key, its doc, unit and range."""
    unit = row.get('unit', '–')
    return '%s.%s: %s%s; %s' % (
        prefix,
        row['key'],
        plain_doc(row),
        '' if unit == '–' else ' [%s]' % unit,
        range_text(row),
    )


def tunables(component):
    t = load(component)
    return [r for r in t['params'] if 'tunable' in r]


def optional_keys(component):
    """Dotted keys that may be left out (the mutation study's 'drop' runs)."""
    t = load(component)
    return [
        '%s.%s' % (t['prefix'], r['key'])
        for r in t['params']
        if r['presence'] == 'optional' and r['type'] != 'section'
    ]


def node_rows(node):
    """The rows of params/nodes.yaml naming `node` (a node's private parameters)."""
    return [r for r in load('nodes')['params'] if node in r['nodes']]


def _type_problem(value, typ):
    """Why `value` (as rospy gives it) is not of the row's type; None when it is."""
    if typ == 'string':
        ok = isinstance(value, str)
    elif typ == 'bool':
        ok = isinstance(value, bool)
    elif typ == 'int':
        ok = isinstance(value, int) and not isinstance(value, bool)
    else:  # double: an int is a number too (a launch <param value="30"/> without a type)
        ok = isinstance(value, (int, float)) and not isinstance(value, bool)
        if ok and not math.isfinite(value):
            return 'expected a finite number, got %r' % (value,)
    return None if ok else 'expected %s %s, got %r' % ('an' if typ == 'int' else 'a', typ, value)


def _check_problem(value, c, typ):
    """Why `value` lies outside the row's check (the C++ reader's wording); None when inside."""
    lo, hi = c.get('min'), c.get('max')
    if lo is not None and (value <= lo if c.get('min_open') else value < lo):
        return 'must be %s, got %r' % (check_text(c, typ), value)
    if hi is not None and (value >= hi if c.get('max_open') else value > hi):
        return 'must be %s, got %r' % (check_text(c, typ), value)
    return None


def read_node_params(node, given, root='~'):
    """A Python node's private parameters (viz_markers) from its table rows: `given` is the dict
    of its private namespace (rospy.get_param('~', {})); each key left out takes the row's
    default, each given one is checked against the row's type and check. Returns (values by
    key, problems), every problem at once, each naming `root + key`."""
    values, problems = {}, []
    for row in node_rows(node):
        key = row['key']
        if key not in given:
            values[key] = row['default']
            continue
        v = given[key]
        why = _type_problem(v, row['type'])
        if why is None and 'check' in row:
            why = _check_problem(v, row['check'], row['type'])
        if why is not None:
            problems.append('%s%s: %s' % (root, key, why))
        values[key] = float(v) if row['type'] == 'double' and why is None else v
    return values, problems
