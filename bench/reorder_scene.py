#!/usr/bin/env python3
"""Renumber a scene's particles_file/contacts_file in Morton (Z-curve) order of the
particles' positions, to measure what the operator product gains from locality.

Usage: reorder_scene.py IN_DIR OUT_DIR   (IN_DIR holds deck.nml, particles.txt,
contacts.txt as bench_scene_eigen writes them; OUT_DIR gets the same three files).
Particle lines are moved whole; each contact line's two particle numbers are mapped
to the new numbering and the contacts sorted by their smaller end, then the other.
The scene is the same (a permutation), so omega_max agrees to the solver's tolerance,
not bit for bit (the Lanczos start vector and the sums follow the numbering).
"""
import shutil
import sys

import numpy as np


def morton_keys(pos, bits=10):
    lo = pos.min(axis=0)
    span = np.maximum(pos.max(axis=0) - lo, 1e-300)
    q = np.minimum(((pos - lo) / span * (1 << bits)).astype(np.int64), (1 << bits) - 1)
    key = np.zeros(len(pos), dtype=np.int64)
    for b in range(bits):
        for d in range(3):
            key |= ((q[:, d] >> b) & 1) << (3 * b + d)
    return key


def main():
    src, dst = sys.argv[1], sys.argv[2]
    with open(f"{src}/particles.txt") as fh:
        lines = fh.readlines()
    pos = np.array([[float(t) for t in ln.split(maxsplit=3)[:3]] for ln in lines])
    order = np.argsort(morton_keys(pos), kind="stable")  # new i -> old order[i]
    new_of_old = np.empty(len(order), dtype=np.int64)
    new_of_old[order] = np.arange(1, len(order) + 1)
    with open(f"{dst}/particles.txt", "w") as fh:
        fh.writelines(lines[i] for i in order)
    del lines
    with open(f"{src}/contacts.txt") as fh:
        rows = []
        for ln in fh:
            a, b, rest = ln.split(maxsplit=2)
            a, b = new_of_old[int(a) - 1], new_of_old[int(b) - 1]
            rows.append((min(a, b), max(a, b), a, b, rest))
    rows.sort(key=lambda r: (r[0], r[1]))
    with open(f"{dst}/contacts.txt", "w") as fh:
        fh.writelines(f"{a} {b} {rest}" for _, _, a, b, rest in rows)
    shutil.copy(f"{src}/deck.nml", f"{dst}/deck.nml")


if __name__ == "__main__":
    main()
