#!/usr/bin/env bash
# Soak test: renders many frames of a small scene with the GI library (bounce
# bench: G-buffer, direct light, every GI pass, no files written) and samples
# the process's resident memory as it runs. After the warm-up share of the
# run, memory must stay flat: the script fails if it grows by more than
# LIMIT_KB. Results for docs/reliability.md.
#   scripts/soak.sh [FRAMES] [SCENE] [WIDTHxHEIGHT]    (default: 10000 cornell 64x48)
#   env: BOUNCE (the binary, default build/bounce), LIMIT_KB (default 1024),
#        WARMUP_PERCENT (default 10)
set -euo pipefail
cd "$(dirname "$0")/.."
frames=${1:-10000}
scene=${2:-cornell}
size=${3:-64x48}
bounce=${BOUNCE:-build/bounce}
limit_kb=${LIMIT_KB:-1024}
warmup_percent=${WARMUP_PERCENT:-10}
log=$(mktemp)
samples=$(mktemp)
trap 'rm -f "$log" "$samples"' EXIT

"$bounce" bench "$scene" --width "${size%x*}" --height "${size#*x}" --frames "$frames" --warmup 0 --rays 0 \
  --copy-mb 0 > "$log" 2>&1 &
pid=$!
start=$(date +%s%N)
milliseconds() { echo $((($(date +%s%N) - start) / 1000000)); }
# Resident memory (kB) every half second, with the time since the start (ms).
while kill -0 "$pid" 2> /dev/null; do
  rss=$(awk '/^VmRSS:/ { print $2 }' "/proc/$pid/status" 2> /dev/null || true)
  [ -n "$rss" ] && echo "$(milliseconds) $rss" >> "$samples"
  sleep 0.5
done
wait "$pid" || { cat "$log"; echo "soak: bounce bench failed" >&2; exit 1; }
seconds=$(($(milliseconds) / 1000))

awk -v total="$seconds" -v warmup="$warmup_percent" -v limit="$limit_kb" -v frames="$frames" '
  { t[NR] = $1; rss[NR] = $2 }
  END {
    if (NR < 4) { print "soak: too few memory samples (" NR "); run more frames"; exit 1 }
    cut = total * 1000 * warmup / 100
    for (i = 1; i <= NR; ++i) if (t[i] >= cut) { first = i; break }
    base = rss[first]; peak = base; low = base
    for (i = first; i <= NR; ++i) { if (rss[i] > peak) peak = rss[i]; if (rss[i] < low) low = rss[i] }
    printf "soak: %d frames in %.0f s; resident memory after %d%% warm-up %.1f MB, at the end %.1f MB, ",
           frames, total, warmup, base / 1024, rss[NR] / 1024
    printf "range after warm-up %.0f kB (limit %d kB, %d samples)\n", peak - low, limit, NR - first + 1
    exit (peak - base > limit) ? 1 : 0
  }' "$samples"
