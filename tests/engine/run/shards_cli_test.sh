#!/usr/bin/env bash
# Shards without arithmetic and the affinity warning, through the real ggk binary.
# One case per call (tests/CMakeLists.txt):
#   shard          --shard I/N: 3 shards written as OUT.shard-I-of-3.h5 (named
#                  after -o, else the job's output), merged by `merge --shards-of`
#                  into the file one process writes; a missing shard is named;
#                  N > runs, I >= N, a malformed shard and --shard with --runs:
#                  exit 2 and nothing written
#   slurm          --shard slurm in a (simulated) job array's environment: 2 tasks
#                  merge to the whole job; outside an array, or an array from 1:
#                  exit 2 naming the variable
#   study          a --sweep study's shards: merge --shards-of JOB --sweep ... -o
#                  OUT (other options refused naming both), merge -o OUT a b
#   affinity       `taskset -c 0 ggk run -j 2` warns that 2 threads share 1 CPU,
#                  naming srun --cpus-per-task; -j as many as the mask holds does not
# Environment: GGK (the binary), GGK_SOURCE_DIR.
set -euo pipefail
case_name=$1
scratch=$(mktemp -d "${TMPDIR:-/tmp}/ggk-shards-XXXXXX")
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
expect_ok() {
  local s
  s=$(status_of "$@")
  [ "$s" = 0 ] || fail "$*: status $s: $(cat "$scratch/err")"
}

# 5 runs of a small maze job writing results/shards.h5 (from the working directory).
mkdir -p "$scratch/maps" "$scratch/results"
cp "$GGK_SOURCE_DIR/jobs/maps/four-rooms.txt" "$scratch/maps/"
cat >"$scratch/job.toml" <<JOB
name = "shards"
task = "maze"
runs = 5
seed = 11
[sweep]
basis = ["ggk", "ogk"]
kernels = [4, 8]
sigma = [10.0]
solver = ["brm"]
[maze]
map_file = "maps/four-rooms.txt"
series = 10
steps_per_series = 100
[output]
file = "results/shards.h5"
JOB
cd "$scratch"

case $case_name in
shard)
  expect_ok "$GGK" run job.toml -j 2 -q -o whole.h5
  for i in 0 1 2; do expect_ok "$GGK" run job.toml -j 1 -q --shard "$i/3"; done
  for i in 0 1 2; do
    [ -f "results/shards.shard-$i-of-3.h5" ] || fail "no results/shards.shard-$i-of-3.h5: $(ls results)"
  done
  [ ! -e results/shards.h5 ] || fail "a shard wrote the job's own output"
  # runs 0-0, 1-2, 3-4: floor(I 5 / 3)
  for shard in "0 0 1" "1 1 3" "2 3 5"; do  # I first last: floor(I 5 / 3)
    set -- $shard
    selected=$(/usr/bin/python3 -c "import h5py, sys
print(*h5py.File(sys.argv[1], 'r').attrs['runs_selected'])" "results/shards.shard-$1-of-3.h5")
    [ "$selected" = "$2 $3" ] || fail "shard $1/3 holds runs_selected $selected, not $2 $3"
  done
  expect_ok "$GGK" merge --shards-of job.toml
  expect_ok "$GGK" diff whole.h5 results/shards.h5
  # -o names the shards; merge OUT --shards-of JOB finds them beside OUT.
  expect_ok "$GGK" run job.toml -j 1 -q --shard 0/2 -o mine.h5
  [ -f mine.shard-0-of-2.h5 ] || fail "-o mine.h5 --shard 0/2 wrote $(ls)"
  expect_error 2 "1 of 2 shards of mine.h5 missing: mine.shard-1-of-2.h5" \
    "$GGK" merge mine.h5 --shards-of job.toml
  [ ! -e mine.h5 ] || fail "a refused merge wrote mine.h5"
  expect_ok "$GGK" run job.toml -j 1 -q --shard 1/2 -o mine.h5
  expect_ok "$GGK" merge mine.h5 --shards-of job.toml
  expect_ok "$GGK" diff whole.h5 mine.h5
  # Refusals: exit 2, nothing written.
  expect_error 2 "the job has 5 runs, fewer than 6 shards" "$GGK" run job.toml --shard 0/6 -o x.h5
  expect_error 2 "shard 3 of 3 does not exist" "$GGK" run job.toml --shard 3/3 -o x.h5
  expect_error 2 "expected I/N" "$GGK" run job.toml --shard 1-3 -o x.h5
  expect_error 2 "exclude each other" "$GGK" run job.toml --shard 0/2 --runs 0:2 -o x.h5
  expect_error 2 "the job has 7 runs, fewer than 8 shards" \
    "$GGK" run job.toml --shard 0/8 --set runs=7 -o x.h5  # --set runs counts
  if compgen -G "x*.h5" >/dev/null; then fail "a refused shard wrote $(ls x*.h5)"; fi
  expect_error 2 "no shards of other.h5" "$GGK" merge other.h5 --shards-of job.toml
  ;;
slurm)
  expect_ok "$GGK" run job.toml -j 2 -q -o whole.h5
  for i in 0 1; do
    expect_ok env SLURM_ARRAY_TASK_ID=$i SLURM_ARRAY_TASK_COUNT=2 SLURM_ARRAY_TASK_MIN=0 \
      SLURM_ARRAY_TASK_MAX=1 SLURM_ARRAY_TASK_STEP=1 "$GGK" run job.toml -j 1 -q --shard slurm
  done
  expect_ok "$GGK" merge --shards-of job.toml
  grep -qF "merged 5 of 5 runs from 2 shards" "$scratch/err" || fail "merge said: $(cat "$scratch/err")"
  expect_ok "$GGK" diff whole.h5 results/shards.h5
  expect_error 2 "SLURM_ARRAY_TASK_ID is not set" \
    env -u SLURM_ARRAY_TASK_ID "$GGK" run job.toml --shard slurm -o x.h5
  expect_error 2 "the array starts at 1 (SLURM_ARRAY_TASK_MIN=1), not 0" \
    env SLURM_ARRAY_TASK_ID=1 SLURM_ARRAY_TASK_COUNT=2 SLURM_ARRAY_TASK_MIN=1 \
    SLURM_ARRAY_TASK_MAX=2 "$GGK" run job.toml --shard slurm -o x.h5
  if compgen -G "x*.h5" >/dev/null; then fail "a refused shard wrote $(ls x*.h5)"; fi
  ;;
affinity)
  command -v taskset >/dev/null || fail "taskset (util-linux) not found"
  expect_ok taskset -c 0 "$GGK" run job.toml -j 2 -q --set runs=1 -o one-cpu.h5
  grep -qF "ggk: warning: -j 2 starts 2 compute threads, but this process may run on 1 CPU (its affinity mask: 0)" \
    "$scratch/err" || fail "no warning under taskset -c 0: $(cat "$scratch/err")"
  grep -qF "srun --cpus-per-task" "$scratch/err" || fail "the warning names no remedy: $(cat "$scratch/err")"
  cpus=$(nproc)  # the CPUs of this process's mask
  expect_ok "$GGK" run job.toml -j "$cpus" -q --set runs=1 -o all-cpus.h5
  ! grep -q "warning" "$scratch/err" || fail "-j $cpus on $cpus CPUs warned: $(cat "$scratch/err")"
  expect_ok taskset -c 0 "$GGK" run job.toml -q --set runs=1 -o default-threads.h5
  ! grep -q "warning" "$scratch/err" || fail "default -j under taskset warned: $(cat "$scratch/err")"
  ;;
study)
  # A --sweep study's shards are named after its -o (issue 36: merge --shards-of
  # could not find them, and `merge -o` said "did you mean '-h'?"): merge takes
  # -o and the options the shards were run with, refuses other options naming
  # both, and without -o says where such shards are.
  cd "$scratch"
  study=(--sweep kernels=4,8 --set runs=4)
  for i in 0 1; do expect_ok "$GGK" run job.toml -q -j 2 "${study[@]}" -o st.h5 --shard $i/2; done
  expect_ok "$GGK" run job.toml -q -j 2 "${study[@]}" -o whole.h5
  expect_error 2 "give the same -o OUT here" "$GGK" merge --shards-of job.toml "${study[@]}"
  expect_error 2 "was run with --sweep kernels=4,8, not the --sweep kernels=4,16 given here" \
    "$GGK" merge --shards-of job.toml --sweep kernels=4,16 --set runs=4 -o st.h5
  [ ! -e st.h5 ] || fail "a refused merge wrote its output"
  expect_ok "$GGK" merge --shards-of job.toml "${study[@]}" -o st.h5
  expect_ok "$GGK" diff whole.h5 st.h5
  # -o with the shard files by name; --sweep without --shards-of is refused.
  expect_ok "$GGK" merge -q -o by-name.h5 st.shard-0-of-2.h5 st.shard-1-of-2.h5
  expect_ok "$GGK" diff whole.h5 by-name.h5
  expect_error 2 "shard files given by name need neither" \
    "$GGK" merge -o x.h5 st.shard-0-of-2.h5 --sweep kernels=4,8
  ;;
*)
  fail "unknown case $case_name"
  ;;
esac
