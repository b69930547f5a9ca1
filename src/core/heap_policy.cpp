// keep_freed_heap() (include/nclink/heap.hpp says why).
#include <nclink/heap.hpp>

#include <algorithm>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace nclink {

bool keep_freed_heap(std::size_t bytes) {
#if defined(__GLIBC__)
    if (bytes == 0) return false;
    const int keep = static_cast<int>(std::min(bytes, max_heap_keep_bytes));
    // Setting either threshold turns off glibc's own adjustment of the mmap
    // threshold, so both are set: a DTU up to `keep` bytes is then neither
    // mmapped nor trimmed away after use.
    const bool mmap_set = mallopt(M_MMAP_THRESHOLD, keep) == 1;
    const bool trim_set = mallopt(M_TRIM_THRESHOLD, keep) == 1;
    return mmap_set && trim_set;
#else
    (void)bytes;
    return false;
#endif
}

}  // namespace nclink
