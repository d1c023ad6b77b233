#!/usr/bin/env python3
"""Writes the sample device trajectories (*.sttraj, docs/formats.md) the scripted device plugin
replays: a demo without hardware, in the editor (Simulation > Input device > scripted) and from
`softtouch-cli haptic SCENE --device scripted --device-arg FILE`."""
import json
import math
import os

HERE = os.path.dirname(os.path.abspath(__file__))


def write(name, samples):
    doc = {"format": "softtouch-trajectory", "version": 1, "samples": samples}
    with open(os.path.join(HERE, name), "w") as f:
        json.dump(doc, f, separators=(",", ":"))
        f.write("\n")


# A hand that flicks sideways and up in a figure eight for three seconds, then holds still: device
# metres around the workspace centre, one sample per millisecond ([t, x, y, z]).
samples = []
for i in range(3001):
    t = i / 1000.0
    ramp = min(t / 0.5, 1.0)
    x = ramp * 0.04 * math.sin(2 * math.pi * 1.0 * t)
    y = ramp * 0.03 * math.sin(2 * math.pi * 2.0 * t)
    samples.append([round(t, 3), round(x, 6), round(y, 6), 0.0])
write("figure-eight.sttraj", samples)
