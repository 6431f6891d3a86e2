"""The README's "From Python" example prints what the README says; the notebook-style
example runs to its end."""
import re
import subprocess
import sys


def test_readme_example_prints_what_the_readme_says(root):
    text = (root / "README.md").read_text()
    section = text[text.index("\n## From Python\n"):]
    section = section[:section.index("\n## ", 1)]
    code = re.search(r"```python\n(.*?)```", section, re.S).group(1)
    stated = re.search(r"prints `(exact limit: [^`]*)` and\n`(per-contact rule [^`]*)`", section)
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert done.stdout.splitlines() == [stated.group(1), stated.group(2)]


def test_notebook_example_runs(root):
    done = subprocess.run([sys.executable, str(root / "example/python_notebook.py")], capture_output=True,
                          text=True)
    assert done.returncode == 0, done.stderr
    assert "ratio 0.99957" in done.stdout and "DEMSTEP_INVALID_INPUT | x |" in done.stdout
