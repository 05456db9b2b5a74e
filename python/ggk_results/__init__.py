"""ggk_results: ggk's HDF5 results files as labelled data (pandas, xarray),
paired statistics and confidence intervals (scipy), and what the plot scripts
share. python/README.md says how to install it and how to use it."""

from .actions import ACTION_NAMES, action_names
from .adaptive import adaptive_cells, adaptive_rule
from .figures import (FORMATS, add_format_argument, axes_of, axis_values, curve, error_bars,
                      facet_title, facets, legend_below, save, swept_axes)
from .fits import Fit, labelled
from .intervals import (INDICATORS, is_indicator, is_rate, mean_ci, metric_ci,
                        newcombe_paired_ci, paired_t_ci, wilson_ci)
from .paired import paired
from .results_file import Results, fit, open_results, summary_frame
from .runs import complete_runs, run_group, run_locations
from .sequential import asymptotic_confidence_sequence, confidence_sequence
from .tables import AXES, PartialResultsWarning, read_summary, select_where, task_of

__version__ = "0.1.0"
