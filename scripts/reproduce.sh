#!/usr/bin/env bash
# The paper's figures in one command: runs the jobs (with --resume, so what is
# already complete is skipped and a killed reproduction continues) and draws
# every figure, then prints the claims table (ggk info of each results file and
# results/claims.py).
#
#   bash scripts/reproduce.sh            # full scale: maze, arm (Figs. 1-3),
#                                        # Khepera (Figs. 4-6) and the rotation-step
#                                        # study (15, 30, 45 degrees in one file;
#                                        # widths x steps 15 and 45),
#                                        # the arm's LSPI iterations (stopping rules),
#                                        # the classic continuous tasks (pendulum,
#                                        # mountain car, acrobot: ggk's additions)
#                                        # -> results/*.h5, results/figures/
#   bash scripts/reproduce.sh --claim-map  # full scale, and the Khepera claim map
#                                        # (jobs/khepera-claim-map.toml, about 9 minutes
#                                        # more at -j 2) -> results/figures/khepera_claim_map.png
#   bash scripts/reproduce.sh --quick    # reduced: the paper's arm and Khepera jobs
#                                        # with fewer runs and kernel counts (--set),
#                                        # under 2 minutes on 2 cores; every figure of
#                                        # the arm and the Khepera, Figs. 1(a) and 4(a)
#                                        # included -> out/quick/*.h5, out/quick/figures/
#   extra arguments go to every `ggk run` (e.g. -j 8)
# Needs build/ggk (scripts/build.sh) and /usr/bin/python3 with h5py, scipy, matplotlib.
set -euo pipefail
cd "$(dirname "$0")/.."
quick=0
claim_map=0
if [ "${1:-}" = "--quick" ]; then
  quick=1
  shift
elif [ "${1:-}" = "--claim-map" ]; then
  claim_map=1
  shift
fi
ggk=${GGK:-build/ggk}  # GGK=path/to/ggk for another build
python=/usr/bin/python3
[ -x "$ggk" ] || { echo "reproduce.sh: no $ggk: run scripts/build.sh first" >&2; exit 2; }

run() {  # job output [extra ggk run arguments]
  local job=$1 out=$2
  shift 2
  echo "== $job -> $out" >&2
  "$ggk" run "$job" -o "$out" --resume "$@"
}

if [ $quick = 1 ]; then
  dir=out/quick
  figures=$dir/figures
  mkdir -p "$figures"
  # The paper-scale samples, graphs and SOM, fewer runs and kernel counts.
  run jobs/arm-paper.toml "$dir/arm.h5" --set runs=10 --set "sweep.kernels=[16,32,64,128]" "$@"
  run jobs/khepera-paper.toml "$dir/khepera.h5" --set runs=4 --set "sweep.kernels=[10,50,100]" \
    --set 'sweep.solver=["brm"]' "$@"
  $python results/plot_arm.py "$dir/arm.h5" "$figures"
  $python results/plot_khepera.py "$dir/khepera.h5" "$figures"
  $python results/plot_arm_workspace.py "$dir/arm.h5" "$figures"        # Fig. 1(a)
  $python results/plot_khepera_arena.py "$dir/khepera.h5" "$figures"    # Fig. 4(a)
  # The classic continuous tasks at their CI size (3 runs; seconds).
  for task in pendulum mountain-car acrobot; do
    run "jobs/ci-$task.toml" "$dir/$task.h5" "$@"
    $python results/plot_continuous.py "$dir/$task.h5" "$figures"
  done
  echo "== claims (reduced: 10, 4 and 3 runs, wide intervals)" >&2
  for f in "$dir/arm.h5" "$dir/khepera.h5" "$dir/pendulum.h5" "$dir/mountain-car.h5" \
    "$dir/acrobot.h5"; do "$ggk" info "$f"; echo; done
  $python results/claims.py --results "$dir"
  echo "reproduce.sh: the reduced reproduction's figures are in $figures/, e.g." \
    "$figures/arm_workspace.png (paper Fig. 1(a)), $figures/arm_success.png (Fig. 3)," \
    "$figures/khepera_arena.png (Fig. 4(a)) and $figures/khepera_return.png (Fig. 6);" \
    "bash scripts/reproduce.sh runs the paper at full scale" >&2
  exit 0
fi

figures=results/figures
mkdir -p "$figures"
run jobs/maze.toml results/maze.h5 "$@"
run jobs/arm-paper.toml results/arm-paper.h5 "$@"
run jobs/khepera-paper.toml results/khepera-paper.h5 "$@"
run jobs/khepera-study.toml results/khepera-study.h5 "$@"
run jobs/khepera-widths-study.toml results/khepera-widths-study.h5 "$@"
# LSPI's stopping rules (README "Why the arm's curve is not monotone"): the arm job
# with every iteration's policy tested, BRM (as the paper) and LSTD-Q, cap 20 and 100.
run jobs/arm-paper.toml results/arm-paper-iterations.h5 --set lspi.evaluate_iterations=true "$@"
run jobs/arm-paper.toml results/arm-paper-lstdq-iterations.h5 --set lspi.evaluate_iterations=true \
  --set 'sweep.solver=["lstdq"]' "$@"
run jobs/arm-paper.toml results/arm-paper-cap100-iterations.h5 --set lspi.evaluate_iterations=true \
  --set lspi.max_iterations=100 "$@"
run jobs/khepera-paper.toml results/khepera-paper-iterations.h5 --set lspi.evaluate_iterations=true "$@"
# The classic continuous tasks (README "Beyond the paper: classic continuous tasks").
for task in pendulum mountain-car acrobot; do
  run "jobs/$task.toml" "results/$task.h5" "$@"
  $python results/plot_continuous.py "results/$task.h5" "$figures"
done
$python results/plot_maze.py results/maze.h5 "$figures"
$python results/plot_arm.py results/arm-paper.h5 "$figures" --kernels 128
$python results/plot_khepera.py results/khepera-paper.h5 "$figures"
for turn in 30 45; do
  $python results/plot_khepera.py results/khepera-study.h5 "$figures" --prefix khepera_turn$turn \
    --where khepera.motion.turn_deg=$turn
done
for f in arm-paper-iterations arm-paper-lstdq-iterations arm-paper-cap100-iterations \
  khepera-paper-iterations; do
  $python results/plot_iterations.py results/$f.h5 "$figures"
done
for extra in results/plot_arm_workspace.py results/plot_khepera_arena.py; do
  # Figures of the simulators' geometry, where this checkout has them.
  if [ -f "$extra" ]; then
    case $extra in
      *arm*) input=results/arm-paper.h5 ;;
      *) input=results/khepera-paper.h5 ;;
    esac
    $python "$extra" "$input" "$figures" || echo "reproduce.sh: warning: $extra failed" >&2
  fi
done
if [ $claim_map = 1 ]; then
  run jobs/khepera-claim-map.toml results/khepera-claim-map.h5 "$@"
  $python results/plot_claim_map.py results/khepera-claim-map.h5 "$figures"
fi
echo "== claims" >&2
for f in results/maze.h5 results/arm-paper.h5 results/khepera-paper.h5 \
  results/khepera-study.h5 results/khepera-widths-study.h5 results/pendulum.h5 \
  results/mountain-car.h5 results/acrobot.h5; do
  "$ggk" info "$f"
  echo
done
$python results/claims.py
echo "reproduce.sh: every figure is in $figures/ (what each shows: README.md)" >&2
