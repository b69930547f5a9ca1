// Fuzz target for the C plugin helpers' JSON reader
// (include/nclink/driver_plugin_helpers.h): the functions a C driver or C
// firmware uses on the JSON text the host hands it (Set params, new values,
// method args). On any input they must stay inside the text (the smoke run
// is built with the sanitizers' bounds checks in the asan preset), never
// write past the buffer they are given, and agree with a full JSON parser
// wherever that parser accepts the text:
// - a string that parses reads back the same bytes (when it fits);
// - an integer, number or boolean that parses reads back the same value;
// - skip_value ends a valid value exactly where the text ends;
// - member() of an object with plain, distinct keys finds every key, at a
//   value that parses to the parser's member.
#include <nclink/driver_plugin_helpers.h>
#include <nclink/json.hpp>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <string>

namespace {

// Reads the string through a buffer of `capacity` with guard bytes after it.
void check_string(const char* text, const nclink::Json* parsed) {
    for (const std::size_t capacity : {std::size_t{1}, std::size_t{8}, std::size_t{4096}}) {
        std::string buffer(capacity + 16, '\x5a');
        std::size_t length = 12345;
        const int ok = nclink_json_read_string(text, buffer.data(), capacity, &length);
        for (std::size_t i = capacity; i < buffer.size(); ++i)
            if (buffer[i] != '\x5a') std::abort();  // wrote past capacity
        if (ok) {
            if (length >= capacity || buffer[length] != '\0') std::abort();
        }
        if (parsed != nullptr && parsed->is_string()) {
            const std::string& expected = parsed->get_ref<const std::string&>();
            if (expected.size() + 1 <= capacity) {
                if (!ok || std::string(buffer.data(), length) != expected) std::abort();
            } else if (ok) {
                std::abort();  // cannot have fit
            }
        }
    }
}

void check_scalars(const char* text, const nclink::Json* parsed) {
    int b = -1;
    const int is_bool = nclink_json_read_bool(text, &b);
    if (is_bool && b != 0 && b != 1) std::abort();
    double d = 0;
    const int is_number = nclink_json_read_double(text, &d);
    std::int64_t i = 0;
    const int is_int = nclink_json_read_int(text, &i);
    if (parsed == nullptr) return;
    if (parsed->is_boolean() && (!is_bool || b != (parsed->get<bool>() ? 1 : 0))) std::abort();
    if (parsed->is_number()) {
        if (!is_number) std::abort();
        const double expected = parsed->get<double>();
        if (!(d == expected || (std::isinf(d) && std::isinf(expected)))) std::abort();
    } else if (is_number && !parsed->is_number()) {
        std::abort();  // a valid non-number read as a number
    }
    if (parsed->is_number_integer() && !parsed->is_number_unsigned() && (!is_int || i != parsed->get<std::int64_t>()))
        std::abort();
    if (parsed->is_number_unsigned() && parsed->get<std::uint64_t>() <= static_cast<std::uint64_t>(INT64_MAX) &&
        (!is_int || i != parsed->get<std::int64_t>()))
        std::abort();
    if (is_int && parsed->is_number_float()) std::abort();
}

void check_skip(const char* text, const nclink::Json* parsed) {
    const char* end = nclink_json_skip_value(text);
    if (end != nullptr && (end < text || end > text + std::strlen(text))) std::abort();
    if (parsed != nullptr && (end == nullptr || *nclink_json_skip_space(end) != '\0')) std::abort();
}

bool plain(const std::string& key) {
    for (const char c : key)
        if (c == '\\' || c == '"' || static_cast<unsigned char>(c) < 0x20) return false;
    return true;
}

void check_members(const char* text, const nclink::Json* parsed) {
    // Probing keys that may or may not be there must stay in bounds.
    for (const char* key : {"", "a", "id", "value", "params", "\xe8\xbd\xb4"}) {
        const char* at = nclink_json_member(text, key);
        if (at != nullptr && (at < text || at > text + std::strlen(text))) std::abort();
    }
    if (parsed == nullptr || !parsed->is_object()) return;
    // The parser keeps the last of duplicate keys, the helper finds the
    // first: compare only when every key appears once in the text.
    for (const auto& [key, value] : parsed->items()) {
        if (!plain(key)) continue;
        const std::string quoted = "\"" + key + "\"";
        const char* first = std::strstr(text, quoted.c_str());
        if (first == nullptr || std::strstr(first + 1, quoted.c_str()) != nullptr) continue;
        const char* at = nclink_json_member(text, key.c_str());
        if (at == nullptr) std::abort();
        const char* end = nclink_json_skip_value(at);
        if (end == nullptr) std::abort();
        const nclink::Json member = nclink::Json::parse(at, end, nullptr, false);
        if (member.is_discarded() || member != value) std::abort();
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    // The helpers read NUL-terminated text, as the host passes it: cut at the
    // first NUL like a C caller would see it.
    const std::string text(reinterpret_cast<const char*>(data), strnlen(reinterpret_cast<const char*>(data), size));
    const char* c = text.c_str();
    const nclink::Json parsed = nclink::Json::parse(text, nullptr, false);
    const nclink::Json* valid = parsed.is_discarded() ? nullptr : &parsed;
    check_string(c, valid);
    check_scalars(c, valid);
    check_skip(c, valid);
    check_members(c, valid);
    // Everything again on every suffix start inside the first 64 bytes: the
    // helpers are also called on pointers into a larger text.
    for (std::size_t from = 1; from < text.size() && from < 64; ++from) {
        check_string(c + from, nullptr);
        check_scalars(c + from, nullptr);
        check_skip(c + from, nullptr);
        check_members(c + from, nullptr);
    }
    return 0;
}
