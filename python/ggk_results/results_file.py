"""open_results(path): a results file as labelled data. Its rows as a pandas
DataFrame (summary), its metrics as xarray over named dimensions (run and every
axis), and any fit as labelled arrays (fit). Complete, running and interrupted
files alike: without /<task>/summary the rows come from the complete runs
(PartialResultsWarning)."""

import pandas as pd

from .fits import Fit, find_fit_group, fit_point, read_fit
from .metric_specs import read_metric_specs, spec_of
from .runs import run_path
from .tables import open_file, read_summary_table, task_of, text


class Results:
    """The rows of one results file as read when it was opened.

    path, task; axes (the sweep axes, then a study's); study_axes; metrics (the
    columns after `status`); complete (False: read from the complete runs,
    the file has no summary yet); runs (the complete runs' group paths);
    attrs (the root attributes: job, job_resolved, ggk_version, ...);
    metric_specs (each metric's declaration by name: kind, unit, meaning,
    low, high; metric_specs.py; {} for a file written before them)."""

    def __init__(self, path, task=None):
        self.path = str(path)
        with open_file(path) as f:
            self.task = task or task_of(f)
            self.attrs = {k: text(v) if isinstance(v, (bytes, str)) else v
                          for k, v in f.attrs.items()}
            table = read_summary_table(f, self.task)
            self.metric_specs = read_metric_specs(f, self.task)
        self._columns = table.columns
        self.study_axes = table.study_axes
        self.axes = table.axes
        self.metrics = table.metrics
        self.complete = table.complete
        self.runs = table.runs

    def __repr__(self):
        state = "complete" if self.complete else f"partial: {len(self.runs)} complete runs"
        return f"<Results {self.path} ({self.task}, {state}, axes {', '.join(self.axes)})>"

    def summary(self):
        """One row per fit (run, sweep_point, the axes, status, metrics), strings
        as str, so that df[df.basis == "ggk"] selects rows. Its
        attrs["metric_specs"] holds the metrics' declarations, which paired(),
        curve() and plot_metric read."""
        frame = pd.DataFrame({name: column for name, column in self._columns.items()})
        frame.attrs["metric_specs"] = dict(self.metric_specs)
        return frame

    def metric_spec(self, metric):
        """The declaration of one metric (metric_specs.spec_of)."""
        return spec_of(metric, self.metric_specs)

    def dims(self):
        """The named dimensions of dataset(): run, then every axis."""
        return ["run"] + list(self.axes)

    def dataset(self, metrics=None):
        """The metrics (default: all, with status) as an xarray Dataset over
        dims() with the axis values as coordinates, e.g.
        ds.success_rate.sel(basis="ggk", kernels=16).mean("run"). Points
        without a row (a partial file) are NaN. Each metric's variable carries
        its declaration as attrs: units, long_name (its meaning), kind and
        valid_range [low, high]."""
        frame = self.summary()
        dims = self.dims()
        if frame.empty:
            raise ValueError(f"{self.path}: no complete run yet")
        if frame.duplicated(dims).any():
            raise ValueError(f"{self.path}: several rows share one point of {dims}")
        names = list(metrics) if metrics is not None else ["status"] + list(self.metrics)
        missing = [n for n in names if n not in frame]
        if missing:
            raise KeyError(f"{self.path}: no column {', '.join(missing)} "
                           f"(metrics: {', '.join(self.metrics)})")
        dataset = frame.set_index(dims)[names].to_xarray()
        dataset.attrs.update(path=self.path, task=self.task, complete=int(self.complete))
        for name in names:
            if name in self.metric_specs:  # xarray's plots label themselves with these
                spec = self.metric_specs[name]
                dataset[name].attrs.update(units=spec.unit, long_name=spec.meaning,
                                           kind=spec.kind, valid_range=[spec.low, spec.high])
        return dataset

    def data_array(self, metric):
        """One metric as an xarray DataArray over dims()."""
        return self.dataset([metric])[metric]

    def fit(self, run, **point):
        """The fit of run `run` at `point` (basis=, kernels=, sigma=, solver=,
        lambda_= and any study axis; configuration= in a study): a Fit of
        labelled arrays. Every axis with several values at that run must be
        given; an ambiguous or unknown point is a KeyError naming the choices."""
        frame = self.summary()
        rows = frame[frame.run == run] if not frame.empty else frame
        if rows.empty:
            runs = sorted(set(frame.run.tolist())) if not frame.empty else []
            raise KeyError(f"{self.path}: no complete run {run} (runs: {runs})")
        for key, value in point.items():
            column = "lambda" if key == "lambda_" else key
            if column not in rows:
                raise KeyError(f"{self.path}: no axis {column!r} (axes: {', '.join(self.axes)})")
            chosen = rows[rows[column] == value]
            if chosen.empty:
                raise KeyError(f"{self.path}: run {run} has no fit with {column} = {value!r} "
                               f"(values: {sorted(set(rows[column].tolist()))})")
            rows = chosen
        if len(rows) > 1:
            open_axes = [a for a in self.axes + ["configuration"]
                         if a in rows and rows[a].nunique() > 1]
            choices = "; ".join(f"{a}: {sorted(set(rows[a].tolist()))}" for a in open_axes)
            raise KeyError(f"{self.path}: run {run}: {len(rows)} fits match; choose {choices}")
        row = rows.iloc[0]
        configuration = None
        if "configuration" in row:
            with open_file(self.path) as f:
                if any(name.startswith("config_") for name in f[self.task]):
                    configuration = int(row["configuration"])
        with open_file(self.path) as f:
            group = find_fit_group(f, run_path(self.task, run, configuration), row)
            return Fit(self.path, group, fit_point(f[group]), read_fit(f, group, self.task))


def open_results(path, task=None):
    """A results file as labelled data (Results); task defaults to the file's."""
    return Results(path, task)


def fit(path, run=0, **point):
    """The fit of `run` at `point` of the results file at `path` (Results.fit):
    fit("r.h5", run=0, basis="ggk", kernels=16, solver="brm").weights."""
    return open_results(path).fit(run, **point)


def summary_frame(path, task=None):
    """The rows of a results file as a pandas DataFrame (Results.summary)."""
    return open_results(path, task).summary()
