// Generic simulation: every data object of any model reads a plausible value.
#include "sim_test_util.hpp"

#include <nclink/sample_encoder.hpp>

#include <algorithm>
#include <cctype>
#include <set>

using namespace nclink;
using sim_test::Rig;

namespace {

std::string upper(std::string s) {
    for (char& c : s) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    return s;
}

bool digits(const Json& v) {
    if (!v.is_string()) return false;
    const auto& s = v.get_ref<const std::string&>();
    return !s.empty() && std::all_of(s.begin(), s.end(), [](unsigned char c) { return std::isdigit(c); });
}

bool one_of(const Json& v, std::set<std::string> words) { return v.is_string() && words.count(v.get<std::string>()) > 0; }

/// The value fits the object's type/datatype (tables 10-16).
void check_plausible(const Model& model, const std::string& id, const Json& v) {
    const DataObject* o = model.data_object(id);
    REQUIRE(o != nullptr);
    INFO(id << " (" << o->type << ") = " << v.dump());
    if (o->value) {
        CHECK(v == *o->value);
        return;
    }
    const std::string t = upper(o->type);
    if (o->kind == DataKind::list) {
        REQUIRE(v.is_array());
        if (t != "WARNING") CHECK(v.size() == 64);
        if (t == "TOOL")
            for (const auto& e : v) CHECK((e.is_object() && e.contains("radius") && e.contains("length") && e.contains("id")));
        if (t == "COORDINATE") {
            for (const auto& e : v) CHECK((e.is_object() && e["name"].is_string() && e["x"].is_number() && e["z"].is_number()));
            CHECK(v[0]["name"] == "G54");
            CHECK(v[5]["name"] == "G59");
        }
        return;
    }
    if (o->kind == DataKind::dict) {
        REQUIRE(v.is_object());
        if (t != "WARNING") CHECK(v.size() == 64);
        if (t == "PARAMETER")
            for (const auto& [k, e] : v.items()) CHECK(e.is_number());
        if (t == "PROGRAM" || t == "SUBPROGRAM")
            for (const auto& [k, e] : v.items()) CHECK(e.is_string());
        return;
    }
    if (t == "POSITION") {
        REQUIRE(v.is_number());
        CHECK(std::abs(v.get<double>()) <= 500.0);
    } else if (t == "SPEED" || t == "CURRENT" || t == "AXIS_LOAD" || t == "FEED_SPEED" || t == "TOOL_NUMBER") {
        CHECK(v.is_number());
    } else if (t == "SPINDLE_SPEED") {
        REQUIRE(v.is_number());
        CHECK((v.get<double>() >= 0 && v.get<double>() <= 12000));
    } else if (t == "FEED_OVERRIDE" || t == "SPINDLE_OVERRIDE" || t == "SPDL_OVERRIDE") {
        REQUIRE(v.is_number());
        CHECK((v.get<double>() >= 0 && v.get<double>() <= 150));
    } else if (t == "EMG" || t == "DOOR_CLOSED") {
        CHECK(v.is_boolean());
    } else if (t == "STATUS") {
        CHECK(one_of(v, {"running", "free", "holding"}));
    } else if (t == "WORK_MODE") {
        CHECK(one_of(v, {"manual", "auto"}));
    } else if (t == "SPINDLE_MODE") {
        CHECK(one_of(v, {"forward", "stop", "reverse"}));
    } else if (t == "TYPE") {  // appendix B's name for CATAGORY, on a MACHINE
        CHECK(one_of(v, {"lathe", "milling", "grinder", "planer", "other"}));
    } else if (t == "PART_COUNT" || t == "LINE_NUMBER") {
        CHECK(digits(v));
    } else if (t == "PROGRAM" || t == "MODEL" || t == "MANUFACTURER") {
        CHECK((v.is_string() && !v.get<std::string>().empty()));
    } else if (t == "WARNING") {
        REQUIRE(v.is_object());
        if (!v.empty()) {
            CHECK(v["number"].is_string());
            CHECK(v["text"].is_string());
            CHECK(v["emerge_time"].is_number());
        }
    } else {
        FAIL("no expectation for type " << o->type);
    }
}

void check_model(const std::string& file) {
    Rig rig(file);
    const auto model = sim_test::load(file);
    const auto ids = rig.driver->item_ids();
    // Every data object of the device (dataItems and configs) is simulated.
    std::size_t expected = 0;
    for (const auto& o : model->data_objects()) expected += o.device_id == model->devices()[0].id ? 1 : 0;
    CHECK(ids.size() == expected);
    for (std::int64_t step : {0, 1500, 37'000, 600'000}) {
        rig.advance_ms(step);
        const Json all = rig.all();
        for (const auto& [id, v] : all.items()) check_plausible(*model, id, v);
    }
}

}  // namespace

TEST_CASE("every data object of sim-mill.json reads a plausible value") { check_model("sim-mill.json"); }

TEST_CASE("every data object of appendix-b.json reads a plausible value") { check_model("appendix-b.json"); }

TEST_CASE("a deviating model is simulated generically") {
    Rig rig("appendix-b.json");
    CHECK_FALSE(rig.driver->is_mill());
    CHECK(rig.driver->info().name == "nclink-sim");
    CHECK_FALSE(rig.driver->info().concurrent);
    CHECK_FALSE(rig.driver->claims("010302"));    // a data item: the driver's anyway
    CHECK(rig.driver->claims("01031207"));        // config tool table without a value: simulated
    CHECK_FALSE(rig.driver->claims("01030803"));  // config with a fixed value: the SDK's
    CHECK(rig.driver->link().state == MachineLink::connected);
    // dataType: DICT program names, TYPE, manufacturer, SPDL_OVERRIDE.
    CHECK(rig.value("01031217").is_object());
    CHECK(rig.value("01031218").is_object());
    CHECK(rig.value("010301").is_string());
    CHECK(rig.value("01031202").is_string());
    CHECK(rig.value("010306").is_number());
    // The C axis is rotary: its type item has a fixed value, its position is in degrees.
    CHECK(rig.value("01031103") == "rotary");
    for (int i = 0; i < 20; ++i) {
        rig.advance_ms(7'000);
        const double c = rig.value("0103110402").get<double>();
        CHECK((c >= 0 && c <= 360));
    }
}

TEST_CASE("generic values change as the clock advances") {
    Rig rig("appendix-b.json");
    const Json before = rig.all();
    rig.advance_ms(60'000);
    const Json after = rig.all();
    for (const char* id : {"0103080402", "0103090402", "0103100402", "0103080404", "010303"}) {
        INFO(id);
        CHECK(before[id] != after[id]);
    }
    // Small steps give small changes: the drift is smooth.
    const double x0 = rig.value("0103080402").get<double>();
    rig.advance_ms(10);
    const double x1 = rig.value("0103080402").get<double>();
    CHECK(std::abs(x1 - x0) < 5.0);
}

TEST_CASE("the same seed and clock give the same values") {
    for (const char* file : {"sim-mill.json", "appendix-b.json"}) {
        INFO(file);
        Rig a(file, 7);
        Rig b(file, 7);
        Rig c(file, 8);
        bool seed_matters = false;
        for (std::int64_t step : {0, 5, 250, 3'000, 45'000, 400'000}) {
            a.advance_ms(step);
            b.advance_ms(step);
            c.advance_ms(step);
            const Json va = a.all();
            CHECK(va == b.all());
            seed_matters = seed_matters || va != c.all();
        }
        CHECK(seed_matters);
    }
}

TEST_CASE("the read cadence does not change generic values") {
    Rig often("appendix-b.json");
    Rig once("appendix-b.json");
    for (int i = 0; i < 100; ++i) {
        often.advance_ms(100);
        (void)often.all();
    }
    once.advance_ms(10'000);
    CHECK(often.all() == once.all());
}

TEST_CASE("unknown ids answer Node not exists") {
    Rig rig("sim-mill.json");
    auto r = rig.read({"x_position", "no_such_item"});
    CHECK(r[0].ok());
    REQUIRE_FALSE(r[1].ok());
    CHECK(r[1].error().code == ErrorCode::node_not_exists);
    CHECK(rig.set("no_such_item", Json{{"value", 1}}).error().code == ErrorCode::node_not_exists);
}

TEST_CASE("an unknown device or no model is refused") {
    SimOptions options;
    options.device = "lathe";
    auto created = SimDriver::create(sim_test::load("sim-mill.json"), options);
    REQUIRE_FALSE(created.ok());
    CHECK(created.error().code == ErrorCode::node_not_exists);

    SimDriver broken(nullptr);
    CHECK_FALSE(broken.open(DriverContext{}).ok());
    std::vector<PointRef> points{{"x", DataKind::single}};
    std::vector<Result<Json>> results(1, Result<Json>(make_error(ErrorCode::timeout)));
    broken.read(points, results);
    REQUIRE_FALSE(results[0].ok());
    CHECK(results[0].error().code == ErrorCode::unavailable);
}

TEST_CASE("the list size is configurable") {
    SimOptions options;
    options.list_size = 5;
    options.clock = std::make_shared<ManualClock>();
    auto created = SimDriver::create(sim_test::load("appendix-b.json"), options);
    REQUIRE(created.ok());
    std::vector<PointRef> points{{"01031207", DataKind::list}, {"01031217", DataKind::dict}};
    std::vector<Result<Json>> results(2, Result<Json>(make_error(ErrorCode::unavailable)));
    created.value()->read(points, results);
    CHECK(results[0].value().size() == 5);
    CHECK(results[1].value().size() == 5);
}

TEST_CASE("read_samples gives read()'s values typed, texts and objects included") {
    sim_test::Rig json_rig("sim-mill.json", 7), typed_rig("sim-mill.json", 7);
    json_rig.advance_ms(1234);
    typed_rig.advance_ms(1234);
    auto ids = typed_rig.driver->item_ids();
    ids.push_back("no_such_item");
    std::vector<nclink::PointRef> points;
    for (const auto& id : ids) points.push_back({id, nclink::DataKind::single});
    std::vector<nclink::SampleValue> out(points.size());
    REQUIRE(typed_rig.driver->read_samples(points, out.data()));
    const auto expected = json_rig.read(ids);
    bool saw_text = false, saw_object = false;
    for (std::size_t i = 0; i < ids.size(); ++i) {
        INFO(ids[i]);
        if (!expected[i].ok()) {
            CHECK(out[i].is_null());
            continue;
        }
        const nclink::Json& want = expected[i].value();
        std::string got;
        nclink::append_sample_value(got, out[i]);  // what the Sample DTU would carry
        CHECK(nclink::Json::parse(got) == want);
        saw_text = saw_text || want.is_string();
        saw_object = saw_object || want.is_structured();
    }
    CHECK(saw_text);
    CHECK(saw_object);
}
