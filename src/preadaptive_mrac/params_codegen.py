"""C++ from the parameter tables (one declaration per parameter): for each table
params/<component>.yaml, a header preadaptive_mrac/params/<component>_params.hpp with

- the struct of its values (the table's `struct`; the nodes' table: one per node of its
  `structs`, of the rows naming that node; the plant's and scenario's: one per row `struct`,
  of the rows naming it), each member with its default and doc;
- `forEachScalar(self, f)`: f(ParamSpec, member) for every number, bool, string and choice the
  generic reader reads (core/schema/param_table.hpp: readScalars, checkRanges), in the table's
  order;
- `forEachSection(f)`: f(key, absent_note) for every optional section; for a node's struct
  `forEachKey(f)`, every key it has (the unknown-key check);
- per `choices` type: the enum (unless `enum_header` declares it), parseChoice, choiceName,
  choiceNames;

and for a table with tunable rows (the controller's, with its parts' tables), the tunables:
the struct ControllerTunableParams, `forEachTunable(f, c...)` (f(key, reconfigure name,
c.member...)) and the copies to and from the dynamic_reconfigure config.

CMake runs it at build time (cmake/params.cmake) into the devel space; nothing generated is
committed. Usage: python3 -m preadaptive_mrac.params_codegen OUT_DIR [COMPONENT ...]
(default: every table in params/; run with src/ on sys.path)."""

import os
import sys
import textwrap

from . import modes, params_table

CPP_TYPES = {
    'double': 'double',
    'int': 'int',
    'bool': 'bool',
    'string': 'std::string',
    'list of strings': 'std::vector<std::string>',
}
PRESENCE = {
    'required': 'ParamPresence::kRequired',
    'optional': 'ParamPresence::kOptional',
    'in_section': 'ParamPresence::kInSection',
    'optional_unnoted': 'ParamPresence::kOptionalUnnoted',
}


def cpp_type(row):
    if 'cpp_type' in row:
        return row['cpp_type']
    if row['type'].startswith('matrix'):
        return 'Eigen::MatrixXd'
    if row['type'].startswith('vector'):
        return 'Eigen::VectorXd'
    return CPP_TYPES[row['type']]


def field(row):
    return row.get('field', row['key'].split('.')[-1])


def cpp_number(v):
    s = repr(float(v))
    return s if ('e' in s or '.' in s or 'inf' in s) else s + '.0'


def enumerator(choice):
    return 'k' + ''.join(w.capitalize() for w in choice.split('_'))


def enum_text(table):
    """An enum for each `choices` type (once, however many rows use it; `enum_header`: declared
    there, only the functions here), its parser and names (the read is the generic one, or the
    component's for a row read `custom`)."""
    out = []
    done = set()
    for row in table['params']:
        if 'choices' not in row or row['cpp_type'] in done:
            continue
        t = row['cpp_type']
        done.add(t)
        names = ', '.join(row['choices'])
        if 'enum_header' not in row:
            out.append(comment('The values of `%s`: %s.' % (full_key(table, row), names), ''))
            out.append(
                'enum class %s { %s };\n' % (t, ', '.join(enumerator(c) for c in row['choices']))
            )
        out.append('/// \\brief The value named `name`; false when none is.\n')
        out.append('inline bool parseChoice(const std::string& name, %s* v) {\n' % t)
        for c in row['choices']:
            out.append('  if (name == "%s") return *v = %s::%s, true;\n' % (c, t, enumerator(c)))
        out.append('  return false;\n}\n')
        out.append('/// \\brief The name of `v`, as the table writes it.\n')
        out.append('inline const char* choiceName(%s v) {\n' % t)
        for c in row['choices'][:-1]:
            out.append('  if (v == %s::%s) return "%s";\n' % (t, enumerator(c), c))
        out.append('  return "%s";\n}\n' % row['choices'][-1])
        out.append('/// \\brief The names, for messages.\n')
        out.append('inline const char* choiceNames(%s) { return "%s"; }\n\n' % (t, names))
    return ''.join(out)


def cpp_default(row):
    """The member's initialiser ('' for a matrix or vector: sized by the plant)."""
    t = cpp_type(row)
    v = row.get('default')
    if 'choices' in row:
        return ' = %s::%s' % (t, enumerator(v))
    if t.startswith(('Eigen::', 'std::vector')) or v is None:
        return ''
    if t == 'bool':
        return ' = %s' % ('true' if v else 'false')
    if t == 'std::string':
        return ' = "%s"' % v
    if t == 'double':
        return ' = %s' % cpp_number(v)
    return ' = %d' % int(v)


def comment(text, indent):
    lines = textwrap.wrap(text, 96 - len(indent) - 4)
    return ''.join('%s/// %s\n' % (indent, line) for line in lines)


def full_key(table, row):
    """The key as the docs name it: `controller.lqr.R`, or `~dt` for a node's private key."""
    if table['prefix'] == '~':
        return '~' + row['key']
    return '%s.%s' % (table['prefix'], row['key'])


def member_doc(row, key):
    unit = row.get('unit')
    return 'key `%s`: %s%s' % (
        key,
        params_table.plain_doc(row),
        ' [%s]' % unit if unit and unit != '–' else '',
    )


def check_init(row):
    c = row.get('check')
    if not c:
        return 'ParamCheck{}'
    lo, hi = c.get('min'), c.get('max')
    return 'ParamCheck{%s, %s, %s, %s, %s, %s}' % (
        'true' if lo is not None else 'false',
        cpp_number(lo if lo is not None else 0.0),
        'true' if c.get('min_open') else 'false',
        'true' if hi is not None else 'false',
        cpp_number(hi if hi is not None else 0.0),
        'true' if c.get('max_open') else 'false',
    )


def scalar_rows(rows):
    """The rows the generic reader reads: numbers, bools, strings and choices, unless `custom`."""
    return [
        r
        for r in rows
        if r['type'] in ('double', 'int', 'bool', 'string') and r.get('read') != 'custom'
    ]


def structs(table):
    """(struct name, its rows) of each struct generated from a table: the table's `struct`; for
    the nodes' table (`structs`: node -> struct) one per node, of the rows naming it; else one
    per row `struct` (the plant's parts, the scenario's scalars), of the rows naming it (the
    rows without one, matrices, vectors and lists, are read by hand)."""
    if 'struct' in table:
        return [(table['struct'], table['params'])]
    if 'structs' in table:
        return [
            (name, [r for r in table['params'] if node in r.get('nodes', ())])
            for node, name in table['structs'].items()
        ]
    names = []
    for r in table['params']:
        if 'struct' in r and r['struct'] not in names:
            names.append(r['struct'])
    return [(n, [r for r in table['params'] if r.get('struct') == n]) for n in names]


def struct_text(table, name, rows):
    out = []
    out.append(
        comment(
            'The values of params/%s.yaml (key `%s`)%s, with their defaults. Generated: edit'
            ' the table.'
            % (
                table['component'],
                table['prefix'],
                ' that %s reads' % name if 'structs' in table else '',
            ),
            '',
        )
    )
    out.append('struct %s {\n' % name)
    for row in rows:
        if row['type'] == 'section':
            continue
        out.append(comment(member_doc(row, full_key(table, row)), '  '))
        out.append('  %s %s%s;\n' % (cpp_type(row), field(row), cpp_default(row)))
    out.append(
        '\n  /// \\brief Calls f(spec, member) for each number, bool, string and choice the\n'
        '  /// generic reader reads (param_table.hpp), in the table\'s order; Self: this struct\n'
        '  /// or one derived.\n'
        '  template <class Self, class F>\n'
        '  static void forEachScalar(Self& self, F&& f) {\n'
    )
    if not scalar_rows(rows):
        out.append('    (void)self;  // every key read by hand (run_monitor_node: a list)\n')
        out.append('    (void)f;\n')
    for row in scalar_rows(rows):
        key = row['key']
        section = key.rsplit('.', 1)[0] if row['presence'] == 'in_section' else ''
        out.append(
            '    f(ParamSpec{"%s", %s, %s, "%s"}, self.%s);\n'
            % (key, PRESENCE[row['presence']], check_init(row), section, field(row))
        )
    out.append('  }\n')
    out.append(
        '  /// \\brief Calls f(key, absent_note) for each optional section of the table.\n'
        '  template <class F>\n'
        '  static void forEachSection(F&& f) {\n'
    )
    # (a section `optional_unnoted` is absent without a note: controller.model)
    noted = [
        r
        for r in rows
        if r['type'] == 'section' and 'table' not in r and r['presence'] != 'optional_unnoted'
    ]
    for row in noted:
        out.append('    f("%s", "%s");\n' % (row['key'], row['absent_note'].replace('"', '\\"')))
    if not noted:
        out.append('    (void)f;  // no section of its own\n')
    out.append('  }\n')
    if 'structs' in table:
        out.append(
            '  /// \\brief Calls f(key) for each key of the struct (those read by hand too).\n'
            '  template <class F>\n'
            '  static void forEachKey(F&& f) {\n'
        )
        out += ['    f("%s");\n' % r['key'] for r in rows]
        out.append('  }\n')
    if 'absent_note' in table:
        out.append(
            '  /// \\brief What the start-up line says when the whole section is left out.\n'
            '  static constexpr const char* kAbsentNote = "%s";\n' % table['absent_note']
        )
    out.append('};\n')
    return ''.join(out)


def tunable_paths(component):
    """(key below the prefix, reconfigure name, C++ path, C++ type, default) of every tunable
    row, the parts' tables included (their section's member first: robust.margin)."""
    out = []
    for row in params_table.load_own(component)['params']:
        if 'table' in row:
            for sub in params_table.load_own(row['table'])['params']:
                if 'tunable' in sub:
                    out.append(
                        (
                            '%s.%s' % (row['key'], sub['key']),
                            sub['tunable'],
                            '%s.%s' % (field(row), field(sub)),
                            cpp_type(sub),
                            sub,
                        )
                    )
        elif 'tunable' in row:
            out.append((row['key'], row['tunable'], field(row), cpp_type(row), row))
    return out


def tunables_text(component):
    """The tunables of a whole component (its parts' rows included); '' for a part's own table
    (`part_of`), whose tunables its owner's header holds."""
    if 'part_of' in params_table.load_own(component):
        return ''
    paths = tunable_paths(component)
    if not paths:
        return ''
    own = params_table.load_own(component)
    parts = [
        (field(r), params_table.load_own(r['table'])['struct'])
        for r in own['params']
        if 'table' in r and any(p[2].startswith(field(r) + '.') for p in paths)
    ]
    out = [
        comment(
            'The parameters of `%s` that may change while it runs (dynamic_reconfigure): the'
            ' rows with a `tunable` name. Generated: edit the table.' % own['prefix'],
            '',
        ),
        'struct %sTunableParams {\n' % own['struct'].replace('Params', ''),
    ]
    for key, name, path, typ, row in paths:
        if '.' in path:
            continue
        out.append(comment(member_doc(row, '%s.%s' % (own['prefix'], key)), '  '))
        out.append('  %s %s%s;\n' % (typ, path, cpp_default(row)))
    for member, struct in parts:
        out.append(
            '  %s %s;  ///< `%s.%s.*`: its tunable rows\n' % (struct, member, own['prefix'], member)
        )
    out.append('};\n\n')
    out.append(
        comment(
            'Calls f(key, reconfigure name, c.member...) for each tunable parameter, in the'
            ' table\'s order: the same member of every object given (configurations and'
            ' tunables alike).',
            '',
        )
    )
    out.append('template <class F, class... C>\nvoid forEachTunable(F&& f, C&... c) {\n')
    for key, name, path, typ, row in paths:
        out.append('  f("%s", "%s", c.%s...);\n' % (key, name, path))
    out.append('}\n\n')
    copies = (
        (
            'Tunables into a dynamic_reconfigure config R (fields named as the tunables).',
            'tunablesToReconfigure(const T& t, R* r)',
            '  r->{name} = t.{path};\n',
        ),
        (
            'A dynamic_reconfigure config R into tunables.',
            'tunablesFromReconfigure(const R& r, T* t)',
            '  t->{path} = r.{name};\n',
        ),
    )
    for doc, signature, line in copies:
        out.append('/// \\brief %s\ntemplate <class R, class T>\nvoid %s {\n' % (doc, signature))
        out += [line.format(name=p[1], path=p[2]) for p in paths]
        out.append('}\n\n')
    out[-1] = '}\n'
    return ''.join(out)


def header(component):
    table = params_table.load_own(component)
    types = [cpp_type(r) for _, rows in structs(table) for r in rows if r['type'] != 'section']
    includes = ['<cstdint>', '<string>']
    if any(t.startswith('std::vector') for t in types):
        includes.append('<vector>')
    includes.append('"preadaptive_mrac/core/schema/param_spec.hpp"')
    if any(t.startswith('Eigen::') for t in types):
        includes.append('"preadaptive_mrac/core/types.hpp"')
    for r in table['params']:
        if 'enum_header' in r and '"%s"' % r['enum_header'] not in includes:
            includes.append('"%s"' % r['enum_header'])
    for r in table['params']:
        if 'table' in r and any(
            'tunable' in s for s in params_table.load_own(r['table'])['params']
        ):
            includes.append('"preadaptive_mrac/params/%s_params.hpp"' % r['table'])
    tunables = tunables_text(component)
    return (
        '#pragma once\n'
        '/// \\file %s_params.hpp\n'
        '/// \\brief Generated from params/%s.yaml by src/preadaptive_mrac/params_codegen.py\n'
        '/// (cmake/params.cmake, at build time): do not edit, edit the table.\n\n'
        '%s\n\nnamespace preadaptive_mrac {\n\n%s\n%s}  // namespace preadaptive_mrac\n'
        % (
            component,
            component,
            '\n'.join('#include %s' % i for i in includes),
            enum_text(table) + '\n'.join(struct_text(table, n, rows) for n, rows in structs(table)),
            tunables + ('\n' if tunables else ''),
        )
    )


def write_if_changed(path, text):
    """Only a changed header is rewritten: its dependants are not rebuilt for nothing."""
    if os.path.exists(path):
        with open(path) as f:
            if f.read() == text:
                return
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, 'w') as f:
        f.write(text)


def main(argv):
    if len(argv) < 2:
        sys.stderr.write('usage: params_codegen OUT_DIR [COMPONENT ...]  (default: every table)\n')
        return 2
    out_dir = argv[1]
    # (a table without a struct renders docs rows only)
    for component in argv[2:] or params_table.components():
        if not structs(params_table.load_own(component)):
            continue
        write_if_changed(
            os.path.join(out_dir, 'preadaptive_mrac', 'params', component + '_params.hpp'),
            header(component),
        )
    if not argv[2:]:  # every table: the modes' table too (its rows, the C++ mode registry's)
        write_if_changed(
            os.path.join(out_dir, 'preadaptive_mrac', 'params', 'modes_params.hpp'),
            modes.header_text(),
        )
    return 0


if __name__ == '__main__':
    sys.exit(main(sys.argv))
