#include <nclink/driver_plugin.h>
#include <stddef.h>
#include <string.h>
static void* create(const char* c, const nclink_host* h, const nclink_text_output* e) {
    (void)c; (void)h;
    const char* why = "no CNC at 192.0.2.7";
    e->put(e->context, why, strlen(why));
    return NULL;
}
static void destroy(void* s) { (void)s; }
static void read_points(void* s, const char* const* i, const int* k, size_t n, const nclink_read_output* o) { (void)s; (void)i; (void)k; (void)n; (void)o; }
static const nclink_driver_descriptor descriptor = {NCLINK_DRIVER_ABI_VERSION, "refusing", "1", 0, create, destroy, read_points, NULL, NULL, NULL};
__attribute__((visibility("default"))) const nclink_driver_descriptor* nclink_driver_entry(void) { return &descriptor; }
