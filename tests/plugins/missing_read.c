#include <nclink/driver_plugin.h>
#include <stddef.h>
static void* create(const char* c, const nclink_host* h, const nclink_text_output* e) { (void)c; (void)h; (void)e; return NULL; }
static void destroy(void* s) { (void)s; }
static const nclink_driver_descriptor descriptor = {NCLINK_DRIVER_ABI_VERSION, "no-read", "1", 0, create, destroy, NULL, NULL, NULL, NULL};
__attribute__((visibility("default"))) const nclink_driver_descriptor* nclink_driver_entry(void) { return &descriptor; }
