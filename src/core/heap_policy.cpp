// keep_freed_heap() (include/nclink/heap.hpp says why) and
// release_freed_heap() (core/heap_release.hpp).
#include "core/heap_release.hpp"

#include <nclink/heap.hpp>

#include <algorithm>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace nclink {

bool keep_freed_heap(std::size_t bytes) {
#if defined(__GLIBC__)
    if (bytes == 0) return false;
    // glibc refuses an mmap threshold above half its per-thread heap size:
    // 32 MB on a 64-bit target (max_heap_keep_bytes) but 512 kB on a 32-bit
    // one (armhf), where the 32 MB default would leave it unset. The trim
    // threshold has no such bound: freed memory is kept up to `bytes` there
    // too, and only blocks over 512 kB come from mmap.
    constexpr std::size_t kMmapThresholdMax = sizeof(long) >= 8 ? max_heap_keep_bytes : std::size_t{512} << 10;
    const int keep = static_cast<int>(std::min(bytes, max_heap_keep_bytes));
    const int from_heap = static_cast<int>(std::min(bytes, kMmapThresholdMax));
    // Setting either threshold turns off glibc's own adjustment of the mmap
    // threshold, so both are set: a DTU up to `from_heap` bytes is then
    // neither mmapped nor trimmed away after use.
    const bool mmap_set = mallopt(M_MMAP_THRESHOLD, from_heap) == 1;
    const bool trim_set = mallopt(M_TRIM_THRESHOLD, keep) == 1;
    return mmap_set && trim_set;
#else
    (void)bytes;
    return false;
#endif
}

namespace core_detail {

bool release_freed_heap(std::size_t keep_top) {
#if defined(__GLIBC__) && !defined(__SANITIZE_ADDRESS__) && !defined(__SANITIZE_THREAD__)
    (void)malloc_trim(keep_top);  // its result says whether anything was given back, not whether it worked
    return true;
#else
    (void)keep_top;
    return false;
#endif
}

}  // namespace core_detail

}  // namespace nclink
