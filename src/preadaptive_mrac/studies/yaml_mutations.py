"""The mutations of config_mutation_study: every leaf key of the shipped YAML files broken
(dropped, wrong type, NaN, wrong size), which ones must still run, the seeded sample. No ROS."""

import copy
import os
import random
import re

import yaml

from .. import params_table
from ..paths import package_root


ROOT = package_root()


FILES = {
    'controller': 'config/controller/default.yaml',
    'plant': 'config/plant/b747.yaml',
    'scenario': 'config/scenarios/scenario1.yaml',
}
# Which node reads which file (and so names its keys in a refusal).
NODES = {
    'controller': ['mrac_controller'],
    'plant': ['plant_sim', 'mrac_controller'],
    'scenario': ['plant_sim'],
}
KINDS = ('drop', 'type', 'nan', 'size')

ALL = KINDS
# Mutations after which the launch runs normally, each with its reason: (file, key regex on the
# dotted path, kinds). Everything not listed here must be refused.
EXPECT_RUNS = [
    ('plant', r'plant\.description', ALL, 'documentation only: never read'),
    (
        'plant',
        r'plant\.operating_point\.(h|m|Iy)',
        ALL,
        'documentation only (where A and B come from): never read',
    ),
    (
        'plant',
        r'plant\.operating_point\.U',
        ('drop',),
        'runs while plant.turbulence is off (the Dryden filter\'s airspeed V); not in the '
        '"filled with defaults" line (a run without the key reports what it did before)',
    ),
    (
        'plant',
        r'plant\.actuator\.(delay|time_constant)',
        ('drop',),
        'runs with 0 (the paper\'s instant elevator); not in the "filled with defaults" line '
        '(a run without the key reports byte for byte what it did before the key)',
    ),
    (
        'scenario',
        r'scenario\.description',
        ('drop', 'type'),
        'optional (default ""); the type mutation of a string is an integer, which a string key '
        'takes as its text (a name may look like a number: aircraft 737)',
    ),
    (
        'scenario',
        r'scenario\.name',
        ('type',),
        'the type mutation of a string is an integer, which a string key takes as its text',
    ),
    (
        'controller',
        r'controller\.mode',
        ALL,
        'overridden by scenario.launch (<param controller/mode> from arg mode)',
    ),
    (
        'controller',
        r'controller\.sample_time',
        ALL,
        'overridden by scenario.launch (<param controller/sample_time> from arg dt)',
    ),
] + [  # the controller's optional keys: from its table (params/controller.yaml)
    ('controller', re.escape(key), ('drop',), 'optional (params/controller.yaml)')
    for key in params_table.optional_keys('controller')
]


def expected_runs(file_id, key, kind):
    for f, rx, kinds, why in EXPECT_RUNS:
        if f == file_id and kind in kinds and re.fullmatch(rx, key):
            return why
    return None


def named_key(file_id, key, kind):
    """The dotted key a refusal must name. Dropping the `scale` (or `theta`) of a theta
    segment leaves a segment with neither alternative: the problem names the segment."""
    if kind == 'drop' and re.fullmatch(r'scenario\.theta\.\d+\.(scale|theta)', key):
        return key.rsplit('.', 1)[0]
    return key


# ---------------------------------------------------------------- leaves and mutations
def is_scalar(v):
    return not isinstance(v, (dict, list))


def shape(v):
    """'scalar', 'vector' (list of scalars), 'matrix' (list of lists of scalars) or None."""
    if is_scalar(v):
        return 'scalar'
    if isinstance(v, list) and v and all(is_scalar(x) for x in v):
        return 'vector'
    if (
        isinstance(v, list)
        and v
        and all(isinstance(r, list) and r and all(is_scalar(x) for x in r) for r in v)
    ):
        return 'matrix'
    return None


def leaves(node, path=()):
    """(path, value, shape) of every leaf: scalars, vectors and matrices; maps and lists of
    maps (scenario segments) are walked into."""
    if isinstance(node, dict):
        for k, v in node.items():
            yield from leaves(v, path + (k,))
        return
    s = shape(node)
    if s is not None:
        yield path, node, s
        return
    if isinstance(node, list):
        for i, v in enumerate(node):
            yield from leaves(v, path + (i,))


def dotted(path):
    return '.'.join(str(p) for p in path)


def mutations():
    """Every (file_id, path, kind) that applies, in a fixed order."""
    out = []
    for file_id, rel in FILES.items():
        with open(os.path.join(ROOT, rel)) as f:
            doc = yaml.safe_load(f)
        for path, value, s in leaves(doc):
            for kind in KINDS:
                if kind == 'size' and s not in ('vector', 'matrix'):
                    continue
                out.append((file_id, path, kind, s))
    return out


def mutate(doc, path, kind, s):
    doc = copy.deepcopy(doc)
    parent = doc
    for p in path[:-1]:
        parent = parent[p]
    last = path[-1]
    value = parent[last]
    if kind == 'drop':
        del parent[last]
    elif kind == 'type':
        parent[last] = 12345 if isinstance(value, str) else 'not_a_number'
    elif kind == 'nan':
        if s == 'vector':
            value[0] = float('nan')
        elif s == 'matrix':
            value[0][0] = float('nan')
        else:
            parent[last] = float('nan')
    elif kind == 'size':
        value.pop()
    return doc


def pick(all_muts, n, seed):
    """A seeded subset of n: first one mutation per (file, kind) and two that must run, then
    random ones."""
    rng = random.Random(seed)
    chosen = []
    strata = {}
    for m in all_muts:
        strata.setdefault((m[0], m[2]), []).append(m)
    for k in sorted(strata):
        chosen.append(rng.choice(strata[k]))
    runs = [m for m in all_muts if expected_runs(m[0], dotted(m[1]), m[2]) and m not in chosen]
    chosen += rng.sample(runs, min(2, len(runs)))
    seen = {(m[0], m[1], m[2]) for m in chosen}
    rest = [m for m in all_muts if (m[0], m[1], m[2]) not in seen]
    rng.shuffle(rest)
    chosen += rest[: max(0, n - len(chosen))]
    return chosen
