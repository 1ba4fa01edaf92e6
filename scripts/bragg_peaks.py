#!/usr/bin/python3
"""The positional order of hard disks in a periodic box, frame by frame: S(k) / N at the Bragg
peaks of a triangular lattice.

    /usr/bin/python3 scripts/bragg_peaks.py RUN/frames.gsd [--every K] [--from T]

S(k) = |sum_j exp(-i k . r_j)|^2 / N on the box's k-grid, k = 2 pi (m / Lx, n / Ly) for whole m
and n. In the last frame, the strongest k near the first shell of the triangular lattice of the
frame's density is b1, the strongest 60 degrees from it b2 (either sign: S(-k) = S(k)), and
b3 = b2 - b1 the third of the shell. Then for each frame (every K-th, from time T on) S(k) / N
at the strongest grid point within two steps of each of the three: 1 for a perfect lattice, of
order 1 / N for a fluid. A run's positional order has formed where the three stop rising; the
orientational order (psi6, carom analyze) forms long before it. In a periodic box the lattice's
sites are |b1 x b2| (m and n the grid's whole numbers), which need not be N: a crystal whose
sites differ from N holds vacancies (more sites) or interstitials (fewer). The shear strain is
that of b1 and b2 against the triangular lattice of as many sites: (largest - smallest) /
(largest + smallest) principal stretch.

Disks only (the frame's first two coordinates); the search for b1 and b2 takes --sample disks of
the last frame (8192 by default), the values every disk.
"""

import argparse
import sys

import gsd.hoomd
import numpy as np

NEAR = 2  # grid steps either way around a peak, where a frame's peak may have moved
BLOCK = 512  # k-vectors at a time: a block of phases holds BLOCK x N complex numbers


def structure_factor(positions, box, m, n):
    """S(k) / N at k = 2 pi (m / Lx, n / Ly) for each pair of whole numbers (m, n)."""
    x = positions[:, 0] * (2 * np.pi / box[0])
    y = positions[:, 1] * (2 * np.pi / box[1])
    s = np.empty(len(m))
    for b in range(0, len(m), BLOCK):
        phases = np.outer(x, m[b:b + BLOCK]) + np.outer(y, n[b:b + BLOCK])
        s[b:b + BLOCK] = np.abs(np.exp(1j * phases).sum(axis=0)) ** 2
    return s / (len(positions) ** 2)


def first_shell(box, count):
    """The grid's (m, n) in the half plane within 6 % of the first shell of the triangular
    lattice of `count` disks in `box`, and that shell's radius in 2 pi / length."""
    spacing = np.sqrt(2 * box[0] * box[1] / (np.sqrt(3) * count))
    radius = 2 / (np.sqrt(3) * spacing)  # |b| / (2 pi)
    reach = [int(radius * 1.06 * side) + 1 for side in box]
    m, n = np.meshgrid(np.arange(-reach[0], reach[0] + 1), np.arange(0, reach[1] + 1),
                       indexing="ij")
    k = np.hypot(m / box[0], n / box[1])
    keep = (k > 0.94 * radius) & (k < 1.06 * radius) & ((n > 0) | (m > 0))
    return m[keep], n[keep], radius


def lattice(positions, box, sample, seed=1):
    """b1, b2, b3 (whole-number pairs) of the frame, found on `sample` of its disks."""
    m, n, radius = first_shell(box, len(positions))
    if m.size == 0:
        raise ValueError("no k-vector of the box's grid lies near the lattice's first shell")
    rng = np.random.default_rng(seed)
    some = positions[rng.choice(len(positions), size=min(sample, len(positions)), replace=False)]
    s = structure_factor(some, box, m, n)
    angle = np.degrees(np.arctan2(n / box[1], m / box[0])) % 180
    first = int(np.argmax(s))
    apart = np.abs((angle - angle[first]) % 180 - 60) < 12
    if not apart.any():
        raise ValueError("no k-vector of the box's grid lies 60 degrees from the strongest peak")
    second = int(np.flatnonzero(apart)[np.argmax(s[apart])])
    b1 = np.array([m[first], n[first]])
    b2 = np.array([m[second], n[second]])
    if np.hypot(*((b2 - b1) / box)) > 1.2 * radius:  # 120 degrees from b1: -b2 is 60
        b2 = -b2
    return b1, b2, b2 - b1


def shear_strain(b1, b2, box):
    """(largest - smallest) / (largest + smallest) principal stretch of the deformation taking
    the triangular reciprocal basis of the same area to b1, b2."""
    basis = np.column_stack([b1 / box, b2 / box])
    area = abs(np.linalg.det(basis))
    ideal = np.sqrt(area / (np.sqrt(3) / 2)) * np.array([[1, 0.5], [0, np.sqrt(3) / 2]])
    deformation = basis @ np.linalg.inv(ideal)
    stretch = np.sqrt(np.linalg.eigvalsh(deformation.T @ deformation))
    return (stretch[1] - stretch[0]) / (stretch[1] + stretch[0])


def frame_positions(frame):
    if any(frame.configuration.box[3:]):
        raise ValueError("the box is tilted: its k-grid is not the one of a rectangle")
    box = np.array(frame.configuration.box[:2], float)
    positions = np.asarray(frame.particles.position[:, :2], float) + box / 2
    return positions, box


def pair(b):
    """A k-vector's whole numbers, as (m, n)."""
    return f"({int(b[0])}, {int(b[1])})"


def frame_time(frame, index):
    time = frame.log.get("time") if hasattr(frame, "log") else None
    return float(time[0]) if time is not None else float(index)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                     formatter_class=argparse.RawDescriptionHelpFormatter,
                                     epilog=__doc__.split("\n\n", 1)[1])
    parser.add_argument("frames", help="a .gsd trajectory of disks in a periodic box")
    parser.add_argument("--every", type=int, default=1, help="every K-th frame (and the last)")
    parser.add_argument("--from", dest="start", type=float, default=-np.inf,
                        help="frames from this time on")
    parser.add_argument("--sample", type=int, default=8192,
                        help="disks of the last frame the search for the peaks takes")
    args = parser.parse_args(argv)
    if args.every < 1 or args.sample < 1:
        parser.error("--every and --sample must be 1 or more")
    try:
        trajectory = gsd.hoomd.open(args.frames, "rb")
    except (OSError, RuntimeError) as error:
        sys.exit(f"bragg_peaks.py: {args.frames}: cannot read it as GSD: {error}")
    if len(trajectory) == 0:
        sys.exit(f"bragg_peaks.py: {args.frames}: no frames")
    last = len(trajectory) - 1
    try:
        positions, box = frame_positions(trajectory[last])
        if len(positions) < 3:
            raise ValueError("fewer than three disks")
        b1, b2, b3 = lattice(positions, box, args.sample)
    except ValueError as error:
        sys.exit(f"bragg_peaks.py: {args.frames}: {error}")
    sites = abs(int(b1[0] * b2[1] - b1[1] * b2[0]))
    print(f"# {args.frames}: {len(positions)} disks; peaks of the last frame b1 {pair(b1)}, "
          f"b2 {pair(b2)}, b3 {pair(b3)} (whole 2 pi / L); lattice sites {sites} "
          f"(sites - disks {sites - len(positions):+d}), shear strain "
          f"{shear_strain(b1, b2, box):.5f}")
    print("# time, S/N at the three peaks' mean, at b1, b2, b3")
    near = [(i, j) for i in range(-NEAR, NEAR + 1) for j in range(-NEAR, NEAR + 1)]
    m = np.array([b[0] + i for b in (b1, b2, b3) for i, _ in near])
    n = np.array([b[1] + j for b in (b1, b2, b3) for _, j in near])
    chosen = list(range(0, len(trajectory), args.every))
    if chosen[-1] != last:
        chosen.append(last)
    shown = 0
    for index in chosen:
        frame = trajectory[index]
        time = frame_time(frame, index)
        if time < args.start:
            continue
        shown += 1
        try:
            positions, box = frame_positions(frame)
        except ValueError as error:
            sys.exit(f"bragg_peaks.py: {args.frames}, frame {index}: {error}")
        peaks = structure_factor(positions, box, m, n).reshape(3, len(near)).max(axis=1)
        print(f"{time:g} {peaks.mean():.4f} {peaks[0]:.4f} {peaks[1]:.4f} {peaks[2]:.4f}",
              flush=True)
    if shown == 0:
        sys.exit(f"bragg_peaks.py: {args.frames}: no frame from time {args.start:g} on (the last "
                 f"at {frame_time(trajectory[last], last):g})")


if __name__ == "__main__":
    main()
