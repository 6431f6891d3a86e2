"""Shared fixtures: the repository root (data, decks) and the app bundled with the package."""
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
    """Run the bundled demstep app (python -m demstep) on a deck; its result namelist as a dict."""
    def run(deck):
        out = tmp_path_factory.mktemp("app") / "result.nml"
        done = subprocess.run([sys.executable, "-m", "demstep", deck.name, "-o", str(out)], cwd=deck.parent,
                              capture_output=True, text=True)
        assert done.returncode == 0, done.stdout + done.stderr
        return read_namelist(out.read_text())
    return run


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
