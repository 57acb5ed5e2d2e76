#!/usr/bin/env python3
# Copyright (c) 2026, the activecal authors.
# SPDX-License-Identifier: BSD-3-Clause
"""A minimal activecal driver: the bridge between activecal_active and a
robot cell (a robot and a tracker), in plain Python 3 (no activecal import).

activecal starts this program and talks to it over its stdin and stdout, one
JSON object per line (docs/driver_protocol.md):

  activecal -> driver  {"type":"hello","protocol":1,"joint_names":[...],"markers":K,...}
  driver -> activecal  {"type":"hello","protocol":1,"driver":"..."}
  activecal -> driver  {"type":"measure","id":N,"joints_rad":[...]}
  driver -> activecal  {"type":"measurement","id":N,"status":"ok",
                        "joints_rad":[...read...],"points_m":[[x,y,z] or null, ...]}
                   or  {"type":"measurement","id":N,"status":"unreachable"|
                        "not_visible"|"error","message":"..."}
  activecal -> driver  {"type":"bye"}

To drive your cell, replace the bodies of the two functions marked ADAPT:
move_robot() (your robot's SDK) and read_tracker() (your tracker's SDK).
Everything else is the protocol and stays as it is. Print anything you like:
it goes to stderr (activecal shows it), as does whatever your SDKs print;
the protocol has stdout to itself (see PROTOCOL below).

As shipped, the two functions fake a cell: a 6-joint arm (standard DH, the
true values of examples/driver_example_robot.yaml) seen by a tracker with
0.05 mm noise, so that this runs as it is:

  activecal_active --robot=examples/driver_example_robot.yaml \\
      --driver="python3 examples/driver_example.py" --noise_m=5e-5 \\
      --target_rms_m=1e-4 --session=example_run
"""

import json
import math
import os
import random
import sys

# stdout carries the protocol only, so it is taken here, before anything can
# print: the protocol is written on a copy of it, and the real stdout (file
# descriptor 1) becomes stderr. Your prints, an SDK's, and programs they
# run then reach activecal's terminal instead of corrupting the protocol.
# Keep this above the imports of your robot's and tracker's SDKs.
sys.stdout.flush()
PROTOCOL = os.fdopen(os.dup(sys.stdout.fileno()), "w")
os.dup2(sys.stderr.fileno(), sys.stdout.fileno())
sys.stdout = sys.stderr


class Unreachable(Exception):
    """The robot cannot go to the pose (a limit, a collision, a fence)."""


class NotVisible(Exception):
    """The tracker cannot see the target at the pose."""


# --------------------------------------------------------------- ADAPT 1 ---
def move_robot(joints_rad):
    """Moves the robot to `joints_rad` (one value per joint in activecal's
    joint convention: radians, metres for a prismatic joint), waits until it
    has settled, and returns the joint values its encoders read there (what
    activecal identifies from). Raises Unreachable when it cannot go there.

    Replace with your robot's SDK, e.g. for a UR over RTDE:
        rtde_c.moveJ(joints_rad, speed, acceleration)
        return rtde_r.getActualQ()
    (mind the controller's joint convention: the sign and zero of each joint
    where your robot file or URDF differs from the controller,
    data/controllers/).
    """
    return list(joints_rad)  # the fake robot reaches every pose exactly


# --------------------------------------------------------------- ADAPT 2 ---
def read_tracker(joints_read, num_markers):
    """Returns one measured point [x, y, z] (metres, in the tracker's frame)
    per marker, None for a marker the tracker cannot see. Raises NotVisible
    when it sees none.

    Replace with your tracker's SDK: point it at the reflector (or read the
    camera), average a few readings, convert to metres.
    """
    return [fake_point(joints_read, k) for k in range(num_markers)]


# --- the fake cell (delete when adapting) ---------------------------------
# The true robot of examples/driver_example_robot.yaml: the tracker sees the
# robot base at FAKE_BASE (x, y, z m; rx, ry, rz rad, R = Rz Ry Rx), the
# standard DH links (gamma, alpha, a, d), the reflector at FAKE_MARKER in the
# last link's frame.
FAKE_BASE = (2.0, 0.5, -0.3, 0.002, -0.001, 0.3)
FAKE_LINKS = [
    (0.0, math.pi / 2, 0.0, 0.1807),
    (0.001, 0.0, -0.6132, 0.0),
    (-0.0008, 0.0, -0.5712, 0.0),
    (0.0005, math.pi / 2, 0.0, 0.17415),
    (0.0, -math.pi / 2 + 0.0005, 0.0, 0.11985),
    (0.0, 0.0, 0.0, 0.11655),
]
FAKE_MARKER = (0.0512, 0.0196, 0.0803)
FAKE_NOISE_M = 5e-5
fake_random = random.Random(1)


def matmul(a, b):
    return [[sum(a[i][k] * b[k][j] for k in range(4)) for j in range(4)]
            for i in range(4)]


def fake_point(joints, marker):
    x, y, z, rx, ry, rz = FAKE_BASE
    cx, sx, cy, sy, cz, sz = (math.cos(rx), math.sin(rx), math.cos(ry),
                              math.sin(ry), math.cos(rz), math.sin(rz))
    t = [[cz * cy, cz * sy * sx - sz * cx, cz * sy * cx + sz * sx, x],
         [sz * cy, sz * sy * sx + cz * cx, sz * sy * cx - cz * sx, y],
         [-sy, cy * sx, cy * cx, z],
         [0, 0, 0, 1]]
    for q, (gamma, alpha, a, d) in zip(joints, FAKE_LINKS):
        ct, st = math.cos(q + gamma), math.sin(q + gamma)
        ca, sa = math.cos(alpha), math.sin(alpha)
        t = matmul(t, [[ct, -st * ca, st * sa, a * ct],
                       [st, ct * ca, -ct * sa, a * st],
                       [0, sa, ca, d],
                       [0, 0, 0, 1]])
    p = [sum(t[i][k] * FAKE_MARKER[k] for k in range(3)) + t[i][3]
         for i in range(3)]
    return [v + fake_random.gauss(0.0, FAKE_NOISE_M) for v in p]


# --- the protocol (keep) ---------------------------------------------------
def send(message):
    # allow_nan=False: NaN is not JSON; a bad reading must fail here, loudly.
    PROTOCOL.write(json.dumps(message, allow_nan=False) + "\n")
    PROTOCOL.flush()


def main():
    num_joints, num_markers = 0, 1
    for line in sys.stdin:
        if not line.strip():
            continue
        message = json.loads(line)
        kind = message.get("type")
        if kind == "hello":
            if message.get("protocol") != 1:
                print("driver_example: activecal speaks protocol %r, this "
                      "driver 1" % message.get("protocol"), file=sys.stderr)
                return 2
            num_joints = len(message["joint_names"])
            num_markers = message["markers"]
            print("driver_example: robot %r, %d joints, %d markers" %
                  (message.get("robot"), num_joints, num_markers),
                  file=sys.stderr)
            send({"type": "hello", "protocol": 1,
                  "driver": "driver_example.py (fake cell)"})
        elif kind == "measure":
            reply = {"type": "measurement", "id": message["id"]}
            try:
                joints = move_robot(message["joints_rad"])
                points = read_tracker(joints, num_markers)
                if all(p is None for p in points):
                    raise NotVisible("no marker seen")
                reply.update(status="ok", joints_rad=list(joints),
                             points_m=[None if p is None else list(p)
                                       for p in points])
            except Unreachable as e:
                reply.update(status="unreachable", message=str(e))
            except NotVisible as e:
                reply.update(status="not_visible", message=str(e))
            except Exception as e:  # the cell failed at this pose
                reply.update(status="error", message="%s: %s" %
                             (type(e).__name__, e))
            send(reply)
        elif kind == "bye":
            return 0
        else:
            print("driver_example: unknown message %r" % line.strip(),
                  file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
