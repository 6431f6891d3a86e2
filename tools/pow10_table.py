#!/usr/bin/env python3
"""Print the powers of ten of src/demstep/core/demstep_decimal.f90 as Fortran double-doubles.

10^q for q = -280..280 as hi + lo: hi the double nearest 10^q, lo the double
nearest 10^q - hi, both from exact rational arithmetic (float() of a Fraction is
correctly rounded), written with repr (the shortest text that reads back to the
same double). Run: python3 tools/pow10_table.py > table.txt
"""
from fractions import Fraction

LIMIT = 280


def pair(q):
    exact = Fraction(10) ** q
    hi = float(exact)
    lo = float(exact - Fraction(hi))
    return "dd_type(%s_dp, %s_dp)" % (repr(hi), repr(lo))


def table(name, first, last):
    entries = [pair(q) for q in range(first, last + 1)]
    lines = []
    for k in range(0, len(entries), 2):
        lines.append("    " + ", ".join(entries[k:k + 2]))
    print("  type(dd_type), parameter :: %s(%d:%d) = [ &" % (name, first, last))
    print(", &\n".join(lines) + " ]")


table("pow_low", -LIMIT, -1)
table("pow_high", 0, LIMIT)
