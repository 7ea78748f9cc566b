#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# SPDX-FileCopyrightText: 2026 The bimslam authors
# Installs the Debian 12 packages bimslam needs (and, with --test, the npm package of a test tool).
# Idempotent: when everything is present it only asks dpkg (about a second) and changes nothing.
# Usage: sudo toolchain/install-deps.sh [--test|--cross]
#   (no flag)  what building and running need (`make demo`)
#   --test     also the third-party tools the tests run against our files (`make test`), and
#              the npm test tools (npm ci in tests/tools/web_ifc and tests/tools/las) when their
#              node_modules is missing
#   --cross    also the aarch64 cross-build (`make cross`, `make test-cross`): Debian's cross
#              compiler, qemu-user, the arm64 -dev packages that install beside the amd64 ones,
#              and the others unpacked into /opt/bimslam-cross/arm64 (toolchain/stage-arm64.sh)
set -euo pipefail

packages=(
    # build; dpkg-dev (dpkg-shlibdeps) and file for `make deb` (CPack)
    cmake ninja-build g++ make pkg-config dpkg-dev file
    # algorithms: Eigen (common), FLANN and its lz4 headers (scancontext), JSON (io)
    libeigen3-dev libflann-dev liblz4-dev nlohmann-json3-dev
    # LiDAR odometry: Ceres (scan-to-map registration)
    libceres-dev
    # gzip input; PNG output (libpng, below); SHA-256 and base64 by OpenSSL's libcrypto; the
    # Ouster packets' CRC-64 by liblzma on x86-64 (drivers/ouster/crc64.hpp)
    zlib1g-dev libssl-dev liblzma-dev
    # changes.bcf (host_tools/changes): snapshots rendered off screen by Mesa's OSMesa (llvmpipe),
    # written by libpng; the XML by libxml2, the zip by libzip
    libosmesa6-dev libpng-dev libxml2-dev libzip-dev
    # classic pcap files, read and written (drivers/net)
    libpcap0.8-dev
    # LCM messages: library, lcm-gen, and glib for lcm.pc
    liblcm-dev liblcm-bin libglib2.0-dev
    # ROS 1 bags from ouster-ros (drivers/net): the ROS bag library and its serialization headers
    librosbag-storage-dev libroscpp-core-dev
    # command-line tools
    libcli11-dev
    # scenario and configuration files
    libyaml-cpp-dev
    # host tools: IFC++ (BIM ingest), Embree 3 (LiDAR simulation), TBB (parallelism)
    libifcplusplus-dev libembree-dev libtbb-dev
    # the report page's 3D view: three.js r111 and OrbitControls, embedded at build time
    libjs-three
    # `bimslam live --serve`: the page's HTTP server (host_tools/live)
    libcpp-httplib-dev
    # tests and benchmarks
    libgtest-dev libgmock-dev libbenchmark-dev
    # `ip`, for the loopback multicast route the LCM tests need (toolchain/setup-multicast.sh)
    iproute2
)
# The real readers our files must open in (tests/integration/io_interop_test.cpp): PCL's tools,
# Open3D (with numpy) for Debian's python3, CloudCompare; Node.js for web-ifc, the second IFC
# engine the sample building must open in (tests/tools/web_ifc, sample_building_test.cpp), and for
# the LAS readers of tests/tools/las (changes_cli_test.cpp); and
# clang with its libFuzzer runtime for the sanitizer build, unit tests and fuzz targets (preset `asan`).
# systemd-analyze verifies bimslam-rig's unit (tests/integration/rig_lcm_test.cpp); LCM's Java
# library and a JDK build the lcm-spy type jar (lcmtypes/CMakeLists.txt); chromium opens the
# report page headless (tests/integration/report_browser_test.cpp); python3-rosbag writes the ROS
# bags the bag tests read (tests/support/ouster_bag.py); lintian checks the Debian packages
# (tests/integration/deb_package_test.cpp); libfaketime steps a running rig's wall clock
# (tests/integration/rig_faults_test.cpp). changes.bcf is checked with xmllint against the BCF
# schemas and opened with unzip (tests/integration/changes_bcf_test.cpp), and read by
# @parametricos/bcf-js (npm, tests/tools/bcf_js).
test_packages=(pcl-tools python3-open3d cloudcompare nodejs clang libclang-rt-14-dev systemd
    liblcm-java openjdk-17-jdk-headless chromium python3-rosbag lintian libfaketime
    libxml2-utils unzip)
# The aarch64 cross-build: packages that are Multi-Arch: same (or arch all, as Eigen, CLI11 and
# nlohmann-json above) install for arm64 beside amd64; Ceres, glog, gflags, LCM, yaml-cpp and
# the ROS bag library do not, and are staged instead, as are Embree and TBB (for the tests'
# simulator only; their chain reaches libudev1) (toolchain/stage-arm64.sh says why). The ROS
# bag library's own libraries that do install are listed here (its -dev package would pull them
# in, but cannot be installed), with gpgme and OpenSSL for its encryption plugin, which it loads
# when it opens a bag. FLANN's arm64 package pulls in
# an MPI HDF5 that conflicts with the amd64 one: its headers, the same for every architecture, are
# used (toolchain/cmake/BimslamDependencies.cmake).
cross_packages=(crossbuild-essential-arm64 qemu-user-static libc6-dev:arm64 zlib1g-dev:arm64
    libpcap0.8-dev:arm64
    liblz4-dev:arm64 libglib2.0-dev:arm64 libgtest-dev:arm64 libgmock-dev:arm64
    libsuitesparse-dev:arm64 libatlas-base-dev:arm64
    libroscpp-core-dev:arm64 libconsole-bridge-dev:arm64 libboost-filesystem-dev:arm64
    libbz2-1.0:arm64 libtinyxml2-9:arm64 libament-index-cpp0d:arm64 libclass-loader3d:arm64
    librcpputils1d:arm64 librcutils1d:arm64 libroslz4-1d:arm64 libboost-program-options1.74.0:arm64
    libgpgme11:arm64 libssl3:arm64)
if [[ "${1:-}" == "--cross" ]]; then
    if ! dpkg --print-foreign-architectures | grep -qx arm64; then
        if [[ $EUID -ne 0 ]]; then
            echo "install-deps: adding the arm64 architecture needs root: sudo $0 --cross" >&2
            exit 1
        fi
        dpkg --add-architecture arm64
        apt-get update -qq
    fi
    packages+=("${cross_packages[@]}")
elif [[ "${1:-}" == "--test" ]]; then
    packages+=("${test_packages[@]}")
    # Debian's npm, unless npm is there already: a nodejs from NodeSource bundles its own and
    # conflicts with Debian's package.
    command -v npm >/dev/null 2>&1 || packages+=(npm)
elif [[ $# -gt 0 ]]; then
    echo "usage: $0 [--test|--cross]" >&2
    exit 2
fi

missing=()
for p in "${packages[@]}"; do
    # "ii " = installed; anything else (absent, half-installed, removed) gets installed.
    [[ "$(dpkg-query -W -f='${db:Status-Abbrev}' "$p" 2>/dev/null)" == "ii "* ]] || missing+=("$p")
done

if [[ ${#missing[@]} -eq 0 ]]; then
    echo "install-deps: all ${#packages[@]} Debian packages are present"
else
    echo "install-deps: missing: ${missing[*]}"
    if [[ $EUID -ne 0 ]]; then
        echo "install-deps: installing packages needs root. Run:" >&2
        echo "    sudo $0 $*" >&2
        echo "then run your make command again." >&2
        exit 1
    fi
    export DEBIAN_FRONTEND=noninteractive
    apt-get update -qq
    apt-get install -y -qq --no-install-recommends "${missing[@]}"
    echo "install-deps: installed ${#missing[@]} packages"
fi

# web-ifc for tests/tools/web_ifc, loaders.gl's and copc's LAS readers for tests/tools/las (the
# second readers of map_bim.las) and @parametricos/bcf-js for tests/tools/bcf_js (the second BCF
# reader), from the npm registry at the versions their
# package-lock.json pins; node_modules stays in the source tree (git-ignored).
tools="$(cd "$(dirname "$0")/.." && pwd)/tests/tools"
for tool in web_ifc/web-ifc las/copc bcf_js/@parametricos/bcf-js; do
    dir="$tools/${tool%%/*}"
    if [[ "${1:-}" == "--test" && ! -d "$dir/node_modules/${tool#*/}" ]]; then
        echo "install-deps: installing the npm packages of tests/tools/${tool%%/*} (npm ci)"
        npm ci --prefix "$dir" --no-audit --no-fund --loglevel=error
    fi
done

# The arm64 packages that cannot be installed beside their amd64 versions, unpacked.
if [[ "${1:-}" == "--cross" ]]; then
    bash "$(dirname "$0")/stage-arm64.sh"
fi
