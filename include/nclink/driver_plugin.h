/* nclink driver plugin ABI (C), version 2. A plugin is a shared library
 * exporting
 *
 *     const nclink_driver_descriptor* nclink_driver_entry(void);
 *
 * The SDK dlopen()s it, reads abi_version (the first field of every version),
 * checks the required functions, then creates one driver instance.
 *
 * Versions. abi_version 2 is this header, and the only version the host
 * loads (version 1 was removed before the first release); any other is
 * refused with one line naming it. Growth within version 2 needs no new
 * version: every struct starts with
 * struct_size = sizeof as its writer was built, a later header only appends
 * fields, and a reader uses a field only when struct_size covers it
 * (NCLINK_HAS_FIELD), so neither side needs rebuilding when the other grows.
 * abi_version changes only for a change that is not an append. Arrays are
 * arrays of plain numbers or strings and never change.
 *
 * Memory: nothing is freed across the boundary. Strings the host passes in
 * live for the call only; everything the plugin hands out goes through a
 * host callback that copies it before returning.
 *
 * Errors: every fallible call returns 0 or an error code and may say why in
 * `reason` (UTF-8 text, the vendor's words). Codes are table-19 numbers (GB/T
 * 41970-2022: 101 Out of Range, 202 Unavailable, 301 Permission Denied, 405
 * Value type error, ...) or the vendor's own codes below 0. Both reach the
 * wire (docs/wire.md, "Vendor errors"): a table-19 code as `error` with its
 * table-19 `reason`, the vendor's text in the item's privateInfo; a code
 * below 0 as is, its reason the vendor's text; any other code as 202, its
 * number kept in the text.
 *
 * Threading: as for nclink::Driver (driver.hpp): bind/read/write are
 * serialized unless flags has NCLINK_DRIVER_CONCURRENT (bind always runs
 * alone); call_method runs on a method thread of its own, concurrently with
 * read/write and other call_method calls (the plugin synchronizes what they
 * share); the nclink_method_control functions may be called from that thread
 * at any rate until call_method returns; claims and link from any thread,
 * answered from constant data or an atomic. Never called from an MQTT thread.
 *
 * C++ drivers can be exported with NCLINK_EXPORT_DRIVER
 * (driver_plugin_export.hpp); C helpers for JSON text and logging are in
 * driver_plugin_helpers.h.
 */
#ifndef NCLINK_DRIVER_PLUGIN_H
#define NCLINK_DRIVER_PLUGIN_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define NCLINK_DRIVER_ABI_VERSION 2u
/* The oldest version the host loads (docs/abi.md). */
#define NCLINK_DRIVER_ABI_OLDEST 2u
#define NCLINK_DRIVER_ENTRY_SYMBOL "nclink_driver_entry"

/* True when the struct *s (with its struct_size) includes `field`. */
#define NCLINK_HAS_FIELD(s, type, field) ((s) != NULL && (s)->struct_size >= offsetof(type, field) + sizeof(((type*)0)->field))

/* flags */
#define NCLINK_DRIVER_CONCURRENT 1u

/* Data kinds, as in the model's `datatype`; bind() also names methods. */
#define NCLINK_KIND_SINGLE 0
#define NCLINK_KIND_LIST 1
#define NCLINK_KIND_DICT 2
#define NCLINK_KIND_METHOD 3

/* Handles (bind): the plugin's own number for a point, or one of these. */
#define NCLINK_NO_HANDLE UINT64_MAX         /* identify the point by id */
#define NCLINK_NOT_SERVED (UINT64_MAX - 1u) /* the host answers 202 itself */

/* Log levels for nclink_host.log. */
#define NCLINK_LOG_TRACE 0
#define NCLINK_LOG_DEBUG 1
#define NCLINK_LOG_INFO 2
#define NCLINK_LOG_WARN 3
#define NCLINK_LOG_ERROR 4

/* Machine link states (link()). */
#define NCLINK_LINK_UNKNOWN 0
#define NCLINK_LINK_CONNECTED 1
#define NCLINK_LINK_DISCONNECTED 2

/* Frequently used table-19 codes. */
#define NCLINK_OK 0
#define NCLINK_E_OUT_OF_RANGE 101
#define NCLINK_E_PARAMETER_MISSING 102
#define NCLINK_E_UNAVAILABLE 202
#define NCLINK_E_TIMEOUT 203
#define NCLINK_E_PERMISSION_DENIED 301
#define NCLINK_E_NODE_NOT_EXISTS 401
#define NCLINK_E_VALUE_TYPE 405

/* Given to create(); valid until destroy() returns. */
typedef struct nclink_host {
    uint32_t struct_size;
    void* context;
    void (*log)(void* context, int level, const char* message); /* NCLINK_LOG_* */
} nclink_host;

/* Where a function puts text (a reason, a JSON return value); appends. */
typedef struct nclink_text_output {
    uint32_t struct_size;
    void* context;
    void (*put)(void* context, const char* text, size_t length);
} nclink_text_output;

/* bind(): the points of a newly installed model (driver.hpp, "Handles").
 * Arrays of `count`; strings are "" when the model gives none. */
typedef struct nclink_bind_request {
    uint32_t struct_size;
    size_t count;
    const char* const* ids;
    const int* kinds;         /* NCLINK_KIND_*, NCLINK_KIND_METHOD for a METHOD */
    const char* const* types; /* the model's `type` */
    const char* const* names;
    const char* const* units;
    const char* const* paths; /* component paths, "/MACHINE/AXIS@X/POSITION" */
    const int* setable;       /* nonzero when setable */
    uint64_t* handles;        /* out: each arrives NCLINK_NO_HANDLE */
} nclink_bind_request;

/* read(): the points to read. handles[i] is what bind() gave ids[i]
 * (NCLINK_NO_HANDLE when none). */
typedef struct nclink_read_request {
    uint32_t struct_size;
    size_t count;
    const char* const* ids;
    const int* kinds;
    const uint64_t* handles;
    /* Nonzero when the read feeds a sample channel: a failed point is sent
     * as null there (no code, no reason), so a driver may take a faster path
     * that skips error detail. Zero for Query, Set, events. */
    int sampling;
} nclink_read_request;

/* Where read() puts one answer per point: call exactly one of these per
 * index (unanswered points are 202). Typed values need no JSON: the host
 * escapes text itself; json() takes one JSON text (a list or dict item's
 * whole value). All copy what they are given. */
typedef struct nclink_read_output {
    uint32_t struct_size;
    void* context;
    void (*null_value)(void* context, size_t index);
    void (*boolean)(void* context, size_t index, int value);
    void (*int64)(void* context, size_t index, int64_t value);
    void (*uint64)(void* context, size_t index, uint64_t value);
    void (*float64)(void* context, size_t index, double value); /* NaN/Inf are sent as null */
    void (*text)(void* context, size_t index, const char* utf8, size_t length);
    void (*json)(void* context, size_t index, const char* json, size_t length);
    /* code: table 19 or below 0 (never 0); reason may be NULL */
    void (*error)(void* context, size_t index, int code, const char* reason);
} nclink_read_output;

/* write(): one Set item, after the host validated it against the model. */
typedef struct nclink_write_request {
    uint32_t struct_size;
    const char* id;
    int kind;
    uint64_t handle;
    const char* params_json;    /* the item's params as sent */
    const char* new_value_json; /* the whole value after the operation, "null" when unknown */
} nclink_write_request;

/* call_method(): one Method/Call. */
typedef struct nclink_method_request {
    uint32_t struct_size;
    const char* id;
    uint64_t handle;
    const char* args_json; /* checked against the METHOD's args, defaults filled in */
} nclink_method_request;

/* Given to call_method() while a method runs. */
typedef struct nclink_method_control {
    uint32_t struct_size;
    void* context;
    void (*progress)(void* context, double percent);
    int (*cancelled)(void* context);  /* nonzero once cancelled */
    int (*checkpoint)(void* context); /* blocks while paused; 0 if cancelled */
} nclink_method_control;

typedef struct nclink_driver_descriptor {
    uint32_t abi_version; /* NCLINK_DRIVER_ABI_VERSION */
    uint32_t struct_size; /* sizeof(nclink_driver_descriptor) */
    const char* name;
    const char* version;
    uint32_t flags;

    /* Required. config_json is the driver's configuration ("null" if none).
     * Connects to the machine (the driver's open()). Returns 0 with the
     * instance in *instance, or an error code and the reason. */
    int (*create)(const char* config_json, const nclink_host* host, void** instance, const nclink_text_output* reason);
    /* Required. The driver's close(). */
    void (*destroy)(void* instance);

    /* Required. For every point call exactly one function of `out`. */
    void (*read)(void* instance, const nclink_read_request* request, const nclink_read_output* out);

    /* Optional (NULL = every point by id). Sets request->handles[i] for the
     * points of a new model; returns 0, or an error code (and reason) to
     * refuse the model. */
    int (*bind)(void* instance, const nclink_bind_request* request, const nclink_text_output* reason);

    /* Optional (NULL = read-only: 301). Returns 0 or an error code. */
    int (*write)(void* instance, const nclink_write_request* request, const nclink_text_output* reason);

    /* Optional (NULL = no methods: 202). Puts the return value (JSON text;
     * nothing = null) into `result`; returns 0 or an error code. `control`
     * is valid until it returns. */
    int (*call_method)(void* instance, const nclink_method_request* request, const nclink_method_control* control,
                       const nclink_text_output* result, const nclink_text_output* reason);

    /* Optional (NULL = claims nothing). Nonzero when the driver serves `id`
     * although the model gives it a fixed value or makes it a config object
     * (see nclink::Driver::claims). */
    int (*claims)(void* instance, const char* id);

    /* Optional (NULL = unknown). NCLINK_LINK_*; when disconnected, why in
     * `reason`. Called before every batch: cheap, never blocking. */
    int (*link)(void* instance, const nclink_text_output* reason);
} nclink_driver_descriptor;

typedef const nclink_driver_descriptor* (*nclink_driver_entry_fn)(void);

#ifdef __cplusplus
}
#endif

#endif /* NCLINK_DRIVER_PLUGIN_H */
