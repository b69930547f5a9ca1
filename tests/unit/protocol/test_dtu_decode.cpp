// Decode error classification (412/102/413/405), liberal inputs and the
// response helpers.
#include <nclink/dtu.hpp>

#include <catch2/catch.hpp>

using namespace nclink;

namespace {

template <class T>
ErrorCode code_of(std::string_view payload) {
    auto result = decode<T>(payload);
    REQUIRE_FALSE(result.ok());
    return result.error().code;
}

}  // namespace

TEST_CASE("412: payload that is not JSON or not an object") {
    CHECK(code_of<QueryRequest>("") == ErrorCode::syntax_error);
    CHECK(code_of<QueryRequest>("{\"ids\": [") == ErrorCode::syntax_error);
    CHECK(code_of<QueryRequest>("[1,2]") == ErrorCode::syntax_error);
    CHECK(code_of<SetRequest>("\"text\"") == ErrorCode::syntax_error);
    CHECK(code_of<SetRequest>("{\"values\": [],}") == ErrorCode::syntax_error);  // trailing comma
    CHECK(code_of<EventRegisterRequest>("null") == ErrorCode::syntax_error);
    CHECK(code_of<MethodCall>("{\"id\": \"m\"} // comment") == ErrorCode::syntax_error);
    CHECK(code_of<ProbeSetRequest>("{\"probe\": \"{not json\"}") == ErrorCode::syntax_error);
    CHECK(code_of<QueryRequest>("\xff\xfe{}") == ErrorCode::syntax_error);
    // Too deep to hand to nlohmann.
    CHECK(code_of<QueryRequest>(std::string(200, '[') + std::string(200, ']')) == ErrorCode::syntax_error);
    // From an already parsed value.
    auto r = decode_query_request(Json::array());
    REQUIRE_FALSE(r.ok());
    CHECK(r.error().code == ErrorCode::syntax_error);
}

TEST_CASE("102: a required key is simply missing") {
    CHECK(code_of<QueryRequest>(R"({"@id":"1","guid":"d"})") == ErrorCode::parameter_missing);
    CHECK(code_of<SetRequest>(R"({"@id":"1"})") == ErrorCode::parameter_missing);
    CHECK(code_of<MethodCall>(R"({"@id":"1","guid":"d","args":{}})") == ErrorCode::parameter_missing);
    CHECK(code_of<EventRegisterRequest>(R"({"id":"010302"})") == ErrorCode::parameter_missing);  // triggerType
    CHECK(code_of<SampleRegisterRequest>(R"({"uploadInterval":1,"ids":[]})") == ErrorCode::parameter_missing);
    CHECK(code_of<ProbeSetRequest>(R"({"@id":"1"})") == ErrorCode::parameter_missing);
    CHECK(code_of<RegisterRequest>(R"({"@id":"1"})") == ErrorCode::parameter_missing);
    // In a nested entry: an ids entry without "id".
    CHECK(code_of<QueryRequest>(R"({"ids":[{"params":{}}]})") == ErrorCode::parameter_missing);
    // Responses: code is required.
    CHECK(code_of<QueryResponse>(R"({"values":[{"id":"a"}]})") == ErrorCode::parameter_missing);
}

TEST_CASE("413: a required key is missing and unknown keys stand in its place") {
    // A Query using "values" instead of "ids".
    CHECK(code_of<QueryRequest>(R"({"@id":"1","guid":"d","values":[{"id":"a"}]})") == ErrorCode::keys_of_arguments);
    // A Set using "ids" instead of "values".
    CHECK(code_of<SetRequest>(R"({"@id":"1","ids":[{"id":"a"}]})") == ErrorCode::keys_of_arguments);
    CHECK(code_of<MethodControlRequest>(R"({"id":"m","cmd":"stop"})") == ErrorCode::keys_of_arguments);
    CHECK(code_of<SampleUnregisterRequest>(R"({"channel":"c1"})") == ErrorCode::keys_of_arguments);
    CHECK(code_of<QueryRequest>(R"({"ids":[{"name":"a"}]})") == ErrorCode::keys_of_arguments);
    // Unknown keys next to all required ones are ignored (liberal).
    auto q = decode_query_request(R"({"ids":[{"id":"a","extra":1}],"vendor":"x"})");
    REQUIRE(q.ok());
    CHECK(q->ids.at(0).id == "a");
}

TEST_CASE("405: a known key with the wrong type") {
    CHECK(code_of<QueryRequest>(R"({"ids":{"id":"a"}})") == ErrorCode::value_type);
    CHECK(code_of<QueryRequest>(R"({"ids":[5]})") == ErrorCode::value_type);
    CHECK(code_of<QueryRequest>(R"({"ids":[{"id":5}]})") == ErrorCode::value_type);
    CHECK(code_of<QueryRequest>(R"({"guid":7,"ids":[]})") == ErrorCode::value_type);
    CHECK(code_of<QueryRequest>(R"({"@id":{"x":1},"ids":[]})") == ErrorCode::value_type);
    CHECK(code_of<SetRequest>(R"({"values":"a"})") == ErrorCode::value_type);
    CHECK(code_of<SampleRegisterRequest>(R"({"sampleInterval":"10","uploadInterval":1,"ids":[]})") == ErrorCode::value_type);
    CHECK(code_of<EventRegisterRequest>(R"({"id":"a","triggerType":"once","index":"x"})") == ErrorCode::value_type);
    CHECK(code_of<EventRegisterRequest>(R"({"id":"a","triggerType":"once","filters":{}})") == ErrorCode::value_type);
    CHECK(code_of<EventRegisterRequest>(R"({"id":"a","triggerType":"once","filters":[1]})") == ErrorCode::value_type);
    CHECK(code_of<ProbeSetRequest>(R"({"probe":42})") == ErrorCode::value_type);
    CHECK(code_of<ProbeSetRequest>(R"({"probe":"[1,2]"})") == ErrorCode::value_type);
    CHECK(code_of<SampleDtu>(R"({"id":"c","beginTime":"soon","data":[]})") == ErrorCode::value_type);
    CHECK(code_of<QueryResponse>(R"({"values":[{"id":"a","code":1}]})") == ErrorCode::value_type);
}

TEST_CASE("liberal inputs") {
    SECTION("numeric and other scalar @id are echoed verbatim") {
        auto q = decode_query_request(R"({"@id": 42, "ids": [{"id": "a"}]})");
        REQUIRE(q.ok());
        CHECK(q->msg_id == Json(42));
        auto reply = make_reply<QueryResponse>(*q, "dev");
        CHECK(to_json(reply)["@id"] == 42);
        CHECK(to_json(reply)["guid"] == "dev");
        auto f = decode_query_request(R"({"@id": 1.5, "ids": []})");
        REQUIRE(f.ok());
        CHECK(f->msg_id == Json(1.5));
        auto b = decode_method_call(R"({"@id": true, "id": "m"})");
        REQUIRE(b.ok());
        CHECK(to_json(*b)["@id"] == true);
    }
    SECTION("a request without @id still decodes, and its answer has none") {
        auto q = decode_set_request(R"({"values": [{"id": "a", "params": {"value": 1}}]})");
        REQUIRE(q.ok());
        CHECK_FALSE(q->msg_id);
        CHECK_FALSE(to_json(make_reply<SetResponse>(*q, "dev")).contains("@id"));
    }
    SECTION("guid may be omitted in requests") {
        auto q = decode_query_request(R"({"@id":"1","ids":[{"id":"a"}]})");
        REQUIRE(q.ok());
        CHECK(q->guid.empty());
        CHECK_FALSE(to_json(*q).contains("guid"));
        CHECK(decode_event_unregister_request(R"({"id":"e"})").ok());
        CHECK(decode_method_control_request(R"({"id":"m","action":"stop"})").ok());
    }
    SECTION("probe given as a string holding JSON") {
        auto p = decode_probe_set_request(R"({"@id":"1","probe":"{\"id\":\"machine\",\"version\":\"1.0.0\"}"})");
        REQUIRE(p.ok());
        CHECK(p->probe.is_object());
        CHECK(p->probe["id"] == "machine");
        // Sent back strictly, as an object.
        CHECK(to_json(*p)["probe"].is_object());
        auto r = decode_probe_query_response(R"({"code":"OK","probe":"{\"id\":\"m\"}"})");
        REQUIRE(r.ok());
        CHECK((*r->probe)["id"] == "m");
    }
    SECTION("empty payload and {} are valid Probe/Query requests") {
        CHECK(decode_probe_query_request("").ok());
        CHECK(decode_probe_query_request("  \n").ok());
        CHECK(decode_probe_query_request("{}").ok());
        CHECK_FALSE(decode_probe_query_request("[]").ok());
    }
    SECTION("bare id strings in ids") {
        auto q = decode_query_request(R"({"ids":["010203",{"id":"010204"}]})");
        REQUIRE(q.ok());
        CHECK(q->ids.size() == 2);
        CHECK(q->ids[0].id == "010203");
    }
    SECTION("index as a numeric string; beginTime and time as numbers") {
        auto e = decode_event_register_request(R"({"id":"a","index":"5","triggerType":"once"})");
        REQUIRE(e.ok());
        CHECK(e->index == 5);
        auto s = decode_sample(R"({"id":"c","beginTime":1535642875900,"data":[[1,2]]})");
        REQUIRE(s.ok());
        CHECK(s->begin_time == 1535642875900);
        CHECK(to_json(*s)["beginTime"] == "1535642875900");
        CHECK(to_json(*s)["data"] == Json::parse(R"([{"data":[1,2]}])"));
    }
    SECTION("Method/Status with the example's \"process\"") {
        auto m = decode_method_status(R"({"id":"m","status":"executing","process":30})");
        REQUIRE(m.ok());
        CHECK(m->progress == 30.0);
        CHECK(to_json(*m)["progress"] == 30);
        CHECK_FALSE(to_json(*m).contains("process"));
    }
    SECTION("Set response with \"values\" as in 8.2.14 example 3") {
        auto s = decode_set_response(R"({"guid":"d","values":[{"id":"a","code":"OK"}]})");
        REQUIRE(s.ok());
        REQUIRE(s->results.size() == 1);
        CHECK(to_json(*s).contains("results"));
    }
    SECTION("lower-case ok and null deviceList") {
        auto d = decode_discovery_response(R"({"code":"ok","guid":"ex","deviceList":null})");
        REQUIRE(d.ok());
        CHECK(d->status.ok);
        CHECK_FALSE(d->device_list);
        CHECK(to_json(*d)["deviceList"].is_null());
    }
}

TEST_CASE("no exception escapes a decoder, whatever the input") {
    const char* inputs[] = {"",
                            "{",
                            "}",
                            "{\"ids\":[{\"id\":\"a\",\"params\":",
                            "\"\\ud800\"",
                            "1e99999",
                            "{\"@id\":null}",
                            "{\"ids\":null}",
                            "{\"values\":[null]}",
                            "{\"error\":1e300,\"code\":\"NG\"}"};
    for (const char* input : inputs) {
        CHECK_NOTHROW((void)decode_query_request(input));
        CHECK_NOTHROW((void)decode_set_response(input));
        CHECK_NOTHROW((void)decode_event_data(input));
        CHECK_NOTHROW((void)decode_dev_unreachable(input));
    }
    auto r = decode_register_response(R"({"cli_uuid":"a","code":"NG","error":1e300})");
    REQUIRE_FALSE(r.ok());
    CHECK(r.error().code == ErrorCode::value_type);
}

TEST_CASE("ResponseStatus from an Error uses the exact table-19 strings") {
    const ResponseStatus s(make_error(ErrorCode::node_not_exists, "no such item 0102"));
    CHECK_FALSE(s.ok);
    CHECK(s.code() == "NG");
    CHECK(s.reason == std::string("Node not exists"));
    CHECK(s.error == 401);
    CHECK(s.error_code() == ErrorCode::node_not_exists);
    CHECK(ResponseStatus(make_error(ErrorCode::success)).ok);
    CHECK(ResponseStatus::failure(ErrorCode::syntax_error).reason == std::string("syntax error"));

    QueryResponse response;
    response.guid = "dev";
    response.values.push_back({"0102", s, std::nullopt, std::nullopt, std::nullopt});
    response.values.push_back(
        {"0103", ResponseStatus::success(), Json({{"operation", "get_value"}}), Json::array({1}), std::nullopt});
    CHECK(to_json(response) == Json::parse(R"({"guid":"dev","values":[
        {"id":"0102","code":"NG","reason":"Node not exists","error":401},
        {"id":"0103","code":"OK","params":{"operation":"get_value"},"values":[1]}]})"));
}

TEST_CASE("make_error_reply answers undecodable requests with @id and guid") {
    const std::string payload = R"({"@id": 7, "guid": "dev", "values": []})";
    auto q = decode_query_request(payload);
    REQUIRE_FALSE(q.ok());
    CHECK(q.error().code == ErrorCode::keys_of_arguments);
    const auto id = peek_message_id(payload);
    CHECK(id == Json(7));
    auto reply = make_error_reply(TopicKind::query_request, id, "dev", q.error());
    REQUIRE(reply);
    CHECK(*reply == Json::parse(R"({"@id":7,"guid":"dev","code":"NG","reason":"keys of arguments error","error":413,"values":[]})"));
    // and it decodes as a Query response
    auto back = decode_query_response(*reply);
    REQUIRE(back.ok());
    REQUIRE(back->status);
    CHECK(back->status->error == 413);

    auto m = make_error_reply(TopicKind::method_call, std::nullopt, "dev", make_error(ErrorCode::syntax_error));
    REQUIRE(m);
    CHECK((*m)["result"] == "error");
    CHECK(decode_method_result(*m).ok());
    for (TopicKind kind : {TopicKind::probe_query_request, TopicKind::probe_set_request, TopicKind::set_request,
                           TopicKind::sample_register_request, TopicKind::sample_unregister_request,
                           TopicKind::method_control_request, TopicKind::event_register_request,
                           TopicKind::event_unregister_request, TopicKind::register_request, TopicKind::discovery_request}) {
        INFO(to_string(kind));
        auto r = make_error_reply(kind, Json("x"), "dev", make_error(ErrorCode::parameter_missing));
        REQUIRE(r);
        CHECK((*r)["@id"] == "x");
        CHECK((*r)["code"] == "NG");
        CHECK((*r)["error"] == 102);
    }
    CHECK_FALSE(make_error_reply(TopicKind::query_response, std::nullopt, "dev", make_error(ErrorCode::syntax_error)));
    CHECK_FALSE(make_error_reply(TopicKind::sample, std::nullopt, "dev", make_error(ErrorCode::syntax_error)));
    CHECK_FALSE(peek_message_id("not json"));
    CHECK_FALSE(peek_message_id(R"({"@id":[1]})"));
}

TEST_CASE("encode never throws on invalid UTF-8 held in a struct") {
    QueryResponse r;
    r.guid = "dev\xff";
    CHECK_NOTHROW(encode(r));
    CHECK(Json::parse(encode(r))["guid"] == "dev\xEF\xBF\xBD");
}
