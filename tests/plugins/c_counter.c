/* A driver plugin in plain C for ABI version 2 (driver_plugin.h), written
 * with the C helpers (driver_plugin_helpers.h) and built with -Wall -Wextra
 * -Werror. It exercises every part of the ABI:
 * - bind(): a handle per point (its row in `points` below); "hidden" is
 *   not served; reads find their point by handle, never by comparing ids
 *   (a point without a handle, read before any bind, falls back to its id);
 * - typed reads: a counter (int64), "name" (text with quotes and a newline),
 *   "flag" (boolean), "temp" (float64), "tools" (a list as JSON text),
 *   "handle" (the handle it was read with, uint64);
 * - errors with the vendor's reason: "fail" 202, "vendor" the vendor's own
 *   code -7; a write to "ro" 301, to "vendor" -12;
 * - write(): the new value read back from JSON with the helpers;
 * - methods: "count" reports progress and returns {"counted": 3};
 * - link(): disconnected with a reason when the configuration says
 *   {"link_down": true};
 * - {"vendor_id": "<id>"} in the configuration binds that id as "vendor"
 *   (so a model's item can fail with the vendor's code in adapter tests);
 * - the configuration string logged with nclink_logf. */
#include <nclink/driver_plugin.h>
#include <nclink/driver_plugin_helpers.h>

#include <stdlib.h>
#include <string.h>

enum point { P_COUNTER, P_NAME, P_FLAG, P_TEMP, P_TOOLS, P_HANDLE, P_FAIL, P_VENDOR, P_RO, P_SILENT, P_COUNT_METHOD };

static const char* const point_ids[] = {"", "name", "flag", "temp", "tools", "handle", "fail", "vendor", "ro", "silent", "count"};
#define POINT_COUNT (sizeof point_ids / sizeof point_ids[0])

typedef struct counter {
    long reads;
    int64_t written;
    int link_down;
    long binds;
    char vendor_id[64];
    const nclink_host* host;
} counter;

/* By id: only for points that came without a handle. */
static enum point point_of_id(const char* id) {
    size_t p;
    for (p = 1; p < POINT_COUNT; ++p)
        if (strcmp(id, point_ids[p]) == 0) return (enum point)p;
    return P_COUNTER;
}

static enum point point_of(uint64_t handle, const char* id) {
    if (handle != NCLINK_NO_HANDLE && handle < POINT_COUNT) return (enum point)handle;
    return point_of_id(id);
}

static int create(const char* config_json, const nclink_host* host, void** instance, const nclink_text_output* reason) {
    counter* c = (counter*)calloc(1, sizeof(counter));
    const char* down;
    if (c == NULL) {
        nclink_put_text(reason, "out of memory");
        return NCLINK_E_UNAVAILABLE;
    }
    c->host = host;
    down = nclink_json_member(config_json, "link_down");
    if (down != NULL && !nclink_json_read_bool(down, &c->link_down)) {
        nclink_put_text(reason, "link_down must be true or false");
        free(c);
        return NCLINK_E_VALUE_TYPE;
    }
    {
        const char* vendor = nclink_json_member(config_json, "vendor_id");
        if (vendor != NULL && !nclink_json_read_string(vendor, c->vendor_id, sizeof c->vendor_id, NULL)) {
            nclink_put_text(reason, "vendor_id must be a string of at most 63 bytes");
            free(c);
            return NCLINK_E_VALUE_TYPE;
        }
    }
    nclink_logf(host, NCLINK_LOG_INFO, "%s", config_json);
    *instance = c;
    return NCLINK_OK;
}

static void destroy(void* self) { free(self); }

static int bind(void* self, const nclink_bind_request* request, const nclink_text_output* reason) {
    counter* c = (counter*)self;
    size_t i;
    (void)reason;
    ++c->binds;
    for (i = 0; i < request->count; ++i) {
        if (strcmp(request->ids[i], "hidden") == 0) request->handles[i] = NCLINK_NOT_SERVED;
        else if (c->vendor_id[0] != '\0' && strcmp(request->ids[i], c->vendor_id) == 0) request->handles[i] = P_VENDOR;
        else request->handles[i] = (uint64_t)point_of_id(request->ids[i]);
    }
    nclink_logf(c->host, NCLINK_LOG_DEBUG, "bound %zu point(s)", request->count);
    return NCLINK_OK;
}

static void read_points(void* self, const nclink_read_request* request, const nclink_read_output* out) {
    counter* c = (counter*)self;
    size_t i;
    for (i = 0; i < request->count; ++i) {
        const uint64_t handle = request->handles ? request->handles[i] : NCLINK_NO_HANDLE;
        switch (point_of(handle, request->ids[i])) {
            case P_NAME: {
                const char* name = "say \"hi\"\n";
                out->text(out->context, i, name, strlen(name));
                break;
            }
            case P_FLAG: out->boolean(out->context, i, 1); break;
            case P_TEMP: out->float64(out->context, i, 21.5); break;
            case P_TOOLS: {
                char buf[256];
                nclink_json_writer w;
                int t;
                nclink_json_init(&w, buf, sizeof buf);
                nclink_json_begin_array(&w);
                for (t = 1; t <= 2; ++t) {
                    nclink_json_begin_object(&w);
                    nclink_json_key(&w, "id");
                    nclink_json_int(&w, t);
                    nclink_json_key(&w, "name");
                    nclink_json_string(&w, t == 1 ? "drill \"8mm\"" : "mill\\tap");
                    nclink_json_key(&w, "length");
                    nclink_json_double(&w, 50.25 * t);
                    nclink_json_key(&w, "worn");
                    nclink_json_bool(&w, t == 2);
                    nclink_json_end_object(&w);
                }
                nclink_json_end_array(&w);
                if (nclink_json_ok(&w)) out->json(out->context, i, buf, w.length);
                else out->error(out->context, i, NCLINK_E_UNAVAILABLE, "tool table too long");
                break;
            }
            case P_HANDLE: out->uint64(out->context, i, handle); break;
            case P_FAIL: out->error(out->context, i, NCLINK_E_UNAVAILABLE, "sensor disconnected"); break;
            case P_VENDOR: out->error(out->context, i, -7, "spindle drive fault E7"); break;
            case P_SILENT: break; /* says nothing: the host must answer Unavailable */
            default: out->int64(out->context, i, ++c->reads);
        }
    }
}

static int write_point(void* self, const nclink_write_request* request, const nclink_text_output* reason) {
    counter* c = (counter*)self;
    int64_t value;
    switch (point_of(request->handle, request->id)) {
        case P_RO: nclink_put_text(reason, "ro is wired read-only"); return NCLINK_E_PERMISSION_DENIED;
        case P_VENDOR: nclink_put_text(reason, "axis clamp engaged"); return -12;
        default: break;
    }
    if (!nclink_json_read_int(request->new_value_json, &value)) {
        nclink_put_text(reason, "an integer is expected");
        return NCLINK_E_VALUE_TYPE;
    }
    c->written = value;
    return NCLINK_OK;
}

static int call_method(void* self, const nclink_method_request* request, const nclink_method_control* control,
                       const nclink_text_output* result, const nclink_text_output* reason) {
    char buf[64];
    nclink_json_writer w;
    int p;
    (void)self;
    if (point_of(request->handle, request->id) != P_COUNT_METHOD) {
        nclink_put_text(reason, "no such method");
        return NCLINK_E_NODE_NOT_EXISTS;
    }
    for (p = 0; p <= 100; p += 50) {
        control->progress(control->context, p);
        if (!control->checkpoint(control->context)) return NCLINK_OK;
    }
    nclink_json_init(&w, buf, sizeof buf);
    nclink_json_begin_object(&w);
    nclink_json_key(&w, "counted");
    nclink_json_int(&w, 3);
    nclink_json_end_object(&w);
    result->put(result->context, buf, w.length);
    return NCLINK_OK;
}

static int claims(void* self, const char* id) {
    (void)self;
    return strcmp(id, "tool_table") == 0;
}

static int link_state(void* self, const nclink_text_output* reason) {
    const counter* c = (const counter*)self;
    if (!c->link_down) return NCLINK_LINK_CONNECTED;
    nclink_put_text(reason, "CNC cable unplugged");
    return NCLINK_LINK_DISCONNECTED;
}

static const nclink_driver_descriptor descriptor = {NCLINK_DRIVER_ABI_VERSION,
                                                    sizeof(nclink_driver_descriptor),
                                                    "c-counter",
                                                    "1.2.3",
                                                    0,
                                                    create,
                                                    destroy,
                                                    read_points,
                                                    bind,
                                                    write_point,
                                                    call_method,
                                                    claims,
                                                    link_state};

__attribute__((visibility("default"))) const nclink_driver_descriptor* nclink_driver_entry(void) { return &descriptor; }
