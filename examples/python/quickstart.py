#!/usr/bin/env python3
"""The classic assignment's first case from Python: examples/walls_only.txt to t = 20.

Run with Debian's interpreter after `make demo` (or `make python-install`):
    /usr/bin/python3 examples/python/quickstart.py
It prints what `carom run examples/walls_only.txt 20` prints, then the numpy view of the result.
"""
import pathlib

import carom

examples = pathlib.Path(__file__).resolve().parent.parent
sim = carom.read(examples / "walls_only.txt")  # the classic assignment's rule and box: swap, walls
sim.run(20.0)
print(sim.format("table"), end="")  # the command line's table, bit for bit
print(f"{sim.events} collisions by t = {sim.time}; positions (N, {sim.dim}):")
print(sim.positions)
print("wall collisions:", sim.wall_collisions)
