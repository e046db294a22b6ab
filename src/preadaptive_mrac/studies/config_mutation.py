"""Config mutation study (scripts/config_mutation_study): each mutation of yaml_mutations
launched through scenario.launch or compare.launch (scripts/lib/launch_checked): a refused
key must end the launch within the limit, named; a dropped optional key must run and be
named in the node's "optional keys filled with defaults" line."""

import argparse
import os
import re
import shutil
import socket
import statistics
import subprocess
import sys
import tempfile
import time

import yaml

from ..paths import package_root
from .yaml_mutations import FILES, NODES, dotted, expected_runs, mutate, mutations, named_key, pick


ROOT = package_root()
WRAPPER = os.path.join(ROOT, 'scripts', 'lib', 'launch_checked')


# ---------------------------------------------------------------- running
def free_port():
    s = socket.socket()
    s.bind(('127.0.0.1', 0))
    port = s.getsockname()[1]
    s.close()
    return port


def run_one(args, work, i, file_id, path, kind, s, clock, launch):
    key = dotted(path)
    d = os.path.join(work, '%03d' % i)
    os.makedirs(d, exist_ok=True)
    files = {f: os.path.join(ROOT, rel) for f, rel in FILES.items()}
    with open(files[file_id]) as f:
        doc = yaml.safe_load(f)
    mutated = os.path.join(d, os.path.basename(FILES[file_id]))
    with open(mutated, 'w') as f:
        yaml.safe_dump(mutate(doc, path, kind, s), f, default_flow_style=None, sort_keys=False)
    files[file_id] = mutated
    port = free_port()
    env = dict(os.environ)
    env['ROS_MASTER_URI'] = 'http://127.0.0.1:%d' % port
    env['ROS_HOME'] = os.path.join(d, 'ros_home')
    env.pop('ROS_LOG_DIR', None)
    log = os.path.join(d, 'roslaunch.log')
    cmd = [WRAPPER, '--log', log, '--quiet', '--timeout', str(args.timeout)]
    if launch == 'compare':
        reports = [os.path.join(d, 'rac_plant.json'), os.path.join(d, 'pa_plant.json')]
        largs = ['compare.launch', 'record:=false', 'report_dir:=' + d]
    else:
        reports = [os.path.join(d, 'plant.json')]
        largs = ['scenario.launch', 'latency_report:=' + reports[0]]
    for r in reports:
        cmd += ['--expect-report', r]
    cmd += (
        ['--', '-p', str(port), 'preadaptive_mrac']
        + largs
        + [
            'plant_config:=' + files['plant'],
            'controller_config:=' + files['controller'],
            'scenario:=' + files['scenario'],
            'clock:=' + clock,
            'dt:=%g' % args.dt,
            'output:=screen',
        ]
    )
    t0 = time.monotonic()
    p = subprocess.run(
        cmd, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, universal_newlines=True
    )
    elapsed = time.monotonic() - t0
    runs_why = expected_runs(file_id, key, kind)
    want = named_key(file_id, key, kind)
    names = [
        r'/%s/%s(?=[:\[\s]|$)' % (n, re.escape(want.replace('.', '/'))) for n in NODES[file_id]
    ]
    named = any(re.search(rx, p.stderr, re.M) for rx in names)
    if runs_why is None:
        ok = p.returncode == 2 and elapsed <= args.limit and named
        why = []
        if p.returncode != 2:
            why.append('wrapper exit %d, expected 2' % p.returncode)
        if elapsed > args.limit:
            why.append('took %.1f s > %g s' % (elapsed, args.limit))
        if not named:
            why.append('key %s not named on stderr' % want)
    else:
        ok = p.returncode == 0
        why = (
            [] if ok else ['expected a normal run (%s), wrapper exit %d' % (runs_why, p.returncode)]
        )
        if kind == 'drop' and runs_why.startswith('optional'):
            # No silent default: the node's start-up line names the key it filled in.
            named = defaults_line_names(log, names)
            if not named:
                ok = False
                why.append('key %s not in an "optional keys filled with defaults" line' % want)
    return {
        'i': i,
        'file': file_id,
        'key': key,
        'kind': kind,
        'clock': clock,
        'launch': launch,
        'expect': 'runs' if runs_why else 'refused',
        'reason': runs_why or '',
        'rc': p.returncode,
        'time': elapsed,
        'named': named,
        'ok': ok,
        'why': '; '.join(why),
        'stderr': p.stderr,
        'dir': d,
    }


def defaults_line_names(log_path, key_patterns):
    """Whether a node's "optional keys filled with defaults: ..." start-up line in the launch
    log names one of the keys (resolved names, as regular expressions)."""
    try:
        with open(log_path, errors='replace') as f:
            lines = [ln for ln in f if 'optional keys filled with defaults: ' in ln]
    except OSError:
        return False
    return any(
        re.search(rx, ln.split('optional keys filled with defaults: ', 1)[1])
        for ln in lines
        for rx in key_patterns
    )


def main(description=None, argv=None):
    """scripts/config_mutation_study: parse the options and run."""
    ap = argparse.ArgumentParser(
        description=description, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    ap.add_argument(
        '--sample', type=int, default=0, help='run a seeded subset of this size (0 = all)'
    )
    ap.add_argument('--seed', type=int, default=1)
    ap.add_argument(
        '--only',
        action='append',
        default=[],
        help='FILEKEY:KIND, e.g. controller.lqr.R:type (repeatable)',
    )
    ap.add_argument(
        '--clock',
        default='lockstep',
        choices=('lockstep', 'realtime', 'mixed'),
        help='mixed: every other mutation in realtime',
    )
    ap.add_argument('--launch', default='scenario', choices=('scenario', 'compare'))
    ap.add_argument('--dt', type=float, default=0.01)
    ap.add_argument(
        '--timeout',
        type=float,
        default=60.0,
        help='stop a launch after this long [s] (the wrapper then exits 124)',
    )
    ap.add_argument(
        '--limit',
        type=float,
        default=30.0,
        help='a refused key must end the launch within this long [s]',
    )
    ap.add_argument('--check', action='store_true', help='exit 1 unless every mutation behaves')
    ap.add_argument('--list', action='store_true', help='print the mutations and exit')
    ap.add_argument('--keep', help='keep the mutated files and logs in this directory')
    ap.add_argument('--setup', help='devel/setup.bash to source (default: the environment)')
    args = ap.parse_args(argv)

    if args.setup:
        out = subprocess.run(
            ['bash', '-c', 'set +u; source "$1" >/dev/null && env -0', '-', args.setup],
            stdout=subprocess.PIPE,
            check=True,
        ).stdout
        os.environ.update(dict(kv.split('=', 1) for kv in out.decode().split('\0') if '=' in kv))
    all_muts = mutations()
    if args.only:
        want = set(args.only)
        muts = [m for m in all_muts if '%s:%s' % (dotted(m[1]), m[2]) in want]
        missing = want - {'%s:%s' % (dotted(m[1]), m[2]) for m in muts}
        if missing:
            sys.exit('config_mutation_study: no such mutation: ' + ', '.join(sorted(missing)))
    elif args.sample:
        muts = pick(all_muts, args.sample, args.seed)
    else:
        muts = all_muts
    if args.list:
        for m in muts:
            why = expected_runs(m[0], dotted(m[1]), m[2])
            print(
                '%-10s %-45s %-5s %s'
                % (m[0], dotted(m[1]), m[2], 'runs: ' + why if why else 'refused')
            )
        print('%d mutations' % len(muts))
        return 0
    if shutil.which('roslaunch') is None:
        sys.exit('config_mutation_study: roslaunch not found: source devel/setup.bash or --setup')

    work = args.keep or tempfile.mkdtemp(prefix='pmrac_mutations_')
    os.makedirs(work, exist_ok=True)
    print(
        'config_mutation_study: %d mutation(s) of %d, %s.launch, clock %s, dt %g s; work dir %s'
        % (len(muts), len(all_muts), args.launch, args.clock, args.dt, work),
        flush=True,
    )
    results = []
    for i, (file_id, path, kind, s) in enumerate(muts):
        clock = args.clock if args.clock != 'mixed' else ('lockstep', 'realtime')[i % 2]
        r = run_one(args, work, i, file_id, path, kind, s, clock, args.launch)
        results.append(r)
        print(
            '  %3d %-10s %-42s %-4s %-8s expect %-7s exit %3d  %5.1f s  %s%s'
            % (
                i,
                r['file'],
                r['key'],
                r['kind'],
                r['clock'],
                r['expect'],
                r['rc'],
                r['time'],
                'ok' if r['ok'] else 'FAIL',
                (': ' + r['why']) if r['why'] else '',
            ),
            flush=True,
        )
        if not r['ok']:
            for line in r['stderr'].splitlines()[-12:]:
                print('        | ' + line)

    print()
    print(
        '| file | key | mutation | clock | expected | wrapper exit | ended after [s] | key named '
        '| result |'
    )
    print('|---|---|---|---|---|---:|---:|---|---|')
    for r in results:
        print(
            '| %s | `%s` | %s | %s | %s | %d | %.1f | %s | %s |'
            % (
                r['file'],
                r['key'],
                r['kind'],
                r['clock'],
                'runs (%s)' % r['reason'] if r['reason'] else 'refused',
                r['rc'],
                r['time'],
                'yes' if r['named'] else ('-' if r['reason'] else 'NO'),
                'ok' if r['ok'] else 'FAIL: ' + r['why'],
            )
        )
    print()
    refused = [r for r in results if r['expect'] == 'refused']
    ran = [r for r in results if r['expect'] == 'runs']
    bad = [r for r in results if not r['ok']]
    by = {}
    for r in results:
        b = by.setdefault((r['file'], r['kind']), [0, 0])
        b[0] += 1
        b[1] += 1 if r['ok'] else 0
    print(
        'Summary: %d mutation(s): %d expected refused, %d expected to run normally; '
        '%d behaved as expected, %d did not.'
        % (len(results), len(refused), len(ran), len(results) - len(bad), len(bad))
    )
    if refused:
        times = [r['time'] for r in refused]
        print(
            'Refused launches ended after %.1f s median, %.1f s max (limit %g s); '
            'key named in %d of %d.'
            % (
                statistics.median(times),
                max(times),
                args.limit,
                sum(1 for r in refused if r['named']),
                len(refused),
            )
        )
    if ran:
        print(
            'Normal runs took %.1f s median, %.1f s max.'
            % (statistics.median(r['time'] for r in ran), max(r['time'] for r in ran))
        )
    print(
        'Per file and mutation (as expected / run): '
        + ', '.join('%s %s %d/%d' % (f, k, v[1], v[0]) for (f, k), v in sorted(by.items()))
    )
    if not args.keep and not bad:
        shutil.rmtree(work, ignore_errors=True)
    elif bad:
        print('logs of the unexpected ones: ' + ', '.join(r['dir'] for r in bad))
    if args.check and bad:
        return 1
    return 0
