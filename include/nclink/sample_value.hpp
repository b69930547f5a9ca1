// SampleValue: one sampled value as the Sample DTU encoder takes it.
//
// Numbers dominate the sample path, so a SampleValue is 16 bytes, trivially
// copyable and never allocates: it can sit in a lock-free ring as raw bytes.
// Strings (STATUS items) and small JSON values (WARNING objects) are still
// representable, but only *borrowed*: the value holds a pointer and a length to
// text owned elsewhere, which must stay alive until the DTU has been encoded.
// Whoever stores such values across threads (the ring) must therefore keep the
// text in storage it controls (an arena per upload period, interned strings).
#pragma once

#include <nclink/export.hpp>
#include <cstdint>
#include <cstring>
#include <string_view>
#include <type_traits>

namespace nclink {

class NCLINK_API SampleValue {
public:
    enum class Kind : std::uint8_t {
        null,  ///< a missed read: encoded as `null` in its slot
        boolean,
        int64,
        uint64,   ///< for counters beyond INT64_MAX
        float64,  ///< NaN and infinities are not JSON: encoded as `null`
        text,     ///< borrowed UTF-8 text, encoded as a JSON string (escaped)
        json,     ///< borrowed, already serialized JSON text, copied verbatim
    };

    /// A null (missed read).
    SampleValue() noexcept { payload_.i = 0; }

    static SampleValue null() noexcept { return {}; }
    static SampleValue boolean(bool value) noexcept {
        SampleValue v(Kind::boolean);
        v.payload_.b = value;
        return v;
    }
    static SampleValue int64(std::int64_t value) noexcept {
        SampleValue v(Kind::int64);
        v.payload_.i = value;
        return v;
    }
    static SampleValue uint64(std::uint64_t value) noexcept {
        SampleValue v(Kind::uint64);
        v.payload_.u = value;
        return v;
    }
    static SampleValue float64(double value) noexcept {
        SampleValue v(Kind::float64);
        v.payload_.d = value;
        return v;
    }
    /// Borrows `value` (must be valid UTF-8 to pass through unchanged; invalid
    /// bytes are replaced by U+FFFD when encoded). Texts longer than 4 GiB are
    /// truncated, which no sample can reach.
    static SampleValue text(std::string_view value) noexcept {
        SampleValue v(Kind::text);
        v.payload_.p = value.data();
        v.size_ = static_cast<std::uint32_t>(value.size());
        return v;
    }
    /// Borrows `serialized`, which the caller guarantees is one valid JSON text
    /// (e.g. Json::dump() of a WARNING object); an empty view encodes as null.
    static SampleValue json(std::string_view serialized) noexcept {
        SampleValue v(Kind::json);
        v.payload_.p = serialized.data();
        v.size_ = static_cast<std::uint32_t>(serialized.size());
        return v;
    }

    Kind kind() const noexcept { return kind_; }
    bool is_null() const noexcept { return kind_ == Kind::null; }
    bool as_bool() const noexcept { return payload_.b; }
    std::int64_t as_int64() const noexcept { return payload_.i; }
    std::uint64_t as_uint64() const noexcept { return payload_.u; }
    double as_double() const noexcept { return payload_.d; }
    /// The borrowed characters of a text or json value.
    std::string_view as_text() const noexcept { return {payload_.p, size_}; }

private:
    explicit SampleValue(Kind kind) noexcept : kind_(kind) { payload_.i = 0; }

    union Payload {
        bool b;
        std::int64_t i;
        std::uint64_t u;
        double d;
        const char* p;
    } payload_;
    std::uint32_t size_ = 0;
    Kind kind_ = Kind::null;
};

static_assert(std::is_trivially_copyable_v<SampleValue>, "SampleValue goes through lock-free rings as bytes");
static_assert(sizeof(SampleValue) == 16, "SampleValue should stay two words");

}  // namespace nclink
