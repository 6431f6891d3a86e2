"""The enum constants of include/demstep.h, read from the header itself.

The header is the one place where the C API's numbers are written down; the
package carries a copy (``_lib/demstep.h``, put there by the build) and reads
its ``enum { ... }`` blocks, so that no number is written twice.
"""
import re
from pathlib import Path

_ENUM = re.compile(r"enum\s*\{(.*?)\}\s*;", re.S)
_ITEM = re.compile(r"^\s*(DEMSTEP_[A-Z0-9_]+)\s*=\s*(-?\d+)\s*$")
_COMMENT = re.compile(r"/\*.*?\*/", re.S)


def header_path():
    """The header bundled with the package, else the source tree's (a checkout)."""
    here = Path(__file__).resolve().parent
    for candidate in (here / "_lib" / "demstep.h", here.parents[1] / "include" / "demstep.h"):
        if candidate.is_file():
            return candidate
    raise ImportError("demstep: include/demstep.h is neither in the package (_lib/) nor in a "
                      "source tree above it; reinstall the package")


def read_enum_blocks(path):
    """The header's enums, one dict ``{"DEMSTEP_NAME": value}`` per ``enum { }`` block."""
    text = _COMMENT.sub("", Path(path).read_text())
    blocks = []
    for block in _ENUM.findall(text):
        constants = {}
        for item in block.split(","):
            match = _ITEM.match(item)
            if match is None:
                raise ImportError(f"demstep: {path}: an enum item is not NAME = integer: {item.strip()!r}")
            constants[match.group(1)] = int(match.group(2))
        blocks.append(constants)
    return blocks
