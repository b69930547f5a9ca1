// The bridge's pure pieces: MTConnect buffer sequence rules, request
// parameters, documents (validated with xmllint and the MTConnect 1.4
// schemas when present), SHDR lines, the data-write parser.
#include "bridge/bridge_store.hpp"
#include "bridge/gbt_api.hpp"
#include "bridge/json_api.hpp"
#include "bridge/mtconnect_api.hpp"
#include "bridge/mtconnect_documents.hpp"
#include "bridge/observation_buffer.hpp"
#include "bridge/path_filter.hpp"
#include "bridge/request_params.hpp"
#include "bridge/shdr.hpp"

#include <catch2/catch.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <unistd.h>

using namespace nclink;
using namespace nclink::bridge;

namespace {

// CI lays shared/ beside the source tree; NCLINK_SHARED_DIR in the environment overrides it.
std::string schema_dir() {
    const char* env = std::getenv("NCLINK_SHARED_DIR");
    return std::string(env && *env ? env : NCLINK_SHARED_DIR) + "/interop/mtconnect-schema";
}

/// xmllint's verdict on `xml` against MTConnect<kind>_1.4_1.0.xsd; true when the schema is absent (skipped).
bool validates(const std::string& xml, const std::string& kind) {
    const std::string xsd = schema_dir() + "/MTConnect" + kind + "_1.4_1.0.xsd";
    if (!std::filesystem::exists(xsd) || std::system("command -v xmllint >/dev/null 2>&1") != 0) {
        WARN("MTConnect schemas or xmllint absent: " << xsd << " not checked");
        return true;
    }
    // Per process: ctest runs each test case of this file as its own
    // process, two at a time, and a shared name let one case read (or lose)
    // the other's document.
    const auto stem = std::filesystem::temp_directory_path() / ("nclink-bridge-unit-" + kind + "-" + std::to_string(::getpid()));
    const std::string file = stem.string() + ".xml", log_file = stem.string() + ".log";
    std::ofstream(file) << xml;
    const std::string cmd = "xmllint --nonet --noout --schema " + xsd + " " + file + " 2>" + log_file;
    const int rc = std::system(cmd.c_str());
    if (rc != 0) {
        std::ifstream log(log_file);
        std::cerr << log.rdbuf() << "\n" << xml << "\n";
    }
    std::filesystem::remove(file);
    std::filesystem::remove(log_file);
    return rc == 0;
}

const char* kModel = R"({
  "id": "root", "type": "NC_LINK_ROOT", "version": "1.0",
  "devices": [{
    "id": "mill", "name": "Mill", "type": "MACHINE", "guid": "mill-01", "version": "1.0",
    "configs": [{"id": "ch", "type": "SAMPLE_CHANNEL", "sampleInterval": 10, "uploadInterval": 100, "ids": [{"id": "x_position"}]}],
    "components": [{
      "id": "axis_x", "type": "AXIS", "number": "X",
      "dataItems": [{"id": "x_position", "type": "POSITION", "units": "mm"}]
    }, {
      "id": "controller", "type": "CONTROLLER",
      "dataItems": [{"id": "status", "type": "STATUS"}, {"id": "feed_override", "type": "FEED_OVERRIDE", "setable": true}]
    }]
  }]
})";

}  // namespace

TEST_CASE("buffer numbers observations from 1 and keeps first last next") {
    ObservationBuffer b(4);
    CHECK(b.first_sequence() == 1);
    CHECK(b.last_sequence() == 0);
    CHECK(b.next_sequence() == 1);
    for (int i = 0; i < 3; ++i) CHECK(b.append(0, i, 1000 + i) == static_cast<std::uint64_t>(i + 1));
    CHECK(b.first_sequence() == 1);
    CHECK(b.last_sequence() == 3);
    CHECK(b.next_sequence() == 4);
}

TEST_CASE("buffer wraps: the oldest falls out and the last value of every item is kept") {
    ObservationBuffer b(4);
    b.append(0, "a0", 1);                                                      // 1
    b.append(1, "b0", 2);                                                      // 2
    for (int i = 1; i <= 6; ++i) b.append(1, "b" + std::to_string(i), 2 + i);  // 3..8
    CHECK(b.first_sequence() == 5);
    CHECK(b.last_sequence() == 8);
    CHECK(b.find(4) == nullptr);
    REQUIRE(b.find(5) != nullptr);
    CHECK(b.find(5)->value == "b3");
    // item 0 left the buffer long ago: still current (part 1 5.1.3.6)
    REQUIRE(b.latest()[0]);
    CHECK(b.latest()[0]->value == "a0");
    CHECK(b.latest()[0]->sequence == 1);
    // values as of sequence 6: item 0 from before the buffer, item 1 at 6
    auto at = b.values_at(6);
    REQUIRE(at[0]);
    CHECK(at[0]->value == "a0");
    REQUIRE(at[1]);
    CHECK(at[1]->sequence == 6);
    CHECK(at[1]->value == "b4");
}

TEST_CASE("buffer ranges follow part 1 from count and nextSequence") {
    ObservationBuffer b(8);
    for (int i = 0; i < 8; ++i) b.append(static_cast<ItemIndex>(i % 2), i, i);  // 1..8
    auto r = b.range(3, 3, nullptr);
    REQUIRE(r.observations.size() == 3);
    CHECK(r.observations.front().sequence == 3);
    CHECK(r.next_sequence == 6);
    // from + count past the end: nextSequence = lastSequence + 1
    r = b.range(7, 100, nullptr);
    CHECK(r.observations.size() == 2);
    CHECK(r.next_sequence == 9);
    // from = nextSequence: nothing yet
    r = b.range(9, 10, nullptr);
    CHECK(r.observations.empty());
    CHECK(r.next_sequence == 9);
    // a filter counts only wanted observations
    r = b.range(1, 2, [](ItemIndex i) { return i == 1; });
    REQUIRE(r.observations.size() == 2);
    CHECK(r.observations[0].sequence == 2);
    CHECK(r.observations[1].sequence == 4);
    CHECK(r.next_sequence == 5);
}

TEST_CASE("sample parameters: integers in range, INVALID_REQUEST for text, OUT_OF_RANGE beyond") {
    SampleParams p;
    CHECK_FALSE(parse_sample_params({{"from", "5"}, {"count", "10"}, {"interval", "100"}}, 1000, p));
    CHECK(*p.from == 5);
    CHECK(p.count == 10);
    CHECK(p.interval->count() == 100);
    SampleParams gbt;
    CHECK_FALSE(parse_sample_params({{"From", "7"}, {"Count", "2"}}, 1000, gbt));
    CHECK(*gbt.from == 7);
    auto check = [](QueryParams q, MtErrorCode code) {
        SampleParams s;
        auto e = parse_sample_params(q, 1000, s);
        REQUIRE(e);
        CHECK(e->code == code);
    };
    check({{"from", "abc"}}, MtErrorCode::invalid_request);
    check({{"from", "1.5"}}, MtErrorCode::invalid_request);
    check({{"from", ""}}, MtErrorCode::invalid_request);
    check({{"from", "-1"}}, MtErrorCode::out_of_range);
    check({{"from", "0"}}, MtErrorCode::out_of_range);
    check({{"from", "99999999999999999999999"}}, MtErrorCode::out_of_range);
    check({{"count", "0"}}, MtErrorCode::out_of_range);
    check({{"count", "1001"}}, MtErrorCode::out_of_range);
    check({{"count", "x"}}, MtErrorCode::invalid_request);
    check({{"interval", "-5"}}, MtErrorCode::out_of_range);
    check({{"heartbeat", "1"}}, MtErrorCode::out_of_range);
}

TEST_CASE("current parameters and the at and from windows") {
    CurrentParams p;
    CHECK_FALSE(parse_current_params({{"at", "12"}}, 1000, p));
    CHECK(*p.at == 12);
    CurrentParams both;
    auto e = parse_current_params({{"at", "12"}, {"interval", "10"}}, 1000, both);
    REQUIRE(e);
    CHECK(e->code == MtErrorCode::invalid_request);
    CurrentParams bad;
    REQUIRE(parse_current_params({{"at", "x"}}, 1000, bad));
    // part 1 5.5.2: first 12, last 19
    CHECK(check_at(11, 12, 19)->code == MtErrorCode::out_of_range);
    CHECK_FALSE(check_at(12, 12, 19));
    CHECK_FALSE(check_at(19, 12, 19));
    CHECK(check_at(20, 12, 19)->code == MtErrorCode::out_of_range);
    CHECK(check_from(11, 12, 20)->code == MtErrorCode::out_of_range);
    CHECK_FALSE(check_from(20, 12, 20));
    CHECK(check_from(21, 12, 20)->code == MtErrorCode::out_of_range);
    CHECK(http_status(MtErrorCode::no_device) == 404);
    CHECK(http_status(MtErrorCode::out_of_range) == 400);
}

TEST_CASE("error documents validate and carry the Header of part 1") {
    HeaderInfo h;
    h.creation_time = iso_time(1700000000123);
    h.sender = "bridge & co";
    h.instance_id = 42;
    h.buffer_size = 131072;
    const auto doc = error_document(h, {MtError{MtErrorCode::out_of_range, "'from' <bad>"}});
    CHECK(h.creation_time == "2023-11-14T22:13:20.123Z");
    CHECK(doc.find("errorCode=\"OUT_OF_RANGE\"") != std::string::npos);
    CHECK(doc.find("bufferSize=\"131072\"") != std::string::npos);
    CHECK(doc.find("&lt;bad&gt;") != std::string::npos);
    CHECK(validates(doc, "Error"));
}

TEST_CASE("store maps a model: devices and streams documents validate, offline is UNAVAILABLE") {
    BridgeStore store(16, "test", 7);
    store.add_device("mill-01");
    REQUIRE(store.set_model("mill-01", Json::parse(kModel)).ok());
    store.set_state("mill-01", "online");
    store.update("mill-01", "x_position", 12.5, 1700000000000);
    store.update("mill-01", "x_position", 12.5, 1700000000001);  // unchanged: not recorded (5.1.3.5)
    store.update("mill-01", "status", "running", 1700000000002);
    const std::uint64_t last = store.read([](const BridgeState& st) { return st.buffer.last_sequence(); });

    store.read([&](const BridgeState& st) {
        const DeviceEntry* d = st.find_device("mill-01");
        REQUIRE(d);
        CHECK(st.find_device(d->mt.name) == d);
        HeaderInfo h;
        h.creation_time = iso_time(0);
        h.buffer_size = 16;
        const auto devices = devices_document(h, {&d->devices_xml});
        CHECK(validates(devices, "Devices"));
        std::set<std::string> ids;
        CHECK_FALSE(select_data_items(devices, "//DataItem[@type=\"POSITION\"]", ids));
        CHECK(ids == std::set<std::string>{"mill-01.x_position"});  // the terminal id before every id
        ids.clear();
        CHECK(select_data_items(devices, "//DataItem[@type=", ids)->code == MtErrorCode::invalid_path);
        CHECK(select_data_items(devices, "//Nothing", ids)->code == MtErrorCode::invalid_path);

        std::vector<StreamEntry> entries;
        for (ItemIndex i : d->items)
            if (st.buffer.latest()[i]) entries.push_back(StreamEntry{&d->mt, &st.items[i].mt, &*st.buffer.latest()[i]});
        h.first_sequence = st.buffer.first_sequence();
        h.last_sequence = st.buffer.last_sequence();
        h.next_sequence = st.buffer.next_sequence();
        const auto streams = streams_document(h, entries);
        CHECK(streams.find(">12.5</Position>") != std::string::npos);
        CHECK(streams.find(">AVAILABLE</Availability>") != std::string::npos);
        CHECK(validates(streams, "Streams"));
        return 0;
    });

    store.set_state("mill-01", "offline");
    store.read([&](const BridgeState& st) {
        CHECK(st.buffer.last_sequence() > last);
        const DeviceEntry* d = st.find_device("mill-01");
        for (ItemIndex i : d->items) {
            REQUIRE(st.buffer.latest()[i]);
            CHECK(st.buffer.latest()[i]->value.is_null());
            // SHDR says UNAVAILABLE for each
            CHECK(shdr_lines(*d, st.items[i], *st.buffer.latest()[i]).find("|UNAVAILABLE") != std::string::npos);
        }
        return 0;
    });
    // A sample still in flight after "offline" leaves the item UNAVAILABLE.
    store.update("mill-01", "x_position", 99.0, 1700000000010);
    store.read([&](const BridgeState& st) {
        const DeviceEntry* d = st.find_device("mill-01");
        CHECK(st.buffer.latest()[d->by_nclink_id.at("x_position")]->value.is_null());
        return 0;
    });
    store.set_state("mill-01", "online");
    store.update("mill-01", "x_position", 99.0, 1700000000011);
    store.read([&](const BridgeState& st) {
        const DeviceEntry* d = st.find_device("mill-01");
        CHECK(st.buffer.latest()[d->by_nclink_id.at("x_position")]->value == 99.0);
        return 0;
    });
}

TEST_CASE("two devices of one model make one valid document: ids unique, each a device's own") {
    BridgeStore store(64, "test", 7);
    for (const char* dev : {"mill-01", "mill-02"}) {
        store.add_device(dev);
        REQUIRE(store.set_model(dev, Json::parse(kModel)).ok());
        store.set_state(dev, "online");
    }
    store.update("mill-01", "x_position", 1.5, 1700000000000);
    store.update("mill-02", "x_position", 2.5, 1700000000001);
    store.read([&](const BridgeState& st) {
        HeaderInfo h;
        h.creation_time = iso_time(0);
        h.buffer_size = 64;
        std::vector<const std::string*> docs;
        std::vector<StreamEntry> entries;
        for (const auto& d : st.devices) {
            docs.push_back(&d.devices_xml);
            for (ItemIndex i : d.items)
                if (st.buffer.latest()[i]) entries.push_back(StreamEntry{&d.mt, &st.items[i].mt, &*st.buffer.latest()[i]});
        }
        // IDType is xs:ID: xmllint refuses a document with an id twice.
        const auto devices = devices_document(h, docs);
        CHECK(validates(devices, "Devices"));
        CHECK(devices.find(" id=\"mill-01.x_position\"") != std::string::npos);
        CHECK(devices.find(" id=\"mill-02.x_position\"") != std::string::npos);
        const DeviceEntry* second = st.find_device("mill-02");
        REQUIRE(second);
        CHECK(second->by_mtconnect_id.count("mill-02.x_position") == 1);
        CHECK(second->by_mtconnect_id.count("mill-01.x_position") == 0);
        h.last_sequence = st.buffer.last_sequence();
        h.next_sequence = st.buffer.next_sequence();
        const auto streams = streams_document(h, entries);
        CHECK(validates(streams, "Streams"));
        CHECK(streams.find("dataItemId=\"mill-02.x_position\"") != std::string::npos);
        // SHDR keys differ although both Devices have the model's name.
        const ItemEntry& x = st.items[second->by_nclink_id.at("x_position")];
        CHECK(shdr_lines(*second, x, *st.buffer.latest()[x.index]).find("|mill-02:mill-02.x_position|2.5") != std::string::npos);
        return 0;
    });
}

TEST_CASE("current renders a structured value once per observation and follows its changes") {
    const char* model = R"({
      "id": "root", "type": "NC_LINK_ROOT", "version": "1.0",
      "devices": [{"id": "mill", "name": "Mill", "type": "MACHINE", "guid": "mill-01", "version": "1.0",
        "dataItems": [{"id": "tools", "type": "TOOL_TABLE", "datatype": "list"}]}]
    })";
    BridgeStore store(16, "test", 7);
    REQUIRE(store.set_model("mill-01", Json::parse(model)).ok());
    store.set_state("mill-01", "online");
    const MtConnectApi api(store);
    store.update("mill-01", "tools", Json::array({Json{{"id", "T1"}, {"len", 1.5}}}), 1700000000000);
    const std::string first = api.current("", {}).body;
    CHECK(first.find("&quot;T1&quot;") != std::string::npos);
    CHECK(api.current("", {}).body.substr(first.find("<Streams>")) == first.substr(first.find("<Streams>")));
    store.update("mill-01", "tools", Json::array({Json{{"id", "T2"}, {"len", 2.5}}}), 1700000000001);
    const std::string second = api.current("", {}).body;
    CHECK(second.find("&quot;T2&quot;") != std::string::npos);
    CHECK(second.find("&quot;T1&quot;") == std::string::npos);
    CHECK(validates(second, "Streams"));
    // at= an older sequence shows the older value again.
    const std::uint64_t last = store.read([](const BridgeState& st) { return st.buffer.last_sequence(); });
    const std::string older = api.current("", {{"at", std::to_string(last - 1)}}).body;
    CHECK(older.find("&quot;T1&quot;") != std::string::npos);
    CHECK(api.current("", {}).body.find("&quot;T2&quot;") != std::string::npos);
}

TEST_CASE("SHDR lines: timestamp, device-prefixed key, escaped value, PING answered") {
    BridgeStore store(16, "test", 7);
    REQUIRE(store.set_model("mill-01", Json::parse(kModel)).ok());
    store.set_state("mill-01", "online");
    store.update("mill-01", "status", "a|b\nc", 1700000000000);
    store.read([](const BridgeState& st) {
        const DeviceEntry* d = st.find_device("mill-01");
        const ItemEntry& item = st.items[d->by_nclink_id.at("status")];
        const std::string line = shdr_lines(*d, item, *st.buffer.latest()[item.index]);
        // keyed by the Device uuid, which an agent looks up first and which is unique
        CHECK(line.rfind("2023-11-14T22:13:20.000Z|mill-01:mill-01.status|", 0) == 0);
        CHECK(line.back() == '\n');
        CHECK(std::count(line.begin(), line.end(), '\n') == 1);
        CHECK(std::count(line.begin(), line.end(), '|') == 2);
        return 0;
    });
    CHECK(shdr_escape("a|b\r\nc\t") == "a/b  c ");
    CHECK(shdr_answer("* PING", std::chrono::milliseconds(10000)) == "* PONG 10000\n");
    CHECK(shdr_answer("* PING\r", std::chrono::milliseconds(500)) == "* PONG 500\n");
    CHECK(shdr_answer("hello", std::chrono::milliseconds(500)).empty());
}

TEST_CASE("data-write requests parse, and malformed ones are INVALID_REQUEST") {
    GbtApi::WriteRequest w;
    const std::string body =
        R"(<DataWriteRequest><Header version="1.0" sendTime="2024-01-01T00:00:00Z" sender="mes" operationId="7"/>
      <Operation command="SET" description="override"><Value dataItemId="feed_override">80</Value>
      <Value dataItemId="status">"text"</Value></Operation></DataWriteRequest>)";
    REQUIRE_FALSE(GbtApi::parse_write(body, w));
    CHECK(w.sender == "mes");
    REQUIRE(w.values.size() == 2);
    CHECK(w.values[0].value == 80);
    CHECK(w.values[1].value == "text");
    GbtApi::WriteRequest bad;
    CHECK(GbtApi::parse_write("<DataWriteRequest>", bad)->code == MtErrorCode::invalid_request);
    CHECK(GbtApi::parse_write("<Other/>", bad)->code == MtErrorCode::invalid_request);
    CHECK(GbtApi::parse_write(
              "<DataWriteRequest><Operation command=\"DELETE\"><Value dataItemId=\"a\">1</Value></Operation></DataWriteRequest>", bad)
              ->code == MtErrorCode::unsupported);
}

namespace {

BridgeStore::MethodRunUpdate status_of(const std::string& ex, const std::string& call, const std::string& status,
                                       std::optional<double> progress = std::nullopt) {
    BridgeStore::MethodRunUpdate u;
    u.ex = ex;
    u.call = call;
    u.method = "G_HOME";
    u.status = status;
    u.progress = progress;
    return u;
}

BridgeStore::MethodRunUpdate result_of(const std::string& ex, const std::string& call, const std::string& result) {
    BridgeStore::MethodRunUpdate u;
    u.ex = ex;
    u.call = call;
    u.method = "G_HOME";
    u.result = result;
    u.outcome = Json{{"code", "OK"}, {"return", {{"n", 1}}}};
    return u;
}

}  // namespace

TEST_CASE("store activity: one entry per method run, updated by its status and result DTUs") {
    BridgeStore store(16, "test", 7);
    store.add_device("mill-01");
    const std::uint64_t before = store.read([](const BridgeState& st) { return st.activity_sequence; });
    store.record_method_run("mill-01", status_of("mes", "c-1", "executing", 10), 1000);
    store.record_method_run("mill-01", status_of("cam", "c-1", "waiting"), 1001);  // same @id, another caller
    store.record_method_run("mill-01", status_of("mes", "c-1", "executing", 60), 1002);
    store.record_method_run("mill-01", result_of("mes", "c-1", "finished"), 1003);
    store.record_method_run("mill-01", status_of("mes", "c-1", "executing", 70), 1004);  // late: stays finished
    store.record_method_run("mill-99", status_of("mes", "c-2", "executing"), 1005);      // unknown device
    CHECK(store.wait_for_change(std::numeric_limits<std::uint64_t>::max(), std::numeric_limits<std::uint64_t>::max(),
                                std::chrono::milliseconds(0), before));
    store.read([&](const BridgeState& st) {
        const DeviceEntry* d = st.find_device("mill-01");
        REQUIRE(d);
        REQUIRE(d->method_runs.size() == 2);
        const MethodRunEntry& mes = d->method_runs[0];
        CHECK(mes.ex == "mes");
        CHECK(mes.call == "c-1");
        CHECK(mes.method == "G_HOME");
        CHECK(mes.status == "executing");
        CHECK(mes.progress == 60);
        CHECK(mes.result == "finished");
        CHECK(mes.start_ms == 1000);
        CHECK(mes.time_ms == 1004);
        CHECK(d->method_runs[1].ex == "cam");
        CHECK(mes.seq > d->method_runs[1].seq);  // changed last
        CHECK(st.activity_sequence == before + 5);
        const Json j = JsonApi::method_run_json(d->dev, mes);
        CHECK(j["dev"] == "mill-01");
        CHECK(j["result"] == "finished");
        CHECK(j["code"] == "OK");
        CHECK(j["return"] == Json{{"n", 1}});
        CHECK(j["progress"] == 60);
        CHECK_FALSE(JsonApi::method_run_json(d->dev, d->method_runs[1]).contains("result"));
        return 0;
    });
    const std::uint64_t now = store.read([](const BridgeState& st) { return st.activity_sequence; });
    CHECK_FALSE(store.wait_for_change(std::numeric_limits<std::uint64_t>::max(), std::numeric_limits<std::uint64_t>::max(),
                                      std::chrono::milliseconds(0), now));
}

TEST_CASE("store activity: the method-run and event logs keep the newest entries within their bound") {
    BridgeStore store(16, "test", 7, 3);
    CHECK(store.activity_log_size() == 3);
    store.add_device("mill-01");
    for (int i = 1; i <= 5; ++i) {
        store.record_method_run("mill-01", result_of("mes", "c-" + std::to_string(i), "finished"), i);
        EventLogEntry e;
        e.ex = "mes";
        e.event_id = "ev-1";
        e.item = "feed_override";
        e.value = i * 10;
        e.time_ms = i;
        store.record_event("mill-01", e);
    }
    store.record_method_run("mill-01", status_of("mes", "c-1", "executing"), 6);  // c-1 fell out: a new entry
    store.read([&](const BridgeState& st) {
        const DeviceEntry* d = st.find_device("mill-01");
        REQUIRE(d);
        REQUIRE(d->method_runs.size() == 3);
        CHECK(d->method_runs[0].call == "c-4");
        CHECK(d->method_runs[1].call == "c-5");
        CHECK(d->method_runs[2].call == "c-1");
        CHECK(d->method_runs[2].result.empty());
        REQUIRE(d->events.size() == 3);
        CHECK(d->events.front().value == 30);
        CHECK(d->events.back().value == 50);
        const Json j = JsonApi::event_json(d->dev, d->events.back());
        CHECK(j ==
              Json{{"dev", "mill-01"}, {"ex", "mes"}, {"event", "ev-1"}, {"item", "feed_override"}, {"value", 50}, {"time", 5}});
        return 0;
    });
}
