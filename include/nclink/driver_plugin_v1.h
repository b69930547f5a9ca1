/* The nclink driver plugin ABI version 1, frozen: the layout plugins built
 * before version 2 (driver_plugin.h) export. The host still loads them and
 * adapts them (docs/porting-guide.md, "Migrating a v1 plugin"): reads and
 * writes by id, values as JSON text, no bind, no typed read, no link. New
 * plugins use driver_plugin.h; this header is for the host and for tests.
 */
#ifndef NCLINK_DRIVER_PLUGIN_V1_H
#define NCLINK_DRIVER_PLUGIN_V1_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define NCLINK_DRIVER_ABI_VERSION_1 1u

typedef struct nclink_host_v1 {
    void* context;
    void (*log)(void* context, int level, const char* message);
} nclink_host_v1;

typedef struct nclink_read_output_v1 {
    void* context;
    void (*value)(void* context, size_t index, const char* json, size_t json_length);
    void (*error)(void* context, size_t index, int code, const char* detail);
} nclink_read_output_v1;

typedef struct nclink_text_output_v1 {
    void* context;
    void (*put)(void* context, const char* text, size_t length);
} nclink_text_output_v1;

typedef struct nclink_method_control_v1 {
    void* context;
    void (*progress)(void* context, double percent);
    int (*cancelled)(void* context);
    int (*checkpoint)(void* context);
} nclink_method_control_v1;

typedef struct nclink_driver_descriptor_v1 {
    uint32_t abi_version; /* 1 */
    const char* name;
    const char* version;
    uint32_t flags;
    void* (*create)(const char* config_json, const nclink_host_v1* host, const nclink_text_output_v1* error);
    void (*destroy)(void* instance);
    void (*read)(void* instance, const char* const* ids, const int* kinds, size_t count,
                 const nclink_read_output_v1* out);
    int (*write)(void* instance, const char* id, int kind, const char* params_json, const char* new_value_json,
                 const nclink_text_output_v1* detail);
    int (*call_method)(void* instance, const char* method_id, const char* args_json,
                       const nclink_method_control_v1* control, const nclink_text_output_v1* result);
    int (*claims)(void* instance, const char* id);
} nclink_driver_descriptor_v1;

#ifdef __cplusplus
}
#endif

#endif /* NCLINK_DRIVER_PLUGIN_V1_H */
