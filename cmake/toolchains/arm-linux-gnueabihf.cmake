# 32-bit ARM, hard float (armhf: ARMv7-A, Thumb-2, VFPv3-D16) with Debian 12's
# crossbuild-essential-armhf and the -dev:armhf packages; programs run under
# qemu-arm (tools/cross-test.sh). 32-bit pointers, size_t and (on Debian 12)
# time_t: the build that finds narrowing and 64-bit atomics.
set(NCLINK_CROSS_TRIPLET arm-linux-gnueabihf)
set(NCLINK_CROSS_PROCESSOR armv7l)
set(NCLINK_CROSS_QEMU qemu-arm)
include(${CMAKE_CURRENT_LIST_DIR}/debian-multiarch.cmake)
# GCC 7.1 changed how some aggregates are passed on ARM and notes it at every
# such call (-Wpsabi); it concerns only linking against code built by GCC < 7.
set(CMAKE_CXX_FLAGS_INIT "-Wno-psabi")
