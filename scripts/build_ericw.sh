#!/usr/bin/env bash
# Builds ericw-tools' `light` and `vis` from their public source, for side-by-side measurements
# (scripts/ericw_light_compare.py; docs/lights.md, "Against ericw-tools"). Not part of Sightline's
# build or tests: it fetches https://github.com/ericwa/ericw-tools (GPL-3.0) at tag 2.0.0-alpha9,
# the last release that builds against Debian 12's Embree 3, and uses Debian's fmt and nlohmann-json
# in place of its git submodules (pareto and nanobench serve only qbsp, bsputil and its tests).
#
#     scripts/build_ericw.sh DIR        # then DIR/build/light/light and DIR/build/vis/vis
set -euo pipefail

dir=${1:?usage: build_ericw.sh DIR}
if [ ! -d "$dir/.git" ]; then
    git clone --quiet --branch 2.0.0-alpha9 --depth 1 https://github.com/ericwa/ericw-tools "$dir"
fi
sudo=""
[ "$(id -u)" -eq 0 ] || sudo=sudo
packages="libfmt-dev nlohmann-json3-dev libembree-dev libtbb-dev ninja-build"
if ! dpkg -s $packages >/dev/null 2>&1; then
    $sudo apt-get update -qq
    $sudo apt-get install -y --no-install-recommends $packages >/dev/null
fi

cat > "$dir/3rdparty/CMakeLists.txt" <<'EOF'
set(CMAKE_FIND_PACKAGE_TARGETS_GLOBAL ON)
find_package(fmt REQUIRED)
find_package(nlohmann_json REQUIRED)
add_library(pareto INTERFACE)
EOF
sed -i 's|^\s*add_subdirectory(docs)|#add_subdirectory(docs)|' "$dir/CMakeLists.txt"
cmake -S "$dir" -B "$dir/build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DENABLE_LIGHTPREVIEW=OFF -DDISABLE_TESTS=ON >/dev/null
cmake --build "$dir/build" --target light vis
