"""Type stub of the native module (crates/python/src/lib.rs)."""

from typing import Any, Dict, List, Optional

__all__ = ["__version__", "check", "drag", "import_asmt", "import_urdf", "main", "run", "table_csv", "validate"]

__version__: str

def run(
    text: str,
    path: str,
    kind: Optional[str] = None,
    options: Optional[Dict[str, Any]] = None,
    strict: bool = False,
    report: bool = False,
) -> Dict[str, Any]: ...
def check(text: str, path: str) -> Dict[str, Any]: ...
def table_csv(name: str, title: str, columns: List[str], data: bytes) -> str: ...
def import_asmt(text: str, path: str, units: str = "si", inverse_dynamics: bool = False) -> Dict[str, Any]: ...
def import_urdf(text: str, path: str, base: str = "fixed", mimic: str = "couple", limits: bool = True) -> Dict[str, Any]: ...
def validate(text: str, path: str) -> Optional[Dict[str, Any]]: ...
def main(argv: List[str]) -> int: ...
def drag(
    text: str,
    path: str,
    body: str,
    target: List[float],
    point: Optional[str] = None,
    pose: Optional[Dict[str, Any]] = None,
    time: float = 0.0,
) -> Dict[str, Any]: ...
