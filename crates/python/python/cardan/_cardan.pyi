"""Type stub of the native module (crates/python/src/lib.rs)."""

from typing import Any, Dict, List, Optional, Tuple

from typing_extensions import final

__all__ = ["Prepared", "__version__", "check", "drag", "import_asmt", "import_urdf", "main", "parameters", "prepare", "run", "table_csv", "with_parameters"]

__version__: str

@final
class Prepared:
    """A model text read, checked and built (opaque; ``prepare`` makes one)."""

def run(
    text: str,
    path: str,
    kind: Optional[str] = None,
    options: Optional[Dict[str, Any]] = None,
    strict: bool = False,
    report: bool = False,
    model: Optional[Prepared] = None,
) -> Dict[str, Any]: ...
def check(text: str, path: str, model: Optional[Prepared] = None) -> Dict[str, Any]: ...
def table_csv(name: str, title: str, columns: List[str], data: bytes) -> str: ...
def import_asmt(text: Optional[str], path: str, units: str = "si", inverse_dynamics: bool = False) -> Dict[str, Any]: ...
def import_urdf(text: Optional[str], path: str, base: str = "fixed", mimic: str = "couple", limits: bool = True, damping: bool = False, friction: bool = False) -> Dict[str, Any]: ...
def prepare(text: str, path: str) -> Dict[str, Any]: ...
def with_parameters(text: str, path: str, values: List[Tuple[str, str]]) -> Dict[str, Any]: ...
def parameters(text: str, path: str) -> Dict[str, Any]: ...
def main(argv: List[str]) -> int: ...
def drag(
    text: str,
    path: str,
    body: str,
    target: List[float],
    point: Optional[str] = None,
    pose: Optional[Dict[str, Any]] = None,
    time: float = 0.0,
    model: Optional[Prepared] = None,
) -> Dict[str, Any]: ...
