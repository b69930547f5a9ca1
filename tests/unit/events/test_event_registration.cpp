// Register/Event validation (8.2.27, table 19 codes) and element extraction.
#include "events/event_registration.hpp"

#include <catch2/catch.hpp>

using namespace nclink;
using namespace nclink::events_detail;

namespace {

DataObject object(const char* id, DataKind kind) {
    DataObject o;
    o.id = id;
    o.kind = kind;
    return o;
}

EventRegisterRequest request(const char* json) {
    auto decoded = decode<EventRegisterRequest>(std::string_view(json));
    INFO(json);
    REQUIRE(decoded.ok());
    return *decoded;
}

ErrorCode refusal(const char* json, const DataObject* item) {
    auto spec = validate_registration(request(json), item);
    INFO(json);
    REQUIRE_FALSE(spec.ok());
    return spec.error().code;
}

const DataObject kSingle = object("pos", DataKind::single);
const DataObject kList = object("tools", DataKind::list);
const DataObject kDict = object("params", DataKind::dict);

}  // namespace

TEST_CASE("registration: the standard example is accepted") {
    auto spec = validate_registration(request(R"({"@id":"some_mid_001","guid":"dev_uuid","id":"010302",
        "filters":[{"type":"range","from":10,"to":20},{"type":"equal","value":100}],"triggerType":"always"})"),
                                      &kSingle);
    REQUIRE(spec.ok());
    CHECK(spec->item == "010302");
    CHECK(spec->filters.size() == 2);
    CHECK(spec->trigger == TriggerType::always);
    CHECK_FALSE(spec->key);
    CHECK_FALSE(spec->index);
}

TEST_CASE("registration: unknown item is 401") {
    CHECK(refusal(R"({"id":"nope","triggerType":"always"})", nullptr) == ErrorCode::node_not_exists);
}

TEST_CASE("registration: a list item without index is 402") {
    CHECK(refusal(R"({"id":"tools","triggerType":"always"})", &kList) == ErrorCode::no_index);
}

TEST_CASE("registration: a dict item without key is 403") {
    CHECK(refusal(R"({"id":"params","triggerType":"always"})", &kDict) == ErrorCode::no_key);
}

TEST_CASE("registration: key or index that does not fit the item is 409") {
    CHECK(refusal(R"({"id":"pos","key":"a","triggerType":"always"})", &kSingle) == ErrorCode::arguments_nimiety);
    CHECK(refusal(R"({"id":"pos","index":0,"triggerType":"always"})", &kSingle) == ErrorCode::arguments_nimiety);
    CHECK(refusal(R"({"id":"tools","key":"a","triggerType":"always"})", &kList) == ErrorCode::arguments_nimiety);
    CHECK(refusal(R"({"id":"params","index":1,"triggerType":"always"})", &kDict) == ErrorCode::arguments_nimiety);
    CHECK(refusal(R"({"id":"params","key":"a","index":1,"triggerType":"always"})", &kDict) == ErrorCode::arguments_nimiety);
}

TEST_CASE("registration: a negative index is 101") {
    CHECK(refusal(R"({"id":"tools","index":-1,"triggerType":"always"})", &kList) == ErrorCode::out_of_range);
}

TEST_CASE("registration: list and dict elements") {
    auto list = validate_registration(request(R"({"id":"tools","index":"2","triggerType":"normal"})"), &kList);
    REQUIRE(list.ok());
    CHECK(list->index == std::optional<std::size_t>(2));
    CHECK(list->trigger == TriggerType::normal);
    auto dict = validate_registration(request(R"({"id":"params","key":"p1","triggerType":"once"})"), &kDict);
    REQUIRE(dict.ok());
    CHECK(dict->key == std::optional<std::string>("p1"));
    CHECK(dict->trigger == TriggerType::once);
}

TEST_CASE("registration: filter errors are 419 and 421") {
    CHECK(refusal(R"({"id":"pos","filters":[{"type":"bigger","value":1}],"triggerType":"always"})", &kSingle) ==
          ErrorCode::filter_type);
    CHECK(refusal(R"({"id":"pos","filters":[{"type":"change","from":1}],"triggerType":"always"})", &kSingle) ==
          ErrorCode::filter_arguments_mismatch);
}

TEST_CASE("registration: trigger type error is 420") {
    CHECK(refusal(R"({"id":"pos","triggerType":"sometimes"})", &kSingle) == ErrorCode::trigger_type);
}

TEST_CASE("registration: a missing triggerType or id is refused by the decoder") {
    auto no_trigger = decode<EventRegisterRequest>(std::string_view(R"({"@id":"1","id":"pos"})"));
    REQUIRE_FALSE(no_trigger.ok());
    CHECK(no_trigger.error().code == ErrorCode::parameter_missing);
    auto no_id = decode<EventRegisterRequest>(std::string_view(R"({"@id":"1","triggerType":"always"})"));
    REQUIRE_FALSE(no_id.ok());
    CHECK(no_id.error().code == ErrorCode::parameter_missing);
}

TEST_CASE("registration: extract_element picks the watched element") {
    EventSpec whole;
    whole.item = "pos";
    CHECK(*extract_element(whole, 3.5) == 3.5);

    EventSpec dict;
    dict.item = "params";
    dict.kind = DataKind::dict;
    dict.key = "p1";
    CHECK(*extract_element(dict, Json{{"p1", 7}}) == 7);
    CHECK(extract_element(dict, Json{{"p2", 7}}).error().code == ErrorCode::key_error);
    CHECK(extract_element(dict, Json::array()).error().code == ErrorCode::unavailable);

    EventSpec list;
    list.item = "tools";
    list.kind = DataKind::list;
    list.index = 1;
    CHECK(*extract_element(list, Json::array({1, 2})) == 2);
    CHECK(extract_element(list, Json::array({1})).error().code == ErrorCode::out_of_range);
    CHECK(extract_element(list, nullptr).error().code == ErrorCode::unavailable);
}
