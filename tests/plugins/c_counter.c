/* A driver plugin in plain C: every read returns a counter that grows per
 * read; "fail" answers Unavailable; writes to "ro" are refused; method
 * "count" reports progress and returns {"counted": N}. */
#include <nclink/driver_plugin.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct counter { long reads; long written; } counter;

static void* create(const char* config_json, const nclink_host* host, const nclink_text_output* error) {
    (void)error;
    if (host && host->log) host->log(host->context, 2, config_json);
    return calloc(1, sizeof(counter));
}
static void destroy(void* self) { free(self); }

static void read_points(void* self, const char* const* ids, const int* kinds, size_t count, const nclink_read_output* out) {
    counter* c = (counter*)self;
    (void)kinds;
    for (size_t i = 0; i < count; ++i) {
        if (strcmp(ids[i], "fail") == 0) {
            out->error(out->context, i, 202, "sensor disconnected");
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
                       const nclink_text_output* detail) {
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

static int call_method(void* self, const char* method_id, const char* args_json, const nclink_method_control* control,
                       const nclink_text_output* result) {
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

static const nclink_driver_descriptor descriptor = {
    NCLINK_DRIVER_ABI_VERSION, "c-counter", "1.2.3", 0,
    create, destroy, read_points, write_point, call_method, claims};

__attribute__((visibility("default"))) const nclink_driver_descriptor* nclink_driver_entry(void) { return &descriptor; }
