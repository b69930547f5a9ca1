/* nclink embedding API (C11). Firmware written in C hosts an NC-Link adapter
 * in its own process: it gives a configuration (JSON text or a file), a model
 * file and its driver as the C driver struct of driver_plugin.h, starts the
 * adapter, pushes sample rows from its real-time thread, says when a watched
 * value changed, and answers reads, writes and methods through the driver's
 * functions. docs/porting-guide.md, "From C firmware", walks through it;
 * examples/c-firmware/ is a complete program.
 *
 *     nclink_error err = NCLINK_ERROR_INIT;
 *     nclink_adapter_options opt = NCLINK_ADAPTER_OPTIONS_INIT;
 *     nclink_adapter* adapter = NULL;
 *     opt.config_path = "adapter.json";
 *     opt.driver = &my_driver;              // nclink_driver_descriptor
 *     if (nclink_adapter_create(&opt, &adapter, &err) != NCLINK_OK ||
 *         nclink_adapter_start(adapter, &err) != NCLINK_OK) { puts(err.message); ... }
 *     ...
 *     nclink_adapter_stop(adapter, 2000);
 *     nclink_adapter_destroy(adapter);
 *
 * Errors. Every fallible function returns NCLINK_OK (0) or a table-19 code
 * (GB/T 41970-2022; the NCLINK_E_* of driver_plugin.h and below) and, when
 * given an nclink_error, fills it with the code and a message. No C++
 * exception ever crosses this API: the library catches everything at the
 * boundary and returns a code (202 with the exception's text when nothing
 * better is known). Bad input is refused, never a crash: a NULL handle or
 * pointer (102), a struct whose struct_size is not one a version of this
 * header wrote (405), a configuration with unknown keys (413) or wrong types
 * (405), a model that does not validate (412).
 *
 * Growth (the same rules as driver_plugin.h; docs/abi.md). Every struct
 * passed by pointer starts with struct_size = sizeof as the caller was built
 * (the *_INIT macros set it). A later header only appends fields; the library
 * reads (and, for nclink_error, writes) a field only when struct_size covers
 * it, so a program built against an older header keeps working with a newer
 * library without a rebuild, and fields it does not know keep their
 * defaults. A struct_size smaller than the first version of the struct, or
 * larger than NCLINK_MAX_STRUCT_SIZE (an uninitialised struct), is refused
 * with 405. nclink_value is an array element and never changes: a new kind
 * of value is a new NCLINK_VALUE_* number. Functions are only added, never
 * changed; a change that cannot be an addition gets a new name.
 *
 * Threading. create/start/stop/destroy are called by the owner, not
 * concurrently with each other for one adapter, and never from a driver or
 * log callback. nclink_channel_push is wait-free and meant for the firmware's
 * real-time thread, one thread at a time per channel. Everything else is
 * thread-safe. The driver's functions are called as driver_plugin.h says
 * (never from an MQTT thread; call_method on a method thread of its own);
 * the log callback from any SDK thread, several at once, so it must be
 * thread-safe and must not call back into nclink.
 */
#ifndef NCLINK_NCLINK_H
#define NCLINK_NCLINK_H

#include <nclink/driver_plugin.h>

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#if defined(__GNUC__) || defined(__clang__)
#define NCLINK_C_API __attribute__((visibility("default")))
#else
#define NCLINK_C_API
#endif

/* More table-19 codes the embedding API returns (driver_plugin.h has the
 * frequent ones). */
#define NCLINK_E_SYNTAX 412       /* "syntax error": a model or configuration that does not validate */
#define NCLINK_E_UNKNOWN_KEYS 413 /* "keys of arguments error": a configuration key this nclink does not know */

/* Larger struct_size values are taken for uninitialised memory. */
#define NCLINK_MAX_STRUCT_SIZE 4096u

/* A code and a message. Pass one to any function taking it (or NULL). */
typedef struct nclink_error {
    uint32_t struct_size;
    int code;          /* NCLINK_OK or the code the function returned */
    char message[512]; /* UTF-8, NUL-terminated, cut at 511 bytes; "" on success */
} nclink_error;

#define NCLINK_ERROR_INIT              \
    {                                  \
        sizeof(nclink_error), 0, { 0 } \
    }

/* The text of a code: the table-19 reason ("Node not exists"), "OK" for 0,
 * "vendor error" below 0, "unknown error" otherwise. Static storage. */
NCLINK_C_API const char* nclink_error_message(int code);

typedef struct nclink_adapter nclink_adapter; /* opaque */
typedef struct nclink_channel nclink_channel; /* opaque: a push-mode sample channel */

/* nclink_adapter_create() options. Exactly one of config_json and
 * config_path; the configuration is an adapter.json (docs/configuration.md),
 * whose "driver" may give a "config" but no "plugin" (the driver is given
 * here). Relative paths in a file are taken relative to its directory, in
 * config_json relative to the working directory. */
typedef struct nclink_adapter_options {
    uint32_t struct_size;
    const char* config_json; /* the configuration as JSON text, or NULL */
    const char* config_path; /* or the path of a configuration file, or NULL */
    const char* model_path;  /* the model (probe) file; NULL = the configuration's "model" */
    /* Required: the driver (driver_plugin.h, abi_version 2). Copied; the
     * functions it points to must stay loaded until nclink_adapter_destroy()
     * returns. create() is called by nclink_adapter_create() with the
     * configuration's driver.config ("null" if none), destroy() by
     * nclink_adapter_destroy(). */
    const nclink_driver_descriptor* driver;
    /* Log lines of the adapter (NCLINK_LOG_* levels, no trailing newline).
     * NULL = nothing is logged. Called from any SDK thread. */
    void (*log)(void* context, int level, const char* message);
    void* log_context;
} nclink_adapter_options;

#define NCLINK_ADAPTER_OPTIONS_INIT \
    { sizeof(nclink_adapter_options), NULL, NULL, NULL, NULL, NULL, NULL }

/* Reads the configuration, creates the driver (its create()) and the adapter.
 * Nothing connects yet. On success *adapter is the new adapter; on failure it
 * is NULL and nothing needs freeing. */
NCLINK_C_API int nclink_adapter_create(const nclink_adapter_options* options, nclink_adapter** adapter, nclink_error* error);

/* Loads and validates the model (412 with every problem listed when it does
 * not validate), binds the driver, connects and starts serving. Returns once
 * serving has begun; an unreachable broker is retried in the background. */
NCLINK_C_API int nclink_adapter_start(nclink_adapter* adapter, nclink_error* error);

/* Publishes the offline state, flushes what is buffered (up to
 * flush_timeout_ms), disconnects. Idempotent. Push channels taken from the
 * adapter stay valid handles; their pushes are refused from now on. */
NCLINK_C_API int nclink_adapter_stop(nclink_adapter* adapter, uint32_t flush_timeout_ms);

/* Stops the adapter if it runs, destroys the driver instance, frees the
 * adapter. NULL is ignored. Channels must be released before or after (they
 * stay safe to push into and release). */
NCLINK_C_API void nclink_adapter_destroy(nclink_adapter* adapter);

/* Adapter states (GB/T 41970-2022 figure of the terminal's states;
 * docs/state-machines.md). */
#define NCLINK_STATE_INITIAL 0      /* before start, or the model is not loaded */
#define NCLINK_STATE_NORMAL 1       /* connected; every response so far went out */
#define NCLINK_STATE_REQUEST 2      /* connected; a response is kept to send again */
#define NCLINK_STATE_DISCONNECTED 3 /* the link to the broker is down */

/* The adapter's state now (NCLINK_STATE_*), -1 for a NULL adapter. */
NCLINK_C_API int nclink_adapter_state(const nclink_adapter* adapter);

/* One value of a sample row or of a notification. An array element: this
 * layout never changes (new kinds are new numbers). */
#define NCLINK_VALUE_NULL 0
#define NCLINK_VALUE_BOOL 1
#define NCLINK_VALUE_INT64 2
#define NCLINK_VALUE_UINT64 3
#define NCLINK_VALUE_FLOAT64 4 /* NaN and infinities are sent as null */
#define NCLINK_VALUE_TEXT 5    /* UTF-8 text (escaped by the SDK) */
#define NCLINK_VALUE_JSON 6    /* one JSON text, sent as is */

typedef struct nclink_value {
    uint32_t kind;   /* NCLINK_VALUE_* */
    uint32_t length; /* bytes of text/json */
    union {
        int boolean;
        int64_t int64;
        uint64_t uint64;
        double float64;
        const char* text; /* text/json: pushed rows borrow it until published, see nclink_channel_push */
    } as;
} nclink_value;

/* The push-mode handle of a model sample channel listed in the
 * configuration's "sampling": {"push_channels": [...]} (docs/sampling.md,
 * "Push mode"). Call after nclink_adapter_start(), outside the real-time
 * loop. Errors: 401 no such channel, 405 not a push-mode channel, 202 not
 * started or sampling disabled. Release it with nclink_channel_release().
 * The handle follows model changes (Probe/Set): the channel of the new model
 * with the same id is swapped in at the next push, without waiting (a row
 * pushed in the instant between is refused, 202). */
NCLINK_C_API int nclink_adapter_push_channel(nclink_adapter* adapter, const char* channel_id, nclink_channel** channel,
                                             nclink_error* error);

/* Columns per row of the channel (the channel's `ids`, in order); 0 for
 * NULL. Call it from the pushing thread (a model change may change it). */
NCLINK_C_API size_t nclink_channel_points(const nclink_channel* channel);

/* Appends one row: values[i] is the channel's i-th item; count must equal
 * nclink_channel_points(). time_ns is the row's time (wall clock, ns since
 * the Unix epoch), 0 = now (clock_gettime(CLOCK_REALTIME)).
 * Wait-free: never allocates, locks or sleeps; safe from a real-time thread,
 * one thread at a time per channel. Returns NCLINK_OK when the row was
 * queued, 202 when not (wrong count, an unknown kind, the channel gone or the
 * adapter stopped, a full ring under "full_policy": "block"), 102 for NULL.
 * Text and json values are borrowed until the row is published: point them
 * at storage that lives as long as the channel (string literals). */
NCLINK_C_API int nclink_channel_push(nclink_channel* channel, const nclink_value* values, size_t count, int64_t time_ns);

/* Frees the handle (not the channel). NULL is ignored. */
NCLINK_C_API void nclink_channel_release(nclink_channel* channel);

/* Item `id` has the whole value `value` now (the firmware's own change
 * notification): events watching it (docs/events.md) evaluate it at once
 * instead of at the next poll. Copies the value and queues it; never blocks
 * on the network or the driver, but allocates: not for the real-time loop.
 * Ignored before start and for items no event watches. 102 for NULL
 * arguments, 405 for an unknown kind. */
NCLINK_C_API int nclink_adapter_notify(nclink_adapter* adapter, const char* id, const nclink_value* value);

/* The same with the value as JSON text (a list or dict item's whole value);
 * 412 when it is not JSON. */
NCLINK_C_API int nclink_adapter_notify_json(nclink_adapter* adapter, const char* id, const char* value_json);

/* Methods (Method/Call, docs/methods.md) need nothing here: the driver's
 * call_method() runs each call on a method thread of its own, reports
 * progress through nclink_method_control.progress(), pauses in
 * checkpoint(), and returns its result as JSON text in `result` (or an error
 * code and `reason`): the SDK publishes Method/Status and Method/Result. */

#ifdef __cplusplus
}
#endif

#endif /* NCLINK_NCLINK_H */
