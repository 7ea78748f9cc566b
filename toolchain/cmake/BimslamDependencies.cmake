# SPDX-License-Identifier: BSD-3-Clause
# SPDX-FileCopyrightText: 2026 The bimslam authors
# Every third-party dependency, found once, from Debian packages (toolchain/install-deps.sh).
# Nothing is downloaded at build time.
include_guard(GLOBAL)
include(BimslamLayers)

find_package(PkgConfig REQUIRED)
find_package(Eigen3 3.4 REQUIRED NO_MODULE)
find_package(nlohmann_json 3 REQUIRED)
find_package(CLI11 REQUIRED)
# Debian's Ceres is a static library built against ATLAS. Its CMake package links its users with
# ATLAS's whole BLAS/LAPACK line twice: the paths it was built with (liblapack, libblas,
# libf77blas, libatlas) and, through SuiteSparse's targets, CMake's FindBLAS, which prefers ATLAS
# (libf77blas, libatlas). The programs call LAPACK only (Ceres: dpotrf_, dgeqrf_, ...), yet GNU
# ld's --as-needed (Debian's default) recorded libf77blas as NEEDED: it defines BLAS symbols that
# libcholmod.so (dtrsv_) and ATLAS's liblapack.so (ssymv_) leave undefined, and it is not among
# their own NEEDED entries (libblas.so.3, which defines them too, is, so ld does not count that
# one). A dependency nothing of ours uses (dpkg-shlibdeps: "useless dependency"), and
# libatlas3-base in bimslam-rig's Depends, on amd64 and arm64. So: FindBLAS/FindLAPACK's generic
# libblas/liblapack (Debian's alternatives, which bring their own BLAS at run time), and Ceres'
# own line without libf77blas and libatlas.
set(BLA_VENDOR Generic)
find_package(Ceres 2.1 REQUIRED)  # LiDAR odometry's scan-to-map registration
unset(BLA_VENDOR)
get_target_property(_ceres_links Ceres::ceres INTERFACE_LINK_LIBRARIES)
list(FILTER _ceres_links EXCLUDE REGEX "/lib(f77blas|atlas)\\.so$")
set_target_properties(Ceres::ceres PROPERTIES INTERFACE_LINK_LIBRARIES "${_ceres_links}")
# Ceres' FindSuiteSparse also assumes SuiteSparseQR was built with TBB whenever TBB is installed,
# and adds TBB to it; Debian's libspqr.so.2 does not use TBB (no libtbb among its NEEDED), and
# TBB is a host-only library (the simulator's), so the firmware's link line does not get it.
if(TARGET SuiteSparse::SPQR)
    get_target_property(_spqr_links SuiteSparse::SPQR INTERFACE_LINK_LIBRARIES)
    list(FILTER _spqr_links EXCLUDE REGEX "^TBB::|/libtbb[^/]*$")
    set_target_properties(SuiteSparse::SPQR PROPERTIES INTERFACE_LINK_LIBRARIES "${_spqr_links}")
endif()
find_package(yaml-cpp REQUIRED)  # scenario and configuration files
find_package(Threads REQUIRED)
find_package(ZLIB REQUIRED)  # .gz captures and logs, PNG
set_target_properties(ZLIB::ZLIB PROPERTIES IMPORTED_GLOBAL TRUE)
# Classic pcap files, read and written (libpcap0.8-dev; drivers/net).
pkg_check_modules(PCAP REQUIRED IMPORTED_TARGET GLOBAL libpcap)

# LCM 1.3.1 ships only lcm.pc (no CMake package): pkg-config, and lcm-gen for the messages.
pkg_check_modules(LCM REQUIRED IMPORTED_TARGET lcm>=1.3)
bimslam_tag_capability(PkgConfig::LCM lcm)
find_program(LCM_GEN_EXECUTABLE lcm-gen REQUIRED)

# FLANN is used header-only (its KD-tree); flann.pc drags in HDF5 and MPI we do not need, but the
# headers include lz4. The aarch64 cross-build uses the same /usr/include/flann: libflann-dev is
# Multi-Arch: same, so its headers are identical for every architecture (its arm64 package cannot
# be installed here: it pulls in an MPI HDF5 that conflicts with the amd64 one).
find_path(FLANN_INCLUDE_DIR flann/flann.hpp REQUIRED)
pkg_check_modules(LZ4 REQUIRED IMPORTED_TARGET liblz4)
add_library(bimslam_flann INTERFACE)
target_include_directories(bimslam_flann SYSTEM INTERFACE "${FLANN_INCLUDE_DIR}")
target_link_libraries(bimslam_flann INTERFACE PkgConfig::LZ4)
add_library(bimslam::flann ALIAS bimslam_flann)

# ROS 1 bags (ouster-ros recordings): Debian's rosbag_storage (librosbag-storage-dev), the ROS
# library itself. Its CMake package pulls in catkin/ament machinery that runs Python at configure
# time, and its pkg-config file requires pluginlib.pc, which Debian does not ship; so the library
# and the header folders its headers include (pluginlib, class_loader, rcutils, rcpputils,
# ament_index_cpp under /usr/include/<name>) are found by hand. Used by drivers/net only.
find_path(ROSBAG_INCLUDE_DIR rosbag/bag.h REQUIRED)
find_path(ROSCPP_SERIALIZATION_INCLUDE_DIR ros/serialization.h REQUIRED)
find_library(ROSBAG_STORAGE_LIBRARY rosbag_storage REQUIRED)
add_library(bimslam_rosbag INTERFACE)
target_include_directories(bimslam_rosbag SYSTEM INTERFACE "${ROSBAG_INCLUDE_DIR}"
                                                           "${ROSCPP_SERIALIZATION_INCLUDE_DIR}")
# Each as <include>/<name>/<name>/<a header>, searched like any header rather than beside
# rosbag's: the aarch64 cross-build finds rosbag's in its staging (toolchain/stage-arm64.sh) and
# these, Debian's arm64 -dev packages or architecture-independent, in /usr/include.
foreach(sub_header pluginlib/class_loader.hpp class_loader/class_loader.hpp rcutils/env.h
        rcpputils/env.hpp ament_index_cpp/get_package_prefix.hpp)
    get_filename_component(sub "${sub_header}" DIRECTORY)
    find_path(ROSBAG_${sub}_DIR NAMES "${sub_header}" PATH_SUFFIXES "${sub}" REQUIRED)
    target_include_directories(bimslam_rosbag SYSTEM INTERFACE "${ROSBAG_${sub}_DIR}")
endforeach()
foreach(lib roscpp_serialization rostime cpp_common console_bridge boost_filesystem)
    find_library(ROSBAG_DEP_${lib} ${lib} REQUIRED)
    list(APPEND _rosbag_deps "${ROSBAG_DEP_${lib}}")
endforeach()
target_link_libraries(bimslam_rosbag INTERFACE "${ROSBAG_STORAGE_LIBRARY}" ${_rosbag_deps})
add_library(bimslam::rosbag ALIAS bimslam_rosbag)

# Host-only dependencies (host_tools/, and algorithms/simulation for Embree); the layer rules
# keep them out of firmware/ and drivers/. A firmware-only build (the aarch64 cross-build,
# BIMSLAM_HOST_TOOLS=OFF) looks for Embree and TBB only for its scene tests (BIMSLAM_SIMULATION:
# algorithms/simulation, which no program of it links), and never for IFC++.
if(BIMSLAM_SIMULATION)
    # Embree 3: ray casting for the LiDAR simulation.
    find_package(embree 3 REQUIRED)
    bimslam_tag_capability(embree embree)
    # TBB: host-side parallelism (the simulator's columns).
    find_package(TBB REQUIRED)
endif()
if(BIMSLAM_HOST_TOOLS)
    # IFC++ (libifcplusplus-dev) has no CMake package: its libraries and headers by hand. Its headers
    # are included as system headers (they are not -Wall clean).
    find_library(IFCPP_LIBRARY IfcPlusPlus PATHS /usr/lib /usr/lib/ifcplusplus REQUIRED)
    find_library(CARVE_LIBRARY carve PATHS /usr/lib /usr/lib/ifcplusplus REQUIRED)
    find_path(IFCPP_INCLUDE_DIR ifcpp/model/BuildingModel.h REQUIRED)
    add_library(bimslam_ifcpp INTERFACE)
    target_include_directories(bimslam_ifcpp SYSTEM INTERFACE "${IFCPP_INCLUDE_DIR}")
    target_link_libraries(bimslam_ifcpp INTERFACE ${IFCPP_LIBRARY} ${CARVE_LIBRARY})
    add_library(bimslam::ifcpp ALIAS bimslam_ifcpp)
    bimslam_tag_capability(bimslam_ifcpp ifcpp)
    # changes.bcf (host_tools/changes): the snapshots rendered by Mesa's OSMesa (llvmpipe, no
    # display) and written by libpng, the XML by libxml2's text writer, the zip by libzip.
    pkg_check_modules(OSMESA REQUIRED IMPORTED_TARGET osmesa)
    pkg_check_modules(LIBPNG REQUIRED IMPORTED_TARGET libpng)
    pkg_check_modules(LIBXML2 REQUIRED IMPORTED_TARGET libxml-2.0)
    pkg_check_modules(LIBZIP REQUIRED IMPORTED_TARGET libzip)
    # SHA-256 and base64 (algorithms/io, host_tools/report): OpenSSL's libcrypto (libssl-dev).
    find_package(OpenSSL REQUIRED COMPONENTS Crypto)
    # `bimslam live --serve` (host_tools/live): Debian's cpp-httplib (libcpp-httplib-dev).
    pkg_check_modules(CPP_HTTPLIB REQUIRED IMPORTED_TARGET GLOBAL cpp-httplib)
endif()

if(BUILD_TESTING)
    find_package(GTest REQUIRED)
    if(BIMSLAM_HOST_TOOLS)
        find_package(benchmark REQUIRED)
    endif()
    include(GoogleTest)
endif()
