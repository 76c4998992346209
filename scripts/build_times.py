#!/usr/bin/env python3
"""Where a build's time went, from ninja's log: the seconds per kind of step and the slowest units.

Usage: scripts/build_times.py [BUILD_DIR] [--slowest N]   (default build/, 15)

Reads BUILD_DIR/.ninja_log (one line per step: start and end in ms, mtime, output, hash; the newest entry of each
output counts, so run it after a cold build for a cold build's figures). BENCHMARKS.md, "Build time", uses it.
"""
import argparse
import collections
import pathlib
import sys


def kind_of(output: str) -> str:
    if '.gch' in output or '/robossis_pch_' in output:
        return 'precompiled headers and their owners'
    if not output.endswith('.o'):
        return 'links, archives, test discovery'
    if output.startswith('tests/bench/'):
        return 'benchmark units'
    if output.startswith('tests/haptics/fake_dhd/'):
        return 'fake SDK units'
    if output.startswith('tests/'):
        return 'test units'
    if output.startswith('src/apps/CMakeFiles/robossis.dir/'):
        return "the program's units"
    return 'library units'


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('build_dir', nargs='?', default='build')
    parser.add_argument('--slowest', type=int, default=15, help='how many of the slowest units to list')
    args = parser.parse_args()
    log = pathlib.Path(args.build_dir) / '.ninja_log'
    if not log.is_file():
        print(f'build_times.py: {log}: no such file; expected a Ninja build folder', file=sys.stderr)
        return 1
    seconds = {}
    for number, line in enumerate(log.read_text().splitlines(), start=1):
        if line.startswith('#') or not line.strip():
            continue
        fields = line.split('\t')
        if len(fields) != 5:
            print(f'build_times.py: {log} line {number}: expected 5 tab-separated fields', file=sys.stderr)
            return 1
        start_ms, end_ms, _, output, _ = fields
        seconds[output] = (int(end_ms) - int(start_ms)) / 1000.0
    total = collections.Counter()
    steps = collections.Counter()
    for output, s in seconds.items():
        total[kind_of(output)] += s
        steps[kind_of(output)] += 1
    print(f'{len(seconds)} steps, {sum(seconds.values()):.0f} s in all (one core\'s seconds)')
    for kind, s in total.most_common():
        print(f'  {s:7.0f} s  {steps[kind]:4d} steps  {kind}')
    units = sorted(((s, o) for o, s in seconds.items() if o.endswith('.o')), reverse=True)
    print(f'the {args.slowest} slowest units:')
    for s, output in units[:args.slowest]:
        print(f'  {s:7.1f} s  {output}')
    return 0


if __name__ == '__main__':
    sys.exit(main())
