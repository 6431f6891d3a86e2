#!/usr/bin/env python3
"""Write a particles table and a contacts table for demstep's distributed input
benchmark (`mpi/example/mpi_files.f90`): a periodic jittered L x L x L cubic
lattice of spheres (spacing 1, each coordinate moved by up to +-0.05, radii
0.56 to 0.60, masses 1 to 2, solid-sphere inertia), listed x-major so that
contiguous ranges of particle numbers are slabs across x. Its contacts are the
three axis neighbours of each particle (distance at most 1.1 < r_i + r_j; the
diagonal neighbours, at 1.27 or more, never touch), 3 L^3 rows of
`i j k_n k_t` with k_n uniform in [50, 150] and k_t = 0.3 k_n.

    python3 lattice_tables.py L particles.txt contacts.txt [seed]

The periodic cell is [0, L)^3 (cell_hi = L). Written in blocks of x planes, so
memory stays at a few planes.
"""
import sys

import numpy as np


def main():
    if len(sys.argv) < 4:
        sys.exit(__doc__)
    L = int(sys.argv[1])
    seed = int(sys.argv[4]) if len(sys.argv) > 4 else 1
    rng = np.random.default_rng(seed)
    plane = L * L
    with open(sys.argv[2], "w") as pf, open(sys.argv[3], "w") as cf:
        pf.write("# x y z vx vy vz mass radius fixed inertia\n")
        cf.write("# i j k_n k_t\n")
        iy, iz = np.meshgrid(np.arange(L), np.arange(L), indexing="ij")
        iy = iy.ravel()
        iz = iz.ravel()
        for ix in range(L):
            x = np.empty((plane, 3))
            x[:, 0] = ix
            x[:, 1] = iy
            x[:, 2] = iz
            x += rng.uniform(-0.05, 0.05, size=x.shape)
            x %= L
            r = rng.uniform(0.56, 0.60, plane)
            m = rng.uniform(1.0, 2.0, plane)
            inertia = 0.4 * m * r * r
            rows = np.column_stack([x, np.zeros((plane, 3)), m, r, np.zeros(plane), inertia])
            np.savetxt(pf, rows, fmt="%.9g %.9g %.9g %d %d %d %.9g %.9g %d %.9g")
            # particle numbers (1-based, x-major) and the three forward neighbours
            own = ix * plane + iy * L + iz + 1
            nx = ((ix + 1) % L) * plane + iy * L + iz + 1
            ny = ix * plane + ((iy + 1) % L) * L + iz + 1
            nz = ix * plane + iy * L + (iz + 1) % L + 1
            for other in (nx, ny, nz):
                kn = rng.uniform(50.0, 150.0, plane)
                np.savetxt(cf, np.column_stack([own, other, kn, 0.3 * kn]), fmt="%d %d %.9g %.9g")


if __name__ == "__main__":
    main()
