"""Settings, grids and small helpers of the reproduction study (no simulations here)."""

import subprocess
import sys

import numpy as np


from ..modes import PA_MODES, PAPER_MODES  # noqa: E402, F401 (PA_MODES: for the chapters)
from ..paths import package_root  # noqa: E402

ROOT = package_root()


SECTIONS = (
    'headline',
    'detection',
    'peaks',
    'seeds',
    'heatmaps',
    'gradient',
    'responses',
    'network',
)

MODES = PAPER_MODES  # the paper's four, the reproduction's subject
MODE_COLOR = {
    'rac': 'tab:blue',
    'pa': 'tab:orange',
    'pa_learn': 'tab:red',
    'pa_learn_exact': 'tab:purple',
}
SCENARIOS = (1, 2, 3)

K_CE = 'controller.attention.c_e'
K_CED = 'controller.attention.c_ed'
K_TAU = 'controller.velocity_estimator.tau'
K_GPA = 'controller.preadaptation.gamma_pa'
K_SCALE = 'controller.preadaptation.init_scale'

# The two threshold settings the report compares. "paper" is config/controller/default.yaml
# unchanged (the paper's values); "alt" lowers c_ed only. Why 0.015: the detection section
# measures the band of c_ed in which regular adaptive control detects every switch of all three
# scenarios (at c_e = 0.005), and 0.015 lies inside it with margin on both sides; the script
# checks that and says so in the report if it stops being true.
ALT_CED = '0.015'
SETTINGS = {'paper': {}, 'alt': {K_CED: ALT_CED}}
SETTING_TEXT = {
    'paper': 'paper (c_e = 0.005, c_ed = 0.02)',
    'alt': 'all-detect (c_e = 0.005, c_ed = %s)' % ALT_CED,
}

# Grids (strings exactly as passed to the tools).
CED_BAND = ['0.005', '0.0075', '0.01', '0.0125', '0.015', '0.0175', '0.019', '0.02', '0.025']
TAU_LIST = ['0', '0.001', '0.01', '0.03', '0.1', '0.3']
HEAT_CE = ['0.0025', '0.00375', '0.005', '0.0075', '0.01', '0.0125']
HEAT_CED = ['0.005', '0.01', '0.015', '0.0175', '0.02', '0.025']
HEAT_GPA = ['0.3', '1', '3', '10', '30', '100']
HEAT_SCALE = ['0', '0.25', '0.5', '1', '2', '4']

GRIDS = {
    'CED_BAND': CED_BAND,
    'TAU_LIST': TAU_LIST,
    'HEAT_CE': HEAT_CE,
    'HEAT_CED': HEAT_CED,
    'HEAT_GPA': HEAT_GPA,
    'HEAT_SCALE': HEAT_SCALE,
}

SPREAD_ROWS = (44.0, 53.0)  # time range of the every-seed figure [s]

QUICK = {
    'CED_BAND': ['0.01', '0.015', '0.02'],
    'TAU_LIST': ['0', '0.01', '0.1'],
    'HEAT_CE': ['0.0025', '0.005', '0.01'],
    'HEAT_CED': ['0.01', '0.015', '0.02'],
    'HEAT_GPA': ['1', '10', '100'],
    'HEAT_SCALE': ['0', '1', '4'],
}


def fmt_pct(v, signed=True):
    if v is None or not np.isfinite(v):
        return 'n/a'
    return ('%+.0f%%' if signed else '%.0f%%') % v


def mrad(v):
    return 'n/a' if v is None or not np.isfinite(v) else '%.2f' % (1e3 * v)


def quart(a):
    a = np.asarray(a, dtype=float)
    return np.percentile(a, 25), np.median(a), np.percentile(a, 75)


def reduction(peak, peak_rac):
    """Peak reduction against rac in % (positive = lower peak than rac)."""
    return 100.0 * (1.0 - peak / peak_rac)


def md_table(header, rows, align=None):
    align = align or ['---'] + ['---:'] * (len(header) - 1)
    out = [
        '| ' + ' | '.join(h.replace('|', '\\|') for h in header) + ' |',
        '|' + '|'.join(align) + '|',
    ]
    for r in rows:
        out.append('| ' + ' | '.join(str(c).replace('|', '\\|') for c in r) + ' |')
    return '\n'.join(out) + '\n'


def cscale(run, w):
    """The scale c of theta = c * ones in window w."""
    return run['windows'][w]['theta'][0]


def switch_label(run, w):
    return 't = %g s (%g → %g)' % (run['windows'][w]['t_start'], cscale(run, w - 1), cscale(run, w))


def n_switch(run):
    return len(run['windows']) - 1


def events(run, kind):
    return [e for e in run['events'] if e['type'] == kind]


def first_onset(run, w):
    """First onset event in window w, i.e. t in (t_start, t_end]."""
    win = run['windows'][w]
    for e in events(run, 'onset'):
        if win['t_start'] < e['t'] <= win['t_end']:
            return e
    return None


def recovery_after(run, t):
    for e in events(run, 'recovered'):
        if e['t'] > t:
            return e
    return None


def ignored_in(run, w):
    win = run['windows'][w]
    return [e for e in events(run, 'ignored_onset') if win['t_start'] < e['t'] <= win['t_end']]


DEFAULT_BIN = 'build/devel/lib/preadaptive_mrac'


def fail(cmd, p):
    hint = ''
    if p.returncode < 0:
        hint = (
            ' (killed by signal %d: a binary linked against a rebuilt shared library crashes '
            'like this; rebuild the tools or point --bin-dir at a consistent build)' % -p.returncode
        )
    sys.exit(
        'reproduction_study: `%s` failed (exit %d)%s:\n%s'
        % (cmd, p.returncode, hint, p.stderr[-2000:])
    )


def loadavg():
    try:
        with open('/proc/loadavg') as f:
            return ' '.join(f.read().split()[:3])
    except OSError:
        return 'unknown'


def seed_spec(seeds):
    if len(seeds) > 1 and seeds == list(range(seeds[0], seeds[-1] + 1)):
        return '%d-%d' % (seeds[0], seeds[-1])
    return ','.join(str(s) for s in seeds)


def git(*args, raw=False):
    try:
        p = subprocess.run(['git'] + list(args), cwd=ROOT, capture_output=True, text=True)
        if p.returncode != 0:
            return None
        return p.stdout if raw else p.stdout.strip()
    except OSError:
        return None


def block(name, text):
    return '<!-- BEGIN %s -->\n%s\n<!-- END %s -->\n' % (name, text.rstrip() + '\n', name)
