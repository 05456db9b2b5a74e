"""Where a file's runs live: /<task>/run_NNN, or in a study with run-level axes
/<task>/config_NNN/run_NNN; a run is complete when its group has the attribute
complete = 1 (written last)."""


def run_locations(f, task):
    """The groups that hold a task's runs: a study's configuration groups
    (/<task>/config_NNN, in index order), or /<task> itself."""
    group = f[task]
    configurations = sorted(name for name in group if name.startswith("config_"))
    if configurations:
        return [f"{task}/{name}" for name in configurations]
    return [task]


def complete_runs(f, task):
    """Paths of the runs written whole (attribute complete = 1), in the order
    the summary lists them: configuration by configuration, run by run."""
    paths = []
    for location in run_locations(f, task):
        for name in sorted(n for n in f[location] if n.startswith("run_")):
            if f[location][name].attrs.get("complete", 0) == 1:
                paths.append(f"{location}/{name}")
    return paths


def run_path(task, run, configuration=None):
    """"maze/run_007", or in a study "maze/config_002/run_007"."""
    if configuration is None:
        return f"{task}/run_{int(run):03d}"
    return f"{task}/config_{int(configuration):03d}/run_{int(run):03d}"


def run_group(f, task, run=None, needs=(), configuration=None):
    """The group of run `run` of an open file (the first stored run when `run`
    is None) holding every member named in `needs`; exits with a message naming
    the file, the group and the stored runs when there is none."""
    path = f.filename
    if task not in f:
        raise SystemExit(f"{path}: no /{task} group (not a {task} results file)")
    locations = run_locations(f, task)
    if configuration is not None:
        location = f"{task}/config_{int(configuration):03d}"
    else:
        location = locations[0]
    if location not in f:
        raise SystemExit(f"{path}: no /{location} (configurations: "
                         f"{', '.join(l.split('/')[-1] for l in locations)})")
    runs = sorted(name for name in f[location] if name.startswith("run_"))
    if not runs:
        raise SystemExit(f"{path}: no stored run")
    name = f"run_{run:03d}" if run is not None else runs[0]
    group = f[location].get(name)
    missing = [n for n in needs if group is not None and n not in group]
    if group is None or missing:
        what = f"/{location}/{name}" + (f"/{missing[0]}" if missing else "")
        raise SystemExit(f"{path}: {what} not found (runs: {', '.join(runs)}"
                         + ("; files written before issue 11 lack it)" if missing else ")"))
    return group
