"""The ctypes structs and prototypes against include/demstep.h, parsed."""
import ctypes as C
import re

import pytest

import demstep
from demstep import _capi
from demstep._header import header_path

C_TYPES = {"double": C.c_double, "int": C.c_int, "int64_t": C.c_int64, "char": C.c_char,
           "size_t": C.c_size_t}
STRUCTS = {"demstep_error": _capi.Error, "demstep_spring": _capi.Spring,
           "demstep_spring_state": _capi.SpringState, "demstep_nroots": _capi.NRoots,
           "demstep_stiffness_result": _capi.StiffnessResult, "demstep_contact": _capi.Contact,
           "demstep_scene_result": _capi.SceneResult, "demstep_snapshot_info": _capi.SnapshotInfo,
           "demstep_material": _capi.Material, "demstep_material_pair": _capi.MaterialPair,
           "demstep_code_contact": _capi.ContactParameters, "demstep_peer_steps": _capi.PeerSteps}


def header_text():
    return re.sub(r"/\*.*?\*/", "", header_path().read_text(), flags=re.S)


def header_structs():
    structs = {}
    for body, name in re.findall(r"typedef struct \{(.*?)\}\s*(\w+);", header_text(), re.S):
        fields = []
        for declaration in body.split(";"):
            words = declaration.split()
            if not words:
                continue
            ctype = C_TYPES.get(words[0]) or STRUCTS[words[0]]  # a struct declared above
            for item in " ".join(words[1:]).split(","):
                item = item.strip()
                array = re.fullmatch(r"(\w+)\[(\d+)\]", item)
                fields.append((array.group(1), ctype * int(array.group(2))) if array else (item, ctype))
        structs[name] = fields
    assert set(structs) == set(STRUCTS)
    return structs


@pytest.mark.parametrize("name", sorted(STRUCTS))
def test_struct_matches_the_header(name):
    declared = header_structs()[name]
    ours = STRUCTS[name]._fields_
    assert [f for f, _ in ours] == [f for f, _ in declared]
    for (field, mine), (_, theirs) in zip(ours, declared):
        assert C.sizeof(mine) == C.sizeof(theirs) and getattr(mine, "_type_", mine) == \
            getattr(theirs, "_type_", theirs), field


def test_every_function_is_declared():
    declared = re.findall(r"int (demstep_\w+)\(([^)]*)\);", header_text())
    assert {name for name, _ in declared} == set(_capi.PROTOTYPES)
    for name, arguments in declared:
        assert len(arguments.split(",")) == len(_capi.PROTOTYPES[name]), name


def test_constants_are_the_header_values():
    assert demstep.CONSTANTS["DEMSTEP_OK"] == 0
    assert demstep.CONSTANTS["DEMSTEP_EFFECT_ROTATION"] == 32
    assert demstep.CONSTANTS["DEMSTEP_CODE_LAMMPS_HERTZ_MATERIAL"] == 9
    assert _capi.STATUS_NAMES[11] == "DEMSTEP_EIGENSOLVER_FAILURE"
