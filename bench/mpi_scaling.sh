#!/usr/bin/env bash
# Wall time of one job over MPI ranks x oneTBB threads, median of R repetitions,
# each configuration's file checked equal to the first with `ggk diff`.
#   bash bench/mpi_scaling.sh [JOB] [R] [RANKSxTHREADS ...]
# Default: jobs/ci-khepera.toml, 3 repetitions, 1x2 2x1 (this 2-core machine).
# On a 16-core machine: bash bench/mpi_scaling.sh jobs/ci-khepera.toml 3 1x1 2x1 4x1 8x1 16x1 1x16
set -euo pipefail
cd "$(dirname "$0")/.."
job=${1:-jobs/ci-khepera.toml}
reps=${2:-3}
shift $(( $# > 2 ? 2 : $# ))
configs=("$@")
[ ${#configs[@]} -gt 0 ] || configs=(1x2 2x1)
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
root=""
[ "$(id -u)" = 0 ] && root=--allow-run-as-root
printf '%-8s %10s  %s\n' "ranks x threads" "median s" "all s"
for config in "${configs[@]}"; do
  ranks=${config%x*}; threads=${config#*x}
  times=()
  for r in $(seq "$reps"); do
    start=$(date +%s.%N)
    if [ "$ranks" = 1 ]; then
      build/ggk run "$job" -j "$threads" -q --overwrite -o "$out/$config.h5" 2>/dev/null
    else
      mpirun $root --oversubscribe -np "$ranks" build/ggk run "$job" -j "$threads" -q \
        --overwrite -o "$out/$config.h5" 2>/dev/null
    fi
    times+=("$(awk -v a="$(date +%s.%N)" -v b="$start" 'BEGIN { printf "%.2f", a - b }')")
  done
  median=$(printf '%s\n' "${times[@]}" | sort -n | sed -n "$(( (reps + 1) / 2 ))p")
  printf '%-15s %10.2f  %s\n' "$config" "$median" "${times[*]}"
  [ -e "$out/first.h5" ] || cp "$out/$config.h5" "$out/first.h5"
  build/ggk diff "$out/first.h5" "$out/$config.h5" >/dev/null || echo "  $config: results differ!"
done
