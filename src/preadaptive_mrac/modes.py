"""The modes, from their one table params/modes.yaml (no hand-kept mode lists).

The C++ registry (src/core/controller/mode_registry.cpp) is built from the same rows through the
header of `header_text()` (preadaptive_mrac/params/modes_params.hpp, written by params_codegen with
every table, as cmake/params.cmake and scripts/fuzz run it), so
`preadapt_sim --list-modes`, the CLI, the nodes and this package name the same modes in the
same order."""

import os

import yaml

from .paths import package_root

FIELDS = ('name', 'law', 'strategy', 'paper', 'truth', 'label', 'colour', 'doc')


def table_path():
    return os.path.join(package_root(), 'params', 'modes.yaml')


def load():
    """The rows of params/modes.yaml, in order, each checked to have every field."""
    with open(table_path()) as f:
        rows = yaml.safe_load(f)['modes']
    for r in rows:
        missing = [k for k in FIELDS if k not in r]
        if missing:
            raise ValueError('%s: mode %r lacks %s' % (table_path(), r.get('name'), missing))
    return rows


ROWS = load()
#: every mode, in the order of the docs and of preadapt_family's default --modes
MODES = tuple(r['name'] for r in ROWS)
#: the paper's modes (the reproduction: docs/research/reproduction.md)
PAPER_MODES = tuple(r['name'] for r in ROWS if r['paper'])
#: the paper's modes that preadapt (all but its baseline, plain MRAC)
PA_MODES = tuple(r['name'] for r in ROWS if r['paper'] and r['strategy'] != 'paper_rac')
#: the modes that read the simulation's true theta (plant/truth)
TRUTH_MODES = tuple(r['name'] for r in ROWS if r['truth'])
MODE_TEXT = {r['name']: r['label'] for r in ROWS}
MODE_COLOUR = {r['name']: r['colour'] for r in ROWS}


def guess_mode(name):
    """The one mode named in a file name (scenario1_pa_learn.csv -> pa_learn), or None when
    none or more than one is named. A name counts where it stands between separators (not
    letters or digits); a longer name wins over one it contains (pa_learn_exact over
    pa_learn and pa)."""
    s = os.path.splitext(os.path.basename(name))[0].lower().replace('-', '_')
    found = set()
    for m in sorted(MODES, key=len, reverse=True):
        i = s.find(m)
        while i >= 0:
            end = i + len(m)
            before = s[i - 1] if i > 0 else '_'
            after = s[end] if end < len(s) else '_'
            if not before.isalnum() and not after.isalnum():
                found.add(m)
                s = s[:i] + '#' * len(m) + s[end:]  # a shorter name inside it is not another
            i = s.find(m, i + 1)
    return found.pop() if len(found) == 1 else None


def cpp_string(s):
    return '"' + s.replace('\\', '\\\\').replace('"', '\\"') + '"'


def header_text():
    rows = ',\n'.join(
        '    {%s, %s, %s, %s, %s}'
        % (
            cpp_string(r['name']),
            cpp_string(r['doc']),
            cpp_string(r['law']),
            cpp_string(r['strategy']),
            'true' if r['truth'] else 'false',
        )
        for r in ROWS
    )
    return (
        '// Generated from params/modes.yaml by src/preadaptive_mrac/modes.py: do not edit.\n'
        '#pragma once\n\n'
        'namespace preadaptive_mrac {\n'
        'namespace params {\n\n'
        '/// \\brief One row of params/modes.yaml: a mode is an adaptive law and a preadaptation\n'
        '/// strategy, by the names they are registered under (core/control/part_registry.hpp).\n'
        'struct ModeRow {\n'
        '  const char* name;      ///< what `controller.mode` and --mode take\n'
        '  const char* doc;       ///< one line: what the mode does\n'
        '  const char* law;       ///< the registered name of its adaptive law\n'
        '  const char* strategy;  ///< the registered name of its preadaptation strategy\n'
        '  bool truth;            ///< reads the simulation\'s true theta (plant/truth)\n'
        '};\n\n'
        '/// \\brief Every mode, in the table\'s order.\n'
        'inline constexpr ModeRow kModeRows[] = {\n' + rows + '};\n\n'
        '}  // namespace params\n'
        '}  // namespace preadaptive_mrac\n'
    )
