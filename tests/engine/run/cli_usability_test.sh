#!/usr/bin/env bash
# The command line helps: through the real ggk binary. One case per call
# (tests/CMakeLists.txt):
#   version        ggk --version prints the version, the git description and the
#                  embedded Python, exit 0
#   spelling       an unknown command or a mistyped option: exit 2, "did you mean"
#   output_name    -o results.csv (any non-HDF5 name), or such an [output] file, is
#                  refused with exit 2 before anything is written
#   info_csv       ggk info --csv: one header and one line per sweep point, the
#                  means and CI bounds that pandas reads
#   overrides      --set KEY=VALUE changes the job, is validated like the file
#                  (a bad value names the option, a file value its line), is
#                  recorded in the results, and --resume compares the overridden job
#   old_layout     a results file of an older layout (no 'layout' attribute) is
#                  read by info and verify, refused by --resume and merge (exit 2)
#   quiet          -q on every command (run, validate, info, verify, diff, merge)
#                  prints nothing, on either stream, but errors; an error still
#                  prints (exit 2, naming it)
#   relative_paths validate and run resolve a job's paths alike from any working
#                  directory: files it names from its folder, the output from the
#                  working directory
#   copied_job     a job file copied from another (the same name and [output] file,
#                  another seed) is refused at the original's results, which it names
#                  as another job's, with what to change; the original's file is untouched
# Environment: GGK (the binary), GGK_SOURCE_DIR.
set -euo pipefail
case_name=$1
scratch=$(mktemp -d "${TMPDIR:-/tmp}/ggk-cli-XXXXXX")
trap 'rm -rf "$scratch"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }
status_of() { local s=0; "$@" >"$scratch/out" 2>"$scratch/err" || s=$?; echo $s; }
expect_error() {  # status, text the error must contain, command...
  local want=$1 text=$2
  shift 2
  local s
  s=$(status_of "$@")
  [ "$s" = "$want" ] || fail "$*: status $s, not $want: $(cat "$scratch/err")"
  grep -qF -- "$text" "$scratch/err" || fail "$*: no '$text' in: $(cat "$scratch/err")"
}

write_job() {  # file [extra top-level lines]
  mkdir -p "$(dirname "$1")/maps"
  cp "$GGK_SOURCE_DIR/jobs/maps/four-rooms.txt" "$(dirname "$1")/maps/"
  cat >"$1" <<JOB
name = "cli"
task = "maze"
runs = 2
seed = 3
${2:-}
[sweep]
basis = ["ggk", "ogk"]
kernels = [4, 8]
sigma = [10.0]
solver = ["brm"]
[maze]
map_file = "maps/four-rooms.txt"
series = 10
steps_per_series = 100
JOB
}

case $case_name in
version)
  s=$(status_of "$GGK" --version)
  [ "$s" = 0 ] || fail "--version: status $s"
  # The version, the git description, and the Python the python_env task embeds
  # (or that it was built without one).
  grep -qE '^ggk [0-9]+\.[0-9]+\.[0-9]+ \([^)]+\); (python_env embeds CPython [0-9]+\.[0-9]+\.[0-9]+|built without Python \(no python_env task\))$' "$scratch/out" || fail "--version: $(cat "$scratch/out")"
  ;;
spelling)
  write_job "$scratch/job.toml"
  expect_error 2 "unknown command 'rn' (did you mean 'run'?)" "$GGK" rn "$scratch/job.toml"
  expect_error 2 "unknown command 'vaildate' (did you mean 'validate'?)" "$GGK" vaildate x
  expect_error 2 "unknown option '--resum' for 'ggk run' (did you mean '--resume'?)" \
    "$GGK" run "$scratch/job.toml" --resum
  expect_error 2 "unknown option '--cvs' for 'ggk info' (did you mean '--csv'?)" \
    "$GGK" info x.h5 --cvs
  expect_error 2 "unknown option '--overwite' for 'ggk run' (did you mean '--overwrite'?)" \
    "$GGK" run "$scratch/job.toml" -o "$scratch/x.h5" --overwite
  # An option's value may start with '-': not taken for an option.
  s=$(status_of "$GGK" validate "$scratch/job.toml" --set seed=1 -o "$scratch/-x.h5")
  [ "$s" = 0 ] || fail "an option value starting with '-': $(cat "$scratch/err")"
  ;;
output_name)
  write_job "$scratch/job.toml"
  for name in results.csv results out.txt; do
    expect_error 2 "is not a results file name" "$GGK" run "$scratch/job.toml" -q -o "$scratch/$name"
    [ ! -e "$scratch/$name" ] && [ ! -e "$scratch/$name.part" ] && [ ! -e "$scratch/$name.lock" ] ||
      fail "-o $name: something was written"
    expect_error 2 "is not a results file name" "$GGK" validate "$scratch/job.toml" -o "$scratch/$name"
  done
  write_job "$scratch/csv.toml" ""
  printf '[output]\nfile = "%s"\n' "$scratch/r.csv" >>"$scratch/csv.toml"
  expect_error 2 "csv.toml:" "$GGK" run "$scratch/csv.toml" -q
  grep -qF "[output] file: '$scratch/r.csv' is not a results file name" "$scratch/err" ||
    fail "[output] file: $(cat "$scratch/err")"
  s=$(status_of "$GGK" run "$scratch/job.toml" -q -o "$scratch/r.hdf5")
  [ "$s" = 0 ] || fail "-o r.hdf5: $(cat "$scratch/err")"
  expect_error 2 "is not a results file name" "$GGK" merge "$scratch/m.csv" "$scratch/r.hdf5"
  ;;
quiet)
  write_job "$scratch/job.toml"
  silent() {  # command...: exit 0, nothing on stdout or stderr
    local s
    s=$(status_of "$@")
    [ "$s" = 0 ] || fail "$*: status $s: $(cat "$scratch/err")"
    [ ! -s "$scratch/out" ] && [ ! -s "$scratch/err" ] ||
      fail "$*: printed: $(cat "$scratch/out" "$scratch/err")"
  }
  silent "$GGK" run "$scratch/job.toml" -q -j 1 -o "$scratch/r.h5"
  silent "$GGK" run "$scratch/job.toml" -q -j 1 -o "$scratch/r.h5" --resume
  silent "$GGK" run "$scratch/job.toml" -q -j 1 -o "$scratch/a.h5" --runs 0:1
  silent "$GGK" run "$scratch/job.toml" -q -j 1 -o "$scratch/b.h5" --runs 1:2
  silent "$GGK" validate "$scratch/job.toml" -q -o "$scratch/v.h5"
  silent "$GGK" info "$scratch/r.h5" -q
  silent "$GGK" info "$scratch/r.h5" -q --csv --paired basis=ggk,ogk
  silent "$GGK" verify "$scratch/r.h5" -q
  silent "$GGK" merge "$scratch/m.h5" "$scratch/a.h5" "$scratch/b.h5" -q
  silent "$GGK" diff "$scratch/r.h5" "$scratch/m.h5" -q
  # Without -q they print; with it an error still does.
  [ -n "$("$GGK" verify "$scratch/r.h5")" ] || fail "verify without -q printed nothing"
  expect_error 2 "no such file" "$GGK" info -q "$scratch/none.h5"
  expect_error 2 "AXIS=A,B" "$GGK" info -q "$scratch/r.h5" --paired basis
  ;;
info_csv)
  write_job "$scratch/job.toml"
  "$GGK" run "$scratch/job.toml" -q -o "$scratch/r.h5" 2>/dev/null
  "$GGK" info --csv "$scratch/r.h5" >"$scratch/info.csv"
  /usr/bin/python3 - "$scratch/info.csv" <<'PY' || fail "info --csv: $(cat "$scratch/info.csv")"
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
assert len(rows) == 4, rows                       # 2 bases x 2 kernel counts
assert {r["basis"] for r in rows} == {"ggk", "ogk"}
assert {r["lambda"] for r in rows} == {"1e-06"}
for r in rows:
    # The counts never take an axis's name (lspi.max_iterations is one).
    assert int(r["fits"]) == 2 and int(r["fits_failed"]) >= 0 and int(r["fits_capped"]) >= 0
    assert "max_iterations" not in r, r.keys()
    low, mean, high = (float(r[k]) for k in
                       ("success_rate_ci_low", "success_rate", "success_rate_ci_high"))
    assert 0.0 <= low <= mean <= high <= 1.0, r
PY
  # The text form: the CI and the fits that stopped at the iteration cap.
  "$GGK" info "$scratch/r.h5" >"$scratch/info.txt"
  grep -qE "summary: +8 fits \([0-9]+ failed, [0-9]+ capped: stopped at lspi.max_iterations\)" \
    "$scratch/info.txt" || fail "info: $(cat "$scratch/info.txt")"
  grep -qE " capped " "$scratch/info.txt" || fail "info: no capped column"
  # The legend: each metric's unit, range and interval from the file's metric_specs.
  grep -qE "^  success_rate +\[1\] +\[0, 1\] +Student t within the range +share of the start states" \
    "$scratch/info.txt" || fail "info: no legend line for success_rate: $(cat "$scratch/info.txt")"
  grep -qE "^  fit_seconds +\[s\] +\[0, inf\)" "$scratch/info.txt" ||
    fail "info: no legend line for fit_seconds"
  grep -qE "\[[-0-9.e]+, [-0-9.e]+\]" "$scratch/info.txt" || fail "info: no interval"
  ;;
overrides)
  write_job "$scratch/job.toml"
  "$GGK" run "$scratch/job.toml" -q -o "$scratch/r.h5" --set runs=3 --set maze.series=12 \
    --set 'sweep.kernels=[4]' 2>/dev/null || fail "run with --set"
  "$GGK" info "$scratch/r.h5" | grep "runs: *3 of 3 complete" >/dev/null || fail "--set runs=3 not applied"
  /usr/bin/python3 - "$scratch/r.h5" <<'PY' || fail "overrides not recorded"
import sys, tomllib, h5py
with h5py.File(sys.argv[1], "r") as f:
    job = f.attrs["job"]
    assert f.attrs["job_overrides"] == "runs=3\nmaze.series=12\nsweep.kernels=[4]"
    assert len(f["maze/run_000/samples/actions"]) == 12 * 100
parsed = tomllib.loads(job)
assert parsed["runs"] == 3 and parsed["maze"]["series"] == 12 and parsed["sweep"]["kernels"] == [4]
assert job.startswith("# ") and "--set runs=3" in job.splitlines()[0]
PY
  # Validated like the file: the option is named for its value, the line for the file's.
  expect_error 2 "--set runs=0: runs: expected an integer >= 1, got 0" \
    "$GGK" run "$scratch/job.toml" -q -o "$scratch/x.h5" --set runs=0
  expect_error 2 "--set maze.sries=3: [maze] sries: unknown key; did you mean 'series'?" \
    "$GGK" validate "$scratch/job.toml" --set maze.sries=3
  expect_error 2 "--set runs: expected KEY=VALUE" "$GGK" validate "$scratch/job.toml" --set runs
  # Hydra's habit: a bare KEY=VALUE gets the options that do it.
  expect_error 2 "'kernels=4,8': ggk takes no bare KEY=VALUE; write --set kernels=4,8 to override kernels, or --sweep kernels=4,8" \
    "$GGK" run "$scratch/job.toml" kernels=4,8 -o "$scratch/x.h5"
  expect_error 2 "ggk takes no bare KEY=VALUE" "$GGK" validate "$scratch/job.toml" --set runs=2 maze.series=5
  expect_error 2 "--set sweep.solver=brm: [sweep] solver: expected a non-empty array" \
    "$GGK" validate "$scratch/job.toml" --set sweep.solver=brm
  write_job "$scratch/bad.toml" 'lspi_x = 1'
  expect_error 2 "bad.toml:5:" "$GGK" validate "$scratch/bad.toml" --set runs=4
  [ ! -e "$scratch/x.h5" ] || fail "a refused override wrote results"
  # A bare word is a string; --resume compares the overridden job.
  "$GGK" validate "$scratch/job.toml" -o "$scratch/v.h5" --set name=other >/dev/null 2>&1 ||
    fail "bare word"
  s=$(status_of "$GGK" run "$scratch/job.toml" -q -o "$scratch/r.h5" --resume)
  [ "$s" = 2 ] && grep -q "series: 12 in the results file, 10 in the job file" "$scratch/err" ||
    fail "--resume without the overrides: $s $(cat "$scratch/err")"
  s=$(status_of "$GGK" run "$scratch/job.toml" -q -o "$scratch/r.h5" --resume --set runs=3 \
    --set maze.series=12 --set 'sweep.kernels=[4]')
  [ "$s" = 0 ] || fail "--resume with the same overrides: $(cat "$scratch/err")"
  ;;
old_layout)
  write_job "$scratch/job.toml"
  "$GGK" run "$scratch/job.toml" -q -o "$scratch/r.h5" 2>/dev/null
  /usr/bin/python3 -c "
import sys, h5py
with h5py.File(sys.argv[1], 'a') as f:
    assert f.attrs['layout'] == 2
    del f.attrs['layout']
" "$scratch/r.h5"
  "$GGK" info "$scratch/r.h5" | grep "runs: *2 of 2 complete" >/dev/null || fail "info of an old file"
  "$GGK" verify "$scratch/r.h5" >/dev/null || fail "verify of an old file"
  expect_error 2 "it has results layout 1 (written by an older ggk" \
    "$GGK" run "$scratch/job.toml" -q -o "$scratch/r.h5" --resume
  expect_error 2 "cannot merge $scratch/r.h5: it has results layout 1" \
    "$GGK" merge "$scratch/m.h5" "$scratch/r.h5"
  ;;
copied_job)
  mkdir -p "$scratch/project/jobs" "$scratch/project/mine" "$scratch/project/results"
  write_job "$scratch/project/jobs/job.toml"
  cd "$scratch/project"
  "$GGK" run jobs/job.toml -q 2>/dev/null || fail "run the original"
  before=$(sha256sum results/cli.h5)
  sed 's/^seed = 3$/seed = 4/' jobs/job.toml >mine/job.toml
  cp -r jobs/maps mine/
  expect_error 2 "exists and holds the results of a different job (seed: 3 in the results file, 4 in the job file" \
    "$GGK" run mine/job.toml -q
  grep -qF 'a job file copied from another keeps the original'"'"'s `name` and `[output] file`' \
    "$scratch/err" || fail "no hint at the copied name: $(cat "$scratch/err")"
  # The same job, run again: the plain refusal, which --resume answers.
  expect_error 2 "exists: pass --resume to continue it" "$GGK" run jobs/job.toml -q
  # Given -o, the file is not the job's own [output] file: no hint at a copy.
  expect_error 2 "holds the results of a different job" "$GGK" run mine/job.toml -q -o results/cli.h5
  if grep -qF "copied from another" "$scratch/err"; then fail "a copy hint for -o"; fi
  [ "$(sha256sum results/cli.h5)" = "$before" ] || fail "the original's results changed"
  sed -i 's/^name = "cli"$/name = "mine"/' mine/job.toml
  echo '[output]' >>mine/job.toml
  echo 'file = "results/mine.h5"' >>mine/job.toml
  s=$(status_of "$GGK" run mine/job.toml -q)
  [ "$s" = 0 ] && [ -f results/mine.h5 ] || fail "the renamed copy: $(cat "$scratch/err")"
  ;;
relative_paths)
  mkdir -p "$scratch/project/jobs" "$scratch/project/results" "$scratch/elsewhere"
  write_job "$scratch/project/jobs/job.toml"
  cd "$scratch/project"
  # From the project: the map from the job's folder, the output results/cli.h5 here.
  s=$(status_of "$GGK" validate jobs/job.toml)
  [ "$s" = 0 ] || fail "validate from the project: $(cat "$scratch/err")"
  s=$(status_of "$GGK" run jobs/job.toml -q)
  [ "$s" = 0 ] && [ -f results/cli.h5 ] || fail "run from the project: $(cat "$scratch/err")"
  # From the job's folder or elsewhere: the map still resolves; validate and run
  # both refuse the output (no results/ there) with the same words, and both
  # accept it given with -o.
  for dir in "$scratch/project/jobs" "$scratch/elsewhere"; do
    cd "$dir"
    job=$scratch/project/jobs/job.toml
    [ "$dir" = "$scratch/project/jobs" ] && job=job.toml
    expect_error 2 "relative to the working directory" "$GGK" validate "$job"
    cp "$scratch/err" "$scratch/validate.err"
    expect_error 2 "relative to the working directory" "$GGK" run "$job" -q
    [ "$(sed 's/.*: \[output\]/[output]/' "$scratch/validate.err")" = \
      "$(sed 's/.*: \[output\]/[output]/' "$scratch/err")" ] || fail "validate and run differ"
    s=$(status_of "$GGK" validate "$job" -o here.h5)
    [ "$s" = 0 ] || fail "validate -o from $dir: $(cat "$scratch/err")"
    s=$(status_of "$GGK" run "$job" -q -o here.h5)
    [ "$s" = 0 ] && [ -f here.h5 ] || fail "run -o from $dir: $(cat "$scratch/err")"
  done
  ;;
*)
  fail "unknown case $case_name"
  ;;
esac
