import os
from typing import Any, Dict, Literal, Optional, Union

PathLike = Union[str, os.PathLike]

def pair(*, width: int = 960, height: int = 540, seed: int = 1, preset: Literal["default", "wide"] = "default",
         lighting: Literal["standard", "realistic"] = "standard", out: Optional[PathLike] = None,
         bgr: bool = False) -> Dict[str, Any]: ...
def scan(out: PathLike, *, frames: int = 120, width: int = 960, height: int = 540, seed: int = 1, fps: float = 30.0,
         lighting: Literal["standard", "realistic"] = "standard", video: Optional[PathLike] = None) -> Dict[str, Any]: ...
