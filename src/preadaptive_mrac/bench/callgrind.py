"""Instruction counts from callgrind_annotate listings (inclusive and exclusive)."""

import json
import os
import re

# The functions whose inclusive count the report shows, by a pattern of their listing line.
PATTERNS = {
    'total': r'PROGRAM TOTALS',
    'closed_loop_run': r'ClosedLoop::run\(',
    'controller_step': r'Controller::step\(',
    'plant_step': r'Plant::step\(',
    'sensitivity_accumulate': r'SensitivityTracker::accumulate\(',
}

_COUNT = re.compile(r'\s*([\d,]+)\s')


def _count(line):
    m = _COUNT.match(line)
    return int(m.group(1).replace(',', '')) if m else None


def inclusive_counts(listing):
    """{key: instructions} of PATTERNS from an inclusive listing (the first line that matches
    each pattern; keys without a match are left out)."""
    found = {}
    for line in listing.splitlines():
        n = _count(line)
        if n is None:
            continue
        for k, p in PATTERNS.items():
            if k not in found and re.search(p, line):
                found[k] = n
    return found


def gemv_instructions(exclusive_listing):
    """Instructions spent inside Eigen's general matrix-vector kernel (exclusive listing)."""
    total = 0
    for line in exclusive_listing.splitlines():
        n = _count(line)
        if n is not None and 'general_matrix_vector_product' in line:
            total += n
    return total


def record(out_path, mode, listing, exclusive_listing=None):
    """Add one mode's counts to the JSON file `out_path` ({mode: counts}, created if absent)."""
    found = inclusive_counts(listing)
    if exclusive_listing is not None:
        found['eigen_gemv'] = gemv_instructions(exclusive_listing)
    data = {}
    if os.path.exists(out_path):
        with open(out_path) as f:
            data = json.load(f)
    data[mode] = found
    with open(out_path, 'w') as f:
        json.dump(data, f, indent=1)
    return found
