/* A plugin from a future ABI: refused in one line naming its version. */
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
static void read_points(void* s, const nclink_read_request* r, const nclink_read_output* o) {
    (void)s;
    (void)r;
    (void)o;
}
static const nclink_driver_descriptor descriptor = {
    999u, sizeof(nclink_driver_descriptor), "from-the-future", "9", 0, create, destroy, read_points, NULL, NULL, NULL, NULL,
    NULL};
__attribute__((visibility("default"))) const nclink_driver_descriptor* nclink_driver_entry(void) { return &descriptor; }
