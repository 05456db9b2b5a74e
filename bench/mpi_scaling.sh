#!/usr/bin/env bash
# Strong scaling of one job over MPI ranks x oneTBB threads, and the per-run cost
# of the MPI hand-out. Self-contained: needs only ggk, mpirun and python3.
#
#   bash bench/mpi_scaling.sh GGK JOB OUTDIR [CORES ...]
#     Each core count c gives c ranks x 1 thread and 1 rank x c threads; a square
#     c = k x k (k > 1) gives k ranks x k threads too. Default cores: 1 2 4 8 16
#     (1..16 ranks x 1, 1 x 1..16 threads, 4 x 4: the issue's khepera-paper study:
#     bash bench/mpi_scaling.sh build/ggk jobs/khepera-paper.toml scaling).
#     On 2 cores: bash bench/mpi_scaling.sh build/ggk jobs/ci-khepera.toml out 1 2
#     Writes OUTDIR/scaling.csv (ranks, threads, cores, seconds of every repetition,
#     median) and OUTDIR/scaling.md: wall time, speedup and efficiency against
#     1 x 1, and per series (ranks, threads) the serial share s of Amdahl's law
#     T(n) = T(1) (s + (1 - s) / n), fitted by least squares. Every file is checked
#     equal to the 1 x 1 one with `ggk diff`.
#
#   bash bench/mpi_scaling.sh --overhead GGK OUTDIR [NP ...]
#     The hand-out's cost per run: a tiny maze job (each run a few ms) at 40 and
#     240 runs, single process -j 1 and mpirun -np NP -j 1 (default NP 2 4 8,
#     oversubscribed when NP exceeds the cores). The slope (240-run time - 40-run
#     time) / 200 is the wall time per run, free of start-up; the intercept is the
#     start-up (mpirun, MPI_Init, opening the file). Writes OUTDIR/overhead.csv and
#     OUTDIR/overhead.md.
#
# REPS=R repeats every configuration R times (default 1; the median is reported).
# MPIRUN (default mpirun) and MPIRUN_FLAGS (default --bind-to none, plus
# --oversubscribe and, as root, --allow-run-as-root) say how ranks start.
set -euo pipefail

usage() {
  sed -n '2,30p' "$0" | sed 's/^# \{0,1\}//' >&2
  exit 2
}
python=python3
[ -x /usr/bin/python3 ] && python=/usr/bin/python3
reps=${REPS:-1}
mpirun_cmd=${MPIRUN:-mpirun}
if [ -z "${MPIRUN_FLAGS+set}" ]; then
  MPIRUN_FLAGS="--bind-to none --oversubscribe"
  [ "$(id -u)" = 0 ] && MPIRUN_FLAGS+=" --allow-run-as-root"
fi

# Seconds (wall) of one ggk run: ranks, threads, job, output, extra ggk arguments.
time_run() {
  local ranks=$1 threads=$2 job=$3 out=$4
  shift 4
  local start end
  start=$(date +%s.%N)
  if [ "$ranks" = 1 ]; then
    "$ggk" run "$job" -j "$threads" -q --overwrite -o "$out" "$@" 2>"$out.log" ||
      { cat "$out.log" >&2; exit 1; }
  else
    # shellcheck disable=SC2086
    "$mpirun_cmd" $MPIRUN_FLAGS -np "$ranks" "$ggk" run "$job" -j "$threads" -q --overwrite \
      -o "$out" "$@" 2>"$out.log" || { cat "$out.log" >&2; exit 1; }
  fi
  end=$(date +%s.%N)
  awk -v a="$end" -v b="$start" 'BEGIN { printf "%.3f", a - b }'
}

median() { printf '%s\n' "$@" | sort -g | awk '{ v[NR] = $1 } END { print (NR % 2 ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2) }'; }

scaling() {
  [ $# -ge 3 ] || usage
  ggk=$(realpath "$1")
  local job=$2 outdir=$3
  shift 3
  local cores=("$@")
  [ ${#cores[@]} -gt 0 ] || cores=(1 2 4 8 16)
  mkdir -p "$outdir"
  # The configurations, 1 x 1 first (the reference for speedup and diff).
  local configs=("1x1") c k
  for c in "${cores[@]}"; do
    [ "$c" = 1 ] && continue
    configs+=("${c}x1" "1x${c}")
  done
  for c in "${cores[@]}"; do
    for k in $(seq 2 "$c"); do
      [ $((k * k)) = "$c" ] && configs+=("${k}x${k}")
    done
  done
  local csv=$outdir/scaling.csv config ranks threads times t
  echo "ranks,threads,cores,median_s,all_s" >"$csv"
  for config in "${configs[@]}"; do
    ranks=${config%x*}
    threads=${config#*x}
    times=()
    for _ in $(seq "$reps"); do
      t=$(time_run "$ranks" "$threads" "$job" "$outdir/$config.h5")
      times+=("$t")
    done
    "$ggk" diff "$outdir/1x1.h5" "$outdir/$config.h5" >/dev/null ||
      { echo "mpi_scaling: $config's results differ from 1 x 1's" >&2; exit 1; }
    echo "$ranks,$threads,$((ranks * threads)),$(median "${times[@]}"),${times[*]}" >>"$csv"
    echo "$config: $(median "${times[@]}") s (${times[*]})" >&2
    [ "$config" = 1x1 ] || rm -f "$outdir/$config.h5"
    rm -f "$outdir/$config.h5.log"
  done
  "$python" - "$csv" "$job" "$reps" >"$outdir/scaling.md" <<'PY'
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
for r in rows:
    r["ranks"], r["threads"], r["cores"] = int(r["ranks"]), int(r["threads"]), int(r["cores"])
    r["t"] = float(r["median_s"])
t1 = next(r["t"] for r in rows if r["cores"] == 1)
print(f"`{sys.argv[2]}`, median of {sys.argv[3]} repetition(s); speedup and efficiency "
      "against 1 rank x 1 thread.\n")
print("| ranks x threads | cores | wall s | speedup | efficiency |")
print("|---|---|---|---|---|")
for r in rows:
    s = t1 / r["t"]
    print(f"| {r['ranks']} x {r['threads']} | {r['cores']} | {r['t']:.2f} | {s:.2f} | "
          f"{100 * s / r['cores']:.0f} % |")
def amdahl(points):
    # T(n) - T1/n = s * T1 (1 - 1/n): least squares for s through the origin.
    a = [t1 * (1 - 1 / n) for n, _ in points]
    b = [t - t1 / n for n, t in points]
    den = sum(x * x for x in a)
    return sum(x * y for x, y in zip(a, b)) / den if den else float("nan")
print()
for name, key, other in (("ranks x 1 thread", "ranks", "threads"),
                         ("1 rank x threads", "threads", "ranks")):
    points = [(r[key], r["t"]) for r in rows if r[other] == 1 and r[key] > 1]
    if points:
        s = amdahl(points)
        print(f"- {name}: Amdahl serial share s = {s:.3f} (fit over n = "
              f"{', '.join(str(n) for n, _ in points)}; speedup limit 1/s = "
              f"{(1 / s if s > 0 else float('inf')):.1f})")
PY
  cat "$outdir/scaling.md"
}

overhead() {
  [ $# -ge 2 ] || usage
  ggk=$(realpath "$1")
  local outdir=$2
  shift 2
  local nps=("$@")
  [ ${#nps[@]} -gt 0 ] || nps=(2 4 8)
  mkdir -p "$outdir"
  # Two small rooms and a corridor (27 states); a run of a few milliseconds:
  # 2 x 50 random steps, 4 kernels, one fit.
  cat >"$outdir/tiny-map.txt" <<'MAP'
#########
#...#...#
#.#.....#
#...#..G#
##.####.#
#.......#
#########
MAP
  cat >"$outdir/tiny.toml" <<'JOB'
name = "tiny"
task = "maze"
runs = 40
seed = 7
[sweep]
basis = ["ggk"]
kernels = [4]
sigma = [10.0]
solver = ["brm"]
[maze]
map_file = "tiny-map.txt"
series = 2
steps_per_series = 50
[lspi]
max_iterations = 5
JOB
  local csv=$outdir/overhead.csv np runs times t
  echo "ranks,runs,median_s,all_s" >"$csv"
  for np in 1 "${nps[@]}"; do
    for runs in 40 240; do
      times=()
      for _ in $(seq "$reps"); do
        t=$(time_run "$np" 1 "$outdir/tiny.toml" "$outdir/tiny-$np-$runs.h5" --set "runs=$runs")
        times+=("$t")
      done
      echo "$np,$runs,$(median "${times[@]}"),${times[*]}" >>"$csv"
      echo "-np $np, $runs runs: $(median "${times[@]}") s (${times[*]})" >&2
      rm -f "$outdir/tiny-$np-$runs.h5" "$outdir/tiny-$np-$runs.h5.log"
    done
  done
  "$python" - "$csv" "$(nproc)" "$reps" >"$outdir/overhead.md" <<'PY'
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
cores = int(sys.argv[2])
t = {(int(r["ranks"]), int(r["runs"])): float(r["median_s"]) for r in rows}
ranks = sorted({n for n, _ in t})
per_run_1 = (t[(1, 240)] - t[(1, 40)]) / 200
print(f"Tiny maze job (one fit per run), -j 1 per rank, {cores} cores, median of "
      f"{sys.argv[3]} repetition(s). Per run: (T(240 runs) - T(40 runs)) / 200; "
      "start-up: T(40) - 40 x per run. Hand-out cost per run: per run minus the "
      "single process's per-run time spread over min(ranks, cores) cores.\n")
print("| ranks | T(40) s | T(240) s | per run ms | start-up s | hand-out ms per run |")
print("|---|---|---|---|---|---|")
for n in ranks:
    per_run = (t[(n, 240)] - t[(n, 40)]) / 200
    startup = t[(n, 40)] - 40 * per_run
    handout = per_run - per_run_1 / min(n, cores) if n > 1 else 0.0
    print(f"| {n} | {t[(n, 40)]:.2f} | {t[(n, 240)]:.2f} | {1000 * per_run:.2f} | "
          f"{startup:.2f} | {'-' if n == 1 else f'{1000 * handout:.2f}'} |")
PY
  cat "$outdir/overhead.md"
}

case "${1:-}" in
  --overhead)
    shift
    overhead "$@"
    ;;
  "" | -h | --help) usage ;;
  *) scaling "$@" ;;
esac
