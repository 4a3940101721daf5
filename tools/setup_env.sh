#!/usr/bin/env bash
# Bring the project environment .venv/ up to date; idempotent and quick when nothing changed.
#
# Stages (each skipped when its stamp in .venv/.stamps/ matches the hash of its inputs):
#   deps  python3.11 venv + tools/requirements.txt under tools/constraints.txt (ROS 2 Jazzy wheels,
#         numba, mcap, pytest...), then the wheels' CMake exports are pointed at this machine's
#         Python and numpy include folders (they carry /opt/python/... paths from the wheel build).
#   msgs  msg_defs/ (package tether_sim_msgs) configured with cmake against the venv and installed
#         into it (build folder .venv/.build/).
#   tf2   msg_defs/tf2_msgs (TFMessage only) the same way, unless a tf2_msgs is importable already.
#   pkg   tether_sim itself, `pip install -e .` (development mode, no build isolation), and its
#         data files (package.xml, config/*.yaml, data/*, ament index marker) linked into .venv/share,
#         its console scripts into .venv/lib/tether_sim/ (where ros2 run and launch_ros look).
#   colcon  colcon (tools/colcon-requirements.txt) in a venv of its own, .venv/colcon/, for the test
#         that lists and builds this repository as a colcon workspace (test/test_colcon.py); a failed
#         install is a warning (that test then skips, saying so). TETHER_SIM_SKIP_COLCON=1 skips it.
#   warm  the numba kernels compiled into their on-disk cache (python -m tether_sim.warm, progress
#         per kernel group; minutes when cold, seconds when warm). numba keys its cache on each
#         source file's modification time and size, so this stage reruns whenever those of any
#         tether_sim/*.py change (an edit, a checkout). TETHER_SIM_SKIP_WARM=1 skips it.
# Nothing is created outside the repository. Usage: tools/setup_env.sh [--force]
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
VENV="$ROOT/.venv"
STAMPS="$VENV/.stamps"
BUILD="$VENV/.build"
# Bump when this script changes in a way that needs a rebuild of everything.
SETUP_REVISION=1

if [[ "${1:-}" == "--force" ]]; then
    rm -rf "$STAMPS"
fi

say() { printf '[setup] %s\n' "$*"; }
die() { printf '[setup] ERROR: %s\n' "$*" >&2; exit 1; }

hash_of() {  # hash of the given strings and files (missing files hash as their name)
    local item
    for item in "$@"; do
        if [[ -f "$item" ]]; then
            printf '%s\n' "${item#"$ROOT"/}"
            cat "$item"
        else
            printf '%s\n' "$item"
        fi
    done | sha256sum | cut -c1-32
}

links_ok() {  # every data-file link made by tools/link_data_files.py is still there
    [[ -f "$STAMPS/data_files.txt" ]] || return 1
    local link
    while IFS= read -r link; do [[ -e "$link" ]] || return 1; done < "$STAMPS/data_files.txt"
}

stamp_ok() { [[ -f "$STAMPS/$1" && "$(cat "$STAMPS/$1")" == "$2" ]]; }
stamp_set() { mkdir -p "$STAMPS"; printf '%s\n' "$2" > "$STAMPS/$1"; }

quiet_pip() {  # pip, without the per-package warnings of this machine's empty local mirrors
    # (pipefail: the function fails exactly when pip fails)
    "$VENV/bin/python" -m pip "$@" 2>&1 | { grep -v "is ignored: it is neither a file nor a directory" || true; }
}

find_base_python() {
    local candidate
    for candidate in "${PYTHON:-}" python3.11 python3; do
        [[ -n "$candidate" ]] || continue
        if command -v "$candidate" >/dev/null 2>&1 &&
            "$candidate" -c 'import sys; sys.exit(sys.version_info[:2] != (3, 11))' 2>/dev/null; then
            command -v "$candidate"
            return 0
        fi
    done
    return 1
}

venv_works() {
    [[ -x "$VENV/bin/python" ]] &&
        "$VENV/bin/python" -c 'import sys; sys.exit(sys.version_info[:2] != (3, 11))' 2>/dev/null
}

# ---------------------------------------------------------------- quick path: nothing to do
REQ="$ROOT/tools/requirements.txt"
CONS="$ROOT/tools/constraints.txt"
DEPS_HASH="$(hash_of "rev=$SETUP_REVISION" "$REQ" "$CONS")"
MSG_FILES=("$ROOT/msg_defs/CMakeLists.txt" "$ROOT/msg_defs/package.xml" "$ROOT"/msg_defs/msg/*.msg)
MSGS_HASH="$(hash_of "$DEPS_HASH" "${MSG_FILES[@]}")"
TF2_HASH="$(hash_of "$DEPS_HASH" "$ROOT"/msg_defs/tf2_msgs/{CMakeLists.txt,package.xml,msg/TFMessage.msg})"
shopt -s nullglob
PKG_INPUTS=("$ROOT/setup.py" "$ROOT/setup.cfg" "$ROOT/package.xml" "$ROOT"/resource/*)
# config/ and data/ are linked, not copied: only the list of names matters (edits are live)
DATA_LIST="$(cd "$ROOT" && for f in config/*.yaml config/studies/*.yaml data/* launch/*.launch.py rviz/*.rviz foxglove/*.json; do [[ -f "$f" ]] && printf '%s\n' "$f"; done; true)"
shopt -u nullglob
PKG_HASH="$(hash_of "$MSGS_HASH" "${PKG_INPUTS[@]}")"
LINKS_HASH="$(hash_of "$PKG_HASH" "$DATA_LIST" "$ROOT/tools/link_data_files.py")"
# numba's cache key of every source file (name, mtime, size), plus the configurations warmed
WARM_HASH="$(hash_of "$LINKS_HASH" "$(cd "$ROOT" && find tether_sim -name '*.py' -printf '%p %T@ %s\n' | sort)" \
    "$ROOT"/config/*.yaml)"
warm_ok() { [[ "${TETHER_SIM_SKIP_WARM:-0}" == 1 ]] || stamp_ok warm "$WARM_HASH"; }
COLCON_HASH="$(hash_of "rev=$SETUP_REVISION" "$ROOT/tools/colcon-requirements.txt")"
colcon_ok() { [[ "${TETHER_SIM_SKIP_COLCON:-0}" == 1 ]] || stamp_ok colcon "$COLCON_HASH"; }
SITE="$VENV/lib/python3.11/site-packages"

if venv_works && stamp_ok deps "$DEPS_HASH" && stamp_ok msgs "$MSGS_HASH" && stamp_ok pkg "$PKG_HASH" &&
    stamp_ok links "$LINKS_HASH" && stamp_ok tf2 "$TF2_HASH" && [[ -d "$SITE/tether_sim_msgs" ]] && links_ok &&
    warm_ok && colcon_ok; then
    say "environment up to date ($VENV)"
    exit 0
fi

# ---------------------------------------------------------------- one set-up at a time
mkdir -p "$VENV"
exec 9>"$VENV/.setup.lock"
if command -v flock >/dev/null 2>&1; then
    flock 9
fi
T0=$SECONDS

# ---------------------------------------------------------------- stage deps
if ! venv_works || ! stamp_ok deps "$DEPS_HASH"; then
    BASE_PY="$(find_base_python)" || die "Python 3.11 is required (the ROS 2 Jazzy wheels are cp311); set PYTHON=/path/to/python3.11"
    if ! venv_works; then
        say "creating virtual environment $VENV with $BASE_PY"
        # start from an empty folder (a broken or foreign venv goes), keeping the lock we hold
        find "$VENV" -mindepth 1 -maxdepth 1 ! -name .setup.lock -exec rm -rf {} +
        "$BASE_PY" -m venv "$VENV"
    fi
    rm -f "$STAMPS/deps" "$STAMPS/msgs" "$STAMPS/pkg"
    say "installing pinned requirements (ROS 2 Jazzy wheels, numba, mcap, pytest...)"
    quiet_pip install --quiet --disable-pip-version-check -r "$REQ" -c "$CONS"
    say "pointing the wheels' CMake exports at this machine's include folders"
    "$VENV/bin/python" "$ROOT/tools/fix_cmake_paths.py" "$VENV"
    stamp_set deps "$DEPS_HASH"
fi

# AMENT_PREFIX_PATH for every Python of the venv (the wheels do not set it; ament_index needs it)
cat > "$SITE/tether_sim_ament_prefix.pth" <<'PTH'
import os, sys; _p = os.environ.get("AMENT_PREFIX_PATH", ""); os.environ["AMENT_PREFIX_PATH"] = _p if sys.prefix in _p.split(os.pathsep) else os.pathsep.join([sys.prefix] + ([_p] if _p else []))
PTH

# ---------------------------------------------------------------- stage msgs
ros_env() {  # run a command with the library paths the wheels' bootstrapper would set
    local libs="$VENV/lib" dir
    for dir in "$SITE"/ros_*.libs; do libs="$libs:$dir"; done
    env LD_LIBRARY_PATH="$libs${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}" PATH="$VENV/bin:$PATH" \
        AMENT_PREFIX_PATH="$VENV" CMAKE_PREFIX_PATH="$VENV" "$@"
}

build_interfaces() {  # build_interfaces NAME SOURCE_DIR: cmake + make install into the venv
    local name="$1" src="$2" log="$BUILD/$1.log"
    if [[ -f "$STAMPS/${name}_manifest.txt" ]]; then  # remove the previous build's files first
        while IFS= read -r file; do rm -f "$file"; done < "$STAMPS/${name}_manifest.txt"
    fi
    rm -rf "${BUILD:?}/$name"
    mkdir -p "$BUILD/$name"
    if ! (cd "$BUILD/$name" &&
        ros_env cmake "$src" -DCMAKE_BUILD_TYPE=Release -DBUILD_TESTING=OFF \
            -DCMAKE_PREFIX_PATH="$VENV" -DCMAKE_INSTALL_PREFIX="$VENV" \
            -DPython3_EXECUTABLE="$VENV/bin/python" &&
        ros_env make -j"$(nproc 2>/dev/null || echo 2)" install) > "$log" 2>&1; then
        tail -n 40 "$log" >&2
        die "building $src failed (full log: $log)"
    fi
    mkdir -p "$STAMPS"
    cp "$BUILD/$name/install_manifest.txt" "$STAMPS/${name}_manifest.txt"
    "$VENV/bin/python" -c "import $name.msg" || die "$name built but does not import"
}

if ! stamp_ok msgs "$MSGS_HASH" || [[ ! -d "$SITE/tether_sim_msgs" ]]; then
    rm -f "$STAMPS/pkg"
    command -v cmake >/dev/null || die "cmake is needed to build msg_defs/"
    [[ -f "$STAMPS/msgs_manifest.txt" ]] && mv "$STAMPS/msgs_manifest.txt" "$STAMPS/tether_sim_msgs_manifest.txt"
    say "building msg_defs/ (tether_sim_msgs) with cmake into the venv"
    build_interfaces tether_sim_msgs "$ROOT/msg_defs"
    stamp_set msgs "$MSGS_HASH"
fi
# tf2_msgs/TFMessage (/tf, /tf_static): the registry has no tf2_msgs wheel; build it from its
# interface definition unless a tf2_msgs of a ROS 2 install is importable already
if ! stamp_ok tf2 "$TF2_HASH"; then
    if [[ ! -f "$STAMPS/tf2_msgs_manifest.txt" ]] && "$VENV/bin/python" -c "import tf2_msgs.msg" 2>/dev/null; then
        say "tf2_msgs is importable already: msg_defs/tf2_msgs not built"
    else
        command -v cmake >/dev/null || die "cmake is needed to build msg_defs/tf2_msgs"
        say "building msg_defs/tf2_msgs (TFMessage for /tf, /tf_static) with cmake into the venv"
        build_interfaces tf2_msgs "$ROOT/msg_defs/tf2_msgs"
    fi
    stamp_set tf2 "$TF2_HASH"
fi

# ---------------------------------------------------------------- stage pkg
if ! stamp_ok pkg "$PKG_HASH"; then
    rm -f "$STAMPS/links"
    say "installing tether_sim in development mode (pip install -e .)"
    quiet_pip install --quiet --disable-pip-version-check --no-deps --no-build-isolation --use-pep517 -e "$ROOT"
    stamp_set pkg "$PKG_HASH"
fi
# pip -e leaves out data_files (ament index marker, package.xml, config/, data/): link them
if ! stamp_ok links "$LINKS_HASH" || ! links_ok; then
    "$VENV/bin/python" "$ROOT/tools/link_data_files.py" "$ROOT" "$VENV"
    stamp_set links "$LINKS_HASH"
fi

# ---------------------------------------------------------------- stage colcon
if ! colcon_ok; then
    say "installing colcon into $VENV/colcon (a venv of its own, for test/test_colcon.py)"
    rm -rf "$VENV/colcon"
    BASE_PY="$(find_base_python)" || die "Python 3.11 is required"
    if "$BASE_PY" -m venv "$VENV/colcon" &&
        "$VENV/colcon/bin/python" -m pip install --quiet --disable-pip-version-check \
            -r "$ROOT/tools/colcon-requirements.txt" 2>&1 |
            { grep -v "is ignored: it is neither a file nor a directory" || true; }; then
        stamp_set colcon "$COLCON_HASH"
    else
        rm -rf "$VENV/colcon"
        say "WARNING: colcon could not be installed; test/test_colcon.py will skip (rerun make setup to retry)"
    fi
fi

# ---------------------------------------------------------------- stage warm
if ! warm_ok; then
    say "compiling the solver kernels into numba's cache (python -m tether_sim.warm): after a change of"
    say "the sources this takes minutes (a cold cache: 12 min at load 10 on a 2-core machine); when the"
    say "cache is warm, a few seconds"
    "$VENV/bin/python" -u -m tether_sim.warm 2>&1 | sed -u 's/^/[setup] /' || die "the warm-up failed (see above)"
    stamp_set warm "$WARM_HASH"
fi

say "environment ready ($VENV) in $((SECONDS - T0)) s"
