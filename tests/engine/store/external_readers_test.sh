#!/usr/bin/env bash
# Results files as external tools read them, through the real ggk binary and
# Debian's h5py, pandas and h5ls. One case per call (tests/CMakeLists.txt):
#   pandas      the README's pandas one-liner gives str columns that select rows
#               (df[df.basis == "ggk"]), ggk_results.summary_frame too (python/); strings in
#               tables and attributes are variable-length UTF-8; integer arrays
#               and flags are integer datasets; fit groups have one stable name;
#               no /.staging in a finished file; every dataset is documented in
#               results/README.md
#   during_run  while a sweep runs, h5py, h5ls, `ggk info` and ggk_results.open_results
#               open the file and see the runs done so far; the job still finishes to the same
#               results as one nobody read
# Environment: GGK (the binary), GGK_SOURCE_DIR.
set -euo pipefail
case_name=$1
scratch=$(mktemp -d "${TMPDIR:-/tmp}/ggk-readers-XXXXXX")
trap 'rm -rf "$scratch"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }
python=/usr/bin/python3
$python -c "import h5py, pandas" 2>/dev/null || { echo "SKIP: no h5py/pandas"; exit 0; }
map=$GGK_SOURCE_DIR/jobs/maps/four-rooms.txt

write_job() {  # file runs [steps per series]
  cat >"$1" <<JOB
name = "readers"
task = "maze"
runs = $2
seed = 5
[sweep]
basis = ["ggk", "ogk"]
kernels = [8, 16]
sigma = [10.0]
solver = ["brm"]
[maze]
map_file = "$map"
series = 20
steps_per_series = ${3:-150}
JOB
}

check_pandas() {  # results file
  GGK_RESULTS=$GGK_SOURCE_DIR/python $python - "$1" "$GGK_SOURCE_DIR/results/README.md" <<'PY'
import os, re, sys
import h5py, numpy as np, pandas as pd
sys.path.insert(0, os.environ["GGK_RESULTS"])
import ggk_results
path, readme = sys.argv[1], open(sys.argv[2]).read()

def assert_documented(f, readme):
    """Every dataset name is in the schema of results/README.md."""
    names = set()
    f.visititems(lambda n, o: names.add(re.sub(r"_\d+$", "_<i>", n.split("/")[-1]))
                 if isinstance(o, h5py.Dataset) else None)
    missing = sorted(n for n in names if not (n in readme if "<" in n else
                                              re.search(r"\b" + re.escape(n) + r"\b", readme)))
    assert not missing, f"datasets not documented in results/README.md: {missing}"

# The README's one-liner, as printed there (with its file name replaced).
line = next(l for l in readme.splitlines() if l.startswith("df = "))
df = eval(line[len("df = "):].replace('"results/maze.h5"', repr(path)), {"h5py": h5py, "pd": pd})
assert isinstance(df.basis[0], str), type(df.basis[0])
assert len(df[df.basis == "ggk"]) == 4 and len(df[df.solver == "brm"]) == 8, df
assert set(df.status) <= {"converged", "max_iterations", "solver_failed", "invalid"}, df.status
frame = ggk_results.summary_frame(path)
assert len(frame[frame.basis == "ogk"]) == 4 and isinstance(frame.status[0], str)

with h5py.File(path, "r") as f:
    assert isinstance(f.attrs["job"], str) and isinstance(f.attrs["task"], str)
    assert f.attrs["layout"] == 2
    table = f["/maze/summary"]
    for name in ("basis", "solver", "status"):
        info = h5py.check_string_dtype(table.dtype[name])
        assert info is not None and info.length is None and info.encoding == "utf-8", name
    assert table.dtype["run"] == np.int32 and table.dtype["kernels"] == np.int32
    run = f["/maze/run_000"]
    assert run["samples/actions"].dtype == np.int32
    assert run["samples/terminals"].dtype == np.uint8
    assert run["graph/indices"].dtype == np.int32
    assert run["graph/visited"].dtype == np.uint8
    fit = run["fits/ggk/k_0008_sigma10_brm_lambda1e-06"]
    assert isinstance(fit.attrs["basis"], str) and fit.attrs["basis"] == "ggk"
    assert fit["policy"].dtype == np.int32 and fit["centers"].dtype == np.int32
    assert fit["steps_to_goal"].dtype == np.int32
    assert ".staging" not in f, list(f)
    assert_documented(f, readme)
print("ok")
PY
}

# The arm and Khepera files: integer datasets and every dataset documented.
check_tasks() {  # arm file, khepera file
  GGK_RESULTS=$GGK_SOURCE_DIR/python $python - "$1" "$2" "$GGK_SOURCE_DIR/results/README.md" <<'PY'
import os, re, sys
import h5py, numpy as np
arm, khepera, readme = sys.argv[1], sys.argv[2], open(sys.argv[3]).read()

def documented(f):
    names = set()
    f.visititems(lambda n, o: names.add(re.sub(r"_\d+$", "_<i>", n.split("/")[-1]))
                 if isinstance(o, h5py.Dataset) else None)
    return sorted(n for n in names if not (n in readme if "<" in n else
                                           re.search(r"\b" + re.escape(n) + r"\b", readme)))

with h5py.File(arm, "r") as f:
    run = f["arm/run_000"]
    assert run["grid/state_of"].dtype == np.int32 and run["grid/goal"].dtype == np.int32
    assert run["graph/visited"].dtype == np.uint8
    fit = next(iter(run["fits/ggk"].values()))
    assert fit["trajectory_A"].dtype == np.int32 and fit["steps_to_goal"].dtype == np.int32
    assert not documented(f), documented(f)
with h5py.File(khepera, "r") as f:
    run = f["khepera/run_000"]
    assert run["graph/occupied"].dtype == np.uint8 and run["state_units"].dtype == np.int32
    assert run["samples/collisions"].dtype == np.uint8
    fit = next(iter(run["fits/ggk"].values()))
    assert fit["unit_policy"].dtype == np.int32
    assert not documented(f), documented(f)
print("ok")
PY
}

retry() {  # command...: tries 0.1 s apart for up to 60 s of wall-clock time (stdin: kept for each try)
  local input deadline=$((SECONDS + 60))
  input=$(cat)
  until "$@" <<<"$input" >/dev/null 2>"$scratch/retry"; do
    [ "$SECONDS" -lt "$deadline" ] || return 1
    sleep 0.1
  done
}

case $case_name in
pandas)
  write_job "$scratch/job.toml" 2
  "$GGK" run "$scratch/job.toml" -q -o "$scratch/r.h5" 2>/dev/null || fail "run"
  check_pandas "$scratch/r.h5" || fail "pandas"
  "$GGK" run "$GGK_SOURCE_DIR/jobs/arm-quick.toml" -q -o "$scratch/arm.h5" 2>/dev/null || fail "arm"
  "$GGK" run "$GGK_SOURCE_DIR/jobs/khepera-quick.toml" -q -o "$scratch/khepera.h5" 2>/dev/null ||
    fail "khepera"
  check_tasks "$scratch/arm.h5" "$scratch/khepera.h5" || fail "arm and khepera files"
  ;;
during_run)
  # The sweep must outlast several reads (a `ggk info` takes ~0.4 s, an h5py
  # start-up ~0.5 s). How long a run takes depends on the machine and on ggk's
  # speed, so a sweep that ended before it was read part-way is started again
  # with four times the runs (60, 240, 960: at most a few tens of seconds).
  out=$scratch/r.h5
  seen_partial=0
  for runs in 60 240 960; do
    write_job "$scratch/job.toml" $runs 400
    rm -f "$out" "$scratch/reference.h5"
    "$GGK" run "$scratch/job.toml" -j 2 -q -o "$scratch/reference.h5" 2>/dev/null || fail "reference"
    "$GGK" run "$scratch/job.toml" -j 1 -q -o "$out" 2>"$scratch/err" &
    pid=$!
    for _ in $(seq 6000); do
      kill -0 $pid 2>/dev/null || break
      if [ -e "$out" ]; then
        info=$("$GGK" info "$out" 2>&1) || fail "ggk info during the run: $info"
        done_runs=$(sed -n "s/^runs: *\([0-9]*\) of $runs complete\$/\1/p" <<<"$info")
        [ -n "$done_runs" ] || fail "ggk info: $info"
        if [ "$done_runs" -ge 1 ] && [ "$done_runs" -lt $runs ]; then
          grep -q "fits (" <<<"$info" || fail "ggk info shows no rows of the runs done: $info"
          # A reader that comes in the moment of a commit finds HDF5's lock and
          # tries again, as a person would: between commits the file opens.
          retry h5ls -r "$out" </dev/null || fail "h5ls during the run: $(cat "$scratch/retry")"
          retry $python - "$out" <<'PY' || fail "h5py during the run: $(cat "$scratch/retry")"
import sys, h5py
with h5py.File(sys.argv[1], "r") as f:
    runs = [n for n in f["maze"] if n.startswith("run_") and f["maze"][n].attrs.get("complete") == 1]
    assert runs, list(f["maze"])
    assert len(f[f"maze/{runs[0]}/fit_metrics"][:]) == 4
PY
          # The package reads the complete runs (no summary yet), saying so.
          retry env GGK_RESULTS="$GGK_SOURCE_DIR/python" $python - "$out" <<'PY' ||
import os, sys, warnings
sys.path.insert(0, os.environ["GGK_RESULTS"])
import ggk_results
with warnings.catch_warnings(record=True) as caught:
    warnings.simplefilter("always")
    results = ggk_results.open_results(sys.argv[1])
if not results.complete:
    assert any(issubclass(w.category, ggk_results.PartialResultsWarning) for w in caught)
frame = results.summary()
assert len(results.runs) >= 1 and len(frame) == 4 * len(results.runs), (results, len(frame))
assert results.dataset().success_rate.dims[0] == "run"
PY
            fail "ggk_results during the run: $(cat "$scratch/retry")"
          seen_partial=$((seen_partial + 1))
        fi
      fi
      sleep 0.1
    done
    wait $pid || fail "the run failed while read: $(cat "$scratch/err")"
    [ "$seen_partial" -ge 1 ] && break
    echo "a sweep of $runs runs ended before it was read part-way: again with more runs"
  done
  [ "$seen_partial" -ge 1 ] || fail "never saw the file part-way ($seen_partial)"
  "$GGK" diff "$scratch/reference.h5" "$out" >/dev/null || fail "results differ from the reference"
  "$GGK" verify "$out" >/dev/null || fail "damaged"
  echo "read part-way $seen_partial times"
  ;;
*)
  fail "unknown case $case_name"
  ;;
esac
