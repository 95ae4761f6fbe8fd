"""The code blocks of the project's documents, read with markdown-it-py (a CommonMark parser:
fences inside lists and block quotes included, no hand-written fence matching).

A block's info string is its language and, after it, attributes that say how the docs tests
treat it (tests/docs/README.md):

- ``no-run``: shown to the reader, never run (developer tasks, clusters, long runs);
- ``fragment``: a TOML block that is part of a model: parsed as TOML, not checked as a model;
- ``file=NAME``: a TOML block is saved as NAME in the document's working directory (a later
  block runs it); a ``diff`` block is applied to NAME.
"""

from __future__ import annotations

import pathlib
from dataclasses import dataclass, field
from typing import Dict, List

from markdown_it import MarkdownIt

ROOT = pathlib.Path(__file__).resolve().parents[2]
# The attributes a block may carry; any other word after the language is an error (a typo
# would otherwise silently change how a block is tested).
ATTRIBUTES = {"no-run", "fragment", "file"}


@dataclass
class Block:
    """One fenced code block: where it is, its language, attributes and text."""

    doc: str  # the document, relative to the repository root
    line: int  # 1-based line of the opening fence
    lang: str
    attrs: Dict[str, str] = field(default_factory=dict)
    text: str = ""

    @property
    def first_line(self) -> int:
        """The 1-based line of the block's first line of code."""
        return self.line + 1

    def where(self) -> str:
        return f"{self.doc}, block at line {self.line} ({self.lang or 'no language'})"


def documents() -> List[pathlib.Path]:
    """README.md and every Markdown file under docs/."""
    return [ROOT / "README.md", *sorted((ROOT / "docs").rglob("*.md"))]


def parse_info(info: str) -> tuple:
    """``"toml file=a.toml"`` → ``("toml", {"file": "a.toml"})``; unknown attributes raise."""
    words = info.split()
    lang = words[0] if words else ""
    attrs: Dict[str, str] = {}
    for word in words[1:]:
        key, _, value = word.partition("=")
        if key not in ATTRIBUTES:
            raise ValueError(f"unknown block attribute {word!r} (known: {', '.join(sorted(ATTRIBUTES))})")
        attrs[key] = value
    return lang, attrs


def blocks(path: pathlib.Path) -> List[Block]:
    """The fenced code blocks of a Markdown file, in order."""
    doc = str(path.relative_to(ROOT))
    out = []
    for token in MarkdownIt("commonmark").parse(path.read_text(encoding="utf-8")):
        if token.type != "fence" or token.map is None:
            continue
        line = token.map[0] + 1
        try:
            lang, attrs = parse_info(token.info)
        except ValueError as e:
            raise ValueError(f"{doc}, block at line {line}: {e}") from None
        out.append(Block(doc, line, lang, attrs, token.content))
    return out
