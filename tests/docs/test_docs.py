"""Every code block of README.md and docs/ runs (issue 46): a newcomer who follows the documents
meets no error. Each document is one test; its blocks run in order in one working directory
(conftest.workdir), so a later block sees what an earlier one made, and a failure names the
document, the block's line and what failed.

- ``sh``: the commands run (shell.py says which; ``no-run`` blocks are only shown);
- ``toml``: a complete model is checked with ``cardan check`` and, with an [analysis] table,
  run; ``fragment``: parsed as TOML; ``file=NAME``: saved as NAME and checked;
- ``diff file=NAME``: applied to NAME (lines ``-`` removed, ``+`` added, `` `` kept; hunks
  separated by ``@@`` lines), which must hold each hunk's old lines exactly once; then NAME is
  checked;
- ``python``: run in one interpreter per document (pyrunner.py), with the package installed;
- ``rust``: compiled and run as a doctest: the document must be included as a doctest;
- ``text``: output, not code.
"""

from __future__ import annotations

import json
import pathlib
import subprocess
from typing import List, Optional

import pytest
import tomli

import shell
from blocks import ROOT, Block, blocks, documents
from conftest import environment, workdir

DOCS = documents()


class Session:
    """A document's run: its working directory, environment and Python interpreter."""

    def __init__(self, work: pathlib.Path, env: dict, cardan: pathlib.Path, python: pathlib.Path) -> None:
        self.work, self.env, self.cardan, self.python = work, env, cardan, python
        self.runner: Optional[subprocess.Popen] = None
        self.notes: List[str] = []

    def run(self, args: List[str], block: Block) -> subprocess.CompletedProcess:
        out = subprocess.run(args, cwd=self.work, env=self.env, capture_output=True, text=True, check=False)
        if out.returncode != 0:
            pytest.fail(f"{block.where()}: {' '.join(map(str, args))} exited {out.returncode}\n{out.stdout}{out.stderr}")
        return out

    def python_block(self, block: Block) -> None:
        if self.runner is None:
            self.runner = subprocess.Popen(
                [str(self.python), str(pathlib.Path(__file__).with_name("pyrunner.py"))],
                cwd=self.work, env=self.env, stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True,
            )
        assert self.runner.stdin is not None and self.runner.stdout is not None
        self.runner.stdin.write(json.dumps({"doc": str(ROOT / block.doc), "line": block.first_line, "code": block.text}) + "\n")
        self.runner.stdin.flush()
        answer = self.runner.stdout.readline()
        if not answer:
            pytest.fail(f"{block.where()}: the Python interpreter ended (exit code {self.runner.wait()})")
        result = json.loads(answer)
        if not result["ok"]:
            pytest.fail(f"{block.where()}:\n{result['error']}")

    def close(self) -> None:
        if self.runner is not None:
            assert self.runner.stdin is not None
            self.runner.stdin.close()
            self.runner.wait(timeout=60)


def check_model(s: Session, block: Block, path: pathlib.Path, run: bool) -> None:
    s.run([str(s.cardan), "check", str(path)], block)
    if run:
        s.run([str(s.cardan), "run", str(path), "-o", str(path.with_suffix("")) + "-out", "--quiet"], block)


def toml_block(s: Session, block: Block) -> None:
    try:
        data = tomli.loads(block.text)
    except tomli.TOMLDecodeError as e:
        pytest.fail(f"{block.where()}: not TOML: {e}")
    if "fragment" in block.attrs:
        return
    if "file" in block.attrs:
        path = s.work / block.attrs["file"]
        path.write_text(block.text)
        check_model(s, block, path, run=False)
        return
    path = s.work / f"block-{block.line}.toml"
    path.write_text(block.text)
    check_model(s, block, path, run="analysis" in data)


def apply_diff(text: str, diff: str, where: str) -> str:
    """``text`` with each hunk's ``-`` lines replaced by its ``+`` lines (``' '`` lines kept);
    hunks are separated by lines starting with ``@@``."""
    hunks: List[List[str]] = [[]]
    for line in diff.splitlines():
        if line.startswith("@@"):
            hunks.append([])
        else:
            hunks[-1].append(line)
    for hunk in hunks:
        old, new = [], []
        for line in hunk:
            mark, rest = line[:1], line[1:]
            if mark == " ":
                old.append(rest)
                new.append(rest)
            elif mark == "-":
                old.append(rest)
            elif mark == "+":
                new.append(rest)
            elif line.strip():
                pytest.fail(f"{where}: a diff line starts with ' ', '-', '+' or '@@': {line!r}")
        before, after = "\n".join(old) + "\n", "\n".join(new) + "\n"
        if text.count(before) != 1:
            pytest.fail(f"{where}: the lines to change occur {text.count(before)} times in the file, not once:\n{before}")
        text = text.replace(before, after)
    return text


def diff_block(s: Session, block: Block) -> None:
    if "file" not in block.attrs:
        pytest.fail(f"{block.where()}: a diff block names the file it changes (diff file=NAME)")
    path = s.work / block.attrs["file"]
    if not path.exists():
        pytest.fail(f"{block.where()}: {block.attrs['file']} does not exist yet")
    path.write_text(apply_diff(path.read_text(), block.text, block.where()))
    check_model(s, block, path, run=False)


def sh_block(s: Session, block: Block) -> None:
    script, skipped, refused = shell.prepare(block.text)
    if refused:
        pytest.fail(f"{block.where()}:\n" + "\n".join(refused))
    s.notes += [f"{block.where()}: left out {line}" for line in skipped]
    if script:
        trap = 'trap \'echo "failed: $BASH_COMMAND" >&2\' ERR\n'
        s.run(["bash", "-euo", "pipefail", "-c", trap + script], block)


def rust_block(block: Block) -> None:
    # A document included with #[doc = include_str!(...)] under #[cfg(doctest)]: cargo test
    # compiles and runs its Rust blocks (crates/mechanism/src/lib.rs includes README.md).
    included = any(
        f'include_str!("{"../" * (len(p.relative_to(ROOT).parts) - 1)}{block.doc}")' in p.read_text()
        for p in ROOT.glob("crates/*/src/lib.rs")
    )
    if not included:
        pytest.fail(f"{block.where()}: Rust blocks must be doctests: include {block.doc} in a crate's docs")


def run_block(s: Session, block: Block) -> None:
    if "no-run" in block.attrs or block.lang == "text":
        return
    if block.lang == "sh":
        sh_block(s, block)
    elif block.lang == "toml":
        toml_block(s, block)
    elif block.lang == "diff":
        diff_block(s, block)
    elif block.lang == "python":
        s.python_block(block)
    elif block.lang == "rust":
        rust_block(block)
    else:
        pytest.fail(f"{block.where()}: no test runs {block.lang or 'a block without a language'}; "
                    f"give it a language (sh, toml, diff, python, rust, text) or mark it no-run")


@pytest.mark.parametrize("doc", DOCS, ids=[str(d.relative_to(ROOT)) for d in DOCS])
def test_every_block_runs(doc, tmp_path, cardan_bin, venv_python):
    work = workdir(tmp_path, cardan_bin)
    s = Session(work, environment(work, venv_python), cardan_bin, venv_python)
    try:
        for block in blocks(doc):
            run_block(s, block)
    finally:
        s.close()
    for note in s.notes:
        print(note)
