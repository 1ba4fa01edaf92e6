"""The Steinhardt bond order and solid-like clusters of `carom analyze`, written again directly in
numpy, to test carom's against: every pair by brute force (minimum image), the spherical harmonics
from the polar and azimuthal angles and the associated Legendre recursion, and the Wigner 3j
symbols from the Racah formula in exact rational arithmetic."""

from fractions import Fraction
from math import factorial, pi, sqrt

import numpy as np


def neighbour_lists(position, box, periodic, cutoff):
    """Every pair closer than `cutoff` (minimum image in a periodic box): each particle's
    neighbours and the bonds to them."""
    lists = []
    for i in range(len(position)):
        r = position - position[i]
        if periodic:
            r -= box * np.rint(r / box)
        distance2 = np.einsum("ij,ij->i", r, r)
        near = np.flatnonzero((distance2 < cutoff * cutoff) & (distance2 > 0))
        lists.append((near, r[near]))
    return lists


def associated_legendre(l, m, x):
    """P_l^m(x) with the Condon-Shortley phase, m >= 0, by the upward recursion in l."""
    p_mm = (-1) ** m * np.prod(np.arange(1, 2 * m, 2, dtype=float)) * (1 - x * x) ** (m / 2)
    if l == m:
        return p_mm
    below, p = p_mm, x * (2 * m + 1) * p_mm
    for n in range(m + 2, l + 1):
        below, p = p, ((2 * n - 1) * x * p - (n + m - 1) * below) / (n - m)
    return p


def spherical_harmonics(l, bonds):
    """Y_lm of each bond's direction, columns m = -l .. l."""
    r = np.linalg.norm(bonds, axis=1)
    theta, phi = np.arccos(np.clip(bonds[:, 2] / r, -1, 1)), np.arctan2(bonds[:, 1], bonds[:, 0])
    y = np.zeros((len(bonds), 2 * l + 1), dtype=complex)
    for m in range(0, l + 1):
        norm = sqrt((2 * l + 1) / (4 * pi) * factorial(l - m) / factorial(l + m))
        y[:, l + m] = norm * associated_legendre(l, m, np.cos(theta)) * np.exp(1j * m * phi)
        y[:, l - m] = (-1) ** m * np.conj(y[:, l + m])
    return y


def wigner_3j(j1, j2, j3, m1, m2, m3):
    """The Racah formula in rationals; its one square root taken last."""
    if m1 + m2 + m3 != 0 or not abs(j1 - j2) <= j3 <= j1 + j2 or \
            abs(m1) > j1 or abs(m2) > j2 or abs(m3) > j3:
        return 0.0
    f = factorial
    total = sum(Fraction((-1) ** k, f(k) * f(j3 - j2 + k + m1) * f(j3 - j1 + k - m2) *
                         f(j1 + j2 - j3 - k) * f(j1 - k - m1) * f(j2 - k + m2))
                for k in range(0, j1 + j2 + j3 + 1)
                if min(j3 - j2 + k + m1, j3 - j1 + k - m2, j1 + j2 - j3 - k, j1 - k - m1,
                       j2 - k + m2) >= 0)
    square = total * total * Fraction(f(j1 + j2 - j3) * f(j1 - j2 + j3) * f(-j1 + j2 + j3),
                                      f(j1 + j2 + j3 + 1)) * \
        f(j1 + m1) * f(j1 - m1) * f(j2 + m2) * f(j2 - m2) * f(j3 + m3) * f(j3 - m3)
    sign = (-1) ** (j1 - j2 - m3) * (1 if total >= 0 else -1)
    return sign * sqrt(square)


def invariants(l, qlm):
    """q_l and w_l of rows of q_lm (0 and 0 for a row of zeros)."""
    norm2 = np.sum(np.abs(qlm) ** 2, axis=1)
    q = np.sqrt(4 * pi / (2 * l + 1) * norm2)
    w = np.zeros(len(qlm), dtype=complex)
    for m1 in range(-l, l + 1):
        for m2 in range(-l, l + 1):
            m3 = -m1 - m2
            if abs(m3) <= l:
                w += wigner_3j(l, l, l, m1, m2, m3) * qlm[:, m1 + l] * qlm[:, m2 + l] * \
                    qlm[:, m3 + l]
    safe = np.where(norm2 > 0, norm2, 1)
    return q, np.where(norm2 > 0, w.real / safe ** 1.5, 0.0)


def bond_order(position, box, periodic, cutoff):
    """Every particle's q4, w4, q4_bar, ..., solid_bonds, solid_like and cluster (-1: none, else
    the index into the sizes, largest first), and the cluster sizes."""
    lists = neighbour_lists(np.asarray(position, dtype=float), np.asarray(box, dtype=float),
                            periodic, cutoff)
    n = len(lists)
    out = {"neighbours": np.array([len(near) for near, _ in lists])}
    q6m = None
    for l in (4, 6):
        qlm = np.array([spherical_harmonics(l, bonds).mean(axis=0) if len(near)
                        else np.zeros(2 * l + 1, dtype=complex) for near, bonds in lists])
        average = np.array([(qlm[i] + qlm[near].sum(axis=0)) / (len(near) + 1)
                            for i, (near, _) in enumerate(lists)])
        out[f"q{l}"], out[f"w{l}"] = invariants(l, qlm)
        out[f"q{l}_bar"], out[f"w{l}_bar"] = invariants(l, average)
        q6m = qlm
    length = np.linalg.norm(q6m, axis=1)
    solid_bonds = np.zeros(n, dtype=int)
    for i, (near, _) in enumerate(lists):
        for j in near:
            if length[i] > 0 and length[j] > 0:
                product = np.sum(q6m[i] * np.conj(q6m[j])).real / (length[i] * length[j])
                solid_bonds[i] += product > 0.7
    solid = solid_bonds >= 7
    label = -np.ones(n, dtype=int)
    sizes = []
    for seed in range(n):
        if solid[seed] and label[seed] < 0:
            label[seed], stack, size = len(sizes), [seed], 0
            while stack:
                i = stack.pop()
                size += 1
                for j in lists[i][0]:
                    if solid[j] and label[j] < 0:
                        label[j] = len(sizes)
                        stack.append(j)
            sizes.append(size)
    order = sorted(range(len(sizes)), key=lambda c: -sizes[c])  # stable: ties as found
    rank = {c: r for r, c in enumerate(order)}
    out["solid_bonds"], out["solid_like"] = solid_bonds, solid
    out["cluster"] = np.array([rank[c] if c >= 0 else -1 for c in label])
    out["cluster_sizes"] = np.array([sizes[c] for c in order], dtype=int)
    return out
