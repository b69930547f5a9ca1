/* A driver plugin in plain C built for ABI version 1 (driver_plugin_v1.h),
 * as plugins were before version 2: the host must still load it. Every read
 * returns a counter that grows per read; "fail" answers Unavailable;
 * "vendor" answers the vendor's own code -7; writes to "ro" are refused;
 * method "count" reports progress and returns {"counted": N}. */
#include <nclink/driver_plugin_v1.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct counter { long reads; long written; } counter;

static void* create(const char* config_json, const nclink_host_v1* host, const nclink_text_output_v1* error) {
    (void)error;
    if (host && host->log) host->log(host->context, 2, config_json);
    return calloc(1, sizeof(counter));
}
static void destroy(void* self) { free(self); }

static void read_points(void* self, const char* const* ids, const int* kinds, size_t count, const nclink_read_output_v1* out) {
    counter* c = (counter*)self;
    (void)kinds;
    for (size_t i = 0; i < count; ++i) {
        if (strcmp(ids[i], "fail") == 0) {
            out->error(out->context, i, 202, "sensor disconnected");
        } else if (strcmp(ids[i], "vendor") == 0) {
            out->error(out->context, i, -7, "spindle drive fault E7");
        } else if (strcmp(ids[i], "silent") == 0) {
            /* says nothing: the host must answer Unavailable */
        } else {
            char text[64];
            int n = snprintf(text, sizeof text, "%ld", ++c->reads);
            out->value(out->context, i, text, (size_t)n);
        }
    }
}

static int write_point(void* self, const char* id, int kind, const char* params_json, const char* new_value_json,
                       const nclink_text_output_v1* detail) {
    counter* c = (counter*)self;
    (void)kind; (void)params_json;
    if (strcmp(id, "ro") == 0) {
        const char* why = "ro is wired read-only";
        detail->put(detail->context, why, strlen(why));
        return 301;
    }
    c->written = atol(new_value_json);
    return 0;
}

static int call_method(void* self, const char* method_id, const char* args_json, const nclink_method_control_v1* control,
                       const nclink_text_output_v1* result) {
    (void)self; (void)args_json;
    if (strcmp(method_id, "count") != 0) return 401;
    for (int p = 0; p <= 100; p += 50) {
        control->progress(control->context, p);
        if (!control->checkpoint(control->context)) return 0;
    }
    const char* ret = "{\"counted\":3}";
    result->put(result->context, ret, strlen(ret));
    return 0;
}

static int claims(void* self, const char* id) {
    (void)self;
    return strcmp(id, "tool_table") == 0;
}

static const nclink_driver_descriptor_v1 descriptor = {
    NCLINK_DRIVER_ABI_VERSION_1, "c-counter-v1", "1.2.3", 0,
    create, destroy, read_points, write_point, call_method, claims};

__attribute__((visibility("default"))) const nclink_driver_descriptor_v1* nclink_driver_entry(void) { return &descriptor; }
