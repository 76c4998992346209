#!/usr/bin/env python3
"""Writes data/teleop/recorded_hand.csv: a recorded human hand, as the RSR pose it commands, for replay.

Source: a Qualisys motion-capture take of a person's right hand (100 Hz, 60 s, millimetres) published as
test/data/recording.tsv in dfki-ric/hand_embodiment (BSD-3-Clause; data/teleop/README.md gives the commit and
data/teleop/LICENSE_hand_embodiment.txt the licence). The script checks the file's SHA-256, so the output always
comes from the same take.

What it computes, per frame:
- the back of the hand as a rigid body from its three markers (hand_top, hand_left, hand_right): origin at their
  centroid, x from hand_left to hand_right, z normal to the three, y = z x x;
- its motion relative to the first frame: displacement d (mm) and rotation R_rel = R(t) R(0)^T, both in the
  capture volume's axes, taken as the RSR fixed frame F's axes [assumed: the take has no device frame];
- the commanded RSR pose: home + MOTION_SCALE * d, and the rotation R_rel scaled by MOTION_SCALE on its rotation
  vector, written as roll, pitch, yaw (R = Rz Ry Rx, degrees).

MOTION_SCALE is 1:50 [assumed]: the take is a free hand reaching about, faster than a surgeon positioning a bone
(it sweeps about 250 mm at up to 440 mm/s), and 1:50 brings it to 5 mm at up to 8.4 mm/s, below the paper's
10 mm/s demonstration cap and within the motors' top speeds, so that nothing but the motion transfer's filters
stands between the hand and the set-point. A scale changes the speeds, not the timing: the filters' delay is the
same at any scale at which no cap binds.

Output: the render-compare replay format (t_s,x_mm,y_mm,z_mm,roll_deg,pitch_deg,yaw_deg), frame F, absolute,
starting at the RSR home pose, at the take's own 100 Hz. Deterministic: re-running reproduces the file byte for
byte.

Usage: python3 scripts/make_recorded_hand_trajectory.py SOURCE.tsv [OUT.csv]
"""
import hashlib
import math
import os
import sys

SOURCE_SHA256 = "75ea91c0dd0ad54b6ef8860f240ff6a2175a6e2c0db248fc8861cf0c4b640141"
HOME = (0.0, 0.0, 284.0)  # data/config/rsr.yaml home_pose (mm); its orientation is zero
MOTION_SCALE = 0.02
MARKERS = ("hand_top", "hand_left", "hand_right")


def fail(message):
    sys.stderr.write("make_recorded_hand_trajectory: " + message + "\n")
    sys.exit(1)


def sub(a, b):
    return [x - y for x, y in zip(a, b)]


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def unit(a):
    n = math.sqrt(sum(x * x for x in a))
    if n < 1e-9:
        return None
    return [x / n for x in a]


def matmul_t(A, B):
    """A B^T for 3x3 matrices stored row by row."""
    return [[sum(A[i][k] * B[j][k] for k in range(3)) for j in range(3)] for i in range(3)]


def hand_frame(top, left, right):
    x = unit(sub(right, left))
    z = unit(cross(sub(right, left), sub(top, left)))
    if x is None or z is None:
        return None
    y = cross(z, x)
    R = [[x[i], y[i], z[i]] for i in range(3)]  # columns x, y, z
    centroid = [(top[i] + left[i] + right[i]) / 3.0 for i in range(3)]
    return centroid, R


def rotation_vector(R):
    c = max(-1.0, min(1.0, (R[0][0] + R[1][1] + R[2][2] - 1.0) / 2.0))
    angle = math.acos(c)
    v = [R[2][1] - R[1][2], R[0][2] - R[2][0], R[1][0] - R[0][1]]
    s = math.sin(angle)
    if s < 1e-9:
        if angle < 1e-6:
            return [0.0, 0.0, 0.0]
        fail("the hand turned by 180 degrees from its first frame; the rotation vector is ambiguous there")
    return [angle * x / (2.0 * s) for x in v]


def rotation_from_vector(w):
    angle = math.sqrt(sum(x * x for x in w))
    if angle < 1e-12:
        return [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]
    k = [x / angle for x in w]
    c, s, C = math.cos(angle), math.sin(angle), 1.0 - math.cos(angle)
    return [[c + k[0] * k[0] * C, k[0] * k[1] * C - k[2] * s, k[0] * k[2] * C + k[1] * s],
            [k[1] * k[0] * C + k[2] * s, c + k[1] * k[1] * C, k[1] * k[2] * C - k[0] * s],
            [k[2] * k[0] * C - k[1] * s, k[2] * k[1] * C + k[0] * s, c + k[2] * k[2] * C]]


def rpy_deg(R):
    # The inverse of R = Rz(yaw) Ry(pitch) Rx(roll), as src/core/pose.cc computes it.
    pitch = math.asin(max(-1.0, min(1.0, -R[2][0])))
    roll = math.atan2(R[2][1], R[2][2])
    yaw = math.atan2(R[1][0], R[0][0])
    return [math.degrees(roll), math.degrees(pitch), math.degrees(yaw)]


def read_take(path):
    with open(path, "rb") as f:
        raw = f.read()
    digest = hashlib.sha256(raw).hexdigest()
    if digest != SOURCE_SHA256:
        fail("%s: SHA-256 %s, expected %s (test/data/recording.tsv of dfki-ric/hand_embodiment)"
             % (path, digest, SOURCE_SHA256))
    lines = raw.decode("ascii").splitlines()
    header = next((i for i, line in enumerate(lines) if line.startswith("Frame\t")), None)
    if header is None:
        fail("%s: no 'Frame' header row" % path)
    names = lines[header].split("\t")
    columns = {}
    for marker in MARKERS:
        for axis in "XYZ":
            name = "%s %s" % (marker, axis)
            if name not in names:
                fail("%s: column '%s' missing" % (path, name))
            columns[name] = names.index(name)
    frames = []
    for number, line in enumerate(lines[header + 1:], start=header + 2):
        cells = line.split("\t")
        t = float(cells[1])
        points = [[float(cells[columns["%s %s" % (m, a)]]) for a in "XYZ"] for m in MARKERS]
        if any(p == [0.0, 0.0, 0.0] for p in points):
            fail("%s line %d: a hand marker is unlabelled (0, 0, 0); the take used has none" % (path, number))
        frames.append((t, points))
    return frames


def main():
    if len(sys.argv) not in (2, 3):
        fail("usage: make_recorded_hand_trajectory.py SOURCE.tsv [OUT.csv]")
    out = sys.argv[2] if len(sys.argv) == 3 else "data/teleop/recorded_hand.csv"
    frames = read_take(sys.argv[1])
    first = hand_frame(*frames[0][1])
    if first is None:
        fail("the first frame's hand markers are collinear")
    c0, R0 = first
    t0 = frames[0][0]
    rows = []
    for t, points in frames:
        frame = hand_frame(*points)
        if frame is None:
            fail("t = %.2f s: the hand markers are collinear" % t)
        c, R = frame
        d = sub(c, c0)
        w = rotation_vector(matmul_t(R, R0))
        R_cmd = rotation_from_vector([MOTION_SCALE * x for x in w])
        pose = [HOME[i] + MOTION_SCALE * d[i] for i in range(3)] + rpy_deg(R_cmd)
        rows.append("%.4f,%s" % (t - t0, ",".join("%.4f" % (round(v, 4) + 0.0) for v in pose)))
    with open(out + ".tmp", "w", newline="\n") as f:
        f.write("t_s,x_mm,y_mm,z_mm,roll_deg,pitch_deg,yaw_deg\n")
        f.write("\n".join(rows) + "\n")
    os.replace(out + ".tmp", out)


if __name__ == "__main__":
    main()
