#include <nclink/driver_plugin.h>
#include <stddef.h>
#include <string.h>
static int create(const char* c, const nclink_host* h, void** i, const nclink_text_output* e) {
    (void)c;
    (void)h;
    (void)i;
    const char* why = "no CNC at 192.0.2.7";
    e->put(e->context, why, strlen(why));
    return NCLINK_E_UNAVAILABLE;
}
static void destroy(void* s) { (void)s; }
static void read_points(void* s, const nclink_read_request* r, const nclink_read_output* o) {
    (void)s;
    (void)r;
    (void)o;
}
static const nclink_driver_descriptor descriptor = {NCLINK_DRIVER_ABI_VERSION,
                                                    sizeof(nclink_driver_descriptor),
                                                    "refusing",
                                                    "1",
                                                    0,
                                                    create,
                                                    destroy,
                                                    read_points,
                                                    NULL,
                                                    NULL,
                                                    NULL,
                                                    NULL,
                                                    NULL};
__attribute__((visibility("default"))) const nclink_driver_descriptor* nclink_driver_entry(void) { return &descriptor; }
