#!/usr/bin/env python3
"""SciPy's eigsh (ARPACK's implicitly restarted Lanczos) on a mass-scaled
stiffness matrix A' that bench_scene_eigen wrote in Matrix Market format.

Reading the file (scipy.io.mmread) is not timed; only the eigsh call is:
the largest algebraic eigenvalue (which='LA', k=1) to tolerance TOL (default
1e-6), no eigenvector; the median of REPEATS calls (default 3; each from
eigsh's own random start). Prints one line, with the process's peak resident
memory (reading included):

    eigsh <order> <seconds> <eigenvalue> <peak MB>

Usage: python3 bench/eigsh_scene.py FILE.mtx [TOL [REPEATS]]
"""
import resource
import sys
import time

import scipy.io
import scipy.sparse.linalg


def main():
    if len(sys.argv) not in (2, 3, 4):
        sys.exit("usage: eigsh_scene.py FILE.mtx [TOL [REPEATS]]")
    tol = float(sys.argv[2]) if len(sys.argv) >= 3 else 1.0e-6
    repeats = int(sys.argv[3]) if len(sys.argv) == 4 else 3
    a = scipy.io.mmread(sys.argv[1]).tocsr()
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        top = scipy.sparse.linalg.eigsh(a, k=1, which="LA", tol=tol, return_eigenvectors=False)
        times.append(time.perf_counter() - start)
    seconds = sorted(times)[len(times) // 2]
    peak_mb = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0
    print(f"eigsh {a.shape[0]} {seconds:.3f} {top[0]:.16e} {peak_mb:.0f}")


if __name__ == "__main__":
    main()
