"""python -m demstep [app arguments]: the demstep app bundled with the package."""
import os
import sys
from pathlib import Path


def main():
    lib = Path(__file__).resolve().parent / "_lib"
    app = lib / "demstep"
    if not app.is_file():
        sys.exit(f"demstep: the app {app} is missing: install the package with pip (it builds the app)")
    env = dict(os.environ)
    env["LD_LIBRARY_PATH"] = os.pathsep.join(filter(None, [str(lib), env.get("LD_LIBRARY_PATH")]))
    os.execve(str(app), [str(app)] + sys.argv[1:], env)


if __name__ == "__main__":
    main()
