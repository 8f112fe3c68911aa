# Two sub-builds of this same source tree, built with the native build and tested by its ctest:
#   sanitize/      clang, ASan + UBSan, libFuzzer targets; only tests labelled "parser"
#   cross-aarch64/ firmware and its tests for aarch64, run under qemu-aarch64 (label "cross")
include(ExternalProject)

ExternalProject_Add(mocap_sanitize
    SOURCE_DIR ${CMAKE_SOURCE_DIR}
    BINARY_DIR ${CMAKE_BINARY_DIR}/sanitize
    CMAKE_ARGS
        -DCMAKE_BUILD_TYPE=RelWithDebInfo
        -DCMAKE_C_COMPILER=clang
        -DCMAKE_CXX_COMPILER=clang++
        -DMOCAP_SANITIZE=ON
        -DMOCAP_FUZZ=ON
        -DMOCAP_PARSERS_ONLY=ON
        -DMOCAP_TEST_LABEL=sanitize
        -DMOCAP_WERROR=${MOCAP_WERROR}
    CMAKE_CACHE_ARGS
        -DMOCAP_HUB_LAYERS:STRING=${MOCAP_HUB_LAYERS}
        -DMOCAP_FIRMWARE_MODULES:STRING=${MOCAP_FIRMWARE_MODULES}
    BUILD_ALWAYS ON
    INSTALL_COMMAND ""
    USES_TERMINAL_BUILD ON)

ExternalProject_Add(mocap_cross_aarch64
    SOURCE_DIR ${CMAKE_SOURCE_DIR}
    BINARY_DIR ${CMAKE_BINARY_DIR}/cross-aarch64
    CMAKE_ARGS
        -DCMAKE_BUILD_TYPE=Release
        -DCMAKE_TOOLCHAIN_FILE=${CMAKE_SOURCE_DIR}/cmake/aarch64-linux-gnu.cmake
        -DMOCAP_FIRMWARE_ONLY=ON
        -DMOCAP_TEST_LABEL=cross
        -DMOCAP_WERROR=${MOCAP_WERROR}
    CMAKE_CACHE_ARGS
        -DMOCAP_FIRMWARE_MODULES:STRING=${MOCAP_FIRMWARE_MODULES}
    BUILD_ALWAYS ON
    INSTALL_COMMAND ""
    USES_TERMINAL_BUILD ON)

# The arm64 mocap-node package from the cross build, beside the native packages.
add_custom_target(package-arm64
    COMMAND ${CMAKE_COMMAND} --build ${CMAKE_BINARY_DIR}/cross-aarch64 --target package
    COMMAND ${CMAKE_COMMAND} -E make_directory ${CMAKE_BINARY_DIR}/packages
    COMMAND sh -c "cp ${CMAKE_BINARY_DIR}/cross-aarch64/packages/*.deb ${CMAKE_BINARY_DIR}/packages/"
    DEPENDS mocap_cross_aarch64
    COMMENT "mocap-node arm64 package from the aarch64 cross build"
    USES_TERMINAL)

# Pull the sub-builds' tests into this build's ctest run (ctest's subdirs() in CTestTestfile).
file(WRITE ${CMAKE_BINARY_DIR}/SubBuildTests.cmake
    "subdirs(\"${CMAKE_BINARY_DIR}/sanitize\")\nsubdirs(\"${CMAKE_BINARY_DIR}/cross-aarch64\")\n")
set_property(DIRECTORY ${CMAKE_SOURCE_DIR} APPEND PROPERTY TEST_INCLUDE_FILES
    ${CMAKE_BINARY_DIR}/SubBuildTests.cmake)
