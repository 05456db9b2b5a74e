"""ggk_results: ggk's HDF5 results files as labelled data (pandas, xarray),
paired statistics and confidence intervals (scipy), and what the plot scripts
share, with one figure for any metric (plot_metric; `python3 -m ggk_results
plot`). python/README.md says how to install it and how to use it."""

from .actions import ACTION_NAMES, action_names
from .adaptive import adaptive_cells, adaptive_rule
from .figures import (FORMATS, add_format_argument, axes_of, axis_values, curve, error_bars,
                      facet_title, facets, legend_below, save, swept_axes, value_text)
from .fits import Fit, labelled
from .intervals import (INDICATORS, is_indicator, is_rate, mean_ci, metric_ci,
                        newcombe_paired_ci, paired_t_ci, wilson_ci)
from .metric_specs import MetricSpec, legacy_spec, read_metric_specs, spec_of
from .metric_figure import (BASIS_STYLE, job_settings, metric_panels, metric_range,
                            plot_metric)
from .paired import paired
from .results_file import Results, fit, open_results, summary_frame
from .runs import complete_runs, run_group, run_locations
from .sequential import asymptotic_confidence_sequence, confidence_sequence
from .tables import AXES, PartialResultsWarning, read_summary, select_where, task_of

__version__ = "0.1.0"
