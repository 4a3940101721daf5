"""A parameter file's ``tether_sim:`` section for a node started in a namespace.

rcl applies a parameter-file section only to the node whose fully qualified name it matches:
``tether_sim:`` means ``/tether_sim``, so ``tether-sim --ros-args -r __ns:=/rov1 --params-file
config/ropos_L200.yaml`` would silently run ``/rov1/tether_sim`` on default parameters (checked with
rclpy 7.1.6). rcl's own way to address a node in any namespace is a ``/**/tether_sim:`` section,
which the shipped files use (rcl applies it as it is; nothing here touches it). For a file of the
user's with a plain ``tether_sim:`` / ``/tether_sim:`` section, :func:`retarget` hands rcl a copy
with that section renamed to the node's full name (and the node logs it); ``-p`` overrides and the
other sections keep their meaning.
"""

from __future__ import annotations

import atexit
import os
import re
import tempfile
from pathlib import Path

NODE_NAME = "tether_sim"
SECTION = re.compile(rf"^['\"]?/?{NODE_NAME}['\"]?[ \t]*:(?=[ \t]*(#.*)?$)", re.MULTILINE)  # top-level key


def node_fqn(argv, name: str = NODE_NAME) -> str:
    """Fully qualified node name implied by the ``__ns`` / ``__node`` remaps in ``argv``'s
    ``--ros-args`` sections (the last one wins, as in rcl); ``/tether_sim`` without remaps."""
    ns, in_ros, i = "/", False, 0
    argv = list(argv)
    while i < len(argv):
        a = argv[i]
        if a == "--ros-args":
            in_ros = True
        elif a == "--":
            in_ros = False
        elif in_ros and a in ("-r", "--remap") and i + 1 < len(argv):
            rule = argv[i + 1]
            i += 1
            for prefix in ("", f"{NODE_NAME}:"):
                if rule.startswith(prefix + "__ns:="):
                    ns = "/" + rule[len(prefix) + 6:].strip("/")
                elif rule.startswith(prefix + "__node:="):
                    name = rule[len(prefix) + 8:]
        i += 1
    return f"{ns.rstrip('/')}/{name}"


def retarget(argv, log=None, tmpdir=None) -> list:
    """``argv`` with each ``--params-file`` whose plain ``tether_sim`` section would not match the
    node (renamed or in a namespace) replaced by a copy with that section renamed to the node's
    full name. Unchanged when the node is ``/tether_sim``."""
    fqn = node_fqn(argv)
    if fqn == f"/{NODE_NAME}":
        return list(argv)
    out, in_ros = list(argv), False
    for i, a in enumerate(out):
        if a == "--ros-args":
            in_ros = True
        elif a == "--":
            in_ros = False
        elif in_ros and a == "--params-file" and i + 1 < len(out):
            path = Path(out[i + 1])
            try:
                text = path.read_text()
            except OSError:
                continue  # rcl reports an unreadable file itself
            # rename the top-level key only (text edit: the file's own number spelling is kept)
            renamed, count = SECTION.subn(lambda m: f"{fqn}:", text)
            if not count:
                continue
            handle = tempfile.NamedTemporaryFile("w", suffix=f"_{path.name}", prefix="tether_sim_params_",
                                                 dir=tmpdir, delete=False)
            with handle:
                handle.write(renamed)
            out[i + 1] = handle.name
            atexit.register(os.unlink, handle.name)  # rcl has read it by then
            if log:
                log(f"{path}: section '{NODE_NAME}' applied to this node, {fqn}")
    return out
