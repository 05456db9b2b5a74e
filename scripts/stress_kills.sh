#!/usr/bin/env bash
# Kill ggk at random moments and check that --resume always finishes the job to
# the results of an uninterrupted run. Usage:
#   bash scripts/stress_kills.sh [TRIES] [GGK]     (default 50 tries, build/ggk)
# Each try: start the job (or resume the file of the last try), sleep a random
# 0..1.5 s, send SIGKILL, SIGINT or SIGTERM (a third each; some tries kill the
# resume itself), then `ggk run --resume` to the end, `ggk verify` and `ggk diff`
# against the reference. Prints survived / tried and exits 1 on any loss.
set -euo pipefail
tries=${1:-50}
ggk=${2:-build/ggk}
root=$(cd "$(dirname "$0")/.." && pwd)
scratch=$(mktemp -d "${TMPDIR:-/tmp}/ggk-stress-XXXXXX")
trap 'rm -rf "$scratch"' EXIT
cat >"$scratch/job.toml" <<TOML
name = "stress"
task = "maze"
runs = 8
seed = 99
[sweep]
basis = ["ggk", "ogk"]
kernels = [48, 64]
sigma = [10.0]
solver = ["brm", "lstdq"]
[maze]
map_file = "$root/jobs/maps/four-rooms.txt"
series = 20
steps_per_series = 150
[output]
file = "$scratch/default.h5"
TOML
"$ggk" run "$scratch/job.toml" -j 2 -q -o "$scratch/reference.h5" 2>/dev/null
signals=(KILL INT TERM)
survived=0
for try in $(seq "$tries"); do
  out=$scratch/x$try.h5
  signal=${signals[$((RANDOM % 3))]}
  delay=$(printf '0.%03d' $((RANDOM % 1000)))
  [ $((RANDOM % 2)) = 0 ] && delay=1.$((RANDOM % 5))
  set -m  # job control: SIGINT not ignored (ggk keeps an inherited SIG_IGN)
  "$ggk" run "$scratch/job.toml" -j 2 -q -o "$out" 2>/dev/null & pid=$!
  set +m
  sleep "$delay"
  kill -s "$signal" $pid 2>/dev/null || true
  wait $pid 2>/dev/null || true
  # A second kill, of the resume itself, in a third of the tries.
  if [ $((try % 3)) = 0 ]; then
    "$ggk" run "$scratch/job.toml" -j 2 -q --resume -o "$out" 2>/dev/null & pid=$!
    sleep "0.$((RANDOM % 6))"
    kill -s KILL $pid 2>/dev/null || true
    wait $pid 2>/dev/null || true
  fi
  if "$ggk" run "$scratch/job.toml" -j 2 -q --resume -o "$out" 2>"$scratch/err" &&
    "$ggk" verify "$out" >/dev/null && "$ggk" diff "$scratch/reference.h5" "$out" >/dev/null; then
    survived=$((survived + 1))
  else
    echo "try $try (SIG$signal after ${delay}s): LOST: $(head -c 400 "$scratch/err")"
  fi
  rm -f "$out" "$out.part" "$out.lock"
done
echo "kills survived: $survived / $tries"
[ "$survived" = "$tries" ]
