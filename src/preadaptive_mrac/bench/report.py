"""docs/performance.md from the results bench/run_bench.sh collects in one directory:
bench.json (Google Benchmark), timeloop.json and hyperfine.json (the CLI against the Python
prototype), callgrind.json (instructions per mode), meta.json (machine, load, commands) and,
when a baseline build was given, baseline.json and callgrind_base.json (the same CLI runs of
the baseline, interleaved with this build's)."""

import json
import os
import re

from preadaptive_mrac import modes
from preadaptive_mrac.bench import timing

MODES = list(modes.MODES)
# Controller::step aims per mode [ns]; modes without one are reported without a verdict.
AIM_STEP = {'rac': 1000.0, 'pa': 1000.0, 'pa_learn': 3000.0, 'pa_learn_exact': 3000.0}
AIM_SCENARIO3_MS = 20.0  # full scenario 3 per mode
AIM_PROTOTYPE_RATIO = 500.0  # the CLI against the numpy prototype, same work
SAMPLES_S3 = 140000

# The sections render() writes; any other '## ' section of an existing page is kept.
GENERATED = (
    'Controller::step per mode',
    'Full scenario 3 per mode',
    'Against the baseline build',
    'C++ CLI against the Python/numpy prototype',
    'Instructions per sample',
    'Commands',
)


def to_ns(v, unit):
    return v * {'ns': 1.0, 'us': 1e3, 'ms': 1e6, 's': 1e9}[unit]


def verdict(cpu, wall, aim, higher_is_better=False):
    """'met' when both figures meet the aim; the CPU time alone meeting it is reported as
    such (the wall time includes waiting for a core on a busy machine)."""
    ok = (lambda v: v >= aim) if higher_is_better else (lambda v: v < aim)
    if ok(cpu) and ok(wall):
        return 'met'
    if ok(cpu):
        return 'met on CPU time, **missed on wall time** (load)'
    return '**missed**'


def _load(d, name):
    path = os.path.join(d, name)
    if not os.path.exists(path):
        return None
    with open(path) as f:
        return json.load(f)


def load_results(d):
    """Every result file of directory `d` ({name without .json: data}; absent ones None)."""
    names = (
        'meta',
        'bench',
        'timeloop',
        'hyperfine',
        'callgrind',
        'baseline',
        'callgrind_base',
    )
    return {n: _load(d, n + '.json') for n in names}


def benchmark_medians(bench):
    """{benchmark name without /iterations:N: its median aggregate}; with a single repetition
    (no aggregates) the run itself."""
    med, single = {}, {}
    for b in (bench or {}).get('benchmarks', []):
        name = re.sub(r'/iterations:\d+', '', b.get('run_name', b.get('name', '')))
        if b.get('aggregate_name') == 'median':
            med[name] = b
        elif b.get('run_type', 'iteration') == 'iteration':
            single[name] = b
    return med or single


def _header(meta):
    return [
        '# Performance',
        '',
        'Measured by `bench/run_bench.sh` (see the end of this page for every command).',
        '',
        '- date: %s' % meta['date'],
        '- machine: %s, `nproc` = %s, %s' % (meta['cpu'], meta['nproc'], meta['kernel']),
        '- load average before / after the run: %s / %s'
        % (meta['load_before'], meta['load_after']),
        '- compiler: %s; build type %s (`%s`)'
        % (meta['compiler'], meta['build_type'], meta['cxx_flags']),
        '- source: commit %s%s' % (meta['commit'], meta['dirty']),
        '',
        '**The machine is shared and noisy** (2 cores, other builds and test runs going on '
        'at the same time). Every figure is the median of several repetitions from one run '
        'of the script; ratios are taken between medians of the same run. Wall time '
        'includes the time the process waited for a core, CPU time does not; where they '
        'differ a lot the machine was busy, and CPU time is the better measure of the code. '
        'The callgrind instruction counts do not depend on load.',
        '',
    ]


def _controller_step(meta, med):
    L = ['## Controller::step per mode (ns per step, median of %s repetitions)' % meta['reps']]
    L += [
        '',
        'Inputs replayed from a closed-loop run of scenario 3 (140 s, dt = 1 ms) in the '
        'same mode: `trajectory` = every step of the run, in order, %s whole passes per '
        'repetition (the onsets, recoveries, network updates and sensitivity-ODE phases of '
        "the run all happen inside the timed loop; the replay is checked to reproduce the "
        "closed loop's u bit for bit first); `in_phase` = only the steps of the longest "
        'adaptation phase (in learning modes each integrates S_dot = Pi S), the worst '
        'steady cost.' % meta['passes'],
        '',
        '| mode | region | wall [ns/step] | CPU [ns/step] | aim | verdict '
        '| onsets / learned per pass | steps in a phase |',
        '|---|---|---:|---:|---:|---|---|---:|',
    ]
    for region in ('trajectory', 'in_phase'):
        for m in MODES:
            b = med.get('ControllerStep/%s/%s' % (m, region))
            if not b:
                continue
            wall = to_ns(b['real_time'], b['time_unit'])
            cpu = to_ns(b['cpu_time'], b['time_unit'])
            aim = AIM_STEP.get(m)
            if region == 'trajectory':
                ev = '%d / %d' % (b.get('onsets/pass', 0), b.get('learned/pass', 0))
                ph = '%.1f %%' % b.get('in_phase_%', 0)
            else:
                ev = '-'
                ph = '%d (from t = %.3f s)' % (b.get('phase_steps', 0), b.get('phase_t0_s', 0))
            L.append(
                '| %s | %s | %.0f | %.0f | %s | %s | %s | %s |'
                % (
                    m,
                    region,
                    wall,
                    cpu,
                    '< %.0f' % aim if aim else '-',
                    verdict(cpu, wall, aim) if aim else 'no aim set',
                    ev,
                    ph,
                )
            )
    b = med.get('PlantStep/rk4')
    if b:
        L += [
            '',
            'For comparison, one RK4 step of the plant (`PlantStep/rk4`, what the closed '
            'loop adds per sample): wall %.0f ns, CPU %.0f ns.'
            % (to_ns(b['real_time'], b['time_unit']), to_ns(b['cpu_time'], b['time_unit'])),
        ]
    return L + ['']


def _scenario3(med):
    L = [
        '## Full scenario 3 per mode (140 s at dt = 1 ms, 140 000 samples, ClosedLoop::run)',
        '',
        '| mode | wall [ms/run] | CPU [ms/run] | CPU per sample [ns] | aim | verdict |',
        '|---|---:|---:|---:|---:|---|',
    ]
    for m in MODES:
        b = med.get('ClosedLoop/scenario3/%s' % m)
        if not b:
            continue
        wall = to_ns(b['real_time'], b['time_unit']) / 1e6
        cpu = to_ns(b['cpu_time'], b['time_unit']) / 1e6
        L.append(
            '| %s | %.1f | %.1f | %.0f | < %.0f | %s |'
            % (
                m,
                wall,
                cpu,
                b.get('per_step', float('nan')) * 1e9,
                AIM_SCENARIO3_MS,
                verdict(cpu, wall, AIM_SCENARIO3_MS),
            )
        )
    return L + ['']


def _ratio(before, after):
    return before / after if after else float('nan')


def _baseline(meta, baseline, cg_new, cg_base):
    """Before/after: this build's CLI against the baseline build's, interleaved per mode."""
    L = [
        '## Against the baseline build (scenario 3 through the CLI, interleaved, same run)',
        '',
        'Baseline: commit %s, built the same way (`%s`); `preadapt_sim --scenario 3 --mode '
        '<mode> --json` of both builds in turn (this, baseline, this, ...), %s runs each '
        'after one untimed run of each. `in-process` is the run\'s own `wall_time_s` '
        '(design and ClosedLoop::run, no start-up); process CPU includes start-up (YAML '
        'files, dynamic loader). `same bytes`: the JSON line (without `wall_time_s`) and the '
        'CSV of the mode from both builds, compared with `cmp`.'
        % (baseline.get('commit', '?'), baseline.get('build_dir', '?'), baseline.get('reps', '?')),
        '',
        '| mode | same bytes | in-process before [ms] | after [ms] | ratio '
        '| process CPU before [ms] | after [ms] | ratio '
        '| instructions per sample before | after | ratio |',
        '|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|',
    ]
    identical = baseline.get('identical', {})
    for m in MODES:
        res = baseline.get('modes', {}).get(m)
        if not res:
            continue
        new, base = timing.medians(res, 'a'), timing.medians(res, 'b')
        ir = ['-', '-', '-']
        if cg_new and cg_base and m in cg_new and m in cg_base:
            a, b = cg_new[m].get('total'), cg_base[m].get('total')
            if a and b:
                ir = ['%.0f' % (b / SAMPLES_S3), '%.0f' % (a / SAMPLES_S3), '%.2fx' % (b / a)]
        same = {True: 'yes', False: '**no**'}.get(identical.get(m), '-')
        L.append(
            '| %s | %s | %.1f | %.1f | %.2fx | %.1f | %.1f | %.2fx | %s |'
            % (
                m,
                same,
                1e3 * base['inproc'],
                1e3 * new['inproc'],
                _ratio(base['inproc'], new['inproc']),
                1e3 * base['cpu'],
                1e3 * new['cpu'],
                _ratio(base['cpu'], new['cpu']),
                ' | '.join(ir),
            )
        )
    L.append('')
    if baseline.get('load'):
        L += ['Load average before / after this part: %s.' % baseline['load'], '']
    return L


def _prototype(meta, tl, hf, base_commit=None):
    """This build's CLI against the prototype; a third command of the same hyperfine run and
    interleaved loop, when present, is the baseline build's CLI (rows marked so)."""
    L = [
        '## C++ CLI against the Python/numpy prototype (scenario 1, rac, same work)',
        '',
        '`bench/prototype_rac.py` runs the same equations, dt, integrators and per-sample '
        "order; its per-window peak |e| agrees with the CLI's to %s rad (IAE to %s rad s), "
        'events %s.'
        % (
            meta.get('xcheck_peak', '?'),
            meta.get('xcheck_iae', '?'),
            meta.get('xcheck_events', '?'),
        ),
        '',
        '| measure | CLI (median) | prototype (median) | ratio prototype / CLI | aim | verdict |',
        '|---|---:|---:|---:|---:|---|',
    ]
    rows = []
    builds = [('', 0, 'a')]
    if base_commit and (len((hf or {}).get('results', [])) > 2 or (tl and 'c' in tl)):
        builds.append(('baseline build (commit %s): ' % base_commit, 2, 'c'))
    for prefix, hf_index, tl_key in builds:
        if hf and len(hf['results']) > hf_index:
            c, p = hf['results'][hf_index], hf['results'][1]
            rows.append(
                (
                    '%sprocess wall time, hyperfine (%d / %d runs)'
                    % (prefix, len(c['times']), len(p['times'])),
                    c['median'],
                    p['median'],
                )
            )
        if tl and tl_key in tl:
            cli, py = timing.medians(tl, tl_key), timing.medians(tl, 'b')
            for key, label in (
                ('wall', 'process wall time, interleaved loop'),
                ('cpu', 'process CPU time (user + sys), interleaved loop'),
                ('inproc', 'in-process `wall_time_s` (design + run, no start-up/YAML)'),
            ):
                rows.append(
                    ('%s%s (%d runs each)' % (prefix, label, tl['reps']), cli[key], py[key])
                )
    for label, c, p in rows:
        ratio = _ratio(p, c)
        L.append(
            '| %s | %.4f s | %.3f s | %.0fx | >= %.0fx | %s |'
            % (
                label,
                c,
                p,
                ratio,
                AIM_PROTOTYPE_RATIO,
                'met' if ratio >= AIM_PROTOTYPE_RATIO else '**missed**',
            )
        )
    L += [
        '',
        'The process figures include start-up: for the CLI the dynamic loader, YAML files '
        'and design (a few ms), for the prototype the interpreter and the numpy/scipy/yaml '
        'imports (a few hundred ms); the in-process figure is the simulation alone.',
        '',
    ]
    return L


def _instructions(meta, cg):
    steps = meta.get('cg_steps', SAMPLES_S3)
    L = [
        '## Instructions per sample (callgrind, scenario 3 through the CLI; noise-free)',
        '',
        'Inclusive instruction counts divided by the %d samples of scenario 3.' % steps,
        '',
        '| mode | Controller::step | of which SensitivityTracker::accumulate | Plant::step '
        '| ClosedLoop::run | whole process |',
        '|---|---:|---:|---:|---:|---:|',
    ]
    for m in MODES:
        if m not in cg:
            continue
        g = cg[m]

        def f(k, g=g):
            return ('%.0f' % (g[k] / steps)) if k in g else '-'

        L.append(
            '| %s | %s | %s | %s | %s | %s |'
            % (
                m,
                f('controller_step'),
                f('sensitivity_accumulate'),
                f('plant_step'),
                f('closed_loop_run'),
                f('total'),
            )
        )
    L += [
        '',
        '(The sensitivity ODE runs only during phases, so its per-sample average is '
        'diluted by the quiet steps; see the `in_phase` rows above for its cost per '
        'in-phase step.)',
        '',
    ]
    g = cg.get('rac', {})
    if 'plant_step' in g and 'closed_loop_run' in g and 'controller_step' in g:

        def share(k):
            return 100.0 * g[k] / g['closed_loop_run']

        text = (
            "Where the time of a batch run goes (rac): the plant's RK4 step is %.0f %% of "
            "ClosedLoop::run's instructions, the controller %.0f %%, the rest (metrics, "
            'scenario look-up, copies of the step output) %.0f %%.'
            % (
                share('plant_step'),
                share('controller_step'),
                100.0 - share('plant_step') - share('controller_step'),
            )
        )
        if g.get('eigen_gemv'):
            text += (
                " %.0f %% of ClosedLoop::run's instructions are spent inside Eigen's "
                'general matrix-vector kernel (`general_matrix_vector_product`).'
                % share('eigen_gemv')
            )
        text += (
            ' Listings: `%s/callgrind.<mode>.txt` (inclusive), '
            '`callgrind_annotate %s/callgrind.rac.out` (exclusive).' % (meta['res'], meta['res'])
        )
        L += [text, '']
    return L


def render(results):
    """The page's generated part from load_results() output, as markdown text."""
    meta = results['meta']
    med = benchmark_medians(results.get('bench'))
    L = _header(meta)
    if med:
        L += _controller_step(meta, med)
        L += _scenario3(med)
    if results.get('baseline'):
        L += _baseline(
            meta, results['baseline'], results.get('callgrind'), results.get('callgrind_base')
        )
    if results.get('timeloop') or results.get('hyperfine'):
        base_commit = (results.get('baseline') or {}).get('commit')
        L += _prototype(meta, results.get('timeloop'), results.get('hyperfine'), base_commit)
    if results.get('callgrind'):
        L += _instructions(meta, results['callgrind'])
    L += [
        'Note: Debian\'s libbenchmark prints "Library was built as DEBUG"; that concerns '
        'the harness itself (its timer loop), not the code under test, which is built '
        'Release (`-O3 -DNDEBUG`).',
        '',
        '## Commands',
        '',
    ]
    for k, v in meta['commands']:
        L += ['- %s:' % k, '', '  ```', '  %s' % v, '  ```', '']
    return '\n'.join(L)


def sections(text):
    """The page split at its '## ' headings: [(heading or None for the top, text), ...]."""
    out = [(None, [])]
    for line in text.splitlines():
        if line.startswith('## '):
            out.append((line[3:].strip(), []))
        out[-1][1].append(line)
    return [(h, '\n'.join(lines)) for h, lines in out]


def kept_sections(old_text):
    """The sections of an existing page that render() does not write (written by hand, e.g.
    the ROS benchmark copied from docs/reference/ros.md): they are carried over unchanged."""
    kept = []
    for heading, body in sections(old_text):
        if heading is None or any(heading.startswith(g) for g in GENERATED):
            continue
        kept.append(body.rstrip('\n'))
    return kept


def prototype_crosscheck(text):
    """The 'vs_cli' object of bench/prototype_rac.py --cli-json output ({} when absent)."""
    x = {}
    for line in text.splitlines():
        if line.startswith('{'):
            x = json.loads(line).get('vs_cli', {})
    return x


def meta_from_env(env, results_dir, xcheck):
    """meta.json's content from run_bench.sh's META_* variables and the prototype's
    cross-check (prototype_crosscheck()). META_CMDS holds one 'label|command' per line."""
    return {
        'date': env['META_DATE'],
        'cpu': env['META_CPU'],
        'nproc': env['META_NPROC'],
        'kernel': env['META_KERNEL'],
        'load_before': env['META_LOAD_BEFORE'],
        'load_after': env['META_LOAD_AFTER'],
        'compiler': env['META_COMPILER'],
        'build_type': 'Release',
        'cxx_flags': env['META_FLAGS'],
        'commit': env['META_COMMIT'],
        'dirty': env['META_DIRTY'],
        'reps': env['META_REPS'],
        'passes': 3,
        'res': results_dir,
        'xcheck_peak': '%.2g' % xcheck['max_abs_diff_peak_abs_e'] if xcheck else '?',
        'xcheck_iae': '%.2g' % xcheck['max_abs_diff_iae'] if xcheck else '?',
        'xcheck_events': (
            ('identical' if xcheck.get('same_events') else 'DIFFERENT') if xcheck else '?'
        ),
        'commands': [ln.split('|', 1) for ln in env['META_CMDS'].splitlines() if ln],
    }


def write(results_dir, out_path):
    """Render the results into out_path, keeping its hand-written sections; returns the text."""
    text = render(load_results(results_dir)).rstrip('\n') + '\n'
    if os.path.exists(out_path):
        with open(out_path) as f:
            kept = kept_sections(f.read())
        if kept:
            text += '\n' + '\n\n'.join(kept) + '\n'
    with open(out_path, 'w') as f:
        f.write(text)
    return text
