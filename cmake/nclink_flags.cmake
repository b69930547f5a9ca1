# Warning and sanitizer flags shared by every nclink target.
add_library(nclink_flags INTERFACE)
target_compile_options(nclink_flags INTERFACE -Wall -Wextra -Wshadow -Wnon-virtual-dtor -Wpedantic)
if(NCLINK_WERROR)
  target_compile_options(nclink_flags INTERFACE -Werror)
endif()

if(NCLINK_SANITIZER STREQUAL "asan")
  add_compile_options(-fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined)
  add_link_options(-fsanitize=address,undefined)
elseif(NCLINK_SANITIZER STREQUAL "tsan")
  add_compile_options(-fsanitize=thread -fno-omit-frame-pointer)
  add_link_options(-fsanitize=thread)
elseif(NOT NCLINK_SANITIZER STREQUAL "")
  message(FATAL_ERROR "NCLINK_SANITIZER must be '', 'asan' or 'tsan' (got '${NCLINK_SANITIZER}')")
endif()

if(NCLINK_FUZZ AND NOT CMAKE_CXX_COMPILER_ID MATCHES "Clang")
  message(FATAL_ERROR "NCLINK_FUZZ needs clang (CC=clang CXX=clang++), libFuzzer is part of clang")
endif()

# MinSizeRel is the size build for firmware (docs/footprint.md): every
# function and datum in a section of its own, so that the linker drops what
# nothing reaches. It took 131,040 bytes (8 %) off the stripped aarch64
# libnclink.so (1,580,672 -> 1,449,632); other configurations are left as
# they are.
add_compile_options($<$<CONFIG:MinSizeRel>:-ffunction-sections> $<$<CONFIG:MinSizeRel>:-fdata-sections>)
add_link_options($<$<CONFIG:MinSizeRel>:LINKER:--gc-sections>)
