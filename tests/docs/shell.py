"""Shell blocks: which commands the docs tests run, and how.

A shell block is run by bash in the document's working directory (a copy of examples/, the
repository's target/ linked in), with `cardan` the release command and `python`/`pip` those of
target/py-venv. `cargo run --release -p cardan-cli --` (the README's form, which builds the
command first) becomes `cardan`. Every command must be one of those below: a command the tests
cannot run cheaply is refused, so a block must say `no-run` for it, and nothing expensive runs
by accident.
"""

from __future__ import annotations

import re
import shlex
from typing import List, Tuple

CARGO_RUN = re.compile(r"\bcargo run --release -p cardan-cli --\s+")

# Programs a block may run (the file commands a tutorial uses, the cardan command, Python).
PROGRAMS = {"cardan", "python", "python3", "pip", "cp", "mv", "mkdir", "cd", "ls", "cat", "head", "tail", "echo", "export"}

# cardan subcommands that never end by themselves: left out, each tested elsewhere.
LONG_RUNNING = {
    "watch": "it serves until Ctrl-C; crates/cli/tests/watch.rs drives it in a browser",
}

# Commands that set up what the tests themselves set up before they start: left out, not run.
DONE_BEFORE = {
    "scripts/test": "the test command itself (these tests are part of it)",
    "scripts/test-python": "scripts/test runs it before these tests",
    "scripts/python-env": "it made the environment these tests run in",
    "scripts/build-wheel": "scripts/python-env built the wheel before these tests",
}


def logical_lines(text: str) -> List[str]:
    """The block's commands: continuation lines joined, blank lines dropped."""
    out, pending = [], ""
    for raw in text.splitlines():
        if raw.rstrip().endswith("\\"):
            pending += raw.rstrip()[:-1] + " "
            continue
        line = (pending + raw).strip()
        pending = ""
        if line:
            out.append(line)
    if pending.strip():
        out.append(pending.strip())
    return out


def words(line: str) -> List[str]:
    """The words of a command line, comments dropped (a line that is only a comment: none)."""
    return shlex.split(line, comments=True)


def prepare(text: str) -> Tuple[str, List[str], List[str]]:
    """The script to run, the commands left out (with why) and the refused ones (with why)."""
    script, skipped, refused = [], [], []
    for line in logical_lines(CARGO_RUN.sub("cardan ", text)):
        w = words(line)
        if not w:
            continue
        program = w[0]
        if program in DONE_BEFORE:
            skipped.append(f"{line}: {DONE_BEFORE[program]}")
            continue
        if program == "cardan" and len(w) > 1 and w[1] in LONG_RUNNING:
            skipped.append(f"{line}: {LONG_RUNNING[w[1]]}")
            continue
        if program.endswith("/python") and program.startswith("target/py-venv/bin/"):
            program = "python"
        if program not in PROGRAMS:
            refused.append(f"{line}: the docs tests do not run {program!r}; mark the block no-run")
            continue
        if program == "pip" and not all(
            a.startswith("-") or a == "install" or a.startswith("target/wheels/cardan-") or a.startswith("cardan[")
            for a in w[1:]
        ):
            refused.append(f"{line}: only 'pip install' of the built wheel (and cardan[extras]) runs here")
            continue
        script.append(line)
    return "\n".join(script), skipped, refused


def examples_run(text: str) -> List[str]:
    """The bundled examples a block runs: `cardan run examples/X` and `python examples/python/X.py`."""
    found = []
    for line in logical_lines(CARGO_RUN.sub("cardan ", text)):
        w = words(line)
        if len(w) >= 3 and w[0] == "cardan" and w[1] == "run" and w[2].startswith("examples/"):
            found.append(w[2])
        elif len(w) >= 2 and w[0].endswith("python") and w[1].startswith("examples/python/"):
            found.append(w[1])
    return found
