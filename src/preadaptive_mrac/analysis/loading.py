"""Loading inputs: a bag or CSV file per path, unique labels."""

import os
from .bags import _is_bag, _load_bag
from .csv_runs import _load_csv
from .runs import InputError


def load_runs(path):
    """All runs in one file (a compare bag holds several). Raises InputError."""
    if not os.path.exists(path):
        raise InputError(path, 'no such file')
    if os.path.isdir(path):
        raise InputError(path, 'is a directory, not a bag or CSV file')
    size = os.path.getsize(path)
    if size == 0:
        raise InputError(path, 'empty file (0 bytes): nothing was recorded')
    if _is_bag(path):
        return _load_bag(path)
    if path.endswith('.bag') or path.endswith('.bag.active'):
        raise InputError(path, 'not a ROS bag (no "#ROSBAG V2.0" header)')
    return [_load_csv(path)]


def load_inputs(paths, labels=None):
    """Runs of every input, labels made unique (or set from `labels`)."""
    runs = []
    for p in paths:
        runs.extend(load_runs(p))
    if labels:
        if len(labels) != len(runs):
            raise InputError(
                paths[0] if len(paths) == 1 else ', '.join(paths),
                '%d label(s) given for %d run(s) (%s)'
                % (len(labels), len(runs), ', '.join(r.describe() for r in runs)),
            )
        for r, lab in zip(runs, labels):
            r.label = lab
    seen = {}
    for r in runs:
        if r.label in seen:
            seen[r.label] += 1
            r.label = '%s_%d' % (r.label, seen[r.label])
        else:
            seen[r.label] = 1
    return runs
