/* A plugin claiming ABI version 1, which was removed before the first
 * release (docs/abi.md): refused in one line naming its version. Only the
 * first field matters; the host reads nothing else of a version it does not
 * speak. */
#include <stdint.h>
static const uint32_t descriptor[4] = {1u, 0u, 0u, 0u};
__attribute__((visibility("default"))) const void* nclink_driver_entry(void) { return descriptor; }
