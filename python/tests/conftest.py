"""Shared fixtures: the repository root (data, decks) and the app bundled with the package."""
import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="session")
def root():
    return ROOT


@pytest.fixture(scope="session")
def run_app(tmp_path_factory):
    """Run the bundled demstep app (python -m demstep) on a deck; its result namelist as a dict
    (arrays=True: every numeric variable as a list, repeat counts n*value expanded)."""
    def run(deck, arrays=False):
        out = tmp_path_factory.mktemp("app") / "result.nml"
        done = subprocess.run([sys.executable, "-m", "demstep", deck.name, "-o", str(out)], cwd=deck.parent,
                              capture_output=True, text=True)
        assert done.returncode == 0, done.stdout + done.stderr
        text = out.read_text()
        return read_namelist_arrays(text) if arrays else read_namelist(text)
    return run


def read_namelist_arrays(text):
    """NAME=v1, v2, n*v3, ... of a result namelist, as lists of floats by lower-case name."""
    values = {}
    for name, body in re.findall(r"\b([A-Z_]+)=(.*?)(?=\b[A-Z_]+=|/\s*$)", text, re.S):
        items = []
        for item in body.replace("\n", " ").split(","):
            item = item.strip()
            if not item:
                continue
            count, _, value = item.rpartition("*")
            try:
                items += [float(value)] * (int(count) if count else 1)
            except ValueError:
                items = None
                break
        if items:
            values[name.lower()] = items
    return values


def read_namelist(text):
    """NAME=value (one value) of a result namelist, as floats by lower-case name."""
    values = {}
    for line in text.splitlines():
        name, _, value = line.strip().partition("=")
        value = value.rstrip(",").strip()
        if not value or "," in value:
            continue
        try:
            values[name.lower()] = float(value)
        except ValueError:
            pass
    return values
