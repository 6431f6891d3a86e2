"""numpy arrays to the C API's arrays: shape and dtype checked, naming the C parameter.

Values are not checked here (NaN, signs, ranges): the library does that with its
own rules and its own messages.
"""
import ctypes as C

import numpy as np

from ._errors import invalid

_INT32 = np.iinfo(np.int32)


def _shape_text(shape):
    return "(" + ", ".join(str(s) for s in shape) + ("," if len(shape) == 1 else "") + ")"


def as_array(value, function, where, shape, kind, meaning=""):
    """A C-contiguous float64 (kind "float") or int32 (kind "int", "flag") copy of value.

    ``shape`` is the required shape (None for any length along an axis);
    ``meaning`` says what the shape is ("one per particle").
    """
    try:
        array = np.asarray(value)
    except (ValueError, TypeError) as exc:
        raise invalid(function, where, f"is not an array of numbers ({exc})") from None
    accepted = {"float": "fiu", "int": "iu", "flag": "biu"}[kind]
    if array.dtype.kind not in accepted:
        wanted = {"float": "real numbers", "int": "integers", "flag": "booleans or integers"}[kind]
        raise invalid(function, where, f"must hold {wanted}, got dtype {array.dtype}")
    if array.ndim != len(shape) or any(s is not None and s != a for s, a in zip(shape, array.shape)):
        wanted = _shape_text(["n" if s is None else s for s in shape])
        note = f" ({meaning})" if meaning else ""
        raise invalid(function, where, f"must have shape {wanted}{note}, got {_shape_text(array.shape)}")
    if kind == "float":
        return np.ascontiguousarray(array, dtype=np.float64)
    if array.dtype.kind in "iu" and array.size:
        outside = np.flatnonzero((array.ravel() < _INT32.min) | (array.ravel() > _INT32.max))
        if outside.size:
            first = int(outside[0])
            raise invalid(function, where, f"{array.ravel()[first]} is beyond a C int", index=first)
    return np.ascontiguousarray(array, dtype=np.int32)


def pointer(array):
    """The address of a contiguous array for a ``const double *`` or ``const int *``; None: NULL."""
    return None if array is None else array.ctypes.data_as(C.c_void_p)


def count(array, function, where):
    """len(array) as a C int."""
    n = array.shape[0]
    if n > _INT32.max:
        raise invalid(function, where, f"{n} rows are beyond a C int")
    return n
