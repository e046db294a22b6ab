#!/usr/bin/python3
"""Helpers of bench/run_bench.sh; the code is preadaptive_mrac.bench (timing, callgrind, report).

    perf_report.py timeloop --reps N --out FILE -- CMD_A... ::: CMD_B... [::: CMD_C...]
        Runs the commands N times each, interleaved (A, B, C, A, ...), after one untimed run
        of each, so that a change of load on the shared machine hits them alike. Records per
        run: process wall time, the child's CPU time (user + sys), and the in-process
        wall_time_s of its JSON line.
    perf_report.py callgrind --out FILE --mode M --ir-file F [--excl-file F]
        Adds mode M's inclusive instruction counts (and those inside Eigen's GEMV kernel, from
        the exclusive listing) to the JSON file FILE.
    perf_report.py baseline --out FILE --commit C --build-dir D --reps N --load L
                            --identical rac=1,pa=0,... -- TIMELOOP_FILES...
        Collects the per-mode timeloop files against a baseline build (named
        timeloop_base.<mode>.json) and whether both builds' outputs were the same bytes.
    perf_report.py meta --results DIR
        Writes DIR/meta.json from run_bench.sh's META_* variables and DIR/prototype_xcheck.txt.
    perf_report.py report --results DIR --out docs/performance.md
        Writes the page from DIR/{bench, timeloop, hyperfine, callgrind, meta, baseline,
        callgrind_base}.json, keeping the page's sections it does not generate.
"""

import json
import os
import re
import sys

try:
    from preadaptive_mrac.bench import callgrind, report, timing
except ImportError:  # a source tree whose devel space is not sourced
    sys.path.insert(
        0, os.path.join(os.path.dirname(os.path.dirname(os.path.realpath(__file__))), 'src')
    )
    sys.modules.pop('preadaptive_mrac', None)
    from preadaptive_mrac.bench import callgrind, report, timing


def options(argv):
    """--key value pairs as a dict (keys without the dashes)."""
    if len(argv) % 2:
        sys.exit('perf_report: expected --key value pairs, got %s' % ' '.join(argv))
    return {k.lstrip('-'): v for k, v in zip(argv[::2], argv[1::2])}


def cmd_timeloop(argv):
    if '--' not in argv or ':::' not in argv:
        sys.exit('usage: perf_report.py timeloop --reps N --out FILE -- CMD_A... ::: CMD_B...')
    i = argv.index('--')
    opts, rest = options(argv[:i]), argv[i + 1 :]
    cmds = [[]]
    for word in rest:
        if word == ':::':
            cmds.append([])
        else:
            cmds[-1].append(word)
    try:
        res = timing.timeloop(cmds, int(opts.get('reps', 5)), log=lambda s: print(s, flush=True))
    except timing.CommandFailed as e:
        sys.exit(str(e))
    with open(opts['out'], 'w') as f:
        json.dump(res, f, indent=1)


def cmd_callgrind(argv):
    opts = options(argv)
    with open(opts['ir-file']) as f:
        listing = f.read()
    excl = None
    if 'excl-file' in opts:
        with open(opts['excl-file']) as f:
            excl = f.read()
    callgrind.record(opts['out'], opts['mode'], listing, excl)


def cmd_baseline(argv):
    if '--' not in argv:
        sys.exit(
            'usage: perf_report.py baseline --out F --commit C --build-dir D --reps N '
            '--load L --identical MODES -- TIMELOOP_FILES...'
        )
    i = argv.index('--')
    opts, files = options(argv[:i]), argv[i + 1 :]
    modes = {}
    for path in files:
        m = re.search(r'timeloop_base\.(\w+)\.json$', path)
        if m:
            with open(path) as f:
                modes[m.group(1)] = json.load(f)
    identical = {}
    for item in filter(None, opts.get('identical', '').split(',')):
        mode, same = item.split('=')
        identical[mode] = same == '1'
    out = {
        'commit': opts['commit'],
        'build_dir': opts['build-dir'],
        'reps': int(opts['reps']),
        'load': opts['load'],
        'identical': identical,
        'modes': modes,
    }
    with open(opts['out'], 'w') as f:
        json.dump(out, f, indent=1)


def cmd_meta(argv):
    opts = options(argv)
    d = opts['results']
    xcheck = {}
    path = os.path.join(d, 'prototype_xcheck.txt')
    if os.path.exists(path):
        with open(path) as f:
            xcheck = report.prototype_crosscheck(f.read())
    with open(os.path.join(d, 'meta.json'), 'w') as f:
        json.dump(report.meta_from_env(os.environ, d, xcheck), f, indent=1)


def cmd_report(argv):
    opts = options(argv)
    print(report.write(opts['results'], opts['out']))


def main():
    if len(sys.argv) < 2 or sys.argv[1] not in COMMANDS:
        sys.exit(__doc__)
    COMMANDS[sys.argv[1]](sys.argv[2:])


COMMANDS = {
    'timeloop': cmd_timeloop,
    'callgrind': cmd_callgrind,
    'baseline': cmd_baseline,
    'meta': cmd_meta,
    'report': cmd_report,
}

if __name__ == '__main__':
    main()
