# Every third-party dependency, found once, from Debian packages (toolchain/install-deps.sh).
# Nothing is downloaded at build time.
include_guard(GLOBAL)
include(BimslamLayers)

find_package(PkgConfig REQUIRED)
find_package(Eigen3 3.4 REQUIRED NO_MODULE)
find_package(nlohmann_json 3 REQUIRED)
find_package(CLI11 REQUIRED)
find_package(Threads REQUIRED)

# LCM 1.3.1 ships only lcm.pc (no CMake package): pkg-config, and lcm-gen for the messages.
pkg_check_modules(LCM REQUIRED IMPORTED_TARGET lcm>=1.3)
bimslam_tag_capability(PkgConfig::LCM lcm)
find_program(LCM_GEN_EXECUTABLE lcm-gen REQUIRED)

# FLANN is used header-only (its KD-tree); flann.pc drags in HDF5 and MPI we do not need, but the
# headers include lz4.
find_path(FLANN_INCLUDE_DIR flann/flann.hpp REQUIRED)
pkg_check_modules(LZ4 REQUIRED IMPORTED_TARGET liblz4)
add_library(bimslam_flann INTERFACE)
target_include_directories(bimslam_flann SYSTEM INTERFACE "${FLANN_INCLUDE_DIR}")
target_link_libraries(bimslam_flann INTERFACE PkgConfig::LZ4)
add_library(bimslam::flann ALIAS bimslam_flann)

if(BUILD_TESTING)
    find_package(GTest REQUIRED)
    find_package(benchmark REQUIRED)
    include(GoogleTest)
endif()
