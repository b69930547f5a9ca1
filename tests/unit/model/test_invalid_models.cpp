// models/invalid/: one defect per file; each must produce exactly that problem.
#include "model_test_util.hpp"

#include <catch2/catch.hpp>

#include <map>

using namespace nclink;
using nclink::test::describe;

namespace {

struct Expected {
    Severity severity;
    std::string pointer;
};

constexpr auto F = Severity::fatal;
constexpr auto C = Severity::conformance;
constexpr auto W = Severity::warning;

// file name -> its single expected problem.
const std::map<std::string, Expected> kExpected = {
    // fatal
    {"not-json", {F, ""}},
    {"not-object", {F, ""}},
    {"not-utf8-nor-gbk", {F, ""}},
    {"too-deep", {F, ""}},
    {"duplicate-id", {F, "/devices/0/components/0/dataItems/2/id"}},
    {"duplicate-id-across-kinds", {F, "/devices/0/components/0/id"}},
    {"channel-unknown-id", {F, "/devices/0/configs/0/ids/1"}},
    {"channel-names-component", {F, "/devices/0/configs/0/ids/1"}},
    {"nonpositive-interval", {F, "/devices/0/configs/0/sampleInterval"}},
    {"negative-interval", {F, "/devices/0/configs/0/uploadInterval"}},
    {"interval-not-number", {F, "/devices/0/configs/0/sampleInterval"}},
    {"missing-interval", {F, "/devices/0/configs/0/uploadInterval"}},
    {"no-devices", {F, "/devices"}},
    {"missing-devices", {F, "/devices"}},
    {"devices-not-array", {F, "/devices"}},
    {"missing-id", {F, "/devices/0/components/0/id"}},
    {"empty-id", {F, "/devices/0/dataItems/0/id"}},
    {"id-not-string", {F, "/devices/0/dataItems/0/id"}},
    {"missing-root-id", {F, "/id"}},
    // conformance
    {"datatype-alias", {C, "/devices/0/dataItems/1/dataType"}},
    {"datatype-uppercase", {C, "/devices/0/dataItems/1/datatype"}},
    {"datatype-unknown", {C, "/devices/0/dataItems/1/datatype"}},
    {"datatype-both-spellings", {C, "/devices/0/dataItems/1/dataType"}},
    {"datatype-not-string", {C, "/devices/0/dataItems/1/datatype"}},
    {"value-not-matching-datatype", {C, "/devices/0/configs/2/value"}},
    {"settable-alias", {C, "/devices/0/configs/2/settable"}},
    {"setable-string", {C, "/devices/0/configs/2/setable"}},
    {"setable-not-boolean", {C, "/devices/0/configs/2/setable"}},
    {"setable-both-spellings", {C, "/devices/0/configs/2/settable"}},
    {"missing-root-version", {C, "/version"}},
    {"missing-device-version", {C, "/devices/0/version"}},
    {"bad-version", {C, "/devices/0/version"}},
    {"version-major-not-1", {C, "/devices/0/version"}},                          // table 2: 1.x.x
    {"channel-id-too-long", {C, "/devices/0/configs/0/id"}},                     // tables 36/42: at most 16 bytes
    {"channel-in-component-configs", {C, "/devices/0/components/0/configs/0"}},  // table 3
    {"bad-source", {C, "/devices/0/components/0/dataItems/0/source"}},           // 6.2.5 note b
    {"bad-root-version", {C, "/version"}},
    {"version-not-numeric", {C, "/devices/0/version"}},
    {"empty-version", {C, "/devices/0/version"}},
    {"missing-guid", {C, "/devices/0/guid"}},
    {"empty-guid", {C, "/devices/0/guid"}},
    {"missing-type", {C, "/devices/0/components/0/dataItems/1/type"}},
    {"missing-device-type", {C, "/devices/0/type"}},
    {"missing-root-type", {C, "/type"}},
    {"root-type", {C, "/type"}},
    {"attribute-wrong-type", {C, "/devices/0/name"}},
    {"attribute-not-scalar", {C, "/devices/0/components/0/dataItems/0/units"}},
    {"id-number", {C, "/devices/0/dataItems/0/id"}},
    {"config-as-sample-source", {C, "/devices/0/configs/0/ids/2"}},
    {"method-outside-root", {C, "/devices/0/configs/2"}},
    {"method-in-data-items", {C, "/devices/0/components/0/dataItems/2"}},
    {"channel-in-root-configs", {C, "/configs/1"}},
    {"channel-in-data-items", {C, "/devices/0/components/0/dataItems/2"}},
    {"upload-less-than-sample", {F, "/devices/0/configs/0/uploadInterval"}},  // such a channel never runs
    {"fractional-interval", {C, "/devices/0/configs/0/sampleInterval"}},
    {"missing-ids", {C, "/devices/0/configs/0/ids"}},
    {"ids-not-array", {C, "/devices/0/configs/0/ids"}},
    {"ids-entry-string", {C, "/devices/0/configs/0/ids/1"}},
    {"ids-entry-without-id", {C, "/devices/0/configs/0/ids/2"}},
    {"method-missing-args", {C, "/configs/0/args"}},
    {"method-args-wrong-type", {C, "/configs/0/args"}},
    {"entry-not-object", {C, "/devices/0/dataItems/0"}},
    {"device-entry-not-object", {C, "/devices/1"}},
    {"component-entry-not-object", {C, "/devices/0/components/1"}},
    {"configs-not-array", {C, "/configs"}},
    {"components-not-array", {C, "/devices/0/components/0/components"}},
    // warning
    {"unknown-data-type", {W, "/devices/0/dataItems/1/type"}},  // an extension: allowed, reported
    {"abbreviated-type", {C, "/devices/0/dataItems/1/type"}},   // SPDL_OVERRIDE: a misspelt standard type
    {"lowercase-type", {C, "/devices/0/configs/1/type"}},
    {"unknown-device-type", {W, "/devices/0/type"}},
    {"unknown-component-type", {W, "/devices/0/components/0/type"}},
    {"unknown-attribute", {W, "/devices/0/components/0/dataItems/0/precision"}},
    {"unknown-units", {W, "/devices/0/components/0/dataItems/1/units"}},
};

}  // namespace

TEST_CASE("every file in models/invalid produces exactly its one expected problem") {
    const auto files = nclink::test::json_files(nclink::test::model_path("invalid"));
    REQUIRE(files.size() == kExpected.size());
    for (const auto& file : files) {
        const std::string name = file.stem().string();
        INFO("file: " << file.string());
        const auto expected = kExpected.find(name);
        REQUIRE(expected != kExpected.end());
        const LoadResult r = load_model_file(file.string());
        INFO("problems:\n" << describe(r));
        CHECK(r.problems.size() == 1);
        if (r.problems.size() != 1) continue;
        CHECK(r.problems[0].severity == expected->second.severity);
        CHECK(r.problems[0].pointer == expected->second.pointer);
        CHECK_FALSE(r.problems[0].message.empty());
        // fatal <=> no model
        CHECK(r.ok() == (expected->second.severity != Severity::fatal));
    }
}
