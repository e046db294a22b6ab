"""Analysis of preadaptive_mrac runs: bags (single-run or compare.launch) and the batch
CLI's CSV files -> docs/spec.md metrics, a comparison against regular adaptive control, PNG
figures (the paper's Figs. 2-4 and more), metrics.json and metrics.csv.

Modules: runs (the Run record), bags and csv_runs (readers), loading, metrics, report (text,
JSON, CSV), figure_style, figures (one run) and figures_compare (several runs), pipeline
(analyze()). Every public name is re-exported here, so `from preadaptive_mrac import analysis`
gives the whole API; a module's private helpers stay in their module. Needs
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
)
from .loading import (  # noqa: F401
    load_inputs,
    load_runs,
)
from .metrics import (  # noqa: F401
    choose_baseline,
    compare,
    decision_list,
    find_switches,
    run_metrics,
)
from .report import (  # noqa: F401
    CSV_COLUMNS,
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
)
from .figures import (  # noqa: F401
    plot_alpha,
    plot_decisions,
    plot_elevator,
    plot_theta,
    write_figures,
)
from .figures_compare import (  # noqa: F401
    plot_compare,
    plot_cost,
    plot_peaks,
)
from .pipeline import (  # noqa: F401
    analyze,
)
