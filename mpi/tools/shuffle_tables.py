#!/usr/bin/env python3
"""Write the same scene as a particles table and a contacts table in random
order, for the distributed reader's random-order measurements: the particle
rows permuted (particle p of the input becomes number new[p]), the contact
rows permuted too, each contact's two particle numbers renamed by the same
map (its other columns copied as text). Comment lines (starting with '#')
before the first row are kept at the top of each output.

    python3 shuffle_tables.py PARTICLES CONTACTS OUT_PARTICLES OUT_CONTACTS [seed]

The whole tables are held in memory (about 0.4 GB for 1e6 particles and
3e6 contacts).
"""
import sys

import numpy as np


def split_header(lines):
    head = 0
    while head < len(lines) and lines[head].lstrip().startswith("#"):
        head += 1
    return lines[:head], lines[head:]


def main():
    if len(sys.argv) < 5:
        sys.exit(__doc__)
    seed = int(sys.argv[5]) if len(sys.argv) > 5 else 7
    rng = np.random.default_rng(seed)
    with open(sys.argv[1]) as fh:
        p_head, p_rows = split_header(fh.readlines())
    order = rng.permutation(len(p_rows))  # new row k is old row order[k]
    new_of_old = np.empty(len(order), dtype=np.int64)
    new_of_old[order] = np.arange(1, len(order) + 1)
    with open(sys.argv[3], "w") as fh:
        fh.writelines(p_head)
        fh.writelines(p_rows[k] for k in order)
    del p_rows
    with open(sys.argv[2]) as fh:
        c_head, c_rows = split_header(fh.readlines())
    with open(sys.argv[4], "w") as fh:
        fh.writelines(c_head)
        for k in rng.permutation(len(c_rows)):
            i, j, rest = c_rows[k].split(maxsplit=2)
            fh.write(f"{new_of_old[int(i) - 1]} {new_of_old[int(j) - 1]} {rest}")


if __name__ == "__main__":
    main()
