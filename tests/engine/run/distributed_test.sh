#!/usr/bin/env bash
# The distributed engine end to end, through the real ggk binary: one case per
# call (ctest registers each, see tests/CMakeLists.txt).
#   ranks  mpiexec -n 1..4 writes the file a single process writes (ggk diff), and
#          its progress counts the fits of every rank; on 4 ranks the last round's
#          runs are computed in pieces (their fits spread over the ranks)
#   shards --runs A:B shards merged equal the whole job; merge refuses foreign and
#          overlapping shards, reports gaps, and --allow-partial's printed
#          command completes (with --set overrides too)
#   kill   kill -9 a worker: the job stops naming the rank and its run; every run
#          written stays complete; --resume (2 ranks, then none) finishes it identically
#   interrupt  SIGINT / SIGTERM to mpirun, SIGTERM to every rank: reported as an
#          interruption (no rank blamed), no lock left, the printed command
#          finishes the job identically
#   adaptive   an adaptive study (jobs/ci-adaptive.toml, kernels 2 and 8: its later
#          runs hold some points) over 1 and 3 ranks equals
#          it in one process (its looks handed out rank by rank); SIGINT to mpirun
#          mid-study, then the printed command, equals it too; so do its two
#          shards by configurations (--shard I/2), each over 3 ranks, merged;
#          --runs is refused, and a metric the task lacks at the first look
#          (exit 2, no lock left)
# Environment: GGK (the binary), GGK_SOURCE_DIR, MPIEXEC (launcher with its flags,
# e.g. "mpiexec --oversubscribe --allow-run-as-root"), MPIEXEC_NUMPROC_FLAG.
set -euo pipefail
case_name=$1
scratch=$(mktemp -d "${TMPDIR:-/tmp}/ggk-distributed-XXXXXX")
trap 'rm -rf "$scratch"' EXIT
read -r -a launcher <<<"$MPIEXEC"
np() { printf "%s %s" "${MPIEXEC_NUMPROC_FLAG:--n}" "$1"; }
fail() { echo "FAIL: $*" >&2; exit 1; }
jobs_dir=$GGK_SOURCE_DIR/jobs

# A job's single-process reference file.
reference() { "$GGK" run "$1" -j 2 -q -o "$2" "${@:3}" 2>/dev/null; }

# The first command a ggk message printed in backquotes after "with".
printed_command() { grep -o 'with `[^`]*`' "$1" | head -n 1 | sed 's/^with `//; s/`$//'; }

# Waits that depend on timing poll for their condition and are bounded in
# wall-clock seconds ($SECONDS), not in a count of sleeps, and far beyond what an
# idle machine needs, so that a loaded one (CI beside other work) passes too:
# wait_until SECONDS COMMAND... is true once COMMAND is, false at the deadline.
wait_until() {
  local deadline=$((SECONDS + $1))
  shift
  until "$@"; do
    [ "$SECONDS" -lt "$deadline" ] || return 1
    sleep 0.1
  done
}

# The pid of the ggk process of rank $1 that this test started (empty when none):
# its ranks inherit GGK_DISTRIBUTED_TEST from the launcher (on one host Open MPI
# forks them from mpirun, environment and all), so another job's rank on a
# shared machine is never taken for one, and an orphaned rank still is.
export GGK_DISTRIBUTED_TEST=$scratch
rank_pid() {
  local pid matches
  for pid in $(pgrep -x ggk || true); do
    matches=$(tr '\0' '\n' <"/proc/$pid/environ" 2>/dev/null |
      grep -c -x -e "OMPI_COMM_WORLD_RANK=$1" -e "GGK_DISTRIBUTED_TEST=$scratch" || true)
    if [ "$matches" = 2 ]; then echo "$pid"; fi
  done
}
no_rank_left() { [ -z "$(rank_pid 0)$(rank_pid 1)$(rank_pid 2)" ]; }
file_larger_than() { [ "$(stat -c %s "$1" 2>/dev/null || echo 0)" -gt "$2" ]; }

case $case_name in
ranks)
  reference "$jobs_dir/ci.toml" "$scratch/single.h5"
  for n in 1 2 3 4; do
    # shellcheck disable=SC2046
    "${launcher[@]}" $(np $n) "$GGK" run "$jobs_dir/ci.toml" -j 1 -o "$scratch/np$n.h5" \
      2>"$scratch/np$n.log" || { cat "$scratch/np$n.log"; fail "mpiexec -n $n exited $?"; }
    # Output from rank 0 only: one final line.
    [ "$(grep -c 'runs computed' "$scratch/np$n.log")" = 1 ] || fail "-n $n: not one final line"
    # The progress counts every rank's fits (the workers' heartbeats and results
    # carry their counts): the last line has them all.
    last=$(grep -E '^ggk: runs [0-9]+/[0-9]+, ' "$scratch/np$n.log" | tail -n 1)
    [[ $last =~ fits\ ([0-9]+)/([0-9]+), ]] && [ "${BASH_REMATCH[1]}" = "${BASH_REMATCH[2]}" ] ||
      fail "-n $n: the last progress line does not count every fit: $last"
    "$GGK" diff "$scratch/single.h5" "$scratch/np$n.h5" || fail "-n $n differs from one process"
  done
  # 6 runs on 4 ranks: the last round's 2 runs spread their fits over the ranks
  # (run_pieces.hpp), on 3 ranks none; equal all the same (above).
  grep -q "6 runs computed (2 with their fits spread over ranks)" "$scratch/np4.log" ||
    fail "-n 4: the last round's runs were not spread over the ranks: $(grep 'runs computed' "$scratch/np4.log")"
  grep -q "6 runs computed, " "$scratch/np3.log" || fail "-n 3: runs spread though they fill their rounds"
  # Threads inside ranks too.
  "${launcher[@]}" $(np 2) "$GGK" run "$jobs_dir/ci-khepera.toml" -j 2 -q -o "$scratch/k2.h5"
  reference "$jobs_dir/ci-khepera.toml" "$scratch/k1.h5"
  "$GGK" diff "$scratch/k1.h5" "$scratch/k2.h5" || fail "khepera: 2 ranks x 2 threads differ"
  ;;
shards)
  job=$jobs_dir/ci.toml  # 6 runs
  reference "$job" "$scratch/whole.h5"
  "$GGK" run "$job" -q --runs 0:2 -o "$scratch/a.h5"
  "$GGK" run "$job" -q --runs 2:5 -o "$scratch/b.h5"
  "${launcher[@]}" $(np 2) "$GGK" run "$job" -j 1 -q --runs 5:6 -o "$scratch/c.h5"
  "$GGK" info "$scratch/a.h5" | grep "2 of 6 complete" >/dev/null || fail "shard a: info"
  "$GGK" merge "$scratch/merged.h5" "$scratch/c.h5" "$scratch/a.h5" "$scratch/b.h5"
  "$GGK" diff "$scratch/whole.h5" "$scratch/merged.h5" || fail "merged shards differ from the whole"
  # Refusals: exit 2, no output.
  status=0; "$GGK" run "$job" -q --runs 1:3 -o "$scratch/overlap.h5"
  "$GGK" merge "$scratch/x.h5" "$scratch/a.h5" "$scratch/overlap.h5" 2>"$scratch/err" || status=$?
  [ $status = 2 ] && grep -q "run 1 is complete in both" "$scratch/err" && [ ! -e "$scratch/x.h5" ] ||
    fail "overlap not refused (status $status): $(cat "$scratch/err")"
  status=0; "$GGK" run "$jobs_dir/quick.toml" -q -o "$scratch/other.h5"
  "$GGK" merge "$scratch/x.h5" "$scratch/a.h5" "$scratch/other.h5" 2>"$scratch/err" || status=$?
  [ $status = 2 ] && grep -q "another job" "$scratch/err" && [ ! -e "$scratch/x.h5" ] ||
    fail "foreign shard not refused (status $status): $(cat "$scratch/err")"
  status=0; "$GGK" merge "$scratch/x.h5" "$scratch/a.h5" "$scratch/c.h5" 2>"$scratch/err" || status=$?
  [ $status = 2 ] && grep -q "complete in no shard: 2-4" "$scratch/err" && [ ! -e "$scratch/x.h5" ] ||
    fail "gap not reported (status $status): $(cat "$scratch/err")"
  status=0; "$GGK" run "$job" -q --runs 4:9 -o "$scratch/y.h5" 2>"$scratch/err" || status=$?
  [ $status = 2 ] && grep -q "is not a range of runs" "$scratch/err" || fail "--runs 4:9 accepted"
  # A partial merge, finished by the command it prints, equals the whole; with
  # --set overrides too.
  "$GGK" merge --allow-partial "$scratch/partial.h5" "$scratch/a.h5" "$scratch/c.h5" 2>"$scratch/err"
  bash -c "$(printed_command "$scratch/err")" 2>/dev/null || fail "merge's command: $(cat "$scratch/err")"
  "$GGK" diff "$scratch/whole.h5" "$scratch/partial.h5" || fail "partial merge + resume differs"
  sets=(--set runs=4 --set 'sweep.sigma=[5.0]')
  reference "$job" "$scratch/whole4.h5" "${sets[@]}"
  "$GGK" run "$job" -q "${sets[@]}" --runs 1:2 -o "$scratch/s1.h5" 2>/dev/null
  "$GGK" merge --allow-partial "$scratch/partial4.h5" "$scratch/s1.h5" 2>"$scratch/err"
  bash -c "$(printed_command "$scratch/err")" 2>/dev/null || fail "merge's command: $(cat "$scratch/err")"
  "$GGK" diff "$scratch/whole4.h5" "$scratch/partial4.h5" || fail "partial merge with --set differs"
  # ggk diff itself: another seed differs, with exit 1.
  sed 's/^seed = .*/seed = 99/' "$job" >"$jobs_dir/.distributed-seed-$$.toml"
  trap 'rm -rf "$scratch" "$jobs_dir/.distributed-seed-$$.toml"' EXIT
  "$GGK" run "$jobs_dir/.distributed-seed-$$.toml" -q -o "$scratch/seed.h5"
  status=0; "$GGK" diff "$scratch/whole.h5" "$scratch/seed.h5" >"$scratch/diff" || status=$?
  [ $status = 1 ] && grep -q "^differs: " "$scratch/diff" || fail "ggk diff missed another seed"
  ;;
kill)
  # ci-khepera with 9 runs (~1 s each) in a copy of jobs/, so that the kill lands mid-job.
  mkdir "$scratch/jobs" && cp -r "$jobs_dir/arenas" "$scratch/jobs/"
  sed 's/^runs = .*/runs = 9/' "$jobs_dir/ci-khepera.toml" >"$scratch/jobs/k.toml"
  job=$scratch/jobs/k.toml
  reference "$job" "$scratch/single.h5"
  status=0
  "${launcher[@]}" $(np 3) "$GGK" run "$job" -j 1 -q -o "$scratch/killed.h5" \
    >"$scratch/log" 2>&1 &
  launcher_pid=$!
  # Kill rank 1 once a run has been written (bounded: 240 s).
  wait_until 240 file_larger_than "$scratch/killed.h5" 200000 || fail "no run written in 240 s"
  victim=$(rank_pid 1)
  [ -n "$victim" ] || fail "no rank 1 found"
  kill -9 "$victim"
  wait "$launcher_pid" || status=$?
  [ $status != 0 ] || fail "the job did not stop after its rank 1 was killed"
  grep -Eq "run [0-9]+ on rank 1 \(silent" "$scratch/log" || { cat "$scratch/log"; fail "no message naming rank 1 and its run"; }
  # Named first, not after a "stopped by SIGTERM" that mpirun's SIGKILL may
  # leave alone (stop 41's campaign, F11).
  grep -q "ggk: error: rank 1 .*died or was killed, and mpirun then sent SIGTERM" "$scratch/log" ||
    { cat "$scratch/log"; fail "the dead rank 1 is not named as dead"; }
  ! grep -q "stopped by SIGTERM" "$scratch/log" || { cat "$scratch/log"; fail "the kill of rank 1 was reported as a stop"; }
  grep -q -- "--resume" "$scratch/log" || fail "no hint to resume"
  "$GGK" info "$scratch/killed.h5" | grep "complete"
  "${launcher[@]}" $(np 2) "$GGK" run "$job" -j 1 -q --resume --runs 0:5 -o "$scratch/killed.h5"
  "$GGK" run "$job" -q --resume -o "$scratch/killed.h5"
  "$GGK" diff "$scratch/single.h5" "$scratch/killed.h5" || fail "resumed file differs"
  ;;
interrupt)
  # A stop by the user or a scheduler is an interruption, not a dead rank: the
  # lock is gone and the printed command, pasted into a shell, finishes the job.
  # mpirun's own exit status is 1 whenever mpirun itself was signalled (Open MPI
  # 4.1); the ranks' 128 + signal shows when only they are (a scheduler's stop).
  mkdir "$scratch/jobs" && cp -r "$jobs_dir/arenas" "$scratch/jobs/"
  sed 's/^runs = .*/runs = 3/' "$jobs_dir/ci-khepera.toml" >"$scratch/jobs/k.toml"
  job=$scratch/jobs/k.toml
  sets=(--set runs=7)
  reference "$job" "$scratch/single.h5" "${sets[@]}"
  for how in INT-mpirun TERM-mpirun TERM-ranks; do
    out=$scratch/$how.h5
    set -m  # mpirun in a process group of its own, as a shell's job
    "${launcher[@]}" $(np 3) "$GGK" run "$job" -j 1 -q "${sets[@]}" -o "$out" >"$scratch/log" 2>&1 &
    launcher_pid=$!
    set +m
    wait_until 240 test -e "$out" || fail "$how: no run written in 240 s"
    signal=${how%%-*}
    if [ "${how#*-}" = mpirun ]; then
      kill -s "$signal" "$launcher_pid"
    else
      # shellcheck disable=SC2046
      kill -s "$signal" $(rank_pid 0) $(rank_pid 1) $(rank_pid 2)  # at once, as a scheduler
    fi
    status=0; wait "$launcher_pid" || status=$?
    [ $status != 0 ] || fail "$how: the job did not stop"
    [ "$how" != TERM-ranks ] || [ $status = 143 ] || fail "$how: status $status, not 143"
    grep -q "ggk: stopped by SIG$signal\|ggk: stopped by SIGTERM\|interrupted (SIG$signal)" "$scratch/log" ||
      { cat "$scratch/log"; fail "$how: not reported as an interruption"; }
    ! grep -q "died\|killed" "$scratch/log" || { cat "$scratch/log"; fail "$how: blamed a rank"; }
    [ ! -e "$out.lock" ] || fail "$how: lock file left behind"
    command=$(printed_command "$scratch/log")
    grep -q "under mpirun as before" "$scratch/log" || fail "$how: no word of mpirun"
    # As a person would: the command is pasted once the ranks are gone (a rank
    # still exiting holds the HDF5 file's lock; bounded wait, 120 s).
    wait_until 120 no_rank_left || fail "$how: ranks still running 120 s after the stop"
    bash -c "$command" 2>"$scratch/resume-err" ||
      { cat "$scratch/resume-err" "$scratch/log"; fail "$how: the printed command failed: $command"; }
    "$GGK" diff "$scratch/single.h5" "$out" >/dev/null || fail "$how: resumed results differ"
  done
  ;;
adaptive)
  mkdir "$scratch/jobs" && cp -r "$jobs_dir/maps" "$scratch/jobs/"
  job=$scratch/jobs/ci-adaptive.toml
  cp "$jobs_dir/ci-adaptive.toml" "$job"
  # ~3 s of runs: the interrupt lands mid-study. Kernels 2 and 8: kernels 2's
  # cells decide first, so later runs hold only kernels 8's fits (new runs of
  # some points, sent to the ranks with them).
  sets=(--set maze.series=30 --set 'sweep.kernels=[2, 8]')
  reference "$job" "$scratch/single.h5" "${sets[@]}"
  read -r held whole < <("$GGK" info --adaptive "$scratch/single.h5" |
    sed -n 's/.*holding \([0-9]*\) of their \([0-9]*\) fits.*/\1 \2/p')
  [ -n "$held" ] && [ "$held" -lt "$whole" ] || fail "no fit left out: $held of $whole"
  for n in 1 3; do
    # shellcheck disable=SC2046
    "${launcher[@]}" $(np $n) "$GGK" run "$job" -j 1 "${sets[@]}" -o "$scratch/np$n.h5" \
      2>"$scratch/log" || { cat "$scratch/log"; fail "mpiexec -n $n failed"; }
    grep -q "adaptive: done after" "$scratch/log" || { cat "$scratch/log"; fail "-n $n: no adaptive summary"; }
    "$GGK" diff "$scratch/single.h5" "$scratch/np$n.h5" >/dev/null || fail "-n $n differs from one process"
  done
  out=$scratch/cut.h5
  set -m  # mpirun in a process group of its own, as a shell's job
  # shellcheck disable=SC2046
  "${launcher[@]}" $(np 3) "$GGK" run "$job" -j 1 -q "${sets[@]}" -o "$out" >"$scratch/log" 2>&1 &
  launcher_pid=$!
  set +m
  wait_until 240 test -e "$out" || fail "no run written in 240 s"
  kill -s INT "$launcher_pid"
  status=0; wait "$launcher_pid" || status=$?
  [ $status != 0 ] || { cat "$scratch/log"; fail "the study ended before the interrupt (make it longer)"; }
  ! grep -q "died\|killed" "$scratch/log" || { cat "$scratch/log"; fail "the interrupt blamed a rank"; }
  command=$(printed_command "$scratch/log")
  wait_until 120 no_rank_left || fail "ranks still running 120 s after the stop"
  bash -c "$command" 2>"$scratch/resume-err" ||
    { cat "$scratch/resume-err" "$scratch/log"; fail "the printed command failed: $command"; }
  "$GGK" diff "$scratch/single.h5" "$out" >/dev/null || fail "the interrupted and resumed study differs"
  # shellcheck disable=SC2046
  status=0; "${launcher[@]}" $(np 2) "$GGK" run "$job" -q --runs 0:5 -o "$scratch/part.h5" \
    2>"$scratch/err" || status=$?
  [ $status = 2 ] || fail "--runs under mpirun: status $status: $(cat "$scratch/err")"
  grep -q "without --runs" "$scratch/err" || fail "--runs: $(cat "$scratch/err")"
  # In two shards by run configurations, each over 3 ranks: merged, the same.
  for i in 0 1; do
    # shellcheck disable=SC2046
    "${launcher[@]}" $(np 3) "$GGK" run "$job" -j 1 -q "${sets[@]}" --shard $i/2 \
      -o "$scratch/sh.h5" 2>"$scratch/log" || { cat "$scratch/log"; fail "shard $i/2 failed"; }
  done
  "$GGK" merge "$scratch/sh.h5" "$scratch/sh.shard-0-of-2.h5" "$scratch/sh.shard-1-of-2.h5" \
    2>/dev/null || fail "the shards did not merge"
  "$GGK" diff "$scratch/single.h5" "$scratch/sh.h5" >/dev/null || fail "the merged shards differ"
  # A metric the task lacks is refused at the first look, as in one process:
  # exit 2 naming it, the runs of that look kept, no lock left.
  sed 's/^metrics = .*/metrics = ["nope"]/; s/^correction = .*/&\n[adaptive.range]\nnope = [0, 1]/' \
    "$job" >"$scratch/jobs/nope.toml"
  # shellcheck disable=SC2046
  status=0; "${launcher[@]}" $(np 3) "$GGK" run "$scratch/jobs/nope.toml" -q -j 1 \
    -o "$scratch/nope.h5" >"$scratch/err" 2>&1 || status=$?
  [ $status = 2 ] || { cat "$scratch/err"; fail "a metric the task lacks: status $status"; }
  grep -q "the task reports no metric 'nope'" "$scratch/err" || fail "nope: $(cat "$scratch/err")"
  [ ! -e "$scratch/nope.h5.lock" ] || fail "nope: lock file left behind"
  ;;
*)
  fail "unknown case $case_name"
  ;;
esac
echo "distributed $case_name: ok"
