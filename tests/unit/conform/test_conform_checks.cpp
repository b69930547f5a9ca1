// The conformance tester's checks, fed good and bad DTUs directly.
#include "conform/checks.hpp"

#include <catch2/catch.hpp>

using namespace nclink;
using namespace nclink::conform;

namespace {

const std::string kDev = "dev-1";

bool mentions(const Problems& problems, const std::string& text) {
    for (const auto& p : problems)
        if (p.find(text) != std::string::npos) return true;
    return false;
}

DataObject item(std::string id, DataKind kind = DataKind::single, std::optional<Json> value = std::nullopt) {
    DataObject d;
    d.id = std::move(id);
    d.kind = kind;
    d.value = std::move(value);
    return d;
}

}  // namespace

TEST_CASE("status keys: OK and NG with reason pass and a wrong code fails") {
    CHECK(check_status_keys(Json{{"code", "OK"}}).empty());
    CHECK(check_status_keys(Json{{"code", "NG"}, {"reason", "Node not exists"}, {"error", 401}}).empty());
    CHECK(mentions(check_status_keys(Json::object()), "\"code\" is missing"));
    CHECK(mentions(check_status_keys(Json{{"code", "ok"}}), "expected \"OK\" or \"NG\""));
    CHECK(mentions(check_status_keys(Json{{"code", "NG"}, {"error", "401"}}), "\"error\" is \"401\", not a number"));
    CHECK(mentions(check_status_keys(Json{{"code", "NG"}}), "cannot tell why"));
}

TEST_CASE("envelope: the request's @id is echoed verbatim and guid names the device") {
    const Json sent = "tester-1";
    CHECK(check_envelope(Json{{"@id", "tester-1"}, {"guid", kDev}}, sent, kDev, true).empty());
    CHECK(
        mentions(check_envelope(Json{{"@id", "tester-2"}, {"guid", kDev}}, sent, kDev, true), "the request's was \"tester-1\""));
    CHECK(mentions(check_envelope(Json{{"guid", kDev}}, sent, kDev, true), "\"@id\" is missing"));
    CHECK(mentions(check_envelope(Json{{"@id", "tester-1"}}, sent, kDev, true), "\"guid\" is missing"));
    CHECK(check_envelope(Json{{"@id", "tester-1"}}, sent, kDev, false).empty());
    CHECK(mentions(check_envelope(Json{{"@id", "tester-1"}, {"guid", "other"}}, sent, kDev, false), "expected \"dev-1\""));
    // A numeric @id is not the string that was sent.
    CHECK_FALSE(check_envelope(Json{{"@id", 1}, {"guid", kDev}}, Json("1"), kDev, true).empty());
}

TEST_CASE("not supported is NG 202 or a reason that says so and never an OK") {
    CHECK(says_not_supported(Json{{"code", "NG"}, {"error", 202}, {"reason", "Unavailable"}}));
    CHECK(says_not_supported(Json{{"code", "NG"}, {"reason", "Unavailable"}}));
    CHECK(says_not_supported(Json{{"code", "NG"}, {"reason", "feature not supported"}}));
    CHECK_FALSE(says_not_supported(Json{{"code", "OK"}, {"error", 202}}));
    CHECK_FALSE(says_not_supported(Json{{"code", "NG"}, {"error", 401}, {"reason", "Node not exists"}}));
    // 406-408 concern one operation on one item, not the feature.
    CHECK_FALSE(says_not_supported(Json{{"code", "NG"}, {"reason", "unsupported operation get_length"}, {"error", 406}}));
}

TEST_CASE("register and discovery responses of an agent") {
    CHECK(check_register_response(Json{{"@id", "a"}, {"cli_uuid", "me"}, {"code", "OK"}}, Json("a"), "me").empty());
    auto refused = check_register_response(
        Json{{"@id", "a"}, {"cli_uuid", "me"}, {"code", "NG"}, {"reason", "Permission Denied"}, {"error", 301}}, Json("a"), "me");
    CHECK(mentions(refused, "registration refused"));
    CHECK(mentions(check_register_response(Json{{"@id", "a"}, {"cli_uuid", "you"}, {"code", "OK"}}, Json("a"), "me"),
                   "\"cli_uuid\" is \"you\""));

    const Json good = Json::parse(R"({"@id":"d","code":"OK","guid":"me","deviceList":[
        {"guid":"other","status":"offline","lastAliveTimeStamp":"1611176010"},
        {"guid":"dev-1","status":"online","lastAliveTimeStamp":"1611287021","privateInfo":null}]})");
    CHECK(check_discovery_response(good, Json("d"), "me", kDev).empty());
    Json missing = good;
    missing["deviceList"].erase(1);
    CHECK(mentions(check_discovery_response(missing, Json("d"), "me", kDev), "not in deviceList"));
    Json bad_entry = good;
    bad_entry["deviceList"][1]["status"] = "up";
    bad_entry["deviceList"][1]["lastAliveTimeStamp"] = 1611287021;
    auto problems = check_discovery_response(bad_entry, Json("d"), "me", kDev);
    CHECK(mentions(problems, "deviceList[1]: \"status\" is \"up\""));
    CHECK(mentions(problems, "\"lastAliveTimeStamp\" is 1611287021"));
    Json null_list = good;
    null_list["deviceList"] = nullptr;
    CHECK(mentions(check_discovery_response(null_list, Json("d"), "me", kDev), "is not discovered"));
}

TEST_CASE("probe response: an object or a string holding JSON and never a missing probe") {
    auto object = check_probe_response(Json{{"@id", "p"}, {"code", "OK"}, {"probe", {{"id", "root"}}}}, Json("p"), kDev);
    CHECK(object.problems.empty());
    REQUIRE(object.model);
    CHECK((*object.model)["id"] == "root");
    auto text = check_probe_response(Json{{"@id", "p"}, {"code", "OK"}, {"probe", R"({"id":"root"})"}}, Json("p"), kDev);
    CHECK(text.problems.empty());
    CHECK(text.model);
    auto broken = check_probe_response(Json{{"@id", "p"}, {"code", "OK"}, {"probe", "{not json"}}, Json("p"), kDev);
    CHECK(mentions(broken.problems, "not JSON"));
    CHECK_FALSE(broken.model);
    CHECK(mentions(check_probe_response(Json{{"@id", "p"}, {"code", "OK"}}, Json("p"), kDev).problems, "\"probe\" is missing"));
}

TEST_CASE("query response: one entry per id in order with values arrays") {
    const Json good = Json::parse(R"({"@id":"q","guid":"dev-1","values":[
        {"id":"a","code":"OK","values":[1]},
        {"id":"b","code":"NG","reason":"Node not exists","error":401}]})");
    CHECK(check_query_response(good, Json("q"), kDev, {"a", "b"}).empty());
    CHECK(mentions(check_query_response(good, Json("q"), kDev, {"a", "b", "c"}), "2 entries for 3 requested items"));
    CHECK(mentions(check_query_response(good, Json("q"), kDev, {"b", "a"}), "request order"));
    Json scalar = good;
    scalar["values"][0]["values"] = 1;
    CHECK(mentions(check_query_response(scalar, Json("q"), kDev, {"a", "b"}), "not an array"));
    Json no_values = good;
    no_values["values"][0].erase("values");
    CHECK(mentions(check_query_response(no_values, Json("q"), kDev, {"a", "b"}), "code OK without \"values\""));
    Json wrong_id = good;
    wrong_id["@id"] = "other";
    CHECK(mentions(check_query_response(wrong_id, Json("q"), kDev, {"a", "b"}), "\"@id\" is \"other\""));
}

TEST_CASE("whole values follow the data type and the model's fixed value") {
    CHECK(check_whole_value(item("s"), Json::array({3.5})).empty());
    CHECK(check_whole_value(item("s"), Json::array({nullptr})).empty());
    CHECK(mentions(check_whole_value(item("s"), Json::array({1, 2})), "answered 2 values"));
    CHECK(check_whole_value(item("l", DataKind::list), Json::array({Json::array({1, 2})})).empty());
    CHECK(mentions(check_whole_value(item("l", DataKind::list), Json::array({"x"})), "not an array"));
    CHECK(check_whole_value(item("d", DataKind::dict), Json::array({Json{{"k", 1}}})).empty());
    CHECK(mentions(check_whole_value(item("d", DataKind::dict), Json::array({Json::array()})), "not an object"));
    CHECK(check_whole_value(item("f", DataKind::single, Json("nclink")), Json::array({"nclink"})).empty());
    CHECK(mentions(check_whole_value(item("f", DataKind::single, Json("nclink")), Json::array({"other"})),
                   "the model fixes the value \"nclink\""));
    CHECK(check_whole_value(item("n", DataKind::single, Json(12000)), Json::array({12000.0})).empty());
}

TEST_CASE("get_length and get_keys agree with the whole value") {
    CHECK(check_list_length(Json::array({3}), Json::array({1, 2, 3})).empty());
    CHECK(mentions(check_list_length(Json::array({2}), Json::array({1, 2, 3})), "has 3 elements"));
    CHECK(mentions(check_list_length(Json::array({"3"}), Json()), "non-negative integer"));
    CHECK(check_dict_keys(Json::array({"a", "b"}), Json{{"a", 1}, {"b", 2}}).empty());
    CHECK(mentions(check_dict_keys(Json::array({"a"}), Json{{"a", 1}, {"b", 2}}), "1 keys, the whole dict has 2"));
    CHECK(mentions(check_dict_keys(Json::array({1}), Json()), "array of strings"));
}

TEST_CASE("set response: results in order and the values spelling of example 8.2.14-3") {
    CHECK(check_set_response(Json::parse(R"({"@id":"s","guid":"dev-1","results":[{"id":"a","code":"OK"}]})"), Json("s"), kDev, {"a"})
              .empty());
    CHECK(check_set_response(Json::parse(R"({"@id":"s","guid":"dev-1","values":[{"id":"a","code":"OK"}]})"), Json("s"), kDev, {"a"})
              .empty());
    CHECK(mentions(check_set_response(Json::parse(R"({"@id":"s","guid":"dev-1","results":[]})"), Json("s"), kDev, {"a"}),
                   "0 entries for 1"));
}

TEST_CASE("sample DTU: columns rows and beginTime against the channel") {
    const ChannelSpec spec{"ch", 2, 10, 100};
    const Json good = Json::parse(R"({"guid":"dev-1","id":"ch","beginTime":"1700000000000",
        "data":[{"data":[1,2,3,4,5,6,7,8,9,10]},{"data":[0,0,0,0,0,0,0,0,0,null]}]})");
    auto ok = check_sample_dtu(good, kDev, spec);
    CHECK(ok.problems.empty());
    REQUIRE(ok.shape);
    CHECK(ok.shape->rows == 10);
    CHECK(ok.shape->begin_time == 1700000000000);

    Json columns = good;
    columns["data"].erase(1);
    CHECK(mentions(check_sample_dtu(columns, kDev, spec).problems, "\"data\" has 1 entries; channel \"ch\" samples 2"));
    Json ragged = good;
    ragged["data"][1]["data"].erase(0);
    CHECK(mentions(check_sample_dtu(ragged, kDev, spec).problems, "different numbers of values (10,9)"));
    Json bare = good;
    bare["data"][0] = Json::array({1, 2});
    CHECK(mentions(check_sample_dtu(bare, kDev, spec).problems, "expected {\"data\": [...]}"));
    Json number_time = good;
    number_time["beginTime"] = 1700000000000;
    CHECK(mentions(check_sample_dtu(number_time, kDev, spec).problems, "want a string"));
    Json seconds = good;
    seconds["beginTime"] = "1700000000";
    CHECK(mentions(check_sample_dtu(seconds, kDev, spec).problems, "not a time in milliseconds"));
    Json too_many = good;
    for (auto& c : too_many["data"]) c["data"] = Json(std::vector<int>(50, 1));
    CHECK(mentions(check_sample_dtu(too_many, kDev, spec).problems, "50 values per column"));
    Json wrong_channel = good;
    wrong_channel["id"] = "other";
    CHECK(mentions(check_sample_dtu(wrong_channel, kDev, spec).problems, "\"id\" is \"other\""));
    Json no_guid = good;
    no_guid.erase("guid");
    CHECK(mentions(check_sample_dtu(no_guid, kDev, spec).problems, "\"guid\" is missing"));
}

TEST_CASE("sample sequence: continuity rows and pace") {
    const ChannelSpec spec{"ch", 1, 10, 100};
    std::vector<SampleArrival> good;
    for (int i = 0; i < 5; ++i) good.push_back({1700000000000 + i * 100, 10, 5000 + i * 100 + (i % 2) * 7});
    CHECK(check_sample_sequence(good, spec).empty());

    auto gap = good;
    for (std::size_t i = 2; i < gap.size(); ++i) gap[i].begin_time += 500;
    CHECK(mentions(check_sample_sequence(gap, spec), "a gap of 500 ms"));

    auto backwards = good;
    backwards[2].begin_time = backwards[1].begin_time;
    CHECK(mentions(check_sample_sequence(backwards, spec), "does not follow"));

    auto few_rows = good;
    for (auto& a : few_rows) a.rows = 2;
    for (std::size_t i = 0; i < few_rows.size(); ++i) few_rows[i].begin_time = 1700000000000 + static_cast<std::int64_t>(i) * 20;
    CHECK(mentions(check_sample_sequence(few_rows, spec), "2 values per column (median)"));

    auto slow = good;
    for (std::size_t i = 0; i < slow.size(); ++i) slow[i].arrived_ms = 5000 + static_cast<std::int64_t>(i) * 1000;
    CHECK(mentions(check_sample_sequence(slow, spec), "arrive every 1000 ms"));
    CHECK(check_sample_sequence({good[0]}, spec).empty());
}

TEST_CASE("event data has the shape of table 52") {
    const Json good = Json::parse(R"({"@id":"e1","guid":"dev-1","id":"ev-1","time":1700000000123,
        "event":{"id":"x_position","value":5,"oldValue":4}})");
    CHECK(check_event_data(good, kDev, "ev-1", "x_position").empty());
    Json string_time = good;
    string_time["time"] = "1700000000123";
    CHECK(mentions(check_event_data(string_time, kDev, "ev-1", "x_position"), "\"time\" is \"1700000000123\""));
    Json no_value = good;
    no_value["event"].erase("value");
    CHECK(mentions(check_event_data(no_value, kDev, "ev-1", "x_position"), "no \"value\""));
    Json wrong_item = good;
    wrong_item["event"]["id"] = "y";
    CHECK(mentions(check_event_data(wrong_item, kDev, "ev-1", "x_position"), "\"id\" is \"y\""));
    Json no_id = good;
    no_id.erase("@id");
    CHECK(mentions(check_event_data(no_id, kDev, "ev-1", "x_position"), "\"@id\" is missing"));
}

TEST_CASE("event and sampling registration answers carry the new id") {
    CHECK(check_event_register_response(Json{{"@id", "r"}, {"guid", kDev}, {"id", "ev"}, {"code", "OK"}}, Json("r"), kDev).empty());
    CHECK(mentions(check_event_register_response(Json{{"@id", "r"}, {"guid", kDev}, {"code", "OK"}}, Json("r"), kDev),
                   "without an event \"id\""));
    CHECK(mentions(check_sample_register_response(Json{{"@id", "r"}, {"guid", kDev}, {"code", "OK"}}, Json("r"), kDev),
                   "without a channel \"id\""));
    CHECK(check_unregister_response(Json{{"@id", "u"}, {"guid", kDev}, {"code", "OK"}}, Json("u"), kDev).empty());
}

TEST_CASE("method status result and control answers") {
    CHECK(check_method_status(Json{{"guid", kDev}, {"id", "m"}, {"status", "executing"}, {"progress", 30}}, kDev, "m").empty());
    CHECK(check_method_status(Json{{"guid", kDev}, {"id", "m"}, {"status", "executing"}, {"process", 30}}, kDev, "m").empty());
    CHECK(
        mentions(check_method_status(Json{{"guid", kDev}, {"id", "m"}, {"status", "running"}}, kDev, "m"), "waiting/executing"));
    CHECK(mentions(check_method_status(Json{{"guid", kDev}, {"id", "m"}, {"status", "sleep"}, {"progress", "30%"}}, kDev, "m"),
                   "not a number"));
    CHECK(check_method_result(Json{{"@id", "c"}, {"guid", kDev}, {"id", "m"}, {"result", "finished"}, {"code", "OK"}}, Json("c"),
                              kDev, "m")
              .empty());
    CHECK(mentions(check_method_result(Json{{"@id", "c"}, {"guid", kDev}, {"id", "m"}, {"result", "done"}, {"code", "OK"}},
                                       Json("c"), kDev, "m"),
                   "finished/canceled/error"));
    CHECK(mentions(
        check_method_result(Json{{"@id", "c"}, {"guid", kDev}, {"id", "m"}, {"result", "finished"}, {"code", "NG"}, {"error", 1}},
                            Json("c"), kDev, "m"),
        "finished\" with code NG"));
    CHECK(mentions(check_method_control_response(Json{{"@id", "c"}, {"guid", kDev}, {"code", "OK"}}, Json("c"), kDev, "m"),
                   "\"id\" is missing"));
}

TEST_CASE("notify state: retained online with the adapter's tid") {
    CHECK(check_notify_state(Message{"Notify/State/dev-1", R"({"tid":"dev-1","state":"online"})", 1, true}, kDev).empty());
    CHECK(mentions(check_notify_state(Message{"t", R"({"tid":"dev-1","state":"offline"})", 1, true}, kDev),
                   "\"state\" is \"offline\""));
    CHECK(mentions(check_notify_state(Message{"t", R"({"tid":"dev-1","state":"online"})", 1, false}, kDev), "not retained"));
    CHECK(mentions(check_notify_state(Message{"t", R"({"tid":"x","state":"online"})", 1, true}, kDev), "\"tid\" is \"x\""));
    CHECK(mentions(check_notify_state(Message{"t", "online", 1, true}, kDev), "not JSON"));
}

TEST_CASE("model helpers: counts device lookup and version bump") {
    auto loaded = load_model_file(std::string(NCLINK_MODELS_DIR) + "/sim-mill.json");
    REQUIRE(loaded.model);
    const auto counts = count_objects(*loaded.model);
    CHECK(counts.channels == 2);
    CHECK(counts.methods == 4);
    CHECK(counts.components_standard + counts.components_custom == loaded.model->components().size());
    CHECK(counts.data_standard + counts.data_custom == loaded.model->data_objects().size());
    CHECK(counts.components_custom == 0);
    const Device* d = device_for(*loaded.model, "nclink-sim-mill-01");
    REQUIRE(d);
    CHECK(d->id == "mill");
    CHECK(served_items(*loaded.model, *d).size() == loaded.model->data_objects().size());

    CHECK(bump_version("1.0.0") == "1.0.1");
    CHECK(bump_version("v1.2") == "v1.2.1");
    CHECK(bump_version("") == "1.0.1");
    CHECK(bump_version("2") == "2.0.1");
    CHECK(bump_version("beta") == "beta.1");
    CHECK(plausible_epoch_ms(1700000000000));
    CHECK_FALSE(plausible_epoch_ms(1700000000));
}
