/* Helpers for C driver plugins (driver_plugin.h): header-only, no allocation,
 * C99, clean under -Wall -Wextra -Werror.
 *
 * Simple values need none of this: read() answers numbers, booleans and
 * strings through the typed functions of nclink_read_output. These helpers
 * are for what still crosses as JSON text: the value of a list or dict item
 * (nclink_read_output.json), a method's return value, and the params /
 * new_value / args a write or method receives.
 *
 * Writing: a nclink_json_writer over a buffer of the caller's. Each value
 * function adds the comma it needs; keys come before object members.
 *
 *     char buf[256];
 *     nclink_json_writer w;
 *     nclink_json_init(&w, buf, sizeof buf);
 *     nclink_json_begin_object(&w);
 *     nclink_json_key(&w, "tool");   nclink_json_int(&w, 7);
 *     nclink_json_key(&w, "name");   nclink_json_string(&w, "drill \"8mm\"");
 *     nclink_json_end_object(&w);
 *     if (nclink_json_ok(&w)) out->json(out->context, i, buf, w.length);
 *
 * A writer that ran out of room (or was unbalanced) is not ok: send nothing
 * from it (answer the point with an error instead).
 *
 * Reading: functions over one JSON text (NUL-terminated) that return 1 on
 * success and 0 when the text is not of that type; nclink_json_member finds
 * a key of an object (the Set params' "value", a method's args).
 *
 * Logging: nclink_logf(host, NCLINK_LOG_WARN, "spindle %d: %s", n, why).
 */
#ifndef NCLINK_DRIVER_PLUGIN_HELPERS_H
#define NCLINK_DRIVER_PLUGIN_HELPERS_H

#include <nclink/driver_plugin.h>

#include <errno.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifdef __cplusplus
extern "C" {
#endif

/* ---- logging ------------------------------------------------------------ */

/* printf-style log line through the host (truncated at 511 bytes). */
#if defined(__GNUC__)
__attribute__((format(printf, 3, 4)))
#endif
static inline void
nclink_logf(const nclink_host* host, int level, const char* format, ...) {
    char line[512];
    va_list args;
    if (host == NULL || host->log == NULL) return;
    va_start(args, format);
    vsnprintf(line, sizeof line, format, args);
    va_end(args);
    host->log(host->context, level, line);
}

/* Puts a NUL-terminated text into a text output (a reason, a result). */
static inline void nclink_put_text(const nclink_text_output* out, const char* text) {
    if (out != NULL && out->put != NULL && text != NULL) out->put(out->context, text, strlen(text));
}

/* ---- writing JSON --------------------------------------------------------- */

typedef struct nclink_json_writer {
    char* data;
    size_t capacity;
    size_t length; /* characters written, without the terminating NUL */
    int depth;     /* open arrays/objects */
    int overflow;  /* nonzero once something did not fit */
} nclink_json_writer;

static inline void nclink_json_init(nclink_json_writer* w, char* buffer, size_t capacity) {
    w->data = buffer;
    w->capacity = capacity;
    w->length = 0;
    w->depth = 0;
    w->overflow = capacity == 0;
    if (capacity > 0) buffer[0] = '\0';
}

/* Nonzero when the text is complete (balanced) and nothing was cut off. */
static inline int nclink_json_ok(const nclink_json_writer* w) { return !w->overflow && w->depth == 0 && w->length > 0; }

static inline void nclink_json_raw(nclink_json_writer* w, const char* text, size_t n) {
    if (w->overflow) return;
    if (w->length + n + 1 > w->capacity) {
        w->overflow = 1;
        return;
    }
    memcpy(w->data + w->length, text, n);
    w->length += n;
    w->data[w->length] = '\0';
}

/* The comma before a value or key, unless it opens a container or follows a key. */
static inline void nclink_json_separate(nclink_json_writer* w) {
    if (w->length == 0) return;
    {
        const char last = w->data[w->length - 1];
        if (last != '[' && last != '{' && last != ':') nclink_json_raw(w, ",", 1);
    }
}

static inline void nclink_json_begin_array(nclink_json_writer* w) {
    nclink_json_separate(w);
    nclink_json_raw(w, "[", 1);
    ++w->depth;
}
static inline void nclink_json_end_array(nclink_json_writer* w) {
    nclink_json_raw(w, "]", 1);
    --w->depth;
}
static inline void nclink_json_begin_object(nclink_json_writer* w) {
    nclink_json_separate(w);
    nclink_json_raw(w, "{", 1);
    ++w->depth;
}
static inline void nclink_json_end_object(nclink_json_writer* w) {
    nclink_json_raw(w, "}", 1);
    --w->depth;
}

/* A string value (UTF-8), escaped as JSON requires: quote, backslash and
 * the control characters below 0x20. */
static inline void nclink_json_string_n(nclink_json_writer* w, const char* text, size_t n) {
    static const char hex[] = "0123456789abcdef";
    size_t i;
    nclink_json_separate(w);
    nclink_json_raw(w, "\"", 1);
    for (i = 0; i < n; ++i) {
        const unsigned char c = (unsigned char)text[i];
        switch (c) {
            case '"': nclink_json_raw(w, "\\\"", 2); break;
            case '\\': nclink_json_raw(w, "\\\\", 2); break;
            case '\n': nclink_json_raw(w, "\\n", 2); break;
            case '\r': nclink_json_raw(w, "\\r", 2); break;
            case '\t': nclink_json_raw(w, "\\t", 2); break;
            case '\b': nclink_json_raw(w, "\\b", 2); break;
            case '\f': nclink_json_raw(w, "\\f", 2); break;
            default:
                if (c < 0x20) {
                    char u[6] = {'\\', 'u', '0', '0', hex[c >> 4], hex[c & 15]};
                    nclink_json_raw(w, u, 6);
                } else {
                    nclink_json_raw(w, (const char*)&text[i], 1);
                }
        }
    }
    nclink_json_raw(w, "\"", 1);
}
static inline void nclink_json_string(nclink_json_writer* w, const char* text) {
    nclink_json_string_n(w, text ? text : "", text ? strlen(text) : 0);
}
/* An object member's key; the member's value comes next. */
static inline void nclink_json_key(nclink_json_writer* w, const char* key) {
    nclink_json_string(w, key);
    nclink_json_raw(w, ":", 1);
}
static inline void nclink_json_int(nclink_json_writer* w, int64_t value) {
    char text[24];
    const int n = snprintf(text, sizeof text, "%lld", (long long)value);
    nclink_json_separate(w);
    nclink_json_raw(w, text, (size_t)n);
}
static inline void nclink_json_uint(nclink_json_writer* w, uint64_t value) {
    char text[24];
    const int n = snprintf(text, sizeof text, "%llu", (unsigned long long)value);
    nclink_json_separate(w);
    nclink_json_raw(w, text, (size_t)n);
}
/* A number; NaN and infinities are not JSON and are written as null. */
static inline void nclink_json_double(nclink_json_writer* w, double value) {
    char text[32];
    int n;
    nclink_json_separate(w);
    if (value != value || value > 1.7976931348623157e308 || value < -1.7976931348623157e308) {
        nclink_json_raw(w, "null", 4);
        return;
    }
    /* The shortest of 15 or 17 digits that reads back the same number. */
    n = snprintf(text, sizeof text, "%.15g", value);
    if (strtod(text, NULL) != value) n = snprintf(text, sizeof text, "%.17g", value);
    /* "%g" prints in the C locale's decimal point only under "C": a comma
     * from another locale would not be JSON. */
    {
        int i;
        for (i = 0; i < n; ++i)
            if (text[i] == ',') text[i] = '.';
    }
    nclink_json_raw(w, text, (size_t)n);
}
static inline void nclink_json_bool(nclink_json_writer* w, int value) {
    nclink_json_separate(w);
    if (value) nclink_json_raw(w, "true", 4);
    else nclink_json_raw(w, "false", 5);
}
static inline void nclink_json_null(nclink_json_writer* w) {
    nclink_json_separate(w);
    nclink_json_raw(w, "null", 4);
}

/* ---- reading JSON --------------------------------------------------------- */

static inline const char* nclink_json_skip_space(const char* p) {
    while (p != NULL && (*p == ' ' || *p == '\t' || *p == '\n' || *p == '\r')) ++p;
    return p;
}

/* The end of the JSON value starting at p (after its last character), or
 * NULL when it is not one. Strings and nesting are followed, not validated
 * in every detail. */
static inline const char* nclink_json_skip_value(const char* p) {
    int depth = 0;
    p = nclink_json_skip_space(p);
    if (p == NULL || *p == '\0') return NULL;
    do {
        p = nclink_json_skip_space(p);
        switch (*p) {
            case '\0': return NULL;
            case '"':
                for (++p; *p != '"'; ++p) {
                    if (*p == '\0') return NULL;
                    if (*p == '\\' && *++p == '\0') return NULL;
                }
                ++p;
                break;
            case '[':
            case '{':
                ++depth;
                ++p;
                break;
            case ']':
            case '}':
                if (depth == 0) return NULL;
                --depth;
                ++p;
                break;
            case ',':
            case ':':
                if (depth == 0) return NULL;
                ++p;
                break;
            default: {
                const char* start = p;
                while (*p != '\0' && *p != ',' && *p != ']' && *p != '}' && *p != ':' && *p != ' ' && *p != '\t' && *p != '\n' &&
                       *p != '\r' && *p != '"' && *p != '[' && *p != '{')
                    ++p;
                if (p == start) return NULL;
            }
        }
    } while (depth > 0);
    return p;
}

/* True when p ends a scalar: end of text, or what may follow a member. */
static inline int nclink_json_scalar_end(const char* p) {
    p = nclink_json_skip_space(p);
    return *p == '\0' || *p == ',' || *p == '}' || *p == ']';
}

/* Nonzero when json is true or false; *out gets 1 or 0. */
static inline int nclink_json_read_bool(const char* json, int* out) {
    const char* p = nclink_json_skip_space(json);
    if (p == NULL) return 0;
    if (strncmp(p, "true", 4) == 0 && nclink_json_scalar_end(p + 4)) {
        *out = 1;
        return 1;
    }
    if (strncmp(p, "false", 5) == 0 && nclink_json_scalar_end(p + 5)) {
        *out = 0;
        return 1;
    }
    return 0;
}

/* Nonzero when json is a number (integer or not); *out gets it. */
static inline int nclink_json_read_double(const char* json, double* out) {
    const char* p = nclink_json_skip_space(json);
    char* end = NULL;
    double value;
    if (p == NULL || !(*p == '-' || (*p >= '0' && *p <= '9'))) return 0;
    value = strtod(p, &end);
    if (end == p) return 0;
    if (!nclink_json_scalar_end(end)) return 0;
    *out = value;
    return 1;
}

/* Nonzero when json is an integer that fits int64_t; *out gets it. */
static inline int nclink_json_read_int(const char* json, int64_t* out) {
    const char* p = nclink_json_skip_space(json);
    char* end = NULL;
    long long value;
    if (p == NULL || !(*p == '-' || (*p >= '0' && *p <= '9'))) return 0;
    errno = 0;
    value = strtoll(p, &end, 10);
    if (end == p || errno == ERANGE || *end == '.' || *end == 'e' || *end == 'E') return 0;
    if (!nclink_json_scalar_end(end)) return 0;
    *out = (int64_t)value;
    return 1;
}

/* Nonzero when json is a string; its unescaped UTF-8 goes to out (always
 * NUL-terminated when capacity > 0) and *length (may be NULL) gets its
 * length. 0 also when it does not fit in capacity - 1 bytes. */
static inline int nclink_json_read_string(const char* json, char* out, size_t capacity, size_t* length) {
    const char* p = nclink_json_skip_space(json);
    size_t n = 0;
    if (p == NULL || *p != '"' || capacity == 0) return 0;
    for (++p; *p != '"'; ++p) {
        unsigned long code = 0;
        char bytes[4];
        size_t count = 1, k;
        if (*p == '\0') return 0;
        if (*p != '\\') {
            bytes[0] = *p;
        } else {
            ++p;
            switch (*p) {
                case '"': bytes[0] = '"'; break;
                case '\\': bytes[0] = '\\'; break;
                case '/': bytes[0] = '/'; break;
                case 'b': bytes[0] = '\b'; break;
                case 'f': bytes[0] = '\f'; break;
                case 'n': bytes[0] = '\n'; break;
                case 'r': bytes[0] = '\r'; break;
                case 't': bytes[0] = '\t'; break;
                case 'u': {
                    int d;
                    for (d = 1; d <= 4; ++d) {
                        const char h = p[d];
                        code <<= 4;
                        if (h >= '0' && h <= '9') code |= (unsigned long)(h - '0');
                        else if (h >= 'a' && h <= 'f') code |= (unsigned long)(h - 'a' + 10);
                        else if (h >= 'A' && h <= 'F') code |= (unsigned long)(h - 'A' + 10);
                        else return 0;
                    }
                    p += 4;
                    /* A surrogate pair makes one code point above U+FFFF. */
                    if (code >= 0xD800 && code <= 0xDBFF && p[1] == '\\' && p[2] == 'u') {
                        unsigned long low = 0;
                        for (d = 3; d <= 6; ++d) {
                            const char h = p[d];
                            low <<= 4;
                            if (h >= '0' && h <= '9') low |= (unsigned long)(h - '0');
                            else if (h >= 'a' && h <= 'f') low |= (unsigned long)(h - 'a' + 10);
                            else if (h >= 'A' && h <= 'F') low |= (unsigned long)(h - 'A' + 10);
                            else return 0;
                        }
                        if (low < 0xDC00 || low > 0xDFFF) return 0;
                        code = 0x10000 + ((code - 0xD800) << 10) + (low - 0xDC00);
                        p += 6;
                    }
                    if (code < 0x80) {
                        bytes[0] = (char)code;
                    } else if (code < 0x800) {
                        bytes[0] = (char)(0xC0 | (code >> 6));
                        bytes[1] = (char)(0x80 | (code & 0x3F));
                        count = 2;
                    } else if (code < 0x10000) {
                        bytes[0] = (char)(0xE0 | (code >> 12));
                        bytes[1] = (char)(0x80 | ((code >> 6) & 0x3F));
                        bytes[2] = (char)(0x80 | (code & 0x3F));
                        count = 3;
                    } else {
                        bytes[0] = (char)(0xF0 | (code >> 18));
                        bytes[1] = (char)(0x80 | ((code >> 12) & 0x3F));
                        bytes[2] = (char)(0x80 | ((code >> 6) & 0x3F));
                        bytes[3] = (char)(0x80 | (code & 0x3F));
                        count = 4;
                    }
                    break;
                }
                default: return 0;
            }
        }
        if (n + count + 1 > capacity) return 0;
        for (k = 0; k < count; ++k) out[n++] = bytes[k];
    }
    out[n] = '\0';
    if (length != NULL) *length = n;
    return 1;
}

/* The value of member `key` of the object `json` (a pointer into json, to
 * pass to the read functions above), or NULL when json is not an object or
 * has no such key. Keys with escapes are compared as written. */
static inline const char* nclink_json_member(const char* json, const char* key) {
    const char* p = nclink_json_skip_space(json);
    const size_t key_length = strlen(key);
    if (p == NULL || *p != '{') return NULL;
    p = nclink_json_skip_space(p + 1);
    if (*p == '}') return NULL;
    for (;;) {
        const char* name;
        const char* end;
        if (*p != '"') return NULL;
        name = p + 1;
        end = nclink_json_skip_value(p);
        if (end == NULL) return NULL;
        p = nclink_json_skip_space(end);
        if (*p != ':') return NULL;
        p = nclink_json_skip_space(p + 1);
        if ((size_t)(end - 1 - name) == key_length && strncmp(name, key, key_length) == 0) return p;
        end = nclink_json_skip_value(p);
        if (end == NULL) return NULL;
        p = nclink_json_skip_space(end);
        if (*p != ',') return NULL;
        p = nclink_json_skip_space(p + 1);
    }
}

#ifdef __cplusplus
}
#endif

#endif /* NCLINK_DRIVER_PLUGIN_HELPERS_H */
