"""A sheared run's image flags count real crossings only, and its frames carry the sliding images
(HOOMD's tilted box, extended XYZ's tilted Lattice, LAMMPS' triclinic box): unwrapped positions,
read back by carom, gsd.hoomd and ASE, never jump, and carom analyze's MSD is the fluid's."""

import ase.io
import gsd.hoomd
import numpy as np
import pytest

import carom


def sheared(dim, rate):
    return carom.init(200 if dim == 2 else 150, 0.4, dim=dim, boundary="periodic",
                      rule="elastic", shear=rate, velocity_profile=True)


def unwrapped_gsd(frame):
    """HOOMD's unwrapping: position + image . (a1, a2, a3), a2 = (xy Ly, Ly, 0)."""
    lx, ly, lz, xy = (float(v) for v in frame.configuration.box[:4])
    image = frame.particles.image.astype(np.float64)
    u = frame.particles.position.astype(np.float64)
    u[:, 0] += image[:, 0] * lx + image[:, 1] * xy * ly
    u[:, 1] += image[:, 1] * ly
    u[:, 2] += image[:, 2] * lz
    return u


def unwrapped_xyz(atoms):
    """ASE's cell rows are the lattice vectors: position + image . cell."""
    return atoms.get_positions() + atoms.arrays["image"] @ np.asarray(atoms.get_cell())


def largest_step(frames):
    return max(np.abs(b - a).max() for a, b in zip(frames, frames[1:]))


@pytest.mark.parametrize("dim", [2, 3])
@pytest.mark.parametrize("rate", [1e-9, 0.5])
def test_unwrapped_frames_of_a_sheared_run_never_jump(tmp_path, dim, rate):
    sim = sheared(dim, rate)
    gsd_path, xyz_path = tmp_path / "sheared.gsd", tmp_path / "sheared.xyz"
    sim.run(4, dump=gsd_path, every=0.02)
    other = sheared(dim, rate)
    other.run(4, dump=xyz_path, every=0.02)
    with gsd.hoomd.open(str(gsd_path), "rb") as f:
        from_gsd = [unwrapped_gsd(frame)[:, :dim] for frame in f]
        tilts = [float(frame.configuration.box[3]) for frame in f]
    from_xyz = [unwrapped_xyz(atoms)[:, :dim] for atoms in ase.io.read(xyz_path, index=":")]
    assert len(from_gsd) == len(from_xyz) == 201
    # In 0.02 time units no particle goes further than its speed allows (a few tenths at most at
    # these speeds and streams); a wrong flag moves it by a box side or the images' shift.
    assert largest_step(from_gsd) < 0.4
    assert largest_step(from_xyz) < 0.4
    assert np.allclose(from_xyz[-1], sim.unwrapped_positions, atol=1e-9, rtol=0)
    # HOOMD's box is centred on the origin: its positions are carom's less half the sides.
    centred = sim.unwrapped_positions - 0.5 * np.asarray(sim.box)
    assert np.allclose(from_gsd[-1], centred, atol=1e-3, rtol=0)
    if rate == 0.5:  # the images slide: the frames' tilt follows them, within half a side
        assert len(set(tilts)) > 100 and max(abs(t) for t in tilts) <= 0.5 * sim.box[0] / sim.box[1]
        assert abs(sim.shear_shift) <= 0.5 * sim.box[0]
    # Particles did cross the sheared boundary, and their flags say so.
    assert np.any(sim.images[:, 1] != 0)


def lammps_images(path):
    """The image flags (ix iy iz) of each frame of a LAMMPS dump carom wrote: (frames, N, 3)."""
    lines = open(path).read().splitlines()
    frames = []
    for k, line in enumerate(lines):
        if line.startswith("ITEM: ATOMS"):
            n = int(lines[k - 5])
            frames.append(np.array([row.split()[-3:] for row in lines[k + 1: k + 1 + n]], float))
    return frames


@pytest.mark.parametrize("dim", [2, 3])
def test_a_sheared_lammps_dump_is_the_tilted_cell(tmp_path, dim):
    """A sheared run's LAMMPS dump has LAMMPS' triclinic box (ITEM: BOX BOUNDS xy xz yz: the x
    bounds of the box around the tilted cell, then the tilt), which ASE reads as OVITO does: the
    extended XYZ file's tilted Lattice, frame by frame, with image flags that unwrap alike."""
    lammps_path, xyz_path = tmp_path / "sheared.lammpstrj", tmp_path / "sheared.xyz"
    sim = sheared(dim, 0.5)
    sim.run(2, dump=lammps_path, every=0.05)
    sheared(dim, 0.5).run(2, dump=xyz_path, every=0.05)
    lammps = ase.io.read(lammps_path, index=":", format="lammps-dump-text")
    xyz = ase.io.read(xyz_path, index=":")
    images = lammps_images(lammps_path)
    assert len(lammps) == len(xyz) == len(images) == 41
    tilts = set()
    for atoms, reference, image in zip(lammps, xyz, images):
        cell = np.asarray(atoms.get_cell())
        assert np.allclose(cell, np.asarray(reference.get_cell()), atol=1e-12, rtol=0)
        assert np.allclose(atoms.get_positions(), reference.get_positions(), atol=1e-12, rtol=0)
        assert np.allclose(atoms.get_positions() + image @ cell, unwrapped_xyz(reference),
                           atol=1e-9, rtol=0)
        tilts.add(cell[1, 0])
    assert len(tilts) > 30  # the images slide: every frame its own tilt
    assert np.allclose((atoms.get_positions() + image @ cell)[:, :dim], sim.unwrapped_positions,
                       atol=1e-9, rtol=0)


def test_the_msd_of_a_sheared_run_is_the_fluids(tmp_path):
    # At a shear of 1e-9 the fluid is the fluid at rest: carom analyze's MSD over 5 time units is
    # a few diameters squared, as at rest (before, flags that counted collisions through the
    # sliding images as crossings made it a thousand).
    sim = sheared(2, 1e-9)
    path = tmp_path / "sheared.gsd"
    sim.run(5, dump=path, every=0.05)
    msd = carom.analyze(path)["msd"]["msd"]
    at_rest = carom.init(200, 0.4, dim=2, boundary="periodic", rule="elastic")
    rest_path = tmp_path / "rest.gsd"
    at_rest.run(5, dump=rest_path, every=0.05)
    msd_at_rest = carom.analyze(rest_path)["msd"]["msd"]
    assert 0.3 < msd[-1] / msd_at_rest[-1] < 3.0
    assert msd[-1] < 20.0


def test_the_summarys_offset_is_the_one_at_the_end():
    sim = sheared(2, 0.5)
    shifts = []
    for t in (1.0, 2.0, 3.0):
        sim.run(t)
        shifts.append(sim.observables()["shear"]["offset"])
        assert shifts[-1] == sim.shear_shift
    # The images slide at 0.5 Ly a unit of time: the shift at t = 3 is 1.5 Ly (mod Lx, within
    # half a side), whatever epoch the run stores it from.
    lx, ly = sim.box
    expected = 1.5 * ly - lx * round(1.5 * ly / lx)
    assert shifts[-1] == pytest.approx(expected, abs=1e-9)
    assert len(set(shifts)) == 3


def test_python_refuses_the_shears_the_command_line_refuses():
    for rate in (1e300, -1e101, 1e-300):
        with pytest.raises(ValueError, match="shear= is out of range"):
            sheared(2, rate)


def tilted_separations(position, lx, ly, xy):
    """Every pair's separation through the nearest image of HOOMD's tilted box, (N, N, 2): the
    images one box up lie at (xy Ly, Ly)."""
    r = position[:, None, :2] - position[None, :, :2]
    layers = np.round(r[..., 1] / ly)
    r[..., 0] -= layers * xy * ly
    r[..., 1] -= layers * ly
    r[..., 0] -= np.round(r[..., 0] / lx) * lx
    return r, layers != 0


def test_g_of_r_across_the_sheared_boundary_is_the_fluids(tmp_path):
    """gsd.hoomd reads a sheared run's frames with the tilt xy set; through the tilted box's
    nearest images no two disks overlap, and disks near the sheared boundary have the neighbours
    of disks in the bulk (the same g(r) out to 1.5 d). Read as a rectangular box (xy ignored),
    pairs across the boundary overlap: what the test catches."""
    # A fluid from the start (random placement: a lattice would melt first where it slides), in
    # Couette flow from the start (without the profile the boundary kicks the disks crossing it,
    # and the layer there is hot and thin for a while).
    sim = carom.init(400, 0.4, boundary="periodic", rule="elastic", shear=0.37,
                     velocity_profile=True, seed=3)
    path = tmp_path / "sheared.gsd"
    sim.run(6, dump=path, every=0.5)
    near, bulk, nearest, nearest_flat = [], [], np.inf, np.inf
    with gsd.hoomd.open(str(path), "rb") as f:
        frames = list(f)[2:]
    assert all(float(frame.configuration.box[3]) != 0.0 for frame in frames)
    for frame in frames:
        lx, ly, _, xy = (float(v) for v in frame.configuration.box[:4])
        position = frame.particles.position.astype(np.float64)
        r, _ = tilted_separations(position, lx, ly, xy)
        d = np.linalg.norm(r, axis=-1)
        np.fill_diagonal(d, np.inf)
        nearest = min(nearest, d.min())
        neighbours = (d < 1.5).sum(axis=1)
        edge = np.abs(np.abs(position[:, 1]) - 0.5 * ly) < 1.5  # within 1.5 d of the boundary
        near.extend(neighbours[edge])
        bulk.extend(neighbours[~edge])
        flat, across = tilted_separations(position, lx, ly, 0.0)
        nearest_flat = min(nearest_flat, np.linalg.norm(flat, axis=-1)[across].min())
    assert nearest > 1.0 - 1e-5  # hard disks of diameter 1, positions in single precision
    assert len(near) > 200
    assert abs(np.mean(near) - np.mean(bulk)) < 0.1 * np.mean(bulk), (np.mean(near), np.mean(bulk))
    # The sabotage the test guards against: the rectangular box's images overlap.
    assert nearest_flat < 0.9
