"""Runs a document's Python blocks one after the other in one interpreter, as a reader who
pastes them into one session would: each block is compiled with the document's name and line
numbers (a traceback points into the document) and run in ``__main__``, so the functions it
defines are module-level (picklable for process pools). That ``__main__`` is a fresh module:
the runner's own imports are not visible to the blocks, so a block that forgets an import
fails here as it would for the reader.

Protocol: one JSON object per line on stdin, ``{"doc": ..., "line": ..., "code": ...}``; one
JSON answer per line on the original stdout, ``{"ok": true}`` or ``{"ok": false, "error":
traceback}``. What the blocks print goes to stderr (fd 1 is pointed there, for child processes
too).
"""

import json
import os
import sys
import traceback
import types


def main() -> None:
    answers = os.fdopen(os.dup(1), "w", buffering=1)
    os.dup2(2, 1)
    sys.stdout = sys.stderr
    session = types.ModuleType("__main__")
    sys.modules["__main__"] = session
    for request in sys.stdin:
        block = json.loads(request)
        try:
            # Leading newlines make the code's line numbers the document's.
            code = compile("\n" * (block["line"] - 1) + block["code"], block["doc"], "exec")
            exec(code, session.__dict__)
            answer = {"ok": True}
        except BaseException:  # noqa: B902 (a block's SystemExit or KeyboardInterrupt is its failure)
            answer = {"ok": False, "error": traceback.format_exc()}
        answers.write(json.dumps(answer) + "\n")


if __name__ == "__main__":
    main()
