#!/usr/bin/env python3
"""Compare "name value" lines of programs bit for bit: every value another
program prints must equal the reference's double of the same name exactly.
Lines starting with "bad_" (status reports) are not values."""
import sys


def read(path):
    values = {}
    for line in open(path):
        parts = line.split()
        if len(parts) == 2 and not parts[0].startswith("bad_"):
            values[parts[0]] = float(parts[1])
    return values


reference = read(sys.argv[1])
if not reference:
    sys.exit(f"compare: no values in {sys.argv[1]}")
status = 0
for other in sys.argv[2:]:
    values = read(other)
    bad = [name for name in values if values[name] != reference.get(name)]
    for name in bad:
        print(f"compare: {other}: {name} = {values[name]!r}, Fortran {reference.get(name)!r}")
    if bad or not values:
        status = 1
    else:
        print(f"compare: {other}: {len(values)} values equal to the Fortran ones bit for bit")
sys.exit(status)
