"""The study driver: options, sections in order, the report written or updated in place."""

import argparse
import datetime
import os
import re
import shutil
import sys
import time

from .common import DEFAULT_BIN, block, git
from .detection import DetectionSection
from .gradient import GradientSection
from .headline import HeadlineSection
from .heatmaps import HeatmapSection
from .provenance import ProvenanceHeader
from .responses import ResponseSections
from .runner import StudyBase
from .seeds import PeakSeedSections
from .common import SECTIONS


class Study(
    HeadlineSection,
    ProvenanceHeader,
    ResponseSections,
    GradientSection,
    HeatmapSection,
    PeakSeedSections,
    DetectionSection,
    StudyBase,
):
    """Every section on one set of tools and caches."""


def main(description=None, argv=None):
    """scripts/reproduction_study: parse the options, run the sections, write the report."""
    ap = argparse.ArgumentParser(
        prog='reproduction_study',
        description=description,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    ap.add_argument(
        '--bin-dir',
        default=DEFAULT_BIN,
        help='folder of preadapt_sweep and preadapt_sim (default %(default)s; '
        'relative to the package root)',
    )
    ap.add_argument('--out', default='docs/research/reproduction.md')
    ap.add_argument('--fig-dir', default='docs/figures/reproduction')
    ap.add_argument('--only', default='', help='comma-separated sections: ' + ', '.join(SECTIONS))
    ap.add_argument('--seeds', type=int, default=40, help='seeds 1..N for the distributions')
    ap.add_argument('--heat-seeds', type=int, default=20, help='seeds per heat-map cell')
    ap.add_argument(
        '--spread-seeds', type=int, default=40, help='seeds in the every-seed figure of scenario 1'
    )
    ap.add_argument('--jobs', type=int, default=2)
    ap.add_argument('--dpi', type=int, default=100)
    ap.add_argument('--quick', action='store_true', help='small grids, for testing the script')
    args = ap.parse_args(argv)
    if args.seeds < 1 or args.heat_seeds < 1 or args.spread_seeds < 1:
        ap.error('seed counts must be >= 1')
    only = [s for s in args.only.split(',') if s] if args.only else list(SECTIONS)
    bad = [s for s in only if s not in SECTIONS]
    if bad:
        ap.error('unknown section(s) %s; choose from %s' % (', '.join(bad), ', '.join(SECTIONS)))
    st = Study(args)
    # sanity: the binaries run at all
    st.tool('preadapt_sweep')
    st.tool('preadapt_sim')
    t_start = time.time()
    texts = {}
    # heatmaps before headline, so the headline can quote the grid
    order = [
        s
        for s in (
            'detection',
            'peaks',
            'seeds',
            'heatmaps',
            'gradient',
            'responses',
            'network',
            'headline',
        )
        if s in only
    ]
    try:
        for name in order:
            t0 = time.time()
            st.section_runs = 0
            print('[%s]' % name, flush=True)
            body = getattr(st, 'sec_' + name)()
            now = datetime.datetime.now(datetime.timezone.utc).strftime('%Y-%m-%d %H:%M UTC')
            prov = '\n*Section generated %s at commit %s; %d new simulations, %.0f s.*\n' % (
                now,
                git('rev-parse', '--short', 'HEAD') or 'unknown',
                st.section_runs,
                time.time() - t0,
            )
            texts[name] = body + prov
    finally:
        shutil.rmtree(st.tmp, ignore_errors=True)
    runtime = time.time() - t_start
    os.makedirs(os.path.dirname(st.md_path), exist_ok=True)
    if set(only) == set(SECTIONS) or not os.path.exists(st.md_path):
        doc = [block('header', st.header(runtime, only))]
        for name in SECTIONS:
            doc.append(
                block(
                    name,
                    texts.get(
                        name,
                        '*(not generated yet: run `%s`)*'
                        % ' '.join(['scripts/reproduction_study', '--only', name]),
                    ),
                )
            )
        text = '\n'.join(doc)
    else:
        with open(st.md_path) as f:
            text = f.read()
        for name, body in texts.items():
            pat = re.compile(r'<!-- BEGIN %s -->\n.*?<!-- END %s -->\n' % (name, name), re.S)
            if not pat.search(text):
                sys.exit(
                    'reproduction_study: %s has no block for section %s; rerun without --only'
                    % (st.md_path, name)
                )
            text = pat.sub(lambda _m: block(name, body), text)
    with open(st.md_path, 'w') as f:
        f.write(text)
    print(
        'wrote %s and figures in %s (%d simulations, %.0f s)'
        % (st.md_path, st.fig_dir, st.n_runs, runtime)
    )
