#!/usr/bin/env bash
# The third basis, "pvf" (engine/tasks/pvf_basis.hpp), through the real ggk
# binary. One case per call (tests/CMakeLists.txt):
#   threads   jobs/ci.toml (maze) and jobs/ci-khepera.toml with basis = ["ggk",
#             "ogk", "pvf"]: -j 1 and -j 2 give `ggk diff`-equal files; every run
#             stores each PVF fit's laplacian_eigenvalues (one exact 0 first), `ggk info`
#             has "pvf" rows, `ggk verify` reads the file
#   resume    the maze job's runs 0:2, then --resume to the whole job: the file
#             one process writes (ggk diff); two shards merged: the same
#   errors    a bad [pvf] value or key: exit 2 naming the key, nothing written
# Environment: GGK (the binary), GGK_SOURCE_DIR.
set -euo pipefail
case_name=$1
scratch=$(mktemp -d "${TMPDIR:-/tmp}/ggk-pvf-XXXXXX")
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
jobs_dir=$GGK_SOURCE_DIR/jobs
three='sweep.basis=["ggk","ogk","pvf"]'

case $case_name in
threads)
  for job in ci ci-khepera; do
    "$GGK" run "$jobs_dir/$job.toml" -q -j 1 --set "$three" -o "$scratch/$job-1.h5"
    "$GGK" run "$jobs_dir/$job.toml" -q -j 2 --set "$three" -o "$scratch/$job-2.h5"
    "$GGK" diff "$scratch/$job-1.h5" "$scratch/$job-2.h5" || fail "$job: -j 1 and -j 2 differ"
    # grep reads it all (-q stops at the first match: ggk, still writing, ends by SIGPIPE and
    # pipefail fails the line).
    "$GGK" info "$scratch/$job-1.h5" | grep -E '^ *pvf ' >/dev/null || fail "$job: no pvf rows in ggk info"
    "$GGK" verify "$scratch/$job-1.h5" >/dev/null || fail "$job: ggk verify"
    /usr/bin/python3 - "$scratch/$job-1.h5" <<'PY' || fail "$job: eigenvalues"
import sys
import h5py
with h5py.File(sys.argv[1], "r") as f:
    task = next(iter(k for k in f if isinstance(f[k], h5py.Group)))
    runs = [k for k in f[task] if k.startswith("run_")]
    assert runs, "no runs"
    for run in runs:
        fits = f[task][run]["fits/pvf"]
        assert len(fits) > 0
        for name in fits:
            if "laplacian_eigenvalues" not in fits[name]:  # an invalid fit
                continue
            values = fits[name]["laplacian_eigenvalues"][()]
            assert values[0] == 0.0 and all(values[1:] >= values[:-1] - 1e-12), (run, values[:5])
PY
  done
  ;;
resume)
  job=$jobs_dir/ci.toml
  "$GGK" run "$job" -q --set "$three" -o "$scratch/whole.h5"
  "$GGK" run "$job" -q --set "$three" --runs 0:2 -o "$scratch/part.h5"
  "$GGK" run "$job" -q --set "$three" --resume -o "$scratch/part.h5"
  "$GGK" diff "$scratch/whole.h5" "$scratch/part.h5" || fail "resumed file differs"
  "$GGK" run "$job" -q --set "$three" --runs 0:3 -o "$scratch/a.h5"
  "$GGK" run "$job" -q --set "$three" --runs 3:6 -o "$scratch/b.h5"
  "$GGK" merge "$scratch/merged.h5" "$scratch/b.h5" "$scratch/a.h5"
  "$GGK" diff "$scratch/whole.h5" "$scratch/merged.h5" || fail "merged shards differ"
  ;;
errors)
  out=$scratch/never.h5
  expect_error 2 "laplacian" "$GGK" run "$jobs_dir/ci.toml" --set 'pvf.laplacian="random_walk"' -o "$out"
  expect_error 2 "edge_weights" "$GGK" run "$jobs_dir/ci.toml" --set 'pvf.edge_weights=1' -o "$out"
  expect_error 2 "actions" "$GGK" validate "$jobs_dir/ci.toml" --set 'pvf.actions="all"'
  expect_error 2 "normalised" "$GGK" validate "$jobs_dir/ci.toml" --set 'pvf.normalised=true'
  expect_error 2 "basis" "$GGK" validate "$jobs_dir/ci.toml" --set 'sweep.basis=["pvfs"]'
  [ ! -e "$out" ] || fail "a refused job wrote $out"
  ;;
*)
  fail "unknown case $case_name"
  ;;
esac
