"""Analysis of preadaptive_mrac runs: bags (single-run or compare.launch) and the batch
CLI's CSV files -> docs/spec.md metrics, a comparison against regular adaptive control, PNG
figures (the paper's Figs. 2-4 and more), metrics.json and metrics.csv.

Modules: runs (the Run record), bags and csv_runs (readers), loading, metrics, report (text,
JSON, CSV), figure_style, figures (one run) and figures_compare (several runs), pipeline
(analyze()). Every public name (and the few private helpers the tests use) is re-exported
here, so `from preadaptive_mrac import analysis` gives the whole API. Needs
/usr/bin/python3 with Debian's python3-rosbag for bags (not for CSV files), numpy and
matplotlib. See docs/reference/analysis.md.
"""

from .runs import (  # noqa: F401
    CSV_HEADER,
    CSV_REQUIRED,
    DECISIONS,
    DECISION_FIELDS,
    EPOCH_LIKE,
    EVENT_TYPES,
    InputError,
    MODES,
    MODE_TEXT,
    REQUIRED,
    Run,
    TOPICS,
    WHY,
    _guess_mode,
    _json_decision,
    _msg_decision,
    _no_decision,
    _rebase_epoch,
)
from .bags import (  # noqa: F401
    _fill_from_bag,
    _is_bag,
    _load_bag,
    _msg_times,
    _read_bag,
    _stamp_times,
)
from .csv_runs import (  # noqa: F401
    _load_csv,
    _parse_summary_json,
)
from .loading import (  # noqa: F401
    load_inputs,
    load_runs,
)
from .metrics import (  # noqa: F401
    _cum_trapz,
    _f,
    _pct,
    _scale_of,
    choose_baseline,
    compare,
    decision_list,
    find_switches,
    run_metrics,
)
from .report import (  # noqa: F401
    CSV_COLUMNS,
    _fmt,
    _theta_text,
    final_decisions,
    format_report,
    write_tables,
)
from .figure_style import (  # noqa: F401
    DECISION_STYLE,
    ONSET_COLOR,
    RECOVERY_COLOR,
    SWITCH_COLOR,
    THETA_UNITS,
    _decision_markers,
    _decision_text,
    _event_lines,
    _param_change_lines,
    _first_reset,
    _is_paper_reset,
    _legend,
    _mpl,
    _safe,
    _save,
    _switch_lines,
    _xlim,
    _ylim_to_xlim,
)
from .figures import (  # noqa: F401
    plot_alpha,
    plot_decisions,
    plot_elevator,
    plot_theta,
    write_figures,
)
from .figures_compare import (  # noqa: F401
    _run_colors,
    plot_compare,
    plot_cost,
    plot_peaks,
)
from .pipeline import (  # noqa: F401
    analyze,
)
