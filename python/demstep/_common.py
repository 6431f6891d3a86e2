"""Helpers shared by the package's modules: records, enum names, calls."""
import ctypes as C
import dataclasses
import numbers

from . import _capi
from ._errors import check, invalid

#: Every DEMSTEP_* constant of include/demstep.h (status codes, laws, codes, effects, ...).
CONSTANTS = dict(_capi.CONSTANTS)


def record(struct_type, name, doc, extra=()):
    """A frozen dataclass with the fields of a ctypes struct (and extra ones)."""
    fields = [(field, float if ctype is C.c_double else int) for field, ctype in struct_type._fields_]
    cls = dataclasses.make_dataclass(name, fields + list(extra), frozen=True)
    cls.__doc__ = doc
    cls.__module__ = "demstep"
    return cls


def fill(cls, struct, **extra):
    """The record cls of a filled ctypes struct."""
    return cls(**{field: getattr(struct, field) for field, _ in struct._fields_}, **extra)


def enum(prefix, value, function, where):
    """A header constant by its short name ("linear" for DEMSTEP_LAW_LINEAR), or an int as it is."""
    if isinstance(value, str):
        key = prefix + value.upper()
        if key not in CONSTANTS:
            known = ", ".join(repr(n[len(prefix):].lower()) for n in CONSTANTS if n.startswith(prefix))
            raise invalid(function, where, f"{value!r} is not one of {known}")
        return CONSTANTS[key]
    if isinstance(value, numbers.Integral) and not isinstance(value, bool):
        return int(value)
    raise invalid(function, where, f"must be a name or an int, got {type(value).__name__}")


def call(function, *args):
    """Call a C function with a demstep_error as its last argument; raise its status."""
    err = _capi.Error()
    code = getattr(_capi.LIB, function)(*args, C.byref(err))
    check(code, err, function)


