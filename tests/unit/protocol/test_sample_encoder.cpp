// The fast Sample DTU encoder against nlohmann: same JSON value on random data.
#include <nclink/dtu.hpp>
#include <nclink/sample_encoder.hpp>

#include <catch2/catch.hpp>

#include <charconv>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>

using namespace nclink;

namespace {

/// What nlohmann builds for one value (the reference).
Json reference(const SampleValue& v) {
    switch (v.kind()) {
        case SampleValue::Kind::null: return nullptr;
        case SampleValue::Kind::boolean: return v.as_bool();
        case SampleValue::Kind::int64: return v.as_int64();
        case SampleValue::Kind::uint64: return v.as_uint64();
        case SampleValue::Kind::float64: return v.as_double();  // NaN/Inf: nlohmann dumps null too
        case SampleValue::Kind::text: return std::string(v.as_text());
        case SampleValue::Kind::json: return Json::parse(v.as_text());
    }
    return nullptr;
}

/// Exact equality: same number class where it matters, doubles bit for bit.
bool same(const Json& ours, const Json& ref);

/// The first difference, for failure messages.
std::string first_difference(const Json& ours, const Json& ref, const std::string& path = "") {
    if (ref.is_structured() && ours.is_structured() && ref.type() == ours.type() && ref.size() == ours.size()) {
        if (ref.is_array()) {
            for (std::size_t i = 0; i < ref.size(); ++i)
                if (!same(ours[i], ref[i])) return first_difference(ours[i], ref[i], path + "/" + std::to_string(i));
        } else {
            for (auto it = ref.begin(); it != ref.end(); ++it)
                if (!ours.contains(it.key()) || !same(ours[it.key()], it.value()))
                    return first_difference(ours.value(it.key(), Json()), it.value(), path + "/" + it.key());
        }
    }
    return path + ": ours " + ours.dump() + " (" + ours.type_name() + "), reference " + ref.dump() + " (" + ref.type_name() + ")";
}

bool same(const Json& ours, const Json& ref) {
    if (ref.is_number_float()) {
        const double r = ref.get<double>();
        if (!std::isfinite(r)) return ours.is_null();
        if (!ours.is_number()) return false;
        const double o = ours.get<double>();
        // Integral doubles may print as integers ("414", or to_chars's fixed form when shorter).
        if (ours.is_number_integer()) return o == r && !(r == 0 && std::signbit(r));
        return std::memcmp(&o, &r, sizeof o) == 0;
    }
    if (ref.is_array()) {
        if (!ours.is_array() || ours.size() != ref.size()) return false;
        for (std::size_t i = 0; i < ref.size(); ++i)
            if (!same(ours[i], ref[i])) return false;
        return true;
    }
    if (ref.is_object()) {
        if (!ours.is_object() || ours.size() != ref.size()) return false;
        for (auto it = ref.begin(); it != ref.end(); ++it)
            if (!ours.contains(it.key()) || !same(ours[it.key()], it.value())) return false;
        return true;
    }
    return ours == ref;
}

Json reference_dtu(const SampleDtuHeader& h, const SampleBlock& block) {
    Json dtu = {{"guid", std::string(h.guid)}, {"id", std::string(h.channel_id)}, {"beginTime", std::to_string(h.begin_time_ms)}};
    if (h.msg_id) dtu["@id"] = *h.msg_id;
    if (h.private_info) dtu["privateInfo"] = *h.private_info;
    Json data = Json::array();
    for (std::size_t p = 0; p < block.points; ++p) {
        Json column = Json::array();
        for (std::size_t r = 0; r < block.rows; ++r) column.push_back(reference(block.values[p * block.rows + r]));
        data.push_back({{"data", column}});
    }
    dtu["data"] = data;
    return dtu;
}

const double kEdgeDoubles[] = {0.0,
                               -0.0,
                               1e-310,
                               -1e-310,
                               1.7976931348623157e308,
                               -1.7976931348623157e308,
                               5e-324,
                               2.2250738585072014e-308,
                               0.1,
                               1.0 / 3.0,
                               414.262,
                               1e15,
                               1e16,
                               1e21,
                               9007199254740993.0,
                               -123456789.125,
                               100.23,
                               std::numeric_limits<double>::quiet_NaN(),
                               std::numeric_limits<double>::infinity(),
                               -std::numeric_limits<double>::infinity()};
const std::int64_t kEdgeInts[] = {0,
                                  -1,
                                  1,
                                  9007199254740993LL,
                                  -9007199254740993LL,
                                  std::numeric_limits<std::int64_t>::max(),
                                  std::numeric_limits<std::int64_t>::min()};
const char* const kTexts[] = {"",
                              "RUN",
                              "quote\" backslash\\ slash/",
                              "tab\t nl\n cr\r bs\b ff\f",
                              "\x01\x1f\x7f",
                              "\xE4\xB8\xAD\xE6\x96\x87 UTF-8",
                              "\xF0\x9F\x98\x80 emoji",
                              std::string_view("nul\0inside", 10).data()};
const char* const kJsonTexts[] = {R"({"code":12,"text":"overheat"})", "[1,2,3]", "\"s\"", "null", "-0.5"};

}  // namespace

TEST_CASE("sample encoder: the chapter 8.2.15 example") {
    const SampleValue v[] = {SampleValue::float64(414.262), SampleValue::float64(414.262), SampleValue::float64(414.262),
                             SampleValue::float64(414.262), SampleValue::float64(414.262), SampleValue::float64(414.262),
                             SampleValue::int64(0),         SampleValue::int64(0),         SampleValue::int64(0),
                             SampleValue::float64(0),       SampleValue::float64(0),       SampleValue::float64(0)};
    SampleEncoder encoder;
    SampleDtuHeader header;
    header.guid = "dev_uuid";
    header.channel_id = "cn1";
    header.begin_time_ms = 1535642875900;
    const auto text = encoder.encode(header, SampleBlock{v, 4, 3});
    CHECK(text == R"({"guid":"dev_uuid","id":"cn1","beginTime":"1535642875900","data":[)"
                  R"({"data":[414.262,414.262,414.262]},{"data":[414.262,414.262,414.262]},)"
                  R"({"data":[0,0,0]},{"data":[0,0,0]}]})");
    // And the generic decoder reads it.
    auto decoded = decode_sample(text);
    REQUIRE(decoded.ok());
    CHECK(decoded->data.size() == 4);
}

TEST_CASE("sample encoder: edge values print as nlohmann reads them back") {
    std::string out;
    for (double d : kEdgeDoubles) {
        out.clear();
        append_json_double(out, d);
        INFO(out);
        const Json parsed = Json::parse(out);
        CHECK(same(parsed, Json(d)));
    }
    out.clear();
    append_json_double(out, -0.0);
    CHECK(out == "-0.0");
    out.clear();
    append_json_double(out, std::nan(""));
    CHECK(out == "null");
    out.clear();
    append_json_string(out, "a\"b\\c\n\x01");
    CHECK(out == R"("a\"b\\c\n\u0001")");
    out.clear();
    append_json_string(out, "bad \xC0\xAF \xED\xA0\x80 \xF5 end\xE4");  // overlong, surrogate, >U+10FFFF, truncated
    CHECK(Json::parse(out) == "bad \xEF\xBF\xBD\xEF\xBF\xBD \xEF\xBF\xBD\xEF\xBF\xBD\xEF\xBF\xBD \xEF\xBF\xBD end\xEF\xBF\xBD");
    out.clear();
    append_sample_value(out, SampleValue::uint64(std::numeric_limits<std::uint64_t>::max()));
    CHECK(Json::parse(out) == std::numeric_limits<std::uint64_t>::max());
    out.clear();
    append_sample_value(out, SampleValue::json(""));
    CHECK(out == "null");
}

TEST_CASE("sample encoder: the fixed-point double path is exact and shortest") {
    std::mt19937_64 rng(20221012);
    const double scale[] = {1, 10, 100, 1e3, 1e4, 1e5, 1e6};
    std::string out;
    char reference[64];
    int checked = 0;
    for (int i = 0; i < 200000; ++i) {
        const auto n = static_cast<std::int64_t>(rng() % 9000000000000000ULL) * ((rng() & 1) ? 1 : -1);
        double d = static_cast<double>(n % 5000000000000LL) / scale[rng() % 7];
        switch (rng() % 4) {  // neighbours of short decimals, and the range edges
            case 0: d = std::nextafter(d, 1e300); break;
            case 1: d = std::nextafter(d, -1e300); break;
            case 2: d = (rng() & 1 ? 4294967296.0 : -4294967296.0) - static_cast<double>(rng() % 1000) / 1e3; break;
            default: break;
        }
        out.clear();
        append_json_double(out, d);
        const double back = Json::parse(out).get<double>();
        INFO(out);
        REQUIRE(std::memcmp(&back, &d, sizeof d) == 0);
        // Where std::to_chars prints fixed notation, we print the same text.
        const auto end = std::to_chars(reference, reference + sizeof reference, d).ptr;
        const std::string_view ref(reference, static_cast<std::size_t>(end - reference));
        if (ref.find('e') == std::string_view::npos && !(d == 0 && std::signbit(d))) {
            CHECK(out == ref);
            ++checked;
        }
    }
    CHECK(checked > 100000);
}

TEST_CASE("sample encoder: random DTUs equal nlohmann's build") {
    std::mt19937_64 rng(41970);
    SampleEncoder encoder(64);  // tiny start: exercises growth
    const Json msg_id = "mid-1";
    const Json private_info = {{"vendor", "x"}};
    for (int round = 0; round < 300; ++round) {
        const std::size_t points = rng() % 12;
        const std::size_t rows = rng() % 40;
        std::vector<SampleValue> values(points * rows);
        for (auto& v : values) {
            switch (rng() % 10) {
                case 0: v = SampleValue::null(); break;
                case 1: v = SampleValue::boolean(rng() & 1); break;
                case 2: v = SampleValue::int64(static_cast<std::int64_t>(rng())); break;
                case 3: v = SampleValue::int64(kEdgeInts[rng() % std::size(kEdgeInts)]); break;
                case 4: v = SampleValue::float64(kEdgeDoubles[rng() % std::size(kEdgeDoubles)]); break;
                case 5: {  // any bit pattern (NaNs, subnormals, huge, tiny)
                    const std::uint64_t bits = rng();
                    double d;
                    std::memcpy(&d, &bits, sizeof d);
                    v = SampleValue::float64(d);
                    break;
                }
                case 6: v = SampleValue::text(kTexts[rng() % std::size(kTexts)]); break;
                case 7: v = SampleValue::json(kJsonTexts[rng() % std::size(kJsonTexts)]); break;
                case 8: v = SampleValue::uint64(rng()); break;
                default: {
                    std::uniform_real_distribution<double> dist(-1e6, 1e6);
                    v = SampleValue::float64(std::round(dist(rng) * 1000) / 1000);
                }
            }
        }
        SampleDtuHeader header;
        header.guid = round % 7 == 0 ? std::string_view("dev \"quoted\"") : std::string_view("dev_uuid");
        header.channel_id = "cn1";
        header.begin_time_ms = static_cast<std::int64_t>(rng() % 4000000000000ULL);
        if (round % 5 == 0) header.msg_id = &msg_id;
        if (round % 9 == 0) header.private_info = &private_info;
        const SampleBlock block{values.data(), points, rows};
        const auto text = encoder.encode(header, block);
        INFO(text);
        const Json ours = Json::parse(text);
        const Json ref = reference_dtu(header, block);
        INFO(first_difference(ours, ref));
        CHECK(same(ours, ref));
        // Columns path gives the same bytes.
        std::vector<SampleColumn> columns;
        for (std::size_t p = 0; p < points; ++p) columns.push_back({values.data() + p * rows, rows});
        const std::string copy(text);
        CHECK(encoder.encode(header, columns.data(), columns.size()) == copy);
        // Row-major path (the uploader's, no transpose) gives the same bytes.
        std::vector<SampleValue> row_major(points * rows);
        for (std::size_t p = 0; p < points; ++p)
            for (std::size_t r = 0; r < rows; ++r) row_major[r * points + p] = values[p * rows + r];
        CHECK(encoder.encode(header, SampleRows{row_major.data(), points, rows}) == copy);
    }
}

TEST_CASE("sample encoder: ragged columns and empty blocks") {
    SampleEncoder encoder;
    SampleDtuHeader header;
    header.guid = "d";
    header.channel_id = "c";
    const SampleValue a[] = {SampleValue::int64(1), SampleValue::null()};
    const SampleValue b[] = {SampleValue::text("x")};
    const SampleColumn columns[] = {{a, 2}, {b, 1}, {nullptr, 0}};
    CHECK(Json::parse(encoder.encode(header, columns, 3)) ==
          Json::parse(R"({"guid":"d","id":"c","beginTime":"0","data":[{"data":[1,null]},{"data":["x"]},{"data":[]}]})"));
    CHECK(Json::parse(encoder.encode(header, SampleBlock{})) == Json::parse(R"({"guid":"d","id":"c","beginTime":"0","data":[]})"));
    CHECK(Json::parse(encoder.encode(header, SampleRows{})) == Json::parse(R"({"guid":"d","id":"c","beginTime":"0","data":[]})"));
    // Points but no rows: one empty column each.
    CHECK(Json::parse(encoder.encode(header, SampleRows{a, 2, 0})) ==
          Json::parse(R"({"guid":"d","id":"c","beginTime":"0","data":[{"data":[]},{"data":[]}]})"));
}

TEST_CASE("sample encoder: steady state does not grow the buffer") {
    std::vector<SampleValue> values(10 * 100, SampleValue::float64(123.456789));
    SampleEncoder encoder;
    SampleDtuHeader header;
    header.guid = "dev";
    header.channel_id = "cn";
    (void)encoder.encode(header, SampleBlock{values.data(), 10, 100});
    const auto capacity = encoder.capacity();
    for (int i = 0; i < 10; ++i) (void)encoder.encode(header, SampleBlock{values.data(), 10, 100});
    CHECK(encoder.capacity() == capacity);
}

TEST_CASE("sample value: all-zero bytes are a null, as the driver runner's memset relies on") {
    // DriverRunner::read_samples_direct clears a row with memset before the
    // driver writes it: a slot the driver skips must read as null.
    std::vector<SampleValue> row(8, SampleValue::float64(1.5));
    std::memset(static_cast<void*>(row.data()), 0, row.size() * sizeof(SampleValue));
    for (const auto& v : row) {
        CHECK(v.is_null());
        CHECK(v.kind() == SampleValue::Kind::null);
    }
    SampleEncoder encoder;
    SampleDtuHeader header;
    header.guid = "d";
    header.channel_id = "c";
    CHECK(Json::parse(encoder.encode(header, SampleRows{row.data(), 2, 4}))["data"][0]["data"] ==
          Json::parse("[null,null,null,null]"));
}
