#!/usr/bin/env python3
"""The demo's two real-clock runs (section 8: one process; section 9: two processes over secured DDS), repeated
beside CPU-bound load, with the faults, overruns and speeds of every run: what RELIABILITY.md's fault count at
load comes from. A run "with a fault" is one the follower's summary.json does not call clean (`run_clean`: a fault,
an E-stop, or a follower that stopped following while the leader still sent and did not follow again:
src/teleop/run_verdict.h); watchdog holds that following resumed from are counted apart (`holds`, `hold_ms`).

Usage: scripts/realtime_runs.py [--runs 10] [--load 1] [--duration-s 17] [--link inprocess,dds] [--out DIR]

--load N starts N busy processes (a shell loop each) for the whole measurement and always stops them. Writes
DIR/runs.csv (one row per run: the verdict's reason and description in `fault`) and prints a table; exit status 1
if any run was not clean or did not complete.
"""
import argparse
import csv
import json
import os
import pathlib
import signal
import subprocess
import sys
import tempfile

ROOT = pathlib.Path(__file__).resolve().parent.parent
COMMON = ['--device', 'replay:' + str(ROOT / 'data/teleop/fast_hand.csv'), '--method', 'proxy-safe',
          '--follower', 'sim', '--clock', 'real', '--max-speed-mm-s', '100', '--max-angular-speed-deg-s', '20',
          '--no-plots']
FIELDS = ['link', 'run', 'complete', 'clean', 'fault', 'faults', 'holds', 'hold_ms', 'follower_ticks', 'follower_overruns',
          'follower_overrun_rate', 'leader_overruns', 'leader_overruns_long_tick', 'leader_overrun_rate',
          'max_follower_speed_mm_s', 'limit_violations', 'transitions']


def start_load(n):
    # Each in its own session, so that stopping it never touches this process.
    return [subprocess.Popen(['sh', '-c', 'while :; do :; done'], start_new_session=True) for _ in range(n)]


def stop_load(procs):
    for p in procs:
        try:
            os.killpg(p.pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
        p.wait()


def row_of(link, run, leader, follower):
    transitions = follower.get('follower_transitions', [])
    fault = follower['run_fault']
    return {
        'link': link, 'run': run,
        'complete': bool(follower.get('complete')) and bool(leader.get('complete')),
        'clean': follower['run_clean'] is True,
        'fault': f"{fault['reason']}: {fault['description']}" if fault else '',
        'faults': follower['run_faults'],
        'holds': follower['run_holds'], 'hold_ms': 1e3 * follower['run_hold_s'],
        'follower_ticks': follower['follower_ticks'], 'follower_overruns': follower['follower_overruns'],
        'follower_overrun_rate': follower['follower_overrun_rate'],
        'leader_overruns': leader['leader_overruns'], 'leader_overruns_long_tick': leader['leader_overruns_long_tick'],
        'leader_overrun_rate': leader['leader_overrun_rate'],
        'max_follower_speed_mm_s': follower['max_follower_speed_mm_s'],
        'limit_violations': follower['follower_limit_violations'],
        'transitions': '; '.join(f"{t['t_s']:.3f} s {t['from']}->{t['to']} ({t['reason']}"
                                 + (f", {t['back_end_fault']}" if 'back_end_fault' in t else '') + ')'
                                 for t in transitions),
    }


def run_once(robossis, link, run, duration_s, keys, work):
    out = work / f'{link}-{run}'
    cmd = [robossis, 'teleop', *COMMON, '--duration-s', str(duration_s), '--out', str(out)]
    if link == 'dds':
        cmd += ['--link', 'dds', '--keys', str(keys)]
    result = subprocess.run(cmd, capture_output=True, text=True)
    if result.returncode != 0:
        sys.exit(f'run {run} ({link}) failed with status {result.returncode}:\n{result.stderr[-2000:]}')
    summary = json.loads((out / 'summary.json').read_text())
    if link == 'dds':
        return row_of(link, run, summary['leader'], summary['follower'])
    return row_of(link, run, summary, summary)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('--runs', type=int, default=10)
    parser.add_argument('--load', type=int, default=1, help='CPU-bound processes beside the runs')
    parser.add_argument('--duration-s', type=float, default=17.0)
    parser.add_argument('--link', default='inprocess,dds', help='inprocess, dds, or both (comma-separated)')
    parser.add_argument('--robossis', default=str(ROOT / 'build/robossis'))
    parser.add_argument('--out', default='realtime-runs')
    args = parser.parse_args()
    links = [s for s in args.link.split(',') if s]
    for link in links:
        if link not in ('inprocess', 'dds'):
            parser.error(f'--link: unknown link {link!r}; expected inprocess and/or dds')
    if args.runs < 1 or args.load < 0:
        parser.error('--runs must be >= 1 and --load >= 0')

    out = pathlib.Path(args.out)
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        work = pathlib.Path(tmp)
        keys = work / 'keys'
        if 'dds' in links:
            subprocess.run([args.robossis, 'keys', 'init', str(keys)], check=True, capture_output=True)
        load = start_load(args.load)
        try:
            for run in range(1, args.runs + 1):
                for link in links:
                    row = run_once(args.robossis, link, run, args.duration_s, keys, work)
                    rows.append(row)
                    print(f"[{link} {run}/{args.runs}] {'clean' if row['clean'] else 'FAULT ' + row['fault']}, "
                          f"follower overruns {row['follower_overruns']}/{row['follower_ticks']}, leader overruns "
                          f"{row['leader_overruns']} ({row['leader_overruns_long_tick']} long tick), max speed "
                          f"{row['max_follower_speed_mm_s']:.2f} mm/s", file=sys.stderr, flush=True)
        finally:
            stop_load(load)

    out.mkdir(parents=True, exist_ok=True)
    with open(out / 'runs.csv.tmp', 'w', newline='') as f:
        writer = csv.DictWriter(f, fieldnames=FIELDS)
        writer.writeheader()
        writer.writerows(rows)
    os.replace(out / 'runs.csv.tmp', out / 'runs.csv')

    print(f'| link | runs | with a fault | incomplete | watchdog holds, total (longest run\'s ms) | follower overrun rate, max | leader overrun rate, max '
          f'| leader overruns, max (long tick) | max follower speed (mm/s) | limit violations |')
    print('|---|---|---|---|---|---|---|---|---|---|')
    bad = False
    for link in links:
        r = [x for x in rows if x['link'] == link]
        faulted = sum(1 for x in r if not x['clean'])
        incomplete = sum(1 for x in r if not x['complete'])
        bad = bad or faulted > 0 or incomplete > 0
        print(f"| {link} | {len(r)} | {faulted} | {incomplete} "
              f"| {sum(x['holds'] for x in r)} ({max(x['hold_ms'] for x in r):.1f}) | {max(x['follower_overrun_rate'] for x in r):.2e} "
              f"| {max(x['leader_overrun_rate'] for x in r):.2e} "
              f"| {max(x['leader_overruns'] for x in r)} ({max(x['leader_overruns_long_tick'] for x in r)}) "
              f"| {max(x['max_follower_speed_mm_s'] for x in r):.2f} "
              f"| {sum(x['limit_violations'] for x in r)} |")
    for x in rows:
        if not x['clean']:
            print(f"- {x['link']} run {x['run']}: {x['fault']}")
    print(f'(load: {args.load} CPU-bound process(es); {args.duration_s:g} s per run; rows in {out / "runs.csv"})')
    return 1 if bad else 0


if __name__ == '__main__':
    sys.exit(main())
