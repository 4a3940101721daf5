"""ROS 2 message definitions for MCAP schemas, found the way rosbag2 finds them (no rclpy).

A schema's data is the raw text of the root ``.msg`` file (comments included) followed, for each
dependency, by ``"\\n" + "=" * 80 + "\\n" + "MSG: pkg/Type\\n"`` and that type's raw text.
Dependencies are the non-primitive field types of a text (bare names qualified with the current
package), taken in sorted order, depth-first, each emitted once (rosbag2's
``LocalMessageDefinitionSource``). When no ``.msg`` exists the ``.idl`` files are used the same way
(encoding ``ros2idl``, every part under an ``IDL: pkg/msg/Type`` line).

Files are looked up as ``<prefix>/share/<pkg>/msg/<Type>.msg`` for every prefix of the search path:
explicit entries first, then ``$AMENT_PREFIX_PATH``, then ``sys.prefix``; an entry may also be a
directory holding ``<pkg>/msg/`` directly. ``tether_sim_msgs`` is also found in the repository's
``msg_defs/msg/``. The RIHS01 type hash comes from the installed ``<Type>.json`` type description;
without one it is computed from the definitions with ``rosbags`` when that is installed.
"""

from __future__ import annotations

import json
import os
import re
import sys
from pathlib import Path

SEPARATOR = "=" * 80
PRIMITIVE_TYPES = frozenset(
    "bool byte char float32 float64 int8 uint8 int16 uint16 int32 uint32 int64 uint64 string"
    .split())
_MSG_FIELD_TYPE = re.compile(r"(?:^|\n)\s*([a-zA-Z0-9_/]+)(?:\[[^\]]*\])?\s+")
_IDL_INCLUDE = re.compile(r'(?:^|\n)#include\s+(?:"|<)([a-zA-Z0-9_/]+)\.idl(?:"|>)')
_NAME = r"[a-zA-Z][a-zA-Z0-9_]*"
_TYPE_NAME = re.compile(rf"^({_NAME})/(?:({_NAME})/)?({_NAME})$")
REPO_MSG_DEFS = Path(__file__).resolve().parents[2] / "msg_defs"
REPO_MSG_PACKAGE = "tether_sim_msgs"


class MessageDefinitionError(LookupError):
    """A message type name is malformed or its definition file cannot be found."""


def split_type_name(type_name: str) -> tuple[str, str, str]:
    """'pkg/msg/Type' or 'pkg/Type' -> ('pkg', 'msg', 'Type')."""
    match = _TYPE_NAME.match(type_name)
    if not match:
        raise MessageDefinitionError(
            f"message type {type_name!r} is not of the form 'package/msg/Type'")
    pkg, namespace, name = match.groups()
    return pkg, namespace or "msg", name


def msg_dependencies(text: str, package: str) -> list[str]:
    """Sorted non-primitive field types of a .msg text, as 'pkg/Type' (rosbag2's regex)."""
    deps = set()
    for match in _MSG_FIELD_TYPE.finditer(text):
        field_type = match.group(1)
        if field_type in PRIMITIVE_TYPES:
            continue
        deps.add(field_type if "/" in field_type else f"{package}/{field_type}")
    return sorted(deps)


def default_prefixes(extra=None) -> list[Path]:
    """Search prefixes: explicit entries, $AMENT_PREFIX_PATH, sys.prefix (no duplicates)."""
    entries = [] if extra is None else [extra] if isinstance(extra, (str, os.PathLike)) else list(extra)
    entries += [p for p in os.environ.get("AMENT_PREFIX_PATH", "").split(os.pathsep) if p]
    entries.append(sys.prefix)
    seen, prefixes = set(), []
    for entry in entries:
        path = Path(entry)
        if path not in seen:
            seen.add(path)
            prefixes.append(path)
    return prefixes


class MessageDefinitions:
    """Finds .msg/.idl/.json files and builds rosbag2-style schema texts (cached per type)."""

    def __init__(self, search_path=None):
        self.prefixes = default_prefixes(search_path)
        self._texts: dict[tuple[str, str, str, str], str] = {}

    def find_file(self, pkg: str, namespace: str, name: str, ext: str) -> Path | None:
        filename = f"{name}.{ext}"
        candidates = []
        for prefix in self.prefixes:
            candidates += [prefix / "share" / pkg / namespace / filename,
                           prefix / pkg / namespace / filename]
        if pkg == REPO_MSG_PACKAGE:
            candidates.append(REPO_MSG_DEFS / namespace / filename)
        return next((c for c in candidates if c.is_file()), None)

    def _text(self, pkg: str, namespace: str, name: str, ext: str) -> str:
        key = (pkg, namespace, name, ext)
        if key not in self._texts:
            path = self.find_file(pkg, namespace, name, ext)
            if path is None:
                raise MessageDefinitionError(
                    f"no {ext} definition of {pkg}/{namespace}/{name} under "
                    f"{[str(p) for p in self.prefixes]} (share/{pkg}/{namespace}/{name}.{ext})")
            self._texts[key] = path.read_text(encoding="utf-8")
        return self._texts[key]

    def schema(self, type_name: str) -> tuple[str, str]:
        """(encoding, text) of the complete definition: 'ros2msg' when .msg files exist, else 'ros2idl'."""
        pkg, namespace, name = split_type_name(type_name)
        try:
            return "ros2msg", self._full_msg_text(pkg, namespace, name)
        except MessageDefinitionError as msg_error:
            try:
                root = f"{pkg}/{namespace}/{name}"
                return "ros2idl", self._idl_part(root) + self._full_idl_text(root, set())
            except MessageDefinitionError:
                raise msg_error from None

    def _full_msg_text(self, pkg: str, namespace: str, name: str, seen=None, depth=50) -> str:
        if depth <= 0:
            raise MessageDefinitionError(f"definition of {pkg}/{name} nests too deeply")
        seen = set() if seen is None else seen
        text = self._text(pkg, namespace, name, "msg")
        result = text
        for dep in msg_dependencies(text, pkg):
            if dep in seen:
                continue
            seen.add(dep)
            dep_pkg, dep_ns, dep_name = split_type_name(dep)
            result += f"\n{SEPARATOR}\nMSG: {dep}\n"
            result += self._full_msg_text(dep_pkg, dep_ns, dep_name, seen, depth - 1)
        return result

    @staticmethod
    def _idl_part(type_name: str) -> str:
        return f"{SEPARATOR}\nIDL: {type_name}\n"

    def _full_idl_text(self, type_name: str, seen: set, depth=50) -> str:
        if depth <= 0:
            raise MessageDefinitionError(f"definition of {type_name} nests too deeply")
        pkg, namespace, name = split_type_name(type_name)
        text = self._text(pkg, namespace, name, "idl")
        result = text
        for dep in sorted(set(_IDL_INCLUDE.findall(text))):
            if dep not in seen:
                seen.add(dep)
                result += "\n" + self._idl_part(dep) + self._full_idl_text(dep, seen, depth - 1)
        return result

    def type_hash(self, type_name: str) -> str:
        """'RIHS01_<sha256>' of a type, '' when it can be neither read nor computed."""
        pkg, namespace, name = split_type_name(type_name)
        path = self.find_file(pkg, namespace, name, "json")
        full_name = f"{pkg}/{namespace}/{name}"
        if path is not None:
            try:
                for entry in json.loads(path.read_text(encoding="utf-8")).get("type_hashes", []):
                    if entry.get("type_name") == full_name:
                        return str(entry["hash_string"])
            except (OSError, ValueError, KeyError, TypeError):
                pass
        return self._computed_hash(full_name)

    def _computed_hash(self, full_name: str) -> str:
        try:
            encoding, text = self.schema(full_name)
        except MessageDefinitionError:
            return ""
        if encoding != "ros2msg":
            return ""
        return rihs01_from_schema(full_name, text)


def split_schema(type_name: str, text: str) -> dict[str, str]:
    """Complete ros2msg text -> {'pkg/msg/Type': own text} for the root and each 'MSG:' part."""
    parts = {}
    current, lines = type_name, []
    for line in text.split("\n"):
        if line == SEPARATOR:
            parts[current] = "\n".join(lines)
            current, lines = None, []
        elif current is None and line.startswith("MSG: "):
            pkg, namespace, name = split_type_name(line[5:].strip())
            current = f"{pkg}/{namespace}/{name}"
        else:
            lines.append(line)
    if current is not None:
        parts[current] = "\n".join(lines)
    return parts


def rihs01_from_schema(type_name: str, text: str) -> str:
    """RIHS01 hash of a type from its complete ros2msg text, computed with rosbags ('' if unavailable)."""
    try:
        from rosbags.typesys import Stores, get_types_from_msg, get_typestore
    except ImportError:
        return ""
    try:
        typestore = get_typestore(Stores.EMPTY)
        types = {}
        for name, part in split_schema(type_name, text).items():
            types.update(get_types_from_msg(part, name))
        typestore.register(types)
        return typestore.hash_rihs01(type_name)
    except Exception:  # noqa: BLE001 - rosbags parse errors have no common base; the hash is optional
        return ""


def export_rosbags_definitions(prefix, type_names, store: str = "ros2_jazzy") -> list[Path]:
    """Write <prefix>/share/<pkg>/msg/<Type>.msg for the types (and dependencies) rosbags knows.

    For machines without the ROS wheels: rosbags' built-in definitions are comment-free but
    field-for-field those of the distribution, so schemas and RIHS01 hashes come out the same."""
    from rosbags.typesys import Stores, get_typestore

    typestore = get_typestore(Stores(store))
    written = []
    for type_name in type_names:
        text, _ = typestore.generate_msgdef(type_name, ros_version=2)
        for name, part in split_schema(type_name, text).items():
            pkg, namespace, typ = split_type_name(name)
            path = Path(prefix) / "share" / pkg / namespace / f"{typ}.msg"
            path.parent.mkdir(parents=True, exist_ok=True)
            path.write_text(part.rstrip("\n") + "\n", encoding="utf-8")
            written.append(path)
    return written
