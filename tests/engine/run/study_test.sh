#!/usr/bin/env bash
# Studies (engine/job/study.hpp) through the real ggk binary. One case per call
# (tests/CMakeLists.txt):
#   configuration  a configuration of a study holds exactly what the single job
#                  with its values computes (every dataset of its runs equal);
#                  run r of every configuration draws the same random streams
#                  (an axis that changes only the evaluation leaves the samples
#                  and the graph of run r equal: common random numbers)
#   stages         a fit-level axis (lspi.*) adds fits to the same runs: no
#                  configuration groups, the runs computed once each, each
#                  variant's fits equal to the single job's with that value
#   resume         the command printed on Ctrl-C repeats --sweep and resumes to
#                  the whole study's results; respelled values (0 for 0.0)
#                  resume; other values are refused naming the key; --set or
#                  --sweep without -o is refused (the plain job's output)
#   grow           --resume with more runs or more values of a run-level axis
#                  computes only what is new and equals the larger study from
#                  scratch; fewer are refused, naming what would be dropped
#   grow_fits      --resume with more values of fit-level axes (kernels, solver,
#                  lspi.*) computes only the new fits and equals the larger study
#                  from scratch (maze, Khepera, chain); dropped or reordered
#                  values are refused
#   distributed    mpirun -np 3, and shards merged by --shards-of, equal one
#                  process (ggk diff); a study grown by a kernel count under
#                  mpirun equals it from scratch
# Environment: GGK (the binary), GGK_SOURCE_DIR; MPIEXEC and
# MPIEXEC_NUMPROC_FLAG for `distributed`.
set -euo pipefail
case_name=$1
scratch=$(mktemp -d "${TMPDIR:-/tmp}/ggk-study-XXXXXX")
trap 'rm -rf "$scratch"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }
status_of() { local s=0; "$@" >"$scratch/out" 2>"$scratch/err" || s=$?; echo $s; }

# A small maze job: 3 runs, 4 fits per run.
write_job() {  # file
  mkdir -p "$(dirname "$1")/maps"
  cp "$GGK_SOURCE_DIR/jobs/maps/four-rooms.txt" "$(dirname "$1")/maps/"
  cat >"$1" <<JOB
name = "study"
task = "maze"
runs = 3
seed = 20240601

[sweep]
basis = ["ggk", "ogk"]
kernels = [4, 8]
sigma = [10.0]
solver = ["brm"]
lambda = [1e-6]

[maze]
map_file = "maps/four-rooms.txt"
series = 20
steps_per_series = 200
test_max_steps = 100

[output]
file = "results/study.h5"
JOB
}

# Every dataset under $2 of file $1 equals the one under $4 of file $3; the
# fit_metrics tables compared on the columns both have but fit_seconds. With
# $5 = samples: only samples and graph.
same_groups() {
  /usr/bin/python3 - "$@" <<'PY'
import sys
import h5py
import numpy as np

a_path, a_group, b_path, b_group = sys.argv[1:5]
only = sys.argv[5] if len(sys.argv) > 5 else ""
with h5py.File(a_path, "r") as fa, h5py.File(b_path, "r") as fb:
    a, b = fa[a_group], fb[b_group]
    names = []
    a.visit(lambda name: names.append(name) if isinstance(a[name], h5py.Dataset) else None)
    if only:
        names = [n for n in names if n.split("/")[0] in ("samples", "graph")]
    assert names, f"nothing under {a_group}"
    for name in names:
        x, y = a[name], b[name]
        if name.endswith("fit_metrics"):
            shared = [c for c in x.dtype.names if c in y.dtype.names and c != "fit_seconds"]
            assert shared == [c for c in y.dtype.names if c != "fit_seconds"], name
            for column in shared:
                assert np.array_equal(x[column], y[column]), f"{name}:{column}"
        else:
            assert np.array_equal(x[()], y[()]), name
    print(f"{len(names)} datasets equal")
PY
}

write_job "$scratch/job.toml"
job=$scratch/job.toml
case $case_name in
configuration)
  "$GGK" run "$job" -q -j 2 --sweep maze.slip=0.0,0.2 -o "$scratch/study.h5" 2>/dev/null
  "$GGK" run "$job" -q -j 1 --set maze.slip=0.2 -o "$scratch/single.h5" 2>/dev/null
  for run in run_000 run_001 run_002; do
    same_groups "$scratch/study.h5" "maze/config_001/$run" "$scratch/single.h5" "maze/$run" ||
      fail "configuration 1's $run differs from the single job's"
  done
  # The summary: one typed column for the axis, both configurations' rows.
  /usr/bin/python3 - "$scratch/study.h5" <<'PY' || fail "study summary"
import sys
import h5py
with h5py.File(sys.argv[1], "r") as f:
    s = f["maze/summary"]
    assert s.attrs["study_axes"] == "maze.slip", s.attrs["study_axes"]
    assert s.dtype["maze.slip"].kind == "f", s.dtype
    assert sorted(set(s["maze.slip"])) == [0.0, 0.2]
    assert sorted(set(s["configuration"])) == [0, 1]
    assert len(s) == 2 * 3 * 4
    assert f["maze/config_001"].attrs["study_values"] == "maze.slip = 0.2\n"
PY
  "$GGK" info "$scratch/study.h5" >"$scratch/info"
  grep -q "study: *2 run configurations x 3 runs" "$scratch/info" || fail "info: $(cat "$scratch/info")"
  grep -q "runs: *6 of 6 complete" "$scratch/info" || fail "info: $(cat "$scratch/info")"
  grep -q "maze.slip" "$scratch/info" || fail "info: no axis column"
  "$GGK" verify "$scratch/study.h5" | grep -q "runs: 6 of 6 complete" || fail "verify"
  # Common random numbers: the evaluation's length changes no sample.
  "$GGK" run "$job" -q -j 2 --sweep maze.test_max_steps=50,100 -o "$scratch/crn.h5" 2>/dev/null
  for run in run_000 run_002; do
    same_groups "$scratch/crn.h5" "maze/config_000/$run" "$scratch/crn.h5" "maze/config_001/$run" \
      samples || fail "$run: configurations drew different samples"
  done
  ;;
stages)
  # Slipping moves: the evaluation draws random numbers, which a variant draws
  # as the single job with its value does (the point's stream, not the variant's).
  "$GGK" run "$job" -j 2 --set maze.slip=0.1 --sweep lspi.max_iterations=3,20 \
    -o "$scratch/fits.h5" 2>"$scratch/err"
  grep -q "3 runs computed, 0 already complete, 24 fits" "$scratch/err" ||
    fail "a fit-level axis computed runs again: $(cat "$scratch/err")"
  "$GGK" run "$job" -q -j 1 --set maze.slip=0.1 --set lspi.max_iterations=3 \
    -o "$scratch/three.h5" 2>/dev/null
  /usr/bin/python3 - "$scratch/fits.h5" "$scratch/three.h5" <<'PY' || fail "fit-level variants"
import sys
import h5py
import numpy as np
with h5py.File(sys.argv[1], "r") as study, h5py.File(sys.argv[2], "r") as single:
    assert "config_000" not in study["maze"], "a fit-level axis made configurations"
    for run in ("run_000", "run_002"):
        for name in ("samples/actions", "graph/indices"):
            assert np.array_equal(study[f"maze/{run}/{name}"][()], single[f"maze/{run}/{name}"][()])
        fits = study[f"maze/{run}/fits/ggk"]
        assert sorted(fits) == ["k_0004_sigma10_brm_lambda1e-06_lspi.max_iterations=20",
                                "k_0004_sigma10_brm_lambda1e-06_lspi.max_iterations=3",
                                "k_0008_sigma10_brm_lambda1e-06_lspi.max_iterations=20",
                                "k_0008_sigma10_brm_lambda1e-06_lspi.max_iterations=3"], sorted(fits)
        for k in ("0004", "0008"):
            ours = fits[f"k_{k}_sigma10_brm_lambda1e-06_lspi.max_iterations=3"]
            theirs = single[f"maze/{run}/fits/ggk/k_{k}_sigma10_brm_lambda1e-06"]
            for name in ("weights", "policy", "history/policy_changes"):
                assert np.array_equal(ours[name][()], theirs[name][()]), (run, k, name)
        # Every metric of the variant's rows equals the single job's.
        ours = study[f"maze/{run}/fit_metrics"][()]
        ours = ours[ours["lspi.max_iterations"] == 3]
        theirs = single[f"maze/{run}/fit_metrics"][()]
        for column in ("basis", "kernels", "status", "success_rate", "mean_steps_to_goal",
                       "lspi_iterations"):
            assert np.array_equal(ours[column], theirs[column]), (run, column)
    s = study["maze/summary"]
    assert s.dtype["lspi.max_iterations"].kind == "i" and sorted(set(s["lspi.max_iterations"])) == [3, 20]
PY
  ;;
resume)
  "$GGK" run "$job" -q -j 2 --sweep maze.slip=0.0,0.2 -o "$scratch/whole.h5" 2>/dev/null
  # The output: --sweep and --set never default to the plain job's file.
  s=$(status_of "$GGK" run "$job" --sweep maze.slip=0.0,0.2)
  [ "$s" = 2 ] && grep -q -- "-o FILE.h5" "$scratch/err" || fail "no -o: status $s $(cat "$scratch/err")"
  # Ctrl-C mid-study (slow fits: many kernels), then the printed command.
  sets=(--sweep 'maze.slip=0.0,0.2' --set 'sweep.kernels=[48, 64]' --set 'sweep.sigma=[5.0]')
  "$GGK" run "$job" -q -j 2 "${sets[@]}" -o "$scratch/ref.h5" 2>/dev/null
  out="$scratch/cut it's.h5"
  set -m  # job control: SIGINT not ignored (as a background job of a script starts)
  "$GGK" run "$job" -j 1 "${sets[@]}" -o "$out" 2>"$scratch/err" & pid=$!
  set +m
  # Bounded in wall-clock seconds, far beyond an idle machine's need (a loaded one).
  deadline=$((SECONDS + 240))
  until [ -e "$out" ] || [ "$SECONDS" -ge "$deadline" ]; do sleep 0.05; done
  [ -e "$out" ] || fail "no run written in 240 s"
  kill -INT $pid
  s=0; wait $pid || s=$?
  [ "$s" = 130 ] || fail "SIGINT: status $s: $(cat "$scratch/err")"
  command=$(grep -o 'with `[^`]*`' "$scratch/err" | head -n 1 | sed 's/^with `//; s/`$//')
  case $command in *--sweep*) ;; *) fail "the printed command has no --sweep: $command" ;; esac
  bash -c "$command" 2>"$scratch/resume-err" || fail "the printed command failed: $(cat "$scratch/resume-err")"
  "$GGK" diff "$scratch/ref.h5" "$out" >/dev/null || fail "the resumed study differs"
  # Respelled values are the same study; other values are another.
  s=$(status_of "$GGK" run "$job" -q --sweep maze.slip=0,0.2 -o "$scratch/whole.h5" --resume)
  [ "$s" = 0 ] || fail "0 for 0.0 refused: $(cat "$scratch/err")"
  s=$(status_of "$GGK" run "$job" -q --sweep maze.slip=0.0,0.3 -o "$scratch/whole.h5" --resume)
  [ "$s" = 2 ] && grep -q "maze.slip" "$scratch/err" || fail "other values: status $s $(cat "$scratch/err")"
  ;;
grow)
  # More runs and more values of a run-level axis (inserted: the configurations
  # renumber) compute only what is new, and equal the larger study from scratch.
  "$GGK" run "$job" -q --set runs=2 --sweep maze.slip=0.0,0.2 -o "$scratch/grow.h5" 2>/dev/null
  "$GGK" run "$job" --set runs=3 --sweep maze.slip=0.0,0.1,0.2 -o "$scratch/grow.h5" --resume \
    2>"$scratch/err" || fail "grow: $(cat "$scratch/err")"
  grep -q "5 runs computed, 4 already complete" "$scratch/err" || fail "grow computed: $(cat "$scratch/err")"
  grep -q "growing $scratch/grow.h5" "$scratch/err" || fail "grow said nothing: $(cat "$scratch/err")"
  "$GGK" run "$job" -q --set runs=3 --sweep maze.slip=0.0,0.1,0.2 -o "$scratch/whole.h5" 2>/dev/null
  "$GGK" diff "$scratch/whole.h5" "$scratch/grow.h5" || fail "the grown study differs from the whole"
  # A plain job grows by runs.
  "$GGK" run "$job" -q --set runs=1 -o "$scratch/plain.h5" 2>/dev/null
  "$GGK" run "$job" -q --set runs=3 -o "$scratch/plain.h5" --resume 2>"$scratch/err"
  [ ! -s "$scratch/err" ] || fail "-q printed: $(cat "$scratch/err")"  # issue 37: no "growing"
  "$GGK" run "$job" -q --set runs=3 -o "$scratch/plain3.h5" 2>/dev/null
  "$GGK" diff "$scratch/plain3.h5" "$scratch/plain.h5" >/dev/null || fail "the grown job differs"
  # Fewer runs or values would drop results: refused, naming them.
  s=$(status_of "$GGK" run "$job" -q --set runs=3 --sweep maze.slip=0.0,0.2 -o "$scratch/grow.h5" --resume)
  [ "$s" = 2 ] && grep -q "drops maze.slip = 0.1" "$scratch/err" || fail "dropped value: $s $(cat "$scratch/err")"
  s=$(status_of "$GGK" run "$job" -q --set runs=2 --sweep maze.slip=0.0,0.1,0.2 -o "$scratch/grow.h5" --resume)
  [ "$s" = 2 ] && grep -q "would drop runs 2..2" "$scratch/err" || fail "dropped runs: $s $(cat "$scratch/err")"
  "$GGK" diff "$scratch/whole.h5" "$scratch/grow.h5" >/dev/null || fail "a refusal changed the file"
  # A resume killed while it renumbered (a group still under its moving_ name)
  # is finished by the next resume.
  "$GGK" run "$job" -q --set runs=2 --sweep maze.slip=0.0,0.2 -o "$scratch/cut.h5" 2>/dev/null
  /usr/bin/python3 - "$scratch/cut.h5" <<'PY'
import sys
import h5py
with h5py.File(sys.argv[1], "r+") as f:
    f.move("maze/config_001", "maze/moving_config_002")
PY
  "$GGK" run "$job" -q --set runs=3 --sweep maze.slip=0.0,0.1,0.2 -o "$scratch/cut.h5" --resume \
    2>"$scratch/err" || fail "after a cut renumbering: $(cat "$scratch/err")"
  "$GGK" diff "$scratch/whole.h5" "$scratch/cut.h5" >/dev/null || fail "the cut renumbering differs"
  ;;
grow_fits)
  # More values of fit-level axes (a kernel count inserted, a basis, an lspi.*
  # axis), with more runs: only the new fits are computed, and the file equals
  # the larger study from scratch; for the maze, the Khepera (noisy tests: every
  # fit of a run meets the same test noise) and the chain.
  "$GGK" run "$job" -q --set runs=2 --sweep kernels=4,12 -o "$scratch/fits.h5" 2>/dev/null
  "$GGK" run "$job" --set runs=3 --sweep kernels=4,8,12 -o "$scratch/fits.h5" --resume \
    2>"$scratch/err" || fail "grow by kernels: $(cat "$scratch/err")"
  # Runs 0, 1: 2 new fits each (kernels 8, both bases); run 2: all 6.
  grep -q "3 runs computed, 0 already complete, 10 fits" "$scratch/err" ||
    fail "grow by kernels computed: $(cat "$scratch/err")"
  "$GGK" run "$job" -q --set runs=3 --sweep kernels=4,8,12 -o "$scratch/fits-whole.h5" 2>/dev/null
  "$GGK" diff "$scratch/fits-whole.h5" "$scratch/fits.h5" || fail "grown by kernels: differs"
  # A fit-level study axis and a solver added, on runs 0..1 first (--runs):
  # a file with runs grown and runs not grown yet resumes to the whole.
  sets=(--set runs=3 --sweep kernels=4,8,12 --sweep 'solver=brm,lstdq'
    --sweep lspi.max_iterations=3,20)
  "$GGK" run "$job" -q --set runs=3 --sweep kernels=4,8,12 --sweep lspi.max_iterations=20 \
    -o "$scratch/lspi.h5" 2>/dev/null
  "$GGK" run "$job" -q "${sets[@]}" --runs 0:2 -o "$scratch/lspi.h5" --resume 2>/dev/null ||
    fail "grow by solver and lspi on runs 0..1"
  "$GGK" run "$job" "${sets[@]}" -o "$scratch/lspi.h5" --resume 2>"$scratch/err" ||
    fail "grow the rest: $(cat "$scratch/err")"
  grep -q "1 runs computed, 2 already complete, 18 fits" "$scratch/err" ||
    fail "grow the rest computed: $(cat "$scratch/err")"
  "$GGK" run "$job" -q "${sets[@]}" -o "$scratch/lspi-whole.h5" 2>/dev/null
  "$GGK" diff "$scratch/lspi-whole.h5" "$scratch/lspi.h5" || fail "grown by solver and lspi: differs"
  # Dropped or reordered fit-level values are refused, the file left as it was.
  cp "$scratch/lspi.h5" "$scratch/before.h5"
  s=$(status_of "$GGK" run "$job" -q --set runs=3 --sweep kernels=4,12 --sweep 'solver=brm,lstdq' \
    --sweep lspi.max_iterations=3,20 -o "$scratch/lspi.h5" --resume)
  [ "$s" = 2 ] && grep -q "drops sweep.kernels = 8, whose fits" "$scratch/err" ||
    fail "dropped kernel count: $s $(cat "$scratch/err")"
  s=$(status_of "$GGK" run "$job" -q --set runs=3 --sweep kernels=12,8,4 --sweep 'solver=brm,lstdq' \
    --sweep lspi.max_iterations=3,20 -o "$scratch/lspi.h5" --resume)
  [ "$s" = 2 ] && grep -q "lists the values of sweep.kernels in another order" "$scratch/err" ||
    fail "reordered kernel counts: $s $(cat "$scratch/err")"
  cmp -s "$scratch/before.h5" "$scratch/lspi.h5" || fail "a refusal changed the file"
  # The Khepera and the chain: noisy tests, other graphs.
  for task_job in ci-khepera ci-chain; do
    ci_job=$GGK_SOURCE_DIR/jobs/$task_job.toml
    kernels=$(/usr/bin/python3 -c "import tomllib,sys; print(','.join(map(str,
      tomllib.load(open(sys.argv[1],'rb'))['sweep']['kernels'])))" "$ci_job")
    first=${kernels%%,*}
    "$GGK" run "$ci_job" -q -j 2 --sweep "kernels=$first" -o "$scratch/$task_job.h5" 2>/dev/null
    "$GGK" run "$ci_job" -q -j 2 --sweep "kernels=$kernels" -o "$scratch/$task_job.h5" --resume \
      2>/dev/null || fail "$task_job: grow by kernels"
    "$GGK" run "$ci_job" -q -j 2 --sweep "kernels=$kernels" -o "$scratch/$task_job-whole.h5" \
      2>/dev/null
    "$GGK" diff "$scratch/$task_job-whole.h5" "$scratch/$task_job.h5" ||
      fail "$task_job: grown by kernels differs"
  done
  ;;
distributed)
  read -r -a launcher <<<"$MPIEXEC"
  sets=(--sweep maze.slip=0.0,0.2 --sweep lspi.max_iterations=3,20)
  "$GGK" run "$job" -q -j 2 "${sets[@]}" -o "$scratch/one.h5" 2>/dev/null
  "${launcher[@]}" "${MPIEXEC_NUMPROC_FLAG:--n}" 3 "$GGK" run "$job" -q -j 1 "${sets[@]}" \
    -o "$scratch/mpi.h5" 2>"$scratch/err" || fail "mpirun: $(cat "$scratch/err")"
  "$GGK" diff "$scratch/one.h5" "$scratch/mpi.h5" || fail "3 ranks differ from one process"
  for i in 0 1; do
    "$GGK" run "$job" -q "${sets[@]}" --shard "$i/2" -o "$scratch/sharded.h5" 2>/dev/null
  done
  "$GGK" merge "$scratch/sharded.h5" "$scratch/sharded.shard-0-of-2.h5" \
    "$scratch/sharded.shard-1-of-2.h5" 2>/dev/null
  "$GGK" diff "$scratch/one.h5" "$scratch/sharded.h5" || fail "merged shards differ"
  # Grown by a kernel count under mpirun: other ranks compute the extensions.
  "$GGK" run "$job" -q --sweep kernels=4 -o "$scratch/mpi-grow.h5" 2>/dev/null
  "${launcher[@]}" "${MPIEXEC_NUMPROC_FLAG:--n}" 3 "$GGK" run "$job" -q -j 1 --sweep kernels=4,8 \
    -o "$scratch/mpi-grow.h5" --resume 2>"$scratch/err" || fail "mpirun grow: $(cat "$scratch/err")"
  "$GGK" run "$job" -q --sweep kernels=4,8 -o "$scratch/grow-whole.h5" 2>/dev/null
  "$GGK" diff "$scratch/grow-whole.h5" "$scratch/mpi-grow.h5" || fail "grown under mpirun differs"
  ;;
*)
  fail "unknown case $case_name"
  ;;
esac
echo "study $case_name: ok"
