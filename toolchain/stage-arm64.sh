#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# SPDX-FileCopyrightText: 2026 The bimslam authors
# Unpacks the arm64 packages that cannot be installed beside their amd64 versions into a staging
# folder for the aarch64 cross-build (toolchain/aarch64-linux-gnu.cmake, toolchain/README.md).
# Called by `toolchain/install-deps.sh --cross`; idempotent: it does nothing when the staging
# holds the versions apt would download now.
#
# Why: libgflags2.2, libgoogle-glog0v6 (Ceres' logging), liblcm1 and the -dev packages of Ceres,
# glog, gflags, LCM and yaml-cpp are not Multi-Arch: same, so dpkg refuses to install their arm64
# version beside the amd64 one the host build needs (apt would remove the amd64 Ceres, LCM and
# yaml-cpp). The ROS bag library (drivers/net) neither: librosbag-storage-dev depends on
# pluginlib-dev, an arch-all package without Multi-Arch: foreign, so apt cannot satisfy it for
# arm64; and librosbag-storage4d needs libroslib0d -> librospack0d -> libpython3.11 -> libexpat1,
# whose arm64 versions must equal the amd64 ones installed (Multi-Arch: same), which apt may only
# reach by upgrading the host's Python. The rest of its libraries install (install-deps.sh).
# Embree and TBB (algorithms/simulation, built for the tests' scenes only, never linked by the
# firmware) are Multi-Arch: same, but libtbb12 depends on libtbbbind-2-5 -> libhwloc15 ->
# libudev1, whose arm64 version must equal the host's amd64 one: apt would upgrade the host's
# systemd to get there. They are staged with that whole chain (TBB loads tbbbind at run time).
# Their arm64 files are the same Debian packages, unpacked here instead of installed, with the
# libraries their CMake files name (libceres3, libyaml-cpp0.7):
#   usr/        the packages' files (headers, libraries, CMake and pkg-config files; the .pc files'
#               prefix points here)
#   control/P/  package P's control files: shlibs and symbols declare what depends on them
#   DEBIAN/     all their shlibs and symbols files, concatenated: the staging is then a "package
#               build tree" to dpkg-shlibdeps, which takes the dependencies of a library found
#               under it (not installed, so unknown to dpkg) from the nearest DEBIAN/ above it
#               (make deb-arm64, toolchain/cmake/BimslamPackaging.cmake)
#   packages    the package versions unpacked
set -euo pipefail
staging="${BIMSLAM_ARM64_STAGING:-/opt/bimslam-cross/arm64}"
packages=(libceres-dev libceres3 libgoogle-glog-dev libgoogle-glog0v6 libgflags-dev libgflags2.2
    liblcm-dev liblcm1 libyaml-cpp-dev libyaml-cpp0.7
    librosbag-storage-dev librosbag-storage4d libroslib0d librospack0d libpython3.11 libexpat1
    libembree-dev libembree3-3 libtbb-dev libtbb12 libtbbmalloc2 libtbbbind-2-5 libhwloc15 libudev1)

# The versions apt would download now, one "package:arm64 version" a line, in the list's order.
want="$(apt-cache show --no-all-versions "${packages[@]/%/:arm64}" 2>/dev/null |
    awk '/^Package: /{p=$2} /^Version: /{print p ":arm64 " $2}')"
for p in "${packages[@]}"; do
    if ! grep -q "^$p:arm64 " <<<"$want"; then
        echo "stage-arm64: apt knows no $p:arm64 (dpkg --add-architecture arm64; apt-get update)" >&2
        exit 1
    fi
done
if [[ -f "$staging/packages" && -f "$staging/DEBIAN/shlibs" &&
    "$(cat "$staging/packages")" == "$want" ]]; then
    echo "stage-arm64: $staging holds the ${#packages[@]} arm64 packages"
    exit 0
fi

tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
# apt downloads as its own user, _apt, which must be able to write there.
if id _apt >/dev/null 2>&1; then chown _apt "$tmp"; fi
(cd "$tmp" && apt-get download -qq "${packages[@]/%/:arm64}")

new="$staging.new"
rm -rf "$new"
mkdir -p "$new/control"
for deb in "$tmp"/*.deb; do
    dpkg-deb -x "$deb" "$new"
    name="$(dpkg-deb -f "$deb" Package)"
    dpkg-deb -e "$deb" "$new/control/$name"
done
# pkg-config files: their prefix is here, not /usr.
sed -i "s|^prefix=/usr\$|prefix=$staging/usr|" "$new"/usr/lib/aarch64-linux-gnu/pkgconfig/*.pc
mkdir -p "$new/DEBIAN"
cat "$new"/control/*/shlibs >"$new/DEBIAN/shlibs"
cat "$new"/control/*/symbols >"$new/DEBIAN/symbols"
# Merged /usr, as Debian 12 installs it: libexpat1 ships its library in /lib.
if [[ -d "$new/lib" ]]; then
    cp -a "$new/lib/." "$new/usr/lib/"
    rm -rf "$new/lib"
fi
# pluginlib (the ROS bag library's encryption plugin) looks in <CMAKE_PREFIX_PATH>/lib under
# qemu (toolchain/aarch64-linux-gnu.cmake).
mkdir -p "$new/ros"
ln -s ../usr/lib/aarch64-linux-gnu/ros "$new/ros/lib"
# Documentation folders linked to another package's (libpython3.11 -> libpython3.11-minimal's) are
# not needed here.
find "$new/usr/share/doc" -maxdepth 1 -xtype l -delete
# Every link must resolve inside the staging (the CMake files check the libraries they name).
if find "$new" -xtype l | grep .; then
    echo "stage-arm64: the links above dangle" >&2
    exit 1
fi
printf '%s' "$want" > "$new/packages"
rm -rf "$staging"
mv "$new" "$staging"
echo "stage-arm64: unpacked ${#packages[@]} arm64 packages into $staging"
