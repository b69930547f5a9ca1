/* nclink driver plugin ABI (C). A plugin is a shared library exporting
 *
 *     const nclink_driver_descriptor* nclink_driver_entry(void);
 *
 * The SDK dlopen()s it, checks abi_version == NCLINK_DRIVER_ABI_VERSION and
 * that the required functions are present, then creates one driver instance.
 * Values cross the boundary as UTF-8 JSON text; every output goes through a
 * host-provided callback that copies it, so no memory is ever freed across
 * the boundary. Error codes are table-19 numbers (0 = success).
 *
 * Threading: as for nclink::Driver (driver.hpp): read/write are serialized
 * unless flags has NCLINK_DRIVER_CONCURRENT; call_method runs on a method
 * thread of its own, concurrently with read/write and other call_method
 * calls (the plugin synchronizes what they share); the nclink_method_control
 * functions may be called from that thread at any rate until call_method
 * returns. Never made from an MQTT thread.
 * C++ drivers can be exported with NCLINK_EXPORT_DRIVER (driver_plugin_export.hpp).
 */
#ifndef NCLINK_DRIVER_PLUGIN_H
#define NCLINK_DRIVER_PLUGIN_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define NCLINK_DRIVER_ABI_VERSION 1u
#define NCLINK_DRIVER_ENTRY_SYMBOL "nclink_driver_entry"

/* flags */
#define NCLINK_DRIVER_CONCURRENT 1u

/* data kinds, as in the model's `datatype` */
#define NCLINK_KIND_SINGLE 0
#define NCLINK_KIND_LIST 1
#define NCLINK_KIND_DICT 2

/* Log levels for nclink_host.log: 0 trace .. 4 error. */
typedef struct nclink_host {
    void* context;
    void (*log)(void* context, int level, const char* message);
} nclink_host;

/* Where read() puts results; index is the position in ids[]. */
typedef struct nclink_read_output {
    void* context;
    void (*value)(void* context, size_t index, const char* json, size_t json_length);
    void (*error)(void* context, size_t index, int code, const char* detail);
} nclink_read_output;

/* Where a function puts a text result (a JSON return value, an error detail). */
typedef struct nclink_text_output {
    void* context;
    void (*put)(void* context, const char* text, size_t length);
} nclink_text_output;

/* Given to call_method() while a method runs. */
typedef struct nclink_method_control {
    void* context;
    void (*progress)(void* context, double percent);
    int (*cancelled)(void* context);  /* nonzero once cancelled */
    int (*checkpoint)(void* context); /* blocks while paused; 0 if cancelled */
} nclink_method_control;

typedef struct nclink_driver_descriptor {
    uint32_t abi_version; /* NCLINK_DRIVER_ABI_VERSION */
    const char* name;
    const char* version;
    uint32_t flags;

    /* Required. config_json is the driver's configuration ("null" if none).
     * Returns the instance, or NULL with a reason written to `error`. */
    void* (*create)(const char* config_json, const nclink_host* host, const nclink_text_output* error);
    /* Required. */
    void (*destroy)(void* instance);

    /* Required. For every ids[i] (with kinds[i]) call out->value or
     * out->error exactly once; unanswered items are reported Unavailable. */
    void (*read)(void* instance, const char* const* ids, const int* kinds, size_t count,
                 const nclink_read_output* out);

    /* Optional (NULL = read-only). params_json: the Set item's params;
     * new_value_json: the whole value after the operation, or "null".
     * Returns 0 or a table-19 code with a detail in `detail`. */
    int (*write)(void* instance, const char* id, int kind, const char* params_json,
                 const char* new_value_json, const nclink_text_output* detail);

    /* Optional (NULL = no methods: calls answer 202). Puts the return value
     * (JSON; nothing = null) into `result`; returns 0 or a table-19 code
     * (negative user codes become 202) with a detail in `result`. `control`
     * is valid until it returns: progress 0..100, cancelled() nonzero after a
     * "cancel", checkpoint() blocks while paused and returns 0 if cancelled. */
    int (*call_method)(void* instance, const char* method_id, const char* args_json,
                       const nclink_method_control* control, const nclink_text_output* result);

    /* Optional (NULL = claims nothing). Nonzero when the driver serves `id`
     * although the model gives it a fixed value or makes it a config object
     * (see nclink::Driver::claims). Called from any SDK thread; answer from
     * constant data. */
    int (*claims)(void* instance, const char* id);
} nclink_driver_descriptor;

typedef const nclink_driver_descriptor* (*nclink_driver_entry_fn)(void);

#ifdef __cplusplus
}
#endif

#endif /* NCLINK_DRIVER_PLUGIN_H */
