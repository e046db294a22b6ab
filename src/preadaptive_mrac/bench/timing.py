"""Whole processes timed against each other, interleaved (A, B, A, B, ...), so that a change
of load on a shared machine hits both alike. Per run: wall time, the child's CPU time
(user + sys) and the `wall_time_s` of the last JSON line it printed (the in-process time)."""

import json
import resource
import statistics
import subprocess
import time


class CommandFailed(RuntimeError):
    """A timed command exited non-zero (its stderr in the message)."""


def median(xs):
    """The median, NaN for no values."""
    return statistics.median(xs) if xs else float('nan')


def last_json(text):
    """The last line of `text` that starts with '{', parsed; {} when there is none."""
    lines = [ln for ln in text.strip().splitlines() if ln.startswith('{')]
    return json.loads(lines[-1]) if lines else {}


def run_once(cmd):
    """Run `cmd` (a list) once: {'wall', 'cpu', 'inproc', 'json'} (seconds; inproc None when
    its output has no wall_time_s)."""
    ru0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    p = subprocess.run(
        cmd, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True
    )
    wall = time.perf_counter() - t0
    ru1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    if p.returncode != 0:
        raise CommandFailed('command failed (%d): %s\n%s' % (p.returncode, ' '.join(cmd), p.stderr))
    cpu = (ru1.ru_utime - ru0.ru_utime) + (ru1.ru_stime - ru0.ru_stime)
    out = last_json(p.stdout)
    return {'wall': wall, 'cpu': cpu, 'inproc': out.get('wall_time_s'), 'json': out}


KEYS = 'abcdefgh'


def timeloop(cmds, reps, log=None):
    """`reps` runs of each command of `cmds` (2 to 8 lists), interleaved (A, B, C, A, ...),
    after one untimed run of each (page cache, dynamic loader). Returns {'cmds', 'reps', 'a':
    [run, ...], 'b': [...], ...}, one key per command in order, each run as run_once() without
    its JSON; `log(line)` hears of every run."""
    if not 2 <= len(cmds) <= len(KEYS):
        raise ValueError('timeloop: 2 to %d commands, got %d' % (len(KEYS), len(cmds)))
    keys = KEYS[: len(cmds)]
    res = {'cmds': [list(c) for c in cmds], 'reps': reps}
    for key, cmd in zip(keys, cmds):
        res[key] = []
        run_once(cmd)
    for i in range(reps):
        for key, cmd in zip(keys, cmds):
            r = run_once(cmd)
            r.pop('json')
            res[key].append(r)
            if log:
                inproc = r['inproc']
                log(
                    '  %s run %d/%d: wall %.4f s, cpu %.4f s, in-process %s'
                    % (
                        key,
                        i + 1,
                        reps,
                        r['wall'],
                        r['cpu'],
                        '-' if inproc is None else '%.4f s' % inproc,
                    )
                )
    return res


def medians(res, key):
    """Medians of one command ('a', 'b', ...) of a timeloop() result: {'wall', 'cpu', 'inproc'}."""
    runs = res[key]
    return {
        k: median([r[k] for r in runs if r.get(k) is not None]) for k in ('wall', 'cpu', 'inproc')
    }
