#include <nclink/driver_plugin.h>
#include <stddef.h>
static int create(const char* c, const nclink_host* h, void** i, const nclink_text_output* e) {
    (void)c;
    (void)h;
    (void)i;
    (void)e;
    return 202;
}
static void destroy(void* s) { (void)s; }
static const nclink_driver_descriptor descriptor = {
    NCLINK_DRIVER_ABI_VERSION, sizeof(nclink_driver_descriptor), "no-read", "1", 0, create, destroy, NULL, NULL, NULL, NULL, NULL, NULL};
__attribute__((visibility("default"))) const nclink_driver_descriptor* nclink_driver_entry(void) { return &descriptor; }
