"""``python -m cardan``: the ``cardan`` command, from the Python package.

``python -m cardan run model.toml`` does what ``cardan run model.toml`` does (the same Rust
code: the same files, summary, messages and exit codes), and so do ``check``, ``import`` and
``eval``; ``python -m cardan --help`` lists them. The package also installs the command as
``cardan`` (a console script), so a ``pip install`` is enough to have it.
"""

from __future__ import annotations

import os
import sys
from typing import List, Optional

from . import _cardan


def main(argv: Optional[List[str]] = None) -> int:
    """Runs the ``cardan`` command with ``argv`` (default ``sys.argv[1:]``); returns its exit
    code."""
    args = list(sys.argv[1:] if argv is None else argv)
    program = os.path.basename(sys.argv[0]) if argv is None else "cardan"
    if program in ("__main__.py", "-m", "-c", ""):
        program = "python -m cardan"
    sys.stdout.flush()
    try:
        return _cardan.main([program, *args])
    except KeyboardInterrupt:  # Ctrl-C: the command kept the results so far
        return 130


def _console() -> None:
    """The ``cardan`` console script."""
    sys.exit(main())


if __name__ == "__main__":
    _console()
