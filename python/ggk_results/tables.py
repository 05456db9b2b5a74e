"""The tables of a results file as numpy columns: /<task>/summary, or, while a
job runs or after it was interrupted (no summary yet), the fit_metrics tables of
its complete runs. Strings come back as str (h5py hands a table's strings over
as bytes)."""

import time
import warnings

import h5py
import numpy as np

from .runs import complete_runs

# The sweep axes of every row, in sweep order (jobs/README.md).
AXES = ("basis", "kernels", "sigma", "solver", "lambda")
# Columns before `status` that are not axes: the row's run, its index in the
# run's sweep and (a study with run-level axes) its run configuration.
INDEX_COLUMNS = ("run", "sweep_point", "configuration")
# Every column after `status` is a metric; fit_seconds is the one wall-clock value.
WALL_CLOCK = ("fit_seconds",)
# The summary's attribute naming a study's axis columns, comma-separated.
STUDY_AXES_ATTRIBUTE = "study_axes"


class PartialResultsWarning(UserWarning):
    """The file has no /<task>/summary yet (its job is running or was
    interrupted): what was read comes from the complete runs alone."""


def open_file(path, wait_seconds=10.0):
    """h5py.File(path, "r"), retried for up to `wait_seconds` while ggk holds
    HDF5's lock for the moment of a commit (results/README.md, "Reading a file
    while a sweep runs")."""
    deadline = time.monotonic() + wait_seconds
    while True:
        try:
            return h5py.File(path, "r")
        except OSError as error:
            locked = "lock" in str(error).lower()
            if not locked or time.monotonic() > deadline:
                raise
            time.sleep(0.05)


def decoded(column):
    """A table column with its strings as str (fixed or variable length)."""
    if column.dtype.kind == "S":
        return np.char.decode(column, "utf-8")
    if column.dtype.kind == "O":
        return np.array([v.decode("utf-8") if isinstance(v, bytes) else v for v in column],
                        dtype=object)
    return column


def text(value):
    return value.decode("utf-8") if isinstance(value, bytes) else str(value)


def task_of(path_or_file):
    """The task a results file holds (root attribute `task`)."""
    if isinstance(path_or_file, h5py.File):
        return text(path_or_file.attrs["task"])
    with open_file(path_or_file) as f:
        return text(f.attrs["task"])


def read_table(dataset):
    """A compound dataset as a dict of decoded numpy columns, in column order."""
    table = dataset[:]
    return {name: decoded(table[name]) for name in table.dtype.names}


def study_axes_of(dataset, columns):
    """A table's study axis columns: its `study_axes` attribute when present;
    otherwise (tables written before the attribute) every column before
    `status` that is neither an index column nor a sweep axis."""
    if STUDY_AXES_ATTRIBUTE in dataset.attrs:
        names = text(dataset.attrs[STUDY_AXES_ATTRIBUTE])
        return [n.strip() for n in names.split(",") if n.strip()]
    before_status = list(columns)[:list(columns).index("status")] if "status" in columns else []
    return [c for c in before_status if c not in INDEX_COLUMNS and c not in AXES]


class Summary:
    """The rows of a results file, one per fit: `columns` (dict of numpy
    columns), `study_axes` (the study's axis columns, [] for a plain job),
    `complete` (False when read from the per-run tables), `runs` (the complete
    runs read, as group paths)."""

    def __init__(self, columns, study_axes, complete, runs):
        self.columns = columns
        self.study_axes = study_axes
        self.complete = complete
        self.runs = runs

    @property
    def axes(self):
        """Every axis a row's fit is named by: the sweep axes, then the study's."""
        return list(AXES) + [a for a in self.study_axes if a not in AXES]

    @property
    def metrics(self):
        names = list(self.columns)
        return names[names.index("status") + 1:] if "status" in names else []


def read_summary_table(f, task):
    """The Summary of an open file: /<task>/summary when the job finished,
    else (with a PartialResultsWarning) the complete runs' fit_metrics."""
    path = f.filename
    if task not in f:
        raise KeyError(f"{path}: no /{task} group (not a {task} results file)")
    runs = complete_runs(f, task)
    if "summary" in f[task]:
        table = f[task]["summary"]
        columns = read_table(table)
        keys = [columns[c] for c in ("configuration", "run") if c in columns]
        covered = len(set(zip(*keys))) if keys else 0
        if covered >= len(runs):
            return Summary(columns, study_axes_of(table, columns), True, runs)
        # A summary older than the runs (a study that grows): the runs decide.
        why = f"/{task}/summary covers {covered} of its {len(runs)} complete runs"
    else:
        why = f"no /{task}/summary (the job is running or was interrupted)"
    warnings.warn(f"{path}: {why}: read the fit_metrics of its {len(runs)} complete run(s)",
                  PartialResultsWarning, stacklevel=3)
    parts, study_axes = [], []
    for run in runs:
        table = f[run]["fit_metrics"]
        part = read_table(table)
        study_axes = study_axes or study_axes_of(table, part)
        parts.append(part)
    if not parts:
        return Summary({}, [], False, [])
    columns = {name: np.concatenate([p[name] for p in parts]) for name in parts[0]}
    return Summary(columns, study_axes, False, runs)


def read_summary(path, task=None):
    """The rows of a results file as a dict of numpy columns (strings as str);
    task defaults to the file's. A file without summary gives its complete runs'
    rows (PartialResultsWarning)."""
    with open_file(path) as f:
        return read_summary_table(f, task or task_of(f)).columns


def select_where(columns, where):
    """The rows of a summary (dict of numpy columns) whose columns equal every
    KEY=VALUE of `where` (e.g. "khepera.motion.turn_deg=45": one run
    configuration of a study), and that configuration's index (its
    `configuration` column's one value; None for a plain job's file or a
    selection that spans configurations). Exits with a message naming the key
    or the values when nothing matches."""
    mask = np.ones(len(columns["run"]), dtype=bool)
    for condition in where:
        key, sep, value = condition.partition("=")
        key, value = key.strip(), value.strip()
        if not sep or key not in columns:
            axes = [c for c in columns if "." in c]
            raise SystemExit(f"--where {condition}: expected KEY=VALUE with KEY a column of the "
                             f"summary (study axes: {', '.join(axes) or 'none'})")
        column = columns[key]
        if column.dtype.kind in "iuf":
            try:
                wanted = float(value)
            except ValueError:
                raise SystemExit(f"--where {condition}: {key} is a number") from None
            mask &= column.astype(float) == wanted
        else:
            mask &= column.astype(str) == value.strip('"')
        if not mask.any():
            values = ", ".join(str(v) for v in sorted(set(column.tolist())))
            raise SystemExit(f"--where {condition}: no rows (its values: {values})")
    selected = {name: column[mask] for name, column in columns.items()}
    configuration = None
    if "configuration" in selected:
        found = sorted(set(int(c) for c in selected["configuration"]))
        configuration = found[0] if len(found) == 1 else None
    return selected, configuration
