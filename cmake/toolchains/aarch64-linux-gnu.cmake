# 64-bit ARM (arm64) with Debian 12's crossbuild-essential-arm64 and the
# -dev:arm64 packages; programs run under qemu-aarch64 (tools/cross-test.sh).
set(NCLINK_CROSS_TRIPLET aarch64-linux-gnu)
set(NCLINK_CROSS_PROCESSOR aarch64)
set(NCLINK_CROSS_QEMU qemu-aarch64)
include(${CMAKE_CURRENT_LIST_DIR}/debian-multiarch.cmake)
