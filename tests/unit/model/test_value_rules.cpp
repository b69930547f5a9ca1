// Chapter 7 value rules (value_rules.hpp): each table's rule accepts what the
// table allows and refuses the rest with the table-19 code of its fault.
#include <nclink/model.hpp>
#include <nclink/value_rules.hpp>

#include <catch2/catch.hpp>

#include <limits>
#include <string>

using namespace nclink;

namespace {

// A mill with axes X and Z and one item of each kind of rule.
const char* kModel = R"({"id":"r","type":"NC_LINK_ROOT","version":"1.0.0","devices":[
  {"id":"d","type":"MACHINE","guid":"g","version":"1.0.0",
   "dataItems":[
     {"id":"status","type":"STATUS"},
     {"id":"mode","type":"SPINDLE_MODE"},
     {"id":"warn","type":"WARNING"},
     {"id":"warns","type":"WARNING","datatype":"list"},
     {"id":"coord","type":"COORDINATE"},
     {"id":"kind","type":"CATAGORY"},
     {"id":"mass","type":"MASS"},
     {"id":"temp","type":"TEMPERATURE"},
     {"id":"tempk","type":"TEMPERATURE","units":"K"},
     {"id":"pf","type":"POWER_FACTOR"},
     {"id":"emg","type":"EMG"},
     {"id":"vars","type":"VARIABLE","datatype":"list"},
     {"id":"params","type":"PARAMETER","datatype":"dict"},
     {"id":"tool","type":"TOOL_PARAM"},
     {"id":"mine","type":"MY_OWN_TYPE"},
     {"id":"file","type":"FILE"},
     {"id":"files","type":"FILE","datatype":"list"},
     {"id":"prog","type":"PROGRAM","datatype":"file"},
     {"id":"part","type":"PART"}
   ],
   "components":[
     {"id":"ax","type":"AXIS","number":"X","dataItems":[
        {"id":"pos","type":"POSITION"},{"id":"axkind","type":"CATAGORY"}]},
     {"id":"az","type":"AXIS","number":"Z"}
   ]}]})";

const ValueRules& rules() {
    static const LoadResult loaded = parse_model(kModel);
    static const ValueRules compiled(*loaded.model);
    return compiled;
}

ValueFault check(const char* id, const char* json) {
    const ValueRule* rule = rules().find(id);
    REQUIRE(rule != nullptr);
    return rule->check(Json::parse(json));
}

}  // namespace

TEST_CASE("value rules: table 10 numbers and their physical ranges") {
    CHECK(check("pos", "12.5") == ValueFault::none);
    CHECK(check("pos", "-3") == ValueFault::none);
    CHECK(check("pos", R"("12.5")") == ValueFault::type);
    CHECK(check("mass", "-1") == ValueFault::range);
    CHECK(check("temp", "-273.15") == ValueFault::none);
    CHECK(check("temp", "-300") == ValueFault::range);
    CHECK(check("tempk", "-1") == ValueFault::range);  // units K: absolute zero is 0
    CHECK(check("pf", "1.5") == ValueFault::range);
    CHECK(check("pos", "null") == ValueFault::none);  // no value now is never wrong
}

TEST_CASE("value rules: table 15 and 16 enumerations") {
    CHECK(check("status", R"("running")") == ValueFault::none);
    CHECK(check("status", "2") == ValueFault::none);  // appendix A's integer form
    CHECK(check("status", R"("busy")") == ValueFault::enumeration);
    CHECK(check("status", "7") == ValueFault::enumeration);
    CHECK(check("mode", R"("spinning")") == ValueFault::enumeration);
    CHECK(check("kind", R"("milling")") == ValueFault::none);  // under a MACHINE
    CHECK(check("kind", R"("rotary")") == ValueFault::enumeration);
    CHECK(check("axkind", R"("rotary")") == ValueFault::none);  // under an AXIS
    CHECK(check("emg", "true") == ValueFault::none);
    CHECK(check("emg", "1") == ValueFault::type);
}

TEST_CASE("value rules: table 14 objects, their keys and the device's axes") {
    CHECK(check("warn", R"({"number":"E1","text":"overheat"})") == ValueFault::none);
    CHECK(check("warn", "{}") == ValueFault::none);  // no active warning
    CHECK(check("warn", R"({"number":"E1"})") == ValueFault::missing_key);
    CHECK(check("warn", R"({"number":1,"text":"x"})") == ValueFault::key_type);
    CHECK(check("warns", R"([{"number":"E1","text":"a"},{"number":"E2"}])") == ValueFault::missing_key);
    CHECK(check("warns", R"({"number":"E1","text":"a"})") == ValueFault::kind);
    CHECK(check("coord", R"({"name":"G54","x":1.5,"z":2})") == ValueFault::none);
    CHECK(check("coord", R"({"name":"G54","y":1.5})") == ValueFault::axis);  // no Y axis declared
    CHECK(check("coord", R"({"name":"G54","x":"1.5"})") == ValueFault::key_type);
    CHECK(check("tool", R"({"id":"T1","radius":"5"})") == ValueFault::none);  // appendix A: a string too
    CHECK(check("tool", R"({"radius":5})") == ValueFault::missing_key);
}

TEST_CASE("value rules: datatypes, extension types and the table-19 codes") {
    CHECK(check("vars", "[1, \"a\"]") == ValueFault::none);
    CHECK(check("vars", "3") == ValueFault::kind);
    CHECK(check("params", R"({"k":1})") == ValueFault::none);
    CHECK(check("params", "[1]") == ValueFault::kind);
    CHECK(check("mine", R"({"anything":true})") == ValueFault::none);  // a type of its own: not checked
    CHECK(error_code(ValueFault::type) == ErrorCode::value_type);
    CHECK(error_code(ValueFault::enumeration) == ErrorCode::out_of_range);
    CHECK(error_code(ValueFault::missing_key) == ErrorCode::key_error);
    auto verdict = rules().verify("mode", Json("spinning"));
    REQUIRE_FALSE(verdict);
    CHECK(verdict.error().code == ErrorCode::out_of_range);
    CHECK(verdict.error().message.find("table 15") != std::string::npos);
    CHECK(rules().verify("no-such-item", Json(1)));
}

TEST_CASE("value rules: sampled values are checked without parsing") {
    const ValueRule& pos = *rules().find("pos");
    CHECK(pos.check(SampleValue::float64(1.0)) == ValueFault::none);
    CHECK(pos.check(SampleValue::text("1.0")) == ValueFault::type);
    const ValueRule& status = *rules().find("status");
    CHECK(status.check(SampleValue::text("free")) == ValueFault::none);
    CHECK(status.check(SampleValue::text("idle")) == ValueFault::enumeration);
    const ValueRule& warn = *rules().find("warn");
    CHECK(warn.check(SampleValue::json(R"({"number":"E1"})")) == ValueFault::none);
    CHECK(warn.needs_parse(SampleValue::json(R"({"number":"E1"})")));
    CHECK(warn.check(SampleValue::json("[1]")) == ValueFault::type);
    CHECK_FALSE(pos.needs_parse(SampleValue::float64(1.0)));
}

TEST_CASE("a fixed value that breaks chapter 7 is a located conformance problem") {
    const LoadResult r = parse_model(R"({"id":"r","type":"NC_LINK_ROOT","version":"1.0.0","devices":[
      {"id":"d","type":"MACHINE","guid":"g","version":"1.0.0",
       "configs":[{"id":"m","type":"SPINDLE_MODE","value":"spinning"}]}]})");
    REQUIRE(r.ok());
    bool found = false;
    for (const auto& p : r.problems)
        if (p.pointer == "/devices/0/configs/0/value" && p.severity == Severity::conformance) found = true;
    CHECK(found);
}

TEST_CASE("value rules: the file type (6.2.1, appendix A's FILE is a DICT) is an object naming the file") {
    CHECK(check("file", R"({"name":"O1234.nc"})") == ValueFault::none);
    CHECK(check("file", R"({"name":"O1234.nc","path":"/nc/prog","size":"2048","time":1700000000,
                             "encoding":"base64","content":"TzEyMzQ="})") == ValueFault::none);
    CHECK(check("file", R"({"size":2048})") == ValueFault::missing_key);  // which file?
    CHECK(check("file", R"({"name":42})") == ValueFault::key_type);
    CHECK(check("file", R"({"name":"a","content":[1,2]})") == ValueFault::key_type);
    CHECK(check("file", R"("O1234.nc")") != ValueFault::none);  // a bare name is not the object
    CHECK(check("files", R"([{"name":"a"},{"name":"b","size":3}])") == ValueFault::none);
    CHECK(check("files", R"([{"name":"a"},{"path":"/x"}])") == ValueFault::missing_key);
    // `datatype: "file"` makes any type's value a file object.
    CHECK(check("prog", R"({"name":"O1.nc"})") == ValueFault::none);
    CHECK(check("prog", R"("O1.nc")") != ValueFault::none);
    // Files inside a table-14 object: PART's snap_shot and geometry_file.
    CHECK(check("part", R"({"id":"P1","snap_shot":{"name":"p1.png"}})") == ValueFault::none);
    CHECK(check("part", R"({"id":"P1","geometry_file":{"size":1}})") == ValueFault::key_type);  // not a file object
    auto verdict = rules().verify("file", Json::parse(R"({"size":1})"));
    REQUIRE_FALSE(verdict);
    CHECK(verdict.error().code == ErrorCode::key_error);
}

TEST_CASE("value rules: number bounds agree with check() on every double") {
    const double inf = std::numeric_limits<double>::infinity();
    const double probes[] = {0.0,
                             -0.0,
                             -1.0,
                             1.0,
                             1.5,
                             0.999,
                             -273.15,
                             -273.16,
                             -300.0,
                             12.5,
                             1e300,
                             -1e300,
                             inf,
                             -inf,
                             std::numeric_limits<double>::quiet_NaN(),
                             std::numeric_limits<double>::denorm_min(),
                             -std::numeric_limits<double>::denorm_min()};
    std::string bounded_ids;
    for (const char* id : {"pos", "mass", "temp", "tempk", "pf", "status", "mode", "warn", "warns", "vars", "params", "tool",
                           "mine", "file", "emg"}) {
        const ValueRule* rule = rules().find(id);
        REQUIRE(rule != nullptr);
        double lo = 0, hi = 0;
        if (!rule->number_bounds(lo, hi)) continue;
        bounded_ids += std::string(id) + " ";
        for (double v : probes) {
            INFO(id << " " << v);
            const ValueFault inline_verdict = v < lo || v > hi ? ValueFault::range : ValueFault::none;
            CHECK(inline_verdict == rule->check(SampleValue::float64(v)));
        }
    }
    // Only single numbers: not STATUS (strings or integers), lists, objects.
    CHECK(bounded_ids == "pos mass temp tempk pf ");
    double lo = 0, hi = 0;
    REQUIRE(rules().find("mass")->number_bounds(lo, hi));
    CHECK(lo == 0.0);
    CHECK(hi == inf);
    REQUIRE(rules().find("pf")->number_bounds(lo, hi));
    CHECK(hi == 1.0);
}
