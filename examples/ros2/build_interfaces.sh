#!/usr/bin/env bash
# Build a ROS 2 interface package (.msg/.srv/.action files, a CMakeLists.txt calling
# rosidl_generate_interfaces, a package.xml) with plain CMake, no colcon, from the ROS 2 wheels
# of a Python environment.
#
#   examples/ros2/build_interfaces.sh PYTHON PREFIX [PACKAGE]
#
# PYTHON: a Python whose environment has the build wheels (`make ros-interfaces` makes one in
# build/ros-venv); PREFIX: where the package is installed (several packages can share one);
# PACKAGE: the package's folder (default: the example robot's, gpp_robot_interfaces). With the
# Makefile, one command builds a package of your own into build/ros-interfaces:
#
#   make ros-interfaces ROS_PACKAGE=path/to/my_robot_interfaces
#
# Its dependencies may be the message packages of gpp's [ros] extra (std_msgs, geometry_msgs,
# nav_msgs, builtin_interfaces, action_msgs). Use the result with
#   PYTHONPATH=PREFIX/lib/pythonX.Y/site-packages LD_LIBRARY_PATH=PREFIX/lib
# Needs cmake, a C/C++ compiler and the Python headers.
set -euo pipefail
PYTHON=$1
PREFIX=$(realpath -m "$2")
HERE=$(cd "$(dirname "$0")" && pwd)
PACKAGE=$(realpath "${3:-$HERE/gpp_robot_interfaces}")
test -f "$PACKAGE/CMakeLists.txt" || { echo "$PACKAGE: no CMakeLists.txt (not an interface package)" >&2; exit 1; }
VENV=$("$PYTHON" -c 'import sys; print(sys.prefix)')
PYINC=$("$PYTHON" -c 'import sysconfig; print(sysconfig.get_paths()["include"])')
NPINC=$("$PYTHON" -c 'import numpy; print(numpy.get_include())')
PYVER=$("$PYTHON" -c 'import sys; print(f"{sys.version_info[0]}.{sys.version_info[1]}")')
TAG=$("$PYTHON" -c 'import sys; print(f"cp{sys.version_info[0]}{sys.version_info[1]}")')

# The wheels were built in a manylinux image; their exported CMake targets name its paths.
for f in "$VENV"/share/*/cmake/*.cmake; do
  if grep -q "/opt/python/$TAG-$TAG" "$f"; then
    sed -i -e "s|/opt/python/$TAG-$TAG/include/python$PYVER|$PYINC|g" \
           -e "s|/opt/python/$TAG-$TAG/lib/python$PYVER/site-packages/numpy/_core/include|$NPINC|g" "$f"
  fi
done

BUILD=$(mktemp -d)
trap 'rm -rf "$BUILD"' EXIT
export AMENT_PREFIX_PATH="$VENV"
export PATH="$VENV/bin:$PATH"
GEN=()
command -v ninja >/dev/null && GEN=(-G Ninja)
cmake -S "$PACKAGE" -B "$BUILD" "${GEN[@]}" \
  -DCMAKE_INSTALL_PREFIX="$PREFIX" -DCMAKE_PREFIX_PATH="$VENV" -DCMAKE_BUILD_TYPE=Release \
  -DPython3_EXECUTABLE="$VENV/bin/python" -DBUILD_TESTING=OFF > "$BUILD/configure.log" 2>&1 \
  || { cat "$BUILD/configure.log"; exit 1; }
cmake --build "$BUILD" -j 2 > "$BUILD/build.log" 2>&1 || { tail -50 "$BUILD/build.log"; exit 1; }
cmake --install "$BUILD" > /dev/null
echo "$PREFIX/lib/python$PYVER/site-packages"
