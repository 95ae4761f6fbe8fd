"""Exceptions: every failure of a model or an analysis is a :class:`CardanError`."""

from __future__ import annotations

import re
from typing import TYPE_CHECKING, Any, List, Optional

if TYPE_CHECKING:  # pragma: no cover
    from ._results import Results

_ELEMENT = re.compile(r'\b(?:body|joint|driver|force|coupler|point|vector|spring|damper) "([^"]+)"')
_QUOTED = re.compile(r'"([^"]+)"')
_TIME = re.compile(r"\bt = (-?[0-9][0-9.eE+-]*)")


class CardanError(Exception):
    """A failure of cardan: ``message`` is the one-paragraph explanation the ``cardan``
    command prints, ``printed`` the same with its location and source excerpt."""

    def __init__(self, message: str, printed: Optional[str] = None) -> None:
        super().__init__(printed or message)
        self.message = message
        self.printed = printed or message


class ModelError(CardanError):
    """The model cannot be read, parsed or validated.

    ``file``, ``line`` and ``column`` locate the error in the model text (1-based; ``None``
    when the error has no place), ``element`` names the body, joint, driver or force it
    concerns when the message names one."""

    def __init__(
        self,
        message: str,
        printed: Optional[str] = None,
        file: Optional[str] = None,
        line: Optional[int] = None,
        column: Optional[int] = None,
    ) -> None:
        super().__init__(message, printed)
        self.file = file
        self.line = line
        self.column = column
        m = _ELEMENT.search(message)
        self.element: Optional[str] = m.group(1) if m else None

    def __reduce__(self) -> Any:
        return (type(self), (self.message, self.printed, self.file, self.line, self.column))


class AnalysisError(CardanError):
    """The model is valid but its analysis failed (assembly, a singular configuration, a
    step that does not converge), or stopped early.

    ``time`` is the time the message names (``None`` if it names none), ``equations`` the
    quoted element names it lists (the joints or drivers whose equations failed), ``partial``
    the results up to the failure (``None`` when nothing was solved)."""

    def __init__(
        self,
        message: str,
        printed: Optional[str] = None,
        file: Optional[str] = None,
        line: Optional[int] = None,
        column: Optional[int] = None,
        partial: Optional["Results"] = None,
    ) -> None:
        super().__init__(message, printed)
        self.file = file
        self.line = line
        self.column = column
        self.partial = partial
        m = _TIME.search(message)
        self.time: Optional[float] = float(m.group(1).rstrip(".")) if m else None
        self.equations: List[str] = _QUOTED.findall(message)

    def __reduce__(self) -> Any:
        return (
            type(self),
            (self.message, self.printed, self.file, self.line, self.column, self.partial),
        )


def raise_error(err: dict, partial: Optional["Results"] = None) -> None:
    """Raises the exception of a native error dict."""
    args = (err["message"], err["printed"], err["file"], err["line"], err["column"])
    if err["kind"] == "input":
        raise ModelError(*args)
    if err["kind"] == "output":
        raise CardanError(err["message"], err["printed"])
    raise AnalysisError(*args, partial=partial)
