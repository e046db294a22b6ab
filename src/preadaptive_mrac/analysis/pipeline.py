"""The whole analysis: inputs -> report, tables and figures."""

import os
import sys
from .figures import write_figures
from .loading import load_inputs
from .metrics import choose_baseline, compare, run_metrics
from .report import format_report, write_tables


def analyze(
    paths,
    out_dir=None,
    labels=None,
    baseline=None,
    c_e=0.005,
    xlim=None,
    figures=True,
    stream=sys.stdout,
    elevator_limits=None,
):
    """The whole pipeline; returns (metrics, comparison, files written). `elevator_limits`:
    (max_deflection [rad], max_rate [rad/s]) of the plant's elevator, for the time at each limit
    in the effort metrics (None: not computed)."""
    runs = load_inputs(paths, labels)
    metrics = [run_metrics(r, elevator_limits) for r in runs]
    base = choose_baseline(metrics, baseline)
    comparison = compare(metrics, base) if len(metrics) > 1 else None
    if stream is not None:
        print(format_report(metrics, comparison), file=stream)
    files = []
    if out_dir:
        os.makedirs(out_dir, exist_ok=True)
        settings = {
            'inputs': [os.path.abspath(p) for p in paths],
            'c_e': c_e,
            'baseline': comparison['baseline'] if comparison else None,
            'xlim': list(xlim) if xlim else None,
            'elevator_limits': list(elevator_limits) if elevator_limits else None,
        }
        write_tables(out_dir, metrics, comparison, settings)
        files = [os.path.join(out_dir, 'metrics.json'), os.path.join(out_dir, 'metrics.csv')]
        if figures:
            files += write_figures(out_dir, runs, metrics, comparison, c_e, xlim)
    return metrics, comparison, files
