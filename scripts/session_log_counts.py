#!/usr/bin/env python3
"""How often each value of some fields occurs in one stream of a session log (robossis teleop's session.rlog).

The log is self-describing (src/teleop/session_log.h): a JSON header names each stream's fields, their types and
offsets, so this reads it without the program. Counts the values of scalar fields over every record of the stream,
e.g. how many follower ticks the motors' step rate shortened (actuation_status 2: robot/actuation/actuator.h).

Example: scripts/session_log_counts.py OUT/session.rlog actuation_status guard_status
"""
import argparse
import collections
import json
import struct
import sys

TYPES = {"f64": "d", "i64": "q", "u64": "Q", "u32": "I", "u8": "B", "bool": "?"}


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("log", help="a session log (session.rlog)")
    parser.add_argument("fields", nargs="+", help="scalar fields of the stream")
    parser.add_argument("--stream", default="follower", help="the stream (default: follower)")
    a = parser.parse_args()
    try:
        data = open(a.log, "rb").read()
    except OSError as e:
        print(f"session_log_counts.py: {e}", file=sys.stderr)
        return 1
    if data[:8] != b"RBSSLOG1":
        print(f"session_log_counts.py: {a.log}: not a session log (version 1)", file=sys.stderr)
        return 1
    header_length = struct.unpack_from("<I", data, 8)[0]
    header = json.loads(data[12:12 + header_length])
    streams = {s["id"]: s for s in header["streams"]}
    wanted = [s for s in header["streams"] if s["name"] == a.stream]
    if not wanted:
        print(f"session_log_counts.py: {a.log}: no stream '{a.stream}'", file=sys.stderr)
        return 1
    fields = {f["name"]: f for f in wanted[0]["fields"]}
    for name in a.fields:
        if name not in fields or fields[name]["count"] != 1:
            print(f"session_log_counts.py: {a.log}: '{name}' is not a scalar field of '{a.stream}'", file=sys.stderr)
            return 1
    counts = {name: collections.Counter() for name in a.fields}
    pos, records = 12 + header_length, 0
    while pos < len(data):
        stream = streams[data[pos]]
        size = stream["record_size"]
        if pos + 1 + size > len(data):
            break  # a frame cut short: the run was killed mid-write
        if stream["name"] == a.stream:
            records += 1
            for name in a.fields:
                f = fields[name]
                counts[name][struct.unpack_from("<" + TYPES[f["type"]], data, pos + 1 + f["offset"])[0]] += 1
        pos += 1 + size
    print(f"{records} {a.stream} records")
    for name in a.fields:
        shares = ", ".join(f"{v}: {n} ({100 * n / records:.1f} %)" for v, n in sorted(counts[name].items()))
        print(f"{name}: {shares}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
