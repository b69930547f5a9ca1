// The validator names the standard type or unit a model most likely meant,
// and the starter models pass it without a single problem.
#include "model_test_util.hpp"

#include <nclink/starter_model.hpp>
#include <nclink/vocabulary.hpp>

#include <catch2/catch.hpp>

using namespace nclink;

namespace {

Json model_with(Json component_type, Json item_type, Json units) {
    return Json{
        {"id", "root"},
        {"name", "root"},
        {"type", "NC_LINK_ROOT"},
        {"version", "1.0.0"},
        {"devices",
         Json::array({Json{
             {"id", "dev"},
             {"name", "dev"},
             {"type", "MACHINE"},
             {"guid", "dev-1"},
             {"version", "1.0.0"},
             {"components",
              Json::array({Json{
                  {"id", "c1"},
                  {"name", "c1"},
                  {"type", component_type},
                  {"dataItems", Json::array({Json{{"id", "i1"}, {"name", "i1"}, {"type", item_type}, {"units", units}}})}}})}}})}};
}

std::string message_at(const LoadResult& r, const std::string& pointer) {
    for (const auto& p : r.problems)
        if (p.pointer == pointer) return p.message;
    return "";
}

bool warning_at(const LoadResult& r, const std::string& pointer) {
    for (const auto& p : r.problems)
        if (p.pointer == pointer) return p.severity == Severity::warning;
    return false;
}

}  // namespace

TEST_CASE("unknown types and units get the nearest standard name as a hint") {
    const auto r = parse_model(model_with("SPINDLE", "SPINDLE_SPED", "rpm").dump());
    REQUIRE(r.ok());
    const std::string c = "/devices/0/components/0";
    CHECK(message_at(r, c + "/type") == R"(component type "SPINDLE" is not in table 8 (did you mean AXIS with number "S"?))");
    CHECK(message_at(r, c + "/dataItems/0/type") ==
          R"(data type "SPINDLE_SPED" is not in tables 10, 12, 13 (did you mean SPINDLE_SPEED?))");
    CHECK(message_at(r, c + "/dataItems/0/units") ==
          R"(units "rpm" are not in tables 10/11 or appendix A (did you mean r/min?) (docs/vocabulary.md))");
    // Custom names stay warnings: the standard allows extensions.
    CHECK(warning_at(r, c + "/type"));
    CHECK(warning_at(r, c + "/dataItems/0/type"));
    CHECK(warning_at(r, c + "/dataItems/0/units"));

    const auto far = parse_model(model_with("GANTRY_LOADER", "WIDGET_COLOUR", "furlongs").dump());
    CHECK(message_at(far, c + "/type").find("did you mean") == std::string::npos);
    CHECK(message_at(far, c + "/dataItems/0/units").find("did you mean") == std::string::npos);
}

TEST_CASE("the vocabulary tables hold what the validator accepts") {
    CHECK(vocabulary_component_types().size() == 10);
    bool status = false;
    for (const auto& t : vocabulary_data_types())
        if (t.name == "STATUS") status = t.values.find("running, free, holding") != std::string_view::npos;
    CHECK(status);
    const std::string doc = vocabulary_markdown();
    CHECK(doc.find("| `SPINDLE_SPEED` | table 13 | spindle speed | number | `r/min` |") != std::string::npos);
}

TEST_CASE("starter models of every kind load without a problem") {
    for (auto kind : {MachineKind::lathe, MachineKind::machining_center, MachineKind::generic}) {
        StarterModelOptions o;
        o.kind = kind;
        auto made = make_starter_model(o);
        REQUIRE(made.ok());
        const auto r = parse_model(made->dump());
        INFO(test::describe(r));
        CHECK(r.ok());
        CHECK(r.problems.empty());
    }
    StarterModelOptions lathe;
    lathe.kind = MachineKind::lathe;
    lathe.spindles = 2;
    lathe.channels = 2;
    auto made = make_starter_model(lathe);
    REQUIRE(made.ok());
    const auto r = parse_model(made->dump());
    INFO(test::describe(r));
    CHECK(r.problems.empty());
    REQUIRE(r.model->find("spindle2_speed") != nullptr);
    REQUIRE(r.model->find("status_2") != nullptr);

    StarterModelOptions bad;
    bad.axes = {"X", "Q"};
    CHECK(make_starter_model(bad).error().message.find("not a table 9 number") != std::string::npos);
    CHECK_FALSE(machine_kind_from_string("robot").ok());
}
