"""Where the package finds a data file named in a configuration (a motion record, an RAO table).

A leaf module (it imports nothing of tether_sim), so that every layer can use it.
"""

import os
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]


def resolve_data_path(path, key: str) -> Path:
    """``path`` if absolute, else the first file found relative to the working directory, the
    repository or a package share of AMENT_PREFIX_PATH; FileNotFoundError naming the key otherwise."""
    p = Path(path)
    candidates = [p] if p.is_absolute() else [Path.cwd() / p, REPO / p]
    if not p.is_absolute():
        for prefix in os.environ.get("AMENT_PREFIX_PATH", "").split(os.pathsep):
            if prefix:
                candidates.append(Path(prefix) / "share" / "tether_sim" / p)
    for c in candidates:
        if c.is_file():
            return c
    raise FileNotFoundError(f"{key}: {str(path)!r} not found (looked in {', '.join(map(str, candidates))})")
