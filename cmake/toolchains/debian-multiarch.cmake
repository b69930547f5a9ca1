# Shared part of the Debian 12 cross toolchains (aarch64-linux-gnu.cmake,
# arm-linux-gnueabihf.cmake): the cross compiler of crossbuild-essential-<arch>
# and the target's libraries from the multiarch -dev:<arch> packages, which
# install beside the host's in /usr/lib/<triplet> (docs/building.md,
# "Cross-building"). The including file sets NCLINK_CROSS_TRIPLET,
# NCLINK_CROSS_PROCESSOR and NCLINK_CROSS_QEMU first.
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR ${NCLINK_CROSS_PROCESSOR})
# Makes find_library/find_package look in /usr/lib/<triplet> (and its cmake/
# folder) before the generic folders; the host's /usr/lib/x86_64-linux-gnu is
# never searched.
set(CMAKE_LIBRARY_ARCHITECTURE ${NCLINK_CROSS_TRIPLET})

set(CMAKE_C_COMPILER ${NCLINK_CROSS_TRIPLET}-gcc)
set(CMAKE_CXX_COMPILER ${NCLINK_CROSS_TRIPLET}-g++)

# The root is / itself: multiarch puts the target's libraries in the host's
# tree. A root of /usr/lib/<triplet> would find neither fmt nor the
# architecture-independent nlohmann_json and Catch2 config files.
set(CMAKE_FIND_ROOT_PATH /)
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)   # programs (mosquitto, openssl) are the host's
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE ONLY)

# pkg-config (cpp-httplib) reads the target's .pc files, not the host's.
set(ENV{PKG_CONFIG_LIBDIR} /usr/lib/${NCLINK_CROSS_TRIPLET}/pkgconfig:/usr/share/pkgconfig)

# ctest and Catch2's test discovery run the target's programs under qemu-user.
# Without -L: the multiarch loader (/lib/ld-linux-*.so from libc6:<arch>)
# finds the target's libraries by itself. With -L /usr/<triplet> qemu would
# pair the loader of libc6-<arch>-cross with the libc of libc6:<arch>, and
# every thread then spins forever.
if(NOT CMAKE_CROSSCOMPILING_EMULATOR)
  find_program(NCLINK_CROSS_QEMU_PROGRAM ${NCLINK_CROSS_QEMU})
  if(NCLINK_CROSS_QEMU_PROGRAM)
    set(CMAKE_CROSSCOMPILING_EMULATOR ${NCLINK_CROSS_QEMU_PROGRAM})
  endif()
endif()
