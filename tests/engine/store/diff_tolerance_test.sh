#!/usr/bin/env bash
# `ggk diff --rtol/--atol/--exclude` through the real binary (engine/store/results_diff.hpp).
# One case per call (tests/CMakeLists.txt):
#   sparse_dense  jobs/ci.toml with lspi.linear_algebra = "sparse" and = "dense":
#                 bit for bit they differ (exit 1), and each differing dataset's
#                 line gives its largest absolute difference and where, as h5py
#                 computes them; every metric, policy and table is bit-identical
#                 (only weights, values, the stored systems, the solver's
#                 history and the job text differ); without the solver's
#                 diagnostics and the job text they are the same within
#                 rtol 1e-3, atol 1e-9 (exit 0, saying by how much at most)
#   respelled     one job spelled two ways (sigma = [10] and [10.0]): the same
#                 results (exit 0), the spelling noted; another value differs
#   usage         two files of different tasks, a negative tolerance: exit 2
# Environment: GGK (the binary), GGK_SOURCE_DIR.
set -euo pipefail
case_name=$1
scratch=$(mktemp -d "${TMPDIR:-/tmp}/ggk-diff-XXXXXX")
trap 'rm -rf "$scratch"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }
python=/usr/bin/python3
job=$GGK_SOURCE_DIR/jobs/ci.toml

diff_status() {  # output file, ggk diff arguments...: prints the exit status
  local out=$1
  shift
  local status=0
  "$GGK" diff "$@" >"$out" 2>&1 || status=$?
  echo $status
}

case $case_name in
sparse_dense)
  "$GGK" run "$job" -q -o "$scratch/sparse.h5" --set 'lspi.linear_algebra="sparse"' ||
    fail "sparse run"
  "$GGK" run "$job" -q -o "$scratch/dense.h5" --set 'lspi.linear_algebra="dense"' ||
    fail "dense run"
  a=$scratch/sparse.h5
  b=$scratch/dense.h5

  [ "$(diff_status "$scratch/exact" "$a" "$b")" = 1 ] || fail "bit for bit: not exit 1"
  grep -q '^largest absolute difference .* at /maze/run_' "$scratch/exact" ||
    fail "no overall largest difference: $(tail -3 "$scratch/exact")"
  # One weights line, checked against h5py: the count, the largest |a - b|, its index.
  line=$(grep -m1 '/weights: values differ: ' "$scratch/exact") || fail "no weights line"
  if $python -c "import h5py, numpy" 2>/dev/null; then
    $python - "$a" "$b" "$line" <<'PY' || fail "the weights line does not match h5py: $line"
import re, sys
import h5py, numpy as np
a, b, line = sys.argv[1:]
path = re.match(r"differs: (\S+): values differ: ", line).group(1)
m = re.search(r": values differ: (\d+) of (\d+) elements; largest absolute difference (\S+) "
              r"at \[(\d+)\] \((\S+) vs (\S+)\), largest relative (\S+) at \[(\d+)\]", line)
assert m, line
with h5py.File(a, "r") as fa, h5py.File(b, "r") as fb:
    x, y = fa[path][:], fb[path][:]
differ = x != y
assert int(m.group(1)) == differ.sum() and int(m.group(2)) == x.size, (m.groups(), differ.sum())
absolute = np.abs(x - y)
i = int(np.argmax(absolute))
assert int(m.group(4)) == i, (m.group(4), i)
assert float(m.group(3)) == float(f"{absolute[i]:.2g}"), (m.group(3), absolute[i])
assert float(m.group(5)) == x[i] and float(m.group(6)) == y[i]
relative = np.where(differ, absolute / np.abs(y), 0.0)
assert float(m.group(7)) == float(f"{relative.max():.2g}"), (m.group(7), relative.max())
print("ok")
PY
  fi
  # What differs is what the linear algebra computes, not what the fits achieved.
  if grep '^differs: ' "$scratch/exact" | grep -vE '/(weights|state_values|history/[a-z_]+|A/data|b): values differ|^differs: / @job(_overrides|_resolved)?: '; then
    fail "something else differs between sparse and dense (above)"
  fi
  excluded=(--exclude '*/weights' --exclude '*/state_values' --exclude '*/history/*'
            --exclude '*/A/*' --exclude '*/b' --exclude '/ @job*')
  [ "$(diff_status "$scratch/metrics" "${excluded[@]}" "$a" "$b")" = 0 ] ||
    fail "metrics, policies or tables differ: $(head "$scratch/metrics")"

  # Within tolerance, the solver's diagnostics (rcond estimates and dense_solve
  # flags differ by design) and the job text left out.
  loose=(--rtol 1e-3 --atol 1e-9 --exclude '*/history/*' --exclude '/ @job*')
  [ "$(diff_status "$scratch/loose" "${loose[@]}" "$a" "$b")" = 0 ] ||
    fail "not the same within rtol 1e-3: $(grep -m3 '^differs' "$scratch/loose")"
  grep -q '^same results within rtol 0.001, atol 1e-09: ' "$scratch/loose" ||
    fail "verdict: $(cat "$scratch/loose")"
  grep -q '^[0-9]* of them differ bit for bit, within the tolerance: largest absolute difference ' \
    "$scratch/loose" || fail "no largest difference within tolerance: $(cat "$scratch/loose")"
  # A tolerance tighter than the largest relative difference makes them differ again.
  [ "$(diff_status "$scratch/tight" --rtol 1e-12 --exclude '*/history/*' --exclude '/ @job*' \
    "$a" "$b")" = 1 ] || fail "rtol 1e-12 passed"
  grep -q '^different results beyond rtol 1e-12, atol 0: ' "$scratch/tight" ||
    fail "verdict: $(tail -1 "$scratch/tight")"
  ;;
respelled)
  # The same job spelled two ways (sigma = [10] and [10.0]) holds the same
  # results: where both files record the job's meaning (job_resolved), the job
  # text and the options as typed are provenance, noted, not a difference.
  quick=$GGK_SOURCE_DIR/jobs/quick.toml
  "$GGK" run "$quick" -q -o "$scratch/a.h5" --set 'sweep.sigma=[10]' || fail "run a"
  "$GGK" run "$quick" -q -o "$scratch/b.h5" --set 'sweep.sigma=[10.0]' || fail "run b"
  [ "$(diff_status "$scratch/out" "$scratch/a.h5" "$scratch/b.h5")" = 0 ] ||
    fail "respelled job: $(cat "$scratch/out")"
  grep -q "job_overrides: " "$scratch/out" || fail "the spelling is not noted: $(cat "$scratch/out")"
  # Another value is another job: the key that differs is named in a note, and
  # the fits of the other sigma are only in one file each.
  "$GGK" run "$quick" -q -o "$scratch/c.h5" --set 'sweep.sigma=[10.5]' || fail "run c"
  [ "$(diff_status "$scratch/out" "$scratch/a.h5" "$scratch/c.h5")" = 1 ] ||
    fail "another sigma: not exit 1"
  grep -q "^note: the jobs differ in 1 key: sweep.sigma: \[10.0\] in the first file, \[10.5\] in the second file" \
    "$scratch/out" || fail "job_resolved: $(cat "$scratch/out")"
  ! grep -q "^differs: / @job_resolved" "$scratch/out" || fail "job_resolved as a difference"
  # --common: no fit in both files is no "same results".
  [ "$(diff_status "$scratch/out" "$scratch/a.h5" "$scratch/c.h5" --common)" = 1 ] ||
    fail "--common of files without a shared fit: $(cat "$scratch/out")"
  grep -q "share no fit" "$scratch/out" || fail "--common: $(cat "$scratch/out")"
  ;;
usage)
  "$GGK" run "$GGK_SOURCE_DIR/jobs/quick.toml" -q -o "$scratch/maze.h5" || fail "maze run"
  "$GGK" run "$GGK_SOURCE_DIR/jobs/arm-quick.toml" -q -o "$scratch/arm.h5" || fail "arm run"
  [ "$(diff_status "$scratch/out" "$scratch/maze.h5" "$scratch/arm.h5")" = 2 ] ||
    fail "two tasks: not exit 2"
  grep -q "maze.h5 holds maze results and .*arm.h5 arm results" "$scratch/out" ||
    fail "two tasks: $(cat "$scratch/out")"
  [ "$(diff_status "$scratch/out" --rtol -1 "$scratch/maze.h5" "$scratch/maze.h5")" = 2 ] ||
    fail "negative rtol: not exit 2"
  [ "$(diff_status "$scratch/out" --rtol 1e-6 "$scratch/maze.h5" "$scratch/maze.h5")" = 0 ] ||
    fail "a file against itself: $(cat "$scratch/out")"
  ;;
*)
  fail "unknown case $case_name"
  ;;
esac
echo ok
