#!/usr/bin/env bash
# The fault harness: ggk attacked at random, and what must survive. Usage:
#   bash scripts/stress_kills.sh [--class CLASS] [TRIES] [GGK]
# CLASS (default kills; `all` runs every class with TRIES each), TRIES (default
# 50), GGK (default build/ggk). Each class prints "CLASS survived: S / T" and
# the script exits 1 if any try lost something:
#   kills            start the job (or resume the file of the last try), sleep a
#                    random 0..1.5 s, send SIGKILL, SIGINT or SIGTERM (some tries
#                    kill the resume too), then --resume to the end: `ggk verify`
#                    clean and `ggk diff` equal to an uninterrupted run
#   mpi_kills        the same under `mpirun -np 3` (needs mpirun): SIGINT or
#                    SIGTERM to mpirun, or SIGKILL to one rank; --resume under
#                    mpirun again (or a single process in every other try)
#   hostile_shards   two --runs shards, the second with 1..4 random bytes
#                    overwritten; `ggk merge` either writes the whole job's
#                    results (diff equal) or refuses (exit 1 or 2) leaving no
#                    output, no .merging file and no lock; never a crash or hang
#   hostile_results  a complete results file with random bytes overwritten, or
#                    cut at a random length; info, verify and diff end with 0, 1
#                    or 2 (no crash, no hang, no "internal error"), and --resume
#                    finishes to the reference or refuses (exit 2) leaving the
#                    file as it was
#   hostile_lengths  a complete results file with one string's stored length set
#                    to 1..4 GB; info, verify, diff and --resume answer within
#                    1.4 GB of resident memory (the reading room's bound), and
#                    the resumed file equals the reference
#   tight_memory     info, verify and diff of a whole file under ulimit -v of
#                    108..140 MB: read, or "not enough memory" (exit 2); never
#                    DAMAGED, never a crash
#   reading_stops    SIGTERM to ggk, or SIGINT to its group, while --resume reads
#                    its output back: the resume command printed, no lock, the
#                    file as it was, no reading child left; it then finishes
#   open_readers     an h5py handle open on the file while --resume starts: the
#                    resume finishes to the reference
#   resume_overrides a job with --set and --sweep overrides stopped by SIGINT or
#                    SIGTERM; the resume command ggk printed, pasted into a
#                    shell, finishes to the overridden job's reference
# STRESS_SEED=N seeds bash's RANDOM: the same tries again (the files ggk writes
# are bit-identical, so the same bytes are overwritten). CI runs every class
# with 2 tries and a fixed seed (.ci/run); a campaign: TRIES 50 or more, no seed.
# A try that loses is reported with what it did (and, for hostile_results, the
# input kept under $TMPDIR).
set -euo pipefail
if [ -n "${STRESS_SEED:-}" ]; then RANDOM=$STRESS_SEED; fi
class=kills
if [ "${1:-}" = "--class" ]; then
  class=$2
  shift 2
fi
tries=${1:-50}
ggk=${2:-build/ggk}
root=$(cd "$(dirname "$0")/.." && pwd)
scratch=$(mktemp -d "${TMPDIR:-/tmp}/ggk-stress-XXXXXX")
trap 'rm -rf "$scratch"' EXIT
limit=120  # seconds: any command of ggk that takes longer hangs
lost=0

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

reference=$scratch/reference.h5
"$ggk" run "$scratch/job.toml" -j 2 -q -o "$reference" 2>/dev/null

# Finishes $1 with --resume (extra arguments: a launcher before ggk) and checks it.
finished_equal() {  # out [launcher...]
  local out=$1
  shift
  timeout "$limit" "$@" "$ggk" run "$scratch/job.toml" -j 2 -q --resume -o "$out" \
    2>"$scratch/err" && "$ggk" verify "$out" >/dev/null &&
    "$ggk" diff "$reference" "$out" >/dev/null
}

report() {  # class survived tries
  echo "$1 survived: $2 / $3"
  [ "$2" = "$3" ] || lost=1
}

random_delay() {  # 0.000..0.999 s, or 1.0..1.4 s in half the calls
  if [ $((RANDOM % 2)) = 0 ]; then echo "1.$((RANDOM % 5))"; else printf '0.%03d' $((RANDOM % 1000)); fi
}

# Overwrites `count` random bytes of a file with random values.
overwrite_random_bytes() {  # file count
  local size
  size=$(stat -c %s "$1")
  for _ in $(seq "$2"); do
    printf "\\x$(printf %02x $((RANDOM % 256)))" |
      dd of="$1" bs=1 seek=$(((RANDOM * 32768 + RANDOM) % size)) conv=notrunc 2>/dev/null
  done
}

# 0, 1 and 2 are answers; a signal (>= 124: timeout, crash) or "internal error" is not.
answered() {  # status errfile
  [ "$1" -le 2 ] && ! grep -q "internal error" "$2"
}

kills() {
  local signals=(KILL INT TERM) survived=0 try out signal delay pid
  for try in $(seq "$tries"); do
    out=$scratch/x$try.h5
    signal=${signals[$((RANDOM % 3))]}
    delay=$(random_delay)
    set -m  # job control: SIGINT not ignored (ggk keeps an inherited SIG_IGN)
    "$ggk" run "$scratch/job.toml" -j 2 -q -o "$out" 2>/dev/null &
    pid=$!
    set +m
    sleep "$delay"
    kill -s "$signal" $pid 2>/dev/null || true
    wait $pid 2>/dev/null || true
    if [ $((try % 3)) = 0 ]; then  # a second kill, of the resume itself
      "$ggk" run "$scratch/job.toml" -j 2 -q --resume -o "$out" 2>/dev/null &
      pid=$!
      sleep "0.$((RANDOM % 6))"
      kill -s KILL $pid 2>/dev/null || true
      wait $pid 2>/dev/null || true
    fi
    if finished_equal "$out"; then
      survived=$((survived + 1))
    else
      echo "kills try $try (SIG$signal after ${delay}s): LOST: $(head -c 400 "$scratch/err")"
    fi
    rm -f "$out" "$out.part" "$out.lock"
  done
  report kills $survived "$tries"
}

mpi_kills() {
  if ! command -v mpirun >/dev/null; then
    echo "mpi_kills: skipped (no mpirun)"
    return
  fi
  local mpi=(mpirun --allow-run-as-root --oversubscribe -np 3) survived=0 try out what delay pid rank
  for try in $(seq "$tries"); do
    out=$scratch/m$try.h5
    delay=$(random_delay)
    "${mpi[@]}" "$ggk" run "$scratch/job.toml" -j 1 -q -o "$out" >/dev/null 2>&1 &
    pid=$!
    sleep "$delay"
    case $((RANDOM % 3)) in
    0) what="SIGINT to mpirun"; kill -s INT $pid 2>/dev/null || true ;;
    1) what="SIGTERM to mpirun"; kill -s TERM $pid 2>/dev/null || true ;;
    *)
      # A rank's command line starts with ggk's; mpirun's holds the same words
      # after its options: anchored, so the kill goes to a rank, never to mpirun
      # (whose ranks, orphaned, would run on holding the output's lock).
      rank=$(pgrep -f "^$ggk run $scratch/job.toml -j 1 -q -o $out" | shuf -n 1 || true)
      what="SIGKILL to rank process ${rank:-none}"
      [ -n "$rank" ] && kill -s KILL "$rank" 2>/dev/null || true
      ;;
    esac
    timeout "$limit" tail --pid=$pid -f /dev/null || true
    wait $pid 2>/dev/null || true
    local launcher=("${mpi[@]}")
    [ $((try % 2)) = 0 ] && launcher=()
    if finished_equal "$out" "${launcher[@]}"; then
      survived=$((survived + 1))
    else
      echo "mpi_kills try $try ($what after ${delay}s): LOST: $(head -c 400 "$scratch/err")"
    fi
    rm -f "$out" "$out.part" "$out.lock"
  done
  report mpi_kills $survived "$tries"
}

hostile_shards() {
  local survived=0 try merged s bytes
  "$ggk" run "$scratch/job.toml" -j 2 -q --runs 0:4 -o "$scratch/first.h5" 2>/dev/null
  "$ggk" run "$scratch/job.toml" -j 2 -q --runs 4:8 -o "$scratch/second.h5" 2>/dev/null
  for try in $(seq "$tries"); do
    cp "$scratch/second.h5" "$scratch/hostile.h5"
    bytes=$((1 + RANDOM % 4))
    overwrite_random_bytes "$scratch/hostile.h5" $bytes
    merged=$scratch/merged$try.h5
    s=0
    timeout "$limit" "$ggk" merge "$merged" "$scratch/first.h5" "$scratch/hostile.h5" \
      >/dev/null 2>"$scratch/err" || s=$?
    if answered $s "$scratch/err" &&
      { { [ $s = 0 ] && "$ggk" diff "$reference" "$merged" >/dev/null; } ||
        { [ $s != 0 ] && [ ! -e "$merged" ] && ! ls "$merged".* >/dev/null 2>&1; }; }; then
      survived=$((survived + 1))
    else
      echo "hostile_shards try $try ($bytes bytes): LOST: status $s: $(head -c 400 "$scratch/err")"
    fi
    rm -f "$merged" "$merged".*
  done
  report hostile_shards $survived "$tries"
}

hostile_results() {
  local survived=0 try out what s ok command
  for try in $(seq "$tries"); do
    out=$scratch/h$try.h5
    cp "$reference" "$out"
    if [ $((try % 3)) = 0 ]; then
      what="cut to $((RANDOM % 100)) %"
      truncate -s $(($(stat -c %s "$out") * ${what//[^0-9]/} / 100)) "$out"
    else
      what="$((1 + RANDOM % 8)) bytes overwritten"
      overwrite_random_bytes "$out" "${what%% *}"
    fi
    cp "$out" "$scratch/before.h5"
    ok=1
    for command in info verify diff; do
      s=0
      if [ $command = diff ]; then
        timeout "$limit" "$ggk" diff "$reference" "$out" >/dev/null 2>"$scratch/err" || s=$?
      else
        timeout "$limit" "$ggk" $command "$out" >/dev/null 2>"$scratch/err" || s=$?
      fi
      answered $s "$scratch/err" || {
        ok=0
        echo "hostile_results try $try ($what): ggk $command: status $s: $(head -c 300 "$scratch/err")"
      }
    done
    s=0
    finished_equal "$out" || s=$?
    if [ $s != 0 ]; then
      # Refused with exit 2 and the file as it was is an answer; anything else loses.
      if ! grep -q "^ggk: error:" "$scratch/err" || ! cmp -s "$out" "$scratch/before.h5" ||
        grep -q "internal error" "$scratch/err"; then
        ok=0
        echo "hostile_results try $try ($what): --resume: $(head -c 400 "$scratch/err")"
      fi
    fi
    if [ $ok = 1 ]; then
      survived=$((survived + 1))
    else  # kept for a look: the damaged input, and what --resume made of it
      cp "$scratch/before.h5" "${TMPDIR:-/tmp}/ggk-stress-lost-$try.input.h5"
      cp "$out" "${TMPDIR:-/tmp}/ggk-stress-lost-$try.resumed.h5"
      echo "  kept as ${TMPDIR:-/tmp}/ggk-stress-lost-$try.{input,resumed}.h5"
    fi
    rm -f "$out" "$out".* "$scratch"/h$try.damaged*.h5
  done
  report hostile_results $survived "$tries"
}

# Sets the stored length of one variable-length string value of file $1 (the
# index picks which, modulo their number) to a random 1..4 GB, as a fuzzed byte
# did in stop 41's campaign (F1): HDF5 allocates such a length before it sees
# the damage. Prints what it did.
damage_string_length() {  # file index
  /usr/bin/python3 - "$1" "$2" "$((RANDOM * 32768 + RANDOM))" <<'PY'
import re, struct, sys
path, index, noise = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
data = bytearray(open(path, "rb").read())
heaps = {m.start() for m in re.finditer(b"GCOL", data)}
# A value on disk: its length (uint32), its heap collection's address (uint64),
# the object's index (uint32).
found = [i for i in range(len(data) - 16)
         if struct.unpack_from("<Q", data, i + 4)[0] in heaps
         and 0 < struct.unpack_from("<I", data, i)[0] < 4096]
length = (1 << 30) + noise % (3 << 30)
at = found[index % len(found)]
struct.pack_into("<I", data, at, length)
open(path, "wb").write(data)
print(f"string value at byte {at} (of {len(found)}) claims {length} bytes")
PY
}

# Runs a command; prints its status and the peak resident memory, in MB, of it
# and every process it waited for (ggk reads in a child).
peak_of() {
  /usr/bin/python3 -c '
import resource, subprocess, sys
status = subprocess.run(sys.argv[2:], stdout=subprocess.DEVNULL, stderr=open(sys.argv[1], "w")).returncode
print(status, resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss // 1024)' "$scratch/err" "$@"
}

# F1: a damaged string length: info, verify, diff and --resume answer within
# 1.4 GB of resident memory, and the resumed file equals the reference. The room
# a reader allows itself (engine/run/reading_memory_cap.hpp: 1 GiB + 16 x the
# file beyond what it holds) lets a length of up to ~1.1 GB be read, one beyond
# it fails at once; before, every length was read: 2.2 to 2.9 GB of RSS for
# lengths of 1.1 to 1.5 GB, and up to the OOM killer.
hostile_lengths() {
  local survived=0 try out what s peak ok command
  for try in $(seq "$tries"); do
    out=$scratch/l$try.h5
    cp "$reference" "$out"
    what=$(damage_string_length "$out" $RANDOM)
    ok=1
    for command in info verify diff resume; do
      case $command in
      diff) read -r s peak < <(peak_of timeout "$limit" "$ggk" diff "$reference" "$out") ;;
      resume) read -r s peak < <(peak_of timeout "$limit" "$ggk" run "$scratch/job.toml" -j 2 -q --resume -o "$out") ;;
      *) read -r s peak < <(peak_of timeout "$limit" "$ggk" $command "$out") ;;
      esac
      if ! answered "$s" "$scratch/err" || [ "$peak" -gt 1400 ]; then
        ok=0
        echo "hostile_lengths try $try ($what): ggk $command: status $s, peak $peak MB: $(head -c 300 "$scratch/err")"
      fi
    done
    "$ggk" diff "$reference" "$out" >/dev/null 2>&1 || {
      ok=0
      echo "hostile_lengths try $try ($what): the resumed file differs from the reference"
    }
    [ $ok = 1 ] && survived=$((survived + 1))
    rm -f "$out" "$out".* "$scratch"/l$try.damaged*.h5
  done
  report hostile_lengths $survived "$tries"
}

# F2: a whole file read under a tight address-space limit (ulimit -v, 108..140
# MB): info, verify and diff read it or say "not enough memory" (exit 2); never
# DAMAGED, never a crash. (Below ~105 MB OpenBLAS cannot start its threads when
# it loads, below ~95 MB the loader cannot map the libraries, both before ggk
# runs: their own messages, exit 130 and 127, tolerated here.)
tight_memory() {
  local survived=0 try megabytes command s ok
  for try in $(seq "$tries"); do
    megabytes=$((108 + RANDOM % 33))
    ok=1
    for command in info verify diff; do
      s=0
      if [ $command = diff ]; then
        timeout "$limit" prlimit --as=$((megabytes * 1000000)) "$ggk" diff "$reference" "$reference" >"$scratch/out" 2>"$scratch/err" || s=$?
      else
        timeout "$limit" prlimit --as=$((megabytes * 1000000)) "$ggk" $command "$reference" >"$scratch/out" 2>"$scratch/err" || s=$?
      fi
      # Before ggk runs: the loader, or OpenBLAS starting its threads as it loads.
      [ $s = 127 ] && grep -q "error while loading shared libraries" "$scratch/err" && continue
      [ $s = 130 ] && grep -q "OpenBLAS blas_thread_init" "$scratch/err" && continue
      if [ $s = 1 ] || ! answered $s "$scratch/err" || grep -q DAMAGED "$scratch/out" ||
        { [ $s = 2 ] && ! grep -q "not enough memory" "$scratch/err"; }; then
        ok=0
        echo "tight_memory try $try (${megabytes} MB): ggk $command: status $s: $(head -c 300 "$scratch/out" "$scratch/err")"
      fi
    done
    [ $ok = 1 ] && survived=$((survived + 1))
  done
  report tight_memory $survived "$tries"
}

# F3: SIGTERM to ggk alone, or SIGINT to its process group, while --resume
# reads its output back (in a child): the resume command is printed, no lock is
# left, the file is as it was, no reading child outlives ggk, and the printed
# command finishes the job.
reading_stops() {
  local survived=0 try out signal pid child s ok
  for try in $(seq "$tries"); do
    out=$scratch/s$try.h5
    cp "$reference" "$out"
    signal=$([ $((RANDOM % 2)) = 0 ] && echo INT || echo TERM)
    set -m
    "$ggk" run "$scratch/job.toml" -j 2 --resume -o "$out" 2>"$scratch/err" &
    pid=$!
    set +m
    child=
    for _ in $(seq 400); do  # the reading child, within 2 s
      child=$(pgrep -P $pid || true)
      [ -n "$child" ] && break
      sleep 0.005
    done
    sleep "0.0$((RANDOM % 10))"
    if [ $signal = TERM ]; then kill -TERM $pid 2>/dev/null; else kill -INT -- -$pid 2>/dev/null; fi
    s=0
    wait $pid 2>/dev/null || s=$?
    ok=1
    if [ $s = 0 ]; then
      :  # the reading ended before the signal: the job was already complete
    elif ! grep -q "finish the job with" "$scratch/err"; then
      ok="no resume command: $(head -c 300 "$scratch/err")"
    elif [ -e "$out.lock" ]; then
      ok="the lock was left"
    elif ! cmp -s "$out" "$reference"; then
      ok="the file changed"
    fi
    sleep 0.2  # a zombie (dead, its new parent has not reaped it yet) is no reader
    if [ -n "$child" ] && kill -0 "$child" 2>/dev/null &&
      [[ "$(ps -o stat= -p "$child" 2>/dev/null)" != Z* ]]; then
      ok="the reading child $child outlived ggk"
    fi
    finished_equal "$out" || ok="the resume did not finish equal: $(head -c 300 "$scratch/err")"
    if [ "$ok" = 1 ]; then
      survived=$((survived + 1))
    else
      echo "reading_stops try $try (SIG$signal, status $s): LOST: $ok"
    fi
    rm -f "$out" "$out".*
  done
  report reading_stops $survived "$tries"
}

# F5: a reader holding the file open (h5py, as a notebook does) while --resume
# starts: the resume goes on (HDF5's own file lock gives way to ggk's lock).
open_readers() {
  local survived=0 try out reader
  for try in $(seq "$tries"); do
    out=$scratch/o$try.h5
    "$ggk" run "$scratch/job.toml" -j 2 -q --runs 0:$((1 + RANDOM % 6)) -o "$out" 2>/dev/null
    /usr/bin/python3 -c 'import h5py, sys, time
f = h5py.File(sys.argv[1], "r")
time.sleep(30)' "$out" &
    reader=$!
    sleep 1
    if timeout "$limit" "$ggk" run "$scratch/job.toml" -j 2 -q --resume -o "$out" 2>"$scratch/err" &&
      "$ggk" diff "$reference" "$out" >/dev/null; then
      survived=$((survived + 1))
    else
      echo "open_readers try $try: LOST: $(head -c 400 "$scratch/err")"
    fi
    kill $reader 2>/dev/null || true
    wait $reader 2>/dev/null || true
    rm -f "$out" "$out".*
  done
  report open_readers $survived "$tries"
}

resume_overrides() {
  local overrides=(--set 'lspi.max_iterations=15' --sweep 'kernels=32,48')
  local survived=0 try out signal delay pid command s
  "$ggk" run "$scratch/job.toml" "${overrides[@]}" -j 2 -q -o "$scratch/overridden.h5" 2>/dev/null
  for try in $(seq "$tries"); do
    out=$scratch/o$try.h5
    signal=$([ $((RANDOM % 2)) = 0 ] && echo INT || echo TERM)
    delay=$(random_delay)
    set -m
    "$ggk" run "$scratch/job.toml" "${overrides[@]}" -j 2 -q -o "$out" 2>"$scratch/stopped" &
    pid=$!
    set +m
    sleep "$delay"
    kill -s "$signal" $pid 2>/dev/null || true
    wait $pid 2>/dev/null || true
    # The command ggk printed ("finish the job with `CMD`", or "start the job
    # again with `CMD`" when no run had landed), or none: it finished, or the
    # signal came before ggk had set its handlers (no output yet: a person runs
    # the command again as typed).
    command=$(grep -o 'the job \(again \)\?with `[^`]*`' "$scratch/stopped" | head -n 1 |
      sed 's/^the job \(again \)\?with `//; s/`$//' || true)
    if [ -z "$command" ] && [ ! -e "$out" ]; then
      command="$(printf '%q ' "$ggk" run "$scratch/job.toml" "${overrides[@]}" -j 2 -q -o "$out")"
    fi
    s=0
    : >"$scratch/err"
    if [ -n "$command" ]; then
      timeout "$limit" bash -c "$command" >/dev/null 2>"$scratch/err" || s=$?
    fi
    if [ $s = 0 ] && "$ggk" verify "$out" >/dev/null 2>&1 &&
      "$ggk" diff "$scratch/overridden.h5" "$out" >/dev/null 2>&1; then
      survived=$((survived + 1))
    else
      echo "resume_overrides try $try (SIG$signal after ${delay}s): LOST: printed '$command': $(head -c 300 "$scratch/err")"
    fi
    rm -f "$out" "$out.part" "$out.lock"
  done
  report resume_overrides $survived "$tries"
}

case $class in
kills | mpi_kills | hostile_shards | hostile_results | hostile_lengths | tight_memory | reading_stops | open_readers | resume_overrides) $class ;;
all) for c in kills mpi_kills hostile_shards hostile_results hostile_lengths tight_memory reading_stops open_readers resume_overrides; do $c; done ;;
*)
  echo "stress_kills.sh: unknown class '$class' (kills, mpi_kills, hostile_shards, hostile_results, hostile_lengths, tight_memory, reading_stops, open_readers, resume_overrides, all)" >&2
  exit 2
  ;;
esac
exit $lost
