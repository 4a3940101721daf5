"""Point the CMake exports of the ROS 2 message wheels at this machine's include folders.

The wheels are built in a manylinux container, and their exported targets
(``<venv>/share/*/cmake/*.cmake``) name ``/opt/python/cp311-cp311/include/python3.11`` and that
container's numpy include folder. CMake refuses to configure a package that links against such a
target while those folders do not exist, so ``msg_defs/`` could not be built. This rewrites the
paths, inside the venv only, to the running interpreter's include folder and numpy's. Idempotent.
Usage: ``<venv>/bin/python tools/fix_cmake_paths.py <venv>``.
"""

import re
import sys
import sysconfig
from pathlib import Path

import numpy

# an include folder of the wheel-building interpreter: /opt/python/<tag>/include/python3.11,
# or the numpy include folder below that interpreter's site-packages
FOREIGN_PYTHON_INCLUDE = re.compile(r"/opt/python/[^/;\"]+/include/python3\.\d+")
FOREIGN_NUMPY_INCLUDE = re.compile(r"/opt/python/[^/;\"]+/lib/python3\.\d+/site-packages/numpy/(?:_core|core)/include")


def fix_cmake_exports(prefix: Path) -> list:
    """Rewrite foreign include folders in ``prefix/share/*/cmake/*.cmake``; return the changed files."""
    python_include = sysconfig.get_paths()["include"]
    numpy_include = numpy.get_include()
    if not (Path(python_include) / "Python.h").is_file():
        raise SystemExit(f"Python.h not found in {python_include}: the Python development headers are needed")
    changed = []
    for path in sorted(prefix.glob("share/*/cmake/*.cmake")):
        text = path.read_text()
        if "/opt/python/" not in text:
            continue
        new = FOREIGN_NUMPY_INCLUDE.sub(numpy_include, text)
        new = FOREIGN_PYTHON_INCLUDE.sub(python_include, new)
        if new != text:
            path.write_text(new)
            changed.append(path)
    return changed


if __name__ == "__main__":
    target = Path(sys.argv[1] if len(sys.argv) > 1 else sys.prefix)
    files = fix_cmake_exports(target)
    print(f"[setup] fixed include paths in {len(files)} CMake export files")
