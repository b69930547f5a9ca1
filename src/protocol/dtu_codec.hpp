// Internal: the machinery every DTU decoder/encoder shares. Decoders throw
// DecodeFailure internally (it keeps each one a straight list of reads); the
// decode<T> entry points below catch everything, so nothing escapes.
#pragma once

#include <nclink/dtu.hpp>

#include <cstdint>
#include <initializer_list>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace nclink::protocol_detail {

struct DecodeFailure {
    Error error;
};

[[noreturn]] void fail(ErrorCode code, std::string message);

/// Reads the keys of one JSON object, knowing every key the DTU (or the entry)
/// defines, so that a missing required key can be told apart as 102 (plain
/// omission) or 413 (the object carries keys this DTU does not know).
class Reader {
public:
    /// `what` names the object in messages ("Query request", "ids entry").
    Reader(const Json& object, std::initializer_list<std::string_view> known, std::string_view what);

    const Json* find(std::string_view key) const;
    bool has(std::string_view key) const { return find(key) != nullptr; }
    const Json& require(std::string_view key) const;
    [[noreturn]] void missing(std::string_view key) const;
    [[noreturn]] void wrong_type(std::string_view key, std::string_view expected) const;

    std::string require_string(std::string_view key) const;
    std::optional<std::string> optional_string(std::string_view key) const;
    /// "" when absent.
    std::string string_or_empty(std::string_view key) const { return optional_string(key).value_or(std::string()); }
    double require_number(std::string_view key) const;
    std::optional<double> optional_number(std::string_view key) const;
    /// Integer given as a JSON integer, an integral float or a numeric string.
    std::optional<std::int64_t> optional_integer(std::string_view key) const;
    std::int64_t require_integer(std::string_view key) const;
    const Json& require_array(std::string_view key) const;
    std::optional<Json> optional_any(std::string_view key) const;

    MessageId message_id() const;  ///< "@id": any scalar
    std::optional<Json> private_info() const { return optional_any("privateInfo"); }
    ResponseStatus status() const;  ///< code (required), reason, error
    std::optional<ResponseStatus> optional_status() const;

    const Json& object() const { return object_; }
    std::string_view what() const { return what_; }

private:
    const Json& object_;
    std::vector<std::string_view> known_;
    std::string_view what_;
};

/// The object itself must be a JSON object (405 for a nested one, 412 for the payload).
const Json& expect_object(const Json& value, ErrorCode code, std::string_view what);

/// Probe given as an object or a string holding a JSON object.
Json probe_value(const Json& value, std::string_view what);

/// Refuses payloads nested deeper than max_payload_depth (ignores brackets in strings).
bool depth_ok(std::string_view payload) noexcept;

/// Parses a payload; 412 for empty/invalid JSON or deep nesting.
Json parse_payload(std::string_view payload);

// ---- writers: only keys that are set ----
void put_msg_id(Json& out, const MessageId& id);
void put_if(Json& out, const char* key, const std::string& value);  // non-empty
void put_if(Json& out, const char* key, const std::optional<Json>& value);
void put_if(Json& out, const char* key, const std::optional<std::string>& value);
void put_status(Json& out, const ResponseStatus& status);
/// Integral doubles as integers (20000, not 20000.0), others as doubles.
Json number_json(double value);

// ---- the entry points, instantiated per type in the file that defines its read() ----
template <class T>
struct Tag {};

template <class T>
Result<T> decode_json(const Json& dtu) {
    try {
        if (!dtu.is_object()) fail(ErrorCode::syntax_error, "DTU is not a JSON object");
        return read(dtu, Tag<T>{});
    } catch (const DecodeFailure& failure) {
        return failure.error;
    } catch (const std::exception& e) {
        return make_error(ErrorCode::syntax_error, e.what());
    } catch (...) {
        return make_error(ErrorCode::syntax_error, "unexpected failure while decoding");
    }
}

template <class T>
Result<T> decode_payload(std::string_view payload, bool empty_is_object) {
    try {
        if (empty_is_object && payload.find_first_not_of(" \t\r\n") == std::string_view::npos)
            return decode_json<T>(Json::object());
        return decode_json<T>(parse_payload(payload));
    } catch (const DecodeFailure& failure) {
        return failure.error;
    } catch (const std::exception& e) {
        return make_error(ErrorCode::syntax_error, e.what());
    } catch (...) {
        return make_error(ErrorCode::syntax_error, "unexpected failure while parsing");
    }
}

}  // namespace nclink::protocol_detail

/// Defines the decode<Type> specializations declared in dtu.hpp, for a type
/// whose read(const Json&, Tag<Type>) is visible. Use inside namespace nclink.
#define NCLINK_DEFINE_DECODE_JSON(Type)                 \
    template <>                                         \
    Result<Type> decode<Type>(const Json& dtu) {        \
        return protocol_detail::decode_json<Type>(dtu); \
    }
#define NCLINK_DEFINE_DECODE(Type, empty_is_object)                             \
    NCLINK_DEFINE_DECODE_JSON(Type)                                             \
    template <>                                                                 \
    Result<Type> decode<Type>(std::string_view payload) {                       \
        return protocol_detail::decode_payload<Type>(payload, empty_is_object); \
    }

/// As NCLINK_DEFINE_DECODE, for a request read from text by `fast(payload)`
/// first (a scan or stream that answers nullopt for anything it cannot prove
/// the tree reads the same); the tree decodes the rest and gives every
/// refusal its table-19 code and message.
#define NCLINK_DEFINE_DECODE_FAST(Type, fast)                         \
    NCLINK_DEFINE_DECODE_JSON(Type)                                   \
    template <>                                                       \
    Result<Type> decode<Type>(std::string_view payload) {             \
        if (auto read = fast(payload)) return std::move(*read);       \
        return protocol_detail::decode_payload<Type>(payload, false); \
    }
