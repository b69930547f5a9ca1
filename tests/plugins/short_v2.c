/* A version-2 plugin built against an early 2.x header whose descriptor
 * ended after claims (no link): its struct_size says so, and the host must
 * not read past it. Fields that would follow are garbage on purpose. */
#include <nclink/driver_plugin.h>
#include <stddef.h>
#include <stdint.h>
static int create(const char* c, const nclink_host* h, void** i, const nclink_text_output* e) {
    static int instance;
    (void)c;
    (void)h;
    (void)e;
    *i = &instance;
    return NCLINK_OK;
}
static void destroy(void* s) { (void)s; }
static void read_points(void* s, const nclink_read_request* r, const nclink_read_output* o) {
    size_t i;
    (void)s;
    for (i = 0; i < r->count; ++i) o->int64(o->context, i, 42);
}
static struct {
    nclink_driver_descriptor d;
} descriptor = {{NCLINK_DRIVER_ABI_VERSION, (uint32_t)offsetof(nclink_driver_descriptor, link), "short", "1", 0, create, destroy,
                 read_points, NULL, NULL, NULL, NULL, (int (*)(void*, const nclink_text_output*))(uintptr_t)1}};
__attribute__((visibility("default"))) const nclink_driver_descriptor* nclink_driver_entry(void) { return &descriptor.d; }
