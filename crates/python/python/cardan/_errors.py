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
    command prints, ``printed`` the same with its location and source excerpt; ``file``,
    ``line`` and ``column`` locate it in the model text (1-based; ``None`` when it has no
    place); ``element`` names the body, joint, driver or force it concerns (``None`` when the
    message names none)."""

    def __init__(
        self,
        message: str,
        printed: Optional[str] = None,
        file: Optional[str] = None,
        line: Optional[int] = None,
        column: Optional[int] = None,
    ) -> None:
        super().__init__(printed or message)
        self.message = message
        self.printed = printed or message
        self.file = file
        self.line = line
        self.column = column

    @property
    def element(self) -> Optional[str]:
        """The body, joint, driver, force, coupler, point or vector the message names first."""
        m = _ELEMENT.search(self.message)
        return m.group(1) if m else None

    def _args(self) -> tuple:
        return (self.message, self.printed, self.file, self.line, self.column)

    def __reduce__(self) -> Any:
        return (type(self), self._args())


class ModelError(CardanError):
    """The model cannot be read, parsed or validated (raised when a :class:`Model` is made:
    :func:`load`, :meth:`Model.from_toml`, :meth:`Builder.build`)."""


class AnalysisError(CardanError):
    """The model is valid but its analysis failed (assembly, a singular configuration, a
    step that does not converge), or stopped early.

    ``time`` is the time the message names (``None`` if it names none), ``equations`` the
    quoted element names it lists (the joints or drivers whose equations failed), ``partial``
    the results up to the failure (``None`` when nothing was solved)."""

    def __init__(self, *args: Any, partial: Optional["Results"] = None) -> None:
        super().__init__(*args)
        self.partial = partial
        m = _TIME.search(self.message)
        self.time: Optional[float] = float(m.group(1).rstrip(".")) if m else None
        self.equations: List[str] = _QUOTED.findall(self.message)

    @property
    def element(self) -> Optional[str]:
        """The element the message names first, else the first whose equations it lists."""
        return super().element or (self.equations[0] if self.equations else None)

    def __reduce__(self) -> Any:
        return (_analysis_error, (type(self), self._args(), self.partial))


class SolverError(AnalysisError):
    """The solver could not solve the model: it does not assemble, a configuration is
    singular, the drivers do not match the degrees of freedom, a step does not converge.
    (An :class:`AnalysisError` that is not a ``SolverError``: ``strict=True`` with warnings
    about doubtful results.)"""


def _analysis_error(cls: type, args: tuple, partial: Optional["Results"]) -> AnalysisError:
    return cls(*args, partial=partial)


def raise_error(err: dict, partial: Optional["Results"] = None) -> None:
    """Raises the exception of a native error dict."""
    args = (err["message"], err["printed"], err["file"], err["line"], err["column"])
    if err["kind"] == "input":
        raise ModelError(*args)
    if err["kind"] == "output":
        raise CardanError(*args)
    if err["kind"] in ("strict", "interrupted"):
        raise AnalysisError(*args, partial=partial)
    raise SolverError(*args, partial=partial)
