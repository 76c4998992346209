#!/usr/bin/env bash
# Set-point latency of the DDS link beside Cyclone's own ddsperf, on this machine, in one run (BENCHMARKS.md).
# 1. ddsperf ping/pong over loopback at 1 kHz, waitset triggering, 132-byte payload (~ a set-point sample):
#    round-trip latency; one way is about half of it.
# 2. bench_link: leader -> follower one-way latency at 1 kHz, security off and on.
# Usage: bash tests/link/latency_vs_ddsperf.sh [BUILD_DIR] [SECONDS]
set -euo pipefail
build=${1:-build}
secs=${2:-10}
domain=$((210 + $$ % 20))
export CYCLONEDDS_URI='<CycloneDDS><Domain Id="any"><General><Interfaces><NetworkInterface address="127.0.0.1"/></Interfaces><AllowMulticast>false</AllowMulticast></General><Discovery><Peers><Peer address="127.0.0.1"/></Peers><ParticipantIndex>auto</ParticipantIndex></Discovery></Domain></CycloneDDS>'
echo "== ddsperf ping/pong, 1 kHz, loopback, ${secs} s (round trip, us)"
ddsperf -i "$domain" -D $((secs + 2)) pong waitset > /tmp/ddsperf-pong.$$ 2>&1 &
pong=$!
trap 'kill $pong 2>/dev/null || true; rm -f /tmp/ddsperf-pong.$$' EXIT
sleep 1
# ddsperf prints one line a second; summarise: median of the per-second p50, worst per-second p99, overall max.
ddsperf -i "$domain" -D "$secs" ping 1kHz size 132 waitset 2>&1 | grep "size 132 mean" | tee /dev/stderr |
  sed -E 's/.* 50% ([0-9.]+)us 90% [0-9.]+us 99% ([0-9.]+)us max ([0-9.]+)us cnt ([0-9]+)/\1 \2 \3 \4/' |
  sort -n | awk '{p50[NR]=$1; if ($2>p99) p99=$2; if ($3>mx) mx=$3; n+=$4}
    END {printf "ddsperf round trip: p50 %.1f us (median of seconds), p99 %.1f us (worst second), max %.1f us, %d pings\n",
         p50[int((NR+1)/2)], p99, mx, n}'
wait $pong || true
echo "== bench_link (one way, us)"
"$build/tests/bench/bench_link" --benchmark_filter='SetPointLatency' --benchmark_counters_tabular=true
