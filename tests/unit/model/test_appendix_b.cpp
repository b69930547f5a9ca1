// The standard's own example (appendix B) runs, with its known defects reported.
#include "model_test_util.hpp"

#include <catch2/catch.hpp>

using namespace nclink;
using nclink::test::describe;
using nclink::test::has_problem;
using nclink::test::model_path;
using nclink::test::problems_at;

namespace {
constexpr auto C = Severity::conformance;
constexpr auto W = Severity::warning;
}  // namespace

TEST_CASE("appendix B loads as a runnable model and reports every known defect") {
    const LoadResult r = load_model_file(model_path("appendix-b.json"));
    INFO(describe(r));
    REQUIRE(r.ok());
    CHECK(r.count(Severity::fatal) == 0);
    // Every deviation of the field's files is a conformance problem (docs/wire.md "Model files in the wild");
    // appendix B has no type of its own, so no warnings.
    CHECK(r.count(C) == 17);
    CHECK(r.count(W) == 0);

    // Missing versions (taken as 1.0.0), "1.0" not x.x.x, missing guid.
    CHECK(has_problem(r, C, "/version"));
    CHECK(has_problem(r, C, "/devices/0/version"));
    CHECK(problems_at(r, C, "/devices/0/version")[0].message.find("\"1.0\"") != std::string::npos);
    CHECK(has_problem(r, C, "/devices/0/guid"));
    // dataType/LIST and settable on the controller's configs, dataType/DICT on its dataItems.
    CHECK(has_problem(r, C, "/devices/0/components/4/configs/2/dataType"));
    CHECK(has_problem(r, C, "/devices/0/components/4/configs/2/settable"));
    CHECK(has_problem(r, C, "/devices/0/components/4/configs/3/dataType"));
    CHECK(has_problem(r, C, "/devices/0/components/4/configs/3/settable"));
    CHECK(has_problem(r, C, "/devices/0/components/4/dataItems/0/dataType"));
    CHECK(has_problem(r, C, "/devices/0/components/4/dataItems/1/dataType"));
    // Misspelt standard types (case, abbreviation, appendix A's names for
    // table-12 types) are conformance problems with a hint.
    CHECK(has_problem(r, C, "/devices/0/configs/0/type"));               // TYPE
    CHECK(has_problem(r, C, "/devices/0/components/0/configs/0/type"));  // TYPE
    CHECK(has_problem(r, C, "/devices/0/components/3/configs/1/type"));  // NUMBER
    CHECK(has_problem(r, C, "/devices/0/components/3/configs/2/type"));  // TYPE
    CHECK(has_problem(r, C, "/devices/0/dataItems/3/type"));             // SPDL_OVERRIDE
    const auto lower = problems_at(r, C, "/devices/0/components/4/configs/1/type");
    REQUIRE(lower.size() == 1);
    CHECK(lower[0].message.find("did you mean MANUFACTURER?") != std::string::npos);
    CHECK(problems_at(r, C, "/devices/0/dataItems/3/type")[0].message.find("SPINDLE_OVERRIDE") != std::string::npos);
    CHECK(problems_at(r, C, "/devices/0/configs/0/type")[0].message.find("did you mean CATAGORY?") != std::string::npos);

    // The aliases are understood: the model is what chapter 6 would say.
    const Model& m = *r.model;
    CHECK(m.root().version == "1.0.0");
    REQUIRE(m.devices().size() == 1);
    CHECK(m.devices()[0].version == "1.0");  // kept as written (8.2.8: the model as provided)
    CHECK_FALSE(m.devices()[0].guid.has_value());
    CHECK(resolve_dev_uuid(m.devices()[0]) == "0103");
    const DataObject* tools = m.data_object("01031207");
    REQUIRE(tools != nullptr);
    CHECK(tools->kind == DataKind::list);
    CHECK(tools->setable);
    CHECK(tools->config);
    const DataObject* program = m.data_object("01031217");
    REQUIRE(program != nullptr);
    CHECK(program->kind == DataKind::dict);
    CHECK_FALSE(program->config);
    CHECK(m.data_object("01031102")->value == Json(5));
    CHECK(m.channels().size() == 2);
    CHECK(m.channel("sample_channel1")->ids.size() == 9);
    CHECK(m.find("0103080402")->path == "/MACHINE/AXIS@X/SCREW/POSITION");
}

TEST_CASE("the corrected appendix B and the simulated mill are clean") {
    for (const char* name : {"appendix-b-corrected.json", "sim-mill.json"}) {
        const LoadResult r = load_model_file(model_path(name));
        INFO(name << "\n" << describe(r));
        CHECK(r.ok());
        CHECK(r.problems.empty());
    }
}
