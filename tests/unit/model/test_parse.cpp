// Parsing details: encodings, aliases, normalization, robustness.
#include "model_test_util.hpp"

#include "model/encoding.hpp"

#include <catch2/catch.hpp>

using namespace nclink;
using nclink::test::describe;
using nclink::test::has_problem;
using nclink::test::model_path;

namespace {

// A clean one-device model with `item` as the device's only data item.
std::string with_item(const std::string& item) {
    return R"({"id":"r","type":"NC_LINK_ROOT","version":"1.0.0","devices":[{"id":"d",
      "type":"MACHINE","guid":"g","version":"1.0.0","dataItems":[)" +
           item + "]}]}";
}

}  // namespace

TEST_CASE("a GBK file loads with correct Chinese names and one conformance problem") {
    const LoadResult r = load_model_file(model_path("gbk-encoded.json"));
    INFO(describe(r));
    REQUIRE(r.ok());
    REQUIRE(r.problems.size() == 1);
    CHECK(r.problems[0].severity == Severity::conformance);
    CHECK(r.problems[0].pointer.empty());
    CHECK(r.problems[0].message.find("GBK") != std::string::npos);
    CHECK(r.model->root().name == "华中数控模型");
    CHECK(r.model->devices()[0].name == "数控铣床");
    CHECK(r.model->data_object("x_pos")->name == "实际位置");
    CHECK(*r.model->data_object("maker")->value == "武汉华中数控");
    // Serialized back as UTF-8.
    const std::string text = serialize_model(*r.model);
    CHECK(model_detail::is_valid_utf8(text));
    CHECK(text.find("实际位置") != std::string::npos);
}

TEST_CASE("UTF-8 validation rejects malformed sequences") {
    using model_detail::is_valid_utf8;
    CHECK(is_valid_utf8("plain"));
    CHECK(is_valid_utf8("数控 µm °C"));
    CHECK_FALSE(is_valid_utf8("\xff"));
    CHECK_FALSE(is_valid_utf8("\xc0\xaf"));          // overlong '/'
    CHECK_FALSE(is_valid_utf8("\xed\xa0\x80"));      // surrogate
    CHECK_FALSE(is_valid_utf8("\xe6\x95"));          // truncated
    CHECK_FALSE(is_valid_utf8("\xf4\x90\x80\x80"));  // above U+10FFFF
    CHECK(model_detail::gbk_to_utf8("\xca\xfd\xbf\xd8") == std::string("数控"));
    CHECK_FALSE(model_detail::gbk_to_utf8("\xff\xff").has_value());
}

TEST_CASE("aliases are normalized to chapter-6 values") {
    const LoadResult r = parse_model(with_item(
        R"({"id":"a","type":"VARIABLE","dataType":"LIST","settable":"true"},
           {"id":"b","type":"PARAMETER","datatype":"dict","setable":"false"},
           {"id":"c","type":"VARIABLE","datatype":"Dict","settable":false})"));
    INFO(describe(r));
    REQUIRE(r.ok());
    const Model& m = *r.model;
    CHECK(m.data_object("a")->kind == DataKind::list);
    CHECK(m.data_object("a")->setable);
    CHECK(m.data_object("b")->kind == DataKind::dict);
    CHECK_FALSE(m.data_object("b")->setable);
    CHECK(m.data_object("c")->kind == DataKind::dict);
    CHECK_FALSE(m.data_object("c")->setable);
    CHECK(r.count(Severity::conformance) == 5);
    CHECK(r.count(Severity::warning) == 0);
    // The alias key and the string value are reported in one problem.
    CHECK(nclink::test::problems_at(r, Severity::conformance, "/devices/0/dataItems/0/settable").size() == 1);
}

TEST_CASE("versions are kept as written and checked against 1.x.x") {
    auto device_version = [](const std::string& v) {
        const std::string text = R"({"id":"r","type":"NC_LINK_ROOT","version":"1.2.3","devices":
          [{"id":"d","type":"MACHINE","guid":"g","version":)" +
                                 v + "}]}";
        return parse_model(text);
    };
    const auto ok = device_version(R"("1.10.0")");
    CHECK(ok.problems.empty());
    CHECK(ok.model->devices()[0].version == "1.10.0");
    // Table 2: the model file's version is of the form 1.x.x too.
    const auto major = device_version(R"("2.10.0")");
    CHECK(has_problem(major, Severity::conformance, "/devices/0/version"));
    CHECK(major.model->devices()[0].version == "2.10.0");
    const auto zero = device_version(R"("1.02.0")");
    CHECK(has_problem(zero, Severity::conformance, "/devices/0/version"));
    CHECK(ok.model->root().version == "1.2.3");
    const auto short_form = device_version(R"("1.3")");
    CHECK(short_form.model->devices()[0].version == "1.3");  // kept as written
    CHECK(has_problem(short_form, Severity::conformance, "/devices/0/version"));
    const auto numeric = device_version("1.3");
    CHECK(numeric.model->devices()[0].version == "1.3");
    CHECK(numeric.count(Severity::conformance) == 2);  // not a string, not x.x.x
    const auto missing = parse_model(R"({"id":"r","type":"NC_LINK_ROOT","devices":
          [{"id":"d","type":"MACHINE","guid":"g"}]})");
    REQUIRE(missing.ok());
    CHECK(missing.model->root().version == "1.0.0");
    CHECK(missing.model->devices()[0].version == "1.0.0");
    CHECK(missing.count(Severity::conformance) == 2);
}

TEST_CASE("fatal problems yield no model but every problem is still listed") {
    const LoadResult r = parse_model(R"({"id":"r","type":"NC_LINK_ROOT","version":"1.0.0",
      "devices":[{"id":"d","type":"MACHINE","guid":"g","version":"1.0.0",
        "configs":[{"id":"c","type":"SAMPLE_CHANNEL","sampleInterval":0,"uploadInterval":-1,
                    "ids":[{"id":"x"},{"id":"ghost"}]}],
        "dataItems":[{"id":"x","type":"POSITION"},{"id":"x","type":"SPEED"},
                     {"id":"y","type":"made_up"}]}]})");
    CHECK_FALSE(r.ok());
    INFO(describe(r));
    CHECK(r.count(Severity::fatal) == 4);  // two intervals, duplicate x, ghost
    CHECK(r.count(Severity::warning) == 1);
    CHECK(has_problem(r, Severity::fatal, "/devices/0/configs/0/sampleInterval"));
    CHECK(has_problem(r, Severity::fatal, "/devices/0/configs/0/uploadInterval"));
    CHECK(has_problem(r, Severity::fatal, "/devices/0/dataItems/1/id"));
    CHECK(has_problem(r, Severity::fatal, "/devices/0/configs/0/ids/1"));
}

TEST_CASE("missing value is not a problem (table 4 note a)") {
    const LoadResult r = parse_model(with_item(R"({"id":"a","type":"POSITION"})"));
    CHECK(r.problems.empty());
    CHECK_FALSE(r.model->data_object("a")->value.has_value());
    const LoadResult fixed = parse_model(with_item(R"({"id":"a","type":"VERSION","value":null})"));
    REQUIRE(fixed.model->data_object("a")->value.has_value());
    CHECK(fixed.model->data_object("a")->value->is_null());
}

TEST_CASE("pointers escape ~ and / in member names (RFC 6901)") {
    const LoadResult r = parse_model(with_item(R"({"id":"a","type":"POSITION","x/y~z":1})"));
    REQUIRE(r.problems.size() == 1);
    CHECK(r.problems[0].pointer == "/devices/0/dataItems/0/x~1y~0z");
    CHECK(r.problems[0].severity == Severity::warning);
    // Unknown attributes are kept and written back.
    CHECK(r.model->data_object("a")->extra.at("x/y~z") == 1);
    CHECK(serialize_model(*r.model).find("\"x/y~z\": 1") != std::string::npos);
}

TEST_CASE("hostile input never throws") {
    const char* inputs[] = {"",
                            " ",
                            "null",
                            "0",
                            "\"x\"",
                            "[]",
                            "{}",
                            "{\"devices\":5}",
                            "{\"id\":{},\"devices\":[[],{},null,{\"id\":1e400}]}",
                            "{\"id\":\"r\",\"devices\":[{\"id\":\"d\",\"configs\":[{\"type\":"
                            "\"SAMPLE_CHANNEL\",\"id\":\"c\",\"ids\":[null,1,{}],"
                            "\"sampleInterval\":true,\"uploadInterval\":null}]}]}",
                            "\xef\xbb\xbf{}",
                            "\x80\x81\x82"};
    for (const char* input : inputs) {
        INFO(input);
        LoadResult r;
        CHECK_NOTHROW(r = parse_model(input));
        CHECK_FALSE(r.problems.empty());
    }
    const std::string deep = std::string(100000, '[') + std::string(100000, ']');
    LoadResult r;
    CHECK_NOTHROW(r = parse_model(deep));
    CHECK(r.count(Severity::fatal) == 1);
    CHECK(load_model_file("/nonexistent/model.json").count(Severity::fatal) == 1);
}

TEST_CASE("dict value must be an object, components may carry appendix-A guid") {
    const LoadResult r = parse_model(with_item(
        R"({"id":"p","type":"PARAMETER","datatype":"dict","value":[1]},
           {"id":"q","type":"PARAMETER","datatype":"dict","value":{"P1":1}})"));
    REQUIRE(r.problems.size() == 1);
    CHECK(r.problems[0].pointer == "/devices/0/dataItems/0/value");
    CHECK(r.problems[0].severity == Severity::conformance);

    const LoadResult c = parse_model(R"({"id":"r","type":"NC_LINK_ROOT","version":"1.0.0",
      "devices":[{"id":"d","type":"MACHINE","guid":"g","version":"1.0.0",
        "components":[{"id":"a","type":"AXIS","guid":"axis-guid"}]}]})");
    INFO(describe(c));
    CHECK(c.problems.empty());
    CHECK(c.model->component("a")->extra.at("guid") == "axis-guid");
}
