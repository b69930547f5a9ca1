#define _POSIX_C_SOURCE 200809L /* nanosleep */
/* Reads, the one write and the method of the C firmware, through the C
 * driver struct. bind() gives every point its index in `points` as handle,
 * so read() never compares strings. */
#include "driver.h"

#include <nclink/driver_plugin_helpers.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

machine* firmware_machine = NULL;

enum point { P_X, P_Y, P_Z, P_SPINDLE, P_STATUS, P_PARTS, P_FEED, P_HOME, P_COUNT };
static const char* const points[P_COUNT] = {"x_position", "y_position", "z_position",    "spindle_speed",
                                            "status",     "part_count", "feed_override", "home_axes"};

typedef struct instance {
    machine* m;
    const nclink_host* host;
} instance;

static int point_of(const char* id) {
    int i;
    for (i = 0; i < P_COUNT; ++i)
        if (strcmp(points[i], id) == 0) return i;
    return -1;
}

static int create(const char* config_json, const nclink_host* host, void** out, const nclink_text_output* reason) {
    instance* self;
    (void)config_json;
    if (firmware_machine == NULL) {
        nclink_put_text(reason, "no machine");
        return NCLINK_E_UNAVAILABLE;
    }
    self = (instance*)calloc(1, sizeof *self);
    if (self == NULL) return NCLINK_E_UNAVAILABLE;
    self->m = firmware_machine;
    self->host = host;
    nclink_logf(host, NCLINK_LOG_INFO, "c-firmware driver: %d points", P_COUNT);
    *out = self;
    return NCLINK_OK;
}

static void destroy(void* self) { free(self); }

static int bind_points(void* self, const nclink_bind_request* request, const nclink_text_output* reason) {
    size_t i;
    (void)self;
    (void)reason;
    for (i = 0; i < request->count; ++i) {
        const int p = point_of(request->ids[i]);
        request->handles[i] = p < 0 ? NCLINK_NOT_SERVED : (uint64_t)p;
    }
    return NCLINK_OK;
}

static void read_points(void* self, const nclink_read_request* request, const nclink_read_output* out) {
    const machine_snapshot s = machine_read(((instance*)self)->m);
    size_t i;
    for (i = 0; i < request->count; ++i) {
        const uint64_t h = request->handles[i];
        const int p = h == NCLINK_NO_HANDLE ? point_of(request->ids[i]) : (int)h;
        char text[32];
        switch (p) {
            case P_X:
            case P_Y:
            case P_Z: out->float64(out->context, i, s.position[p]); break;
            case P_SPINDLE: out->float64(out->context, i, s.spindle_speed); break;
            case P_STATUS: out->text(out->context, i, s.status, strlen(s.status)); break;
            case P_PARTS: /* PART_COUNT is a string (table 13) */
                snprintf(text, sizeof text, "%ld", s.part_count);
                out->text(out->context, i, text, strlen(text));
                break;
            case P_FEED: out->int64(out->context, i, machine_feed_override(((instance*)self)->m)); break;
            default: out->error(out->context, i, NCLINK_E_NODE_NOT_EXISTS, "not a point of this machine");
        }
    }
}

static int write_point(void* self, const nclink_write_request* request, const nclink_text_output* reason) {
    int64_t percent;
    const int p = request->handle == NCLINK_NO_HANDLE ? point_of(request->id) : (int)request->handle;
    if (p != P_FEED) {
        nclink_put_text(reason, "only feed_override is settable");
        return NCLINK_E_PERMISSION_DENIED;
    }
    if (!nclink_json_read_int(request->new_value_json, &percent)) {
        nclink_put_text(reason, "feed_override takes an integer");
        return NCLINK_E_VALUE_TYPE;
    }
    if (percent < 0 || percent > 150) {
        nclink_put_text(reason, "feed_override is 0..150 %");
        return NCLINK_E_OUT_OF_RANGE;
    }
    machine_set_feed_override(((instance*)self)->m, (int)percent);
    return NCLINK_OK;
}

/* home_axes: one axis after the other, 100 ms each, paused and cancelled
 * between axes (docs/methods.md). Runs on a method thread of its own. */
static int call_method(void* self, const nclink_method_request* request, const nclink_method_control* control,
                       const nclink_text_output* result, const nclink_text_output* reason) {
    machine* m = ((instance*)self)->m;
    const int p = request->handle == NCLINK_NO_HANDLE ? point_of(request->id) : (int)request->handle;
    int axis, homed = 0;
    char text[64];
    nclink_json_writer w;
    if (p != P_HOME) {
        nclink_put_text(reason, "no such method");
        return NCLINK_E_NODE_NOT_EXISTS;
    }
    machine_set_homing(m, 1);
    for (axis = 0; axis < MACHINE_AXES; ++axis) {
        const struct timespec step = {0, 100 * 1000 * 1000};
        if (!control->checkpoint(control->context)) break; /* cancelled: stop where we are */
        nanosleep(&step, NULL);
        machine_home_axis(m, axis);
        ++homed;
        control->progress(control->context, 100.0 * homed / MACHINE_AXES);
    }
    machine_set_homing(m, 0);
    nclink_json_init(&w, text, sizeof text);
    nclink_json_begin_object(&w);
    nclink_json_key(&w, "homed");
    nclink_json_int(&w, homed);
    nclink_json_end_object(&w);
    nclink_put_text(result, text);
    return NCLINK_OK;
}

static int link_state(void* self, const nclink_text_output* reason) {
    (void)self;
    (void)reason;
    return NCLINK_LINK_CONNECTED; /* the machine is this process */
}

static const nclink_driver_descriptor descriptor = {NCLINK_DRIVER_ABI_VERSION,
                                                    sizeof(nclink_driver_descriptor),
                                                    "c-firmware",
                                                    "1.0.0",
                                                    0,
                                                    create,
                                                    destroy,
                                                    read_points,
                                                    bind_points,
                                                    write_point,
                                                    call_method,
                                                    NULL,
                                                    link_state};

const nclink_driver_descriptor* firmware_driver(void) { return &descriptor; }
