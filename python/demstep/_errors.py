"""DemstepError: every status of the library, and the package's own argument checks."""
from . import _capi


class DemstepError(Exception):
    """A status other than DEMSTEP_OK.

    Attributes: ``code`` (the status, an int: ``DEMSTEP_INVALID_INPUT`` is 1),
    ``code_name`` (``"DEMSTEP_INVALID_INPUT"``), ``message`` (the library's whole
    message, the C function first), ``where`` (the argument or field to change,
    ``""`` when the library names no single one), ``index`` (its 0-based element
    or row, ``None`` when none applies) and ``function`` (the C function).
    """

    def __init__(self, code, message, where="", index=None, function=""):
        super().__init__(message)
        self.code = code
        self.code_name = _capi.STATUS_NAMES.get(code, f"status {code}")
        self.message = message
        self.where = where
        self.index = index
        self.function = function

    def __str__(self):
        return self.message


def check(code, err, function):
    """Raise the library's status held in ``err`` unless ``code`` is DEMSTEP_OK."""
    if code == _capi.CONSTANTS["DEMSTEP_OK"]:
        return
    index = None if err.index < 0 else err.index
    raise DemstepError(code, err.message.decode(errors="replace"), err.where.decode(errors="replace"),
                       index, function)


def invalid(function, where, what, index=None):
    """A DEMSTEP_INVALID_INPUT raised by the package before the call, in the library's form."""
    element = "" if index is None else f"({index})"
    return DemstepError(_capi.CONSTANTS["DEMSTEP_INVALID_INPUT"], f"{function}: {where}{element}: {what}",
                        where, index, function)
