"""Link setup.py's ``data_files`` into the venv prefix, as ``colcon build --symlink-install`` would.

``pip install -e .`` installs the code in development mode but not ``data_files``; without them
the ament index has no ``tether_sim`` marker and ``share/tether_sim/{package.xml,config,data}`` is
missing. Symbolic links keep config edits live. pip also puts the console scripts in ``<prefix>/bin``
only, while ``ros2 run`` and launch_ros' ``Node(package=..., executable=...)`` look for them in
``<prefix>/lib/<package>/`` (where setup.cfg's ``install_scripts`` puts them in a colcon build):
each is linked there too. Links made by an earlier run (recorded in
``<prefix>/.stamps/data_files.txt``) are removed first. Usage:
``<venv>/bin/python tools/link_data_files.py <repo root> <prefix>``.
"""

import os
import runpy
import sys
from pathlib import Path

import setuptools

RECORD = Path(".stamps") / "data_files.txt"


def setup_arguments(root: Path) -> dict:
    """The keyword arguments ``root/setup.py`` gives ``setup()`` (read, not run)."""
    captured = {}
    real_setup = setuptools.setup
    cwd = os.getcwd()
    try:
        setuptools.setup = lambda **kwargs: captured.update(kwargs)  # read the arguments only
        os.chdir(root)  # setup.py globs relative paths
        runpy.run_path("setup.py", run_name="__main__")
    finally:
        os.chdir(cwd)
        setuptools.setup = real_setup
    return captured


def data_files_of(root: Path) -> list:
    """[(target dir, [source paths relative to root])] as declared in ``root/setup.py``."""
    return [(target, list(sources)) for target, sources in setup_arguments(root).get("data_files", [])]


def console_scripts_of(root: Path) -> tuple:
    """(package name, [console script names]) of ``root/setup.py``."""
    arguments = setup_arguments(root)
    scripts = arguments.get("entry_points", {}).get("console_scripts", [])
    return arguments.get("name"), [entry.split("=", 1)[0].strip() for entry in scripts]


def link_data_files(root: Path, prefix: Path) -> list:
    record = prefix / RECORD
    if record.is_file():
        for line in record.read_text().splitlines():
            old = Path(line)
            if old.is_symlink():
                old.unlink()
    links = []
    for target, sources in data_files_of(root):
        for source in sources:
            src = (root / source).resolve()
            dst = prefix / target / src.name
            dst.parent.mkdir(parents=True, exist_ok=True)
            if dst.is_symlink() or dst.exists():
                dst.unlink()
            dst.symlink_to(src)
            links.append(dst)
    package, scripts = console_scripts_of(root)
    for name in scripts:  # lib/<package>/<script> -> bin/<script>, where ros2 run / launch look
        dst = prefix / "lib" / package / name
        dst.parent.mkdir(parents=True, exist_ok=True)
        if dst.is_symlink() or dst.exists():
            dst.unlink()
        dst.symlink_to(prefix / "bin" / name)
        links.append(dst)
    record.parent.mkdir(parents=True, exist_ok=True)
    record.write_text("".join(f"{p}\n" for p in links))
    return links


if __name__ == "__main__":
    made = link_data_files(Path(sys.argv[1]).resolve(), Path(sys.argv[2]).resolve())
    print(f"[setup] linked {len(made)} data files into {sys.argv[2]}")
