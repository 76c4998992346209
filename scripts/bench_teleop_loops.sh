#!/usr/bin/env bash
# Loop timing of `robossis teleop --clock real` beside cyclictest (Debian rt-tests) at the same periods, in one run:
# the machine's own wake-up latency limit next to the leader (1 kHz, 4 kHz) and follower (10 kHz) loops.
# cyclictest runs at SCHED_FIFO 80, the teleop loops at 80 (leader) and 81 (follower), where permitted.
# Usage: scripts/bench_teleop_loops.sh [SECONDS] (default 3; keep it short on a shared machine)
set -euo pipefail
cd "$(dirname "$0")/.."
secs="${1:-3}"
bin=./build/robossis
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT

# p50/p99/max (us) of a cyclictest histogram (-h): lines "latency count" for each thread.
cyclic() {
  local interval_us=$1 loops
  loops=$(( secs * 1000000 / interval_us ))
  cyclictest -q -m -p 80 -i "$interval_us" -l "$loops" -h 20000 > "$tmp/cyclic_$interval_us.txt" 2>/dev/null || true
  python3 - "$tmp/cyclic_$interval_us.txt" "$interval_us" <<'PY'
import sys
counts = {}
for line in open(sys.argv[1]):
    parts = line.split()
    if len(parts) == 2 and parts[0].isdigit():
        counts[int(parts[0])] = counts.get(int(parts[0]), 0) + int(parts[1])
    if line.startswith("# Max Latencies:"):
        mx = int(line.split(":")[1].split()[0])
total = sum(counts.values())
def pct(p):
    seen = 0
    for us in sorted(counts):
        seen += counts[us]
        if seen >= p * total:
            return us
    return max(counts)
print(f"cyclictest period {sys.argv[2]} us: samples {total}, latency p50 {pct(0.5)} us, p99 {pct(0.99)} us, max {mx} us")
PY
}

teleop() {
  local rate=$1
  "$bin" teleop --device sim --method proxy-safe --follower recorder --rate-hz "$rate" --duration-s "$secs" \
    --clock real --no-plots --json --out "$tmp/teleop_$rate" 2>"$tmp/teleop_$rate.err" > "$tmp/teleop_$rate.json"
  python3 - "$tmp/teleop_$rate.json" "$rate" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
r = sys.argv[2]
print(f"teleop leader {r} Hz: ticks {s['leader_ticks']}, wake latency p99 {s['leader_wake_latency_us_p99']:.0f} us, "
      f"period jitter p99 {s['leader_period_jitter_us_p99']:.0f} us max {s['leader_period_jitter_us_max']:.0f} us, "
      f"overrun rate {s['leader_overrun_rate']:.4f}")
print(f"teleop follower 10000 Hz (with leader {r} Hz): ticks {s['follower_ticks']}, wake latency p99 "
      f"{s['follower_wake_latency_us_p99']:.0f} us, period jitter p99 {s['follower_period_jitter_us_p99']:.0f} us "
      f"max {s['follower_period_jitter_us_max']:.0f} us, overrun rate {s['follower_overrun_rate']:.4f}")
d = s['hand_to_setpoint_delay_ms']  # null unless the status is ok (e.g. cap_binds)
d = f"{d:.1f} ms" if d is not None else "none"
print(f"  hand-to-set-point delay {d} ({s['hand_to_setpoint_delay_status']}), limit violations {s['follower_limit_violations']}")
PY
  sed 's/^/  /' "$tmp/teleop_$rate.err"
}

uptime
cyclic 1000
teleop 1000
cyclic 250
teleop 4000
cyclic 100
