// The C embedding API (include/nclink/nclink.h) from its caller's side: bad
// input of every kind gets a code and a message and never a crash, the
// struct_size growth rules hold both ways, and an adapter created from a C
// driver struct starts, takes a push channel, queues rows and notifications,
// and stops. The whole path through a real broker is the C firmware example's
// test (tests/c_firmware/).
#include <nclink/nclink.h>

#include "embed/c_handles.hpp"  // the Adapter behind a handle: to change its model

#include <catch2/catch.hpp>

#include <atomic>
#include <cstring>
#include <fstream>
#include <iterator>
#include <mutex>
#include <string>
#include <vector>

namespace {

const std::string kModels = NCLINK_MODELS_DIR;
// The simulated mill's model: ch_fast has 6 items.
const std::string kMill = kModels + "/sim-mill.json";
const char* const kConfig = R"({"broker": {"url": "tcp://127.0.0.1:1"}, "sampling": {"push_channels": ["ch_fast"]}})";

// A driver answering every point with 1.5; create() refuses when its
// configuration says {"refuse": true}.
std::atomic<int> g_instances{0};
int create(const char* config_json, const nclink_host*, void** instance, const nclink_text_output* reason) {
    if (std::strstr(config_json, "\"refuse\":true") != nullptr) {
        reason->put(reason->context, "no CNC on the bus", 17);
        return NCLINK_E_UNAVAILABLE;
    }
    ++g_instances;
    *instance = &g_instances;
    return NCLINK_OK;
}
void destroy(void*) { --g_instances; }
void read_points(void*, const nclink_read_request* request, const nclink_read_output* out) {
    for (size_t i = 0; i < request->count; ++i) out->float64(out->context, i, 1.5);
}

nclink_driver_descriptor good_driver() {
    nclink_driver_descriptor d{};
    d.abi_version = NCLINK_DRIVER_ABI_VERSION;
    d.struct_size = sizeof d;
    d.name = "c-api-test";
    d.version = "1";
    d.create = create;
    d.destroy = destroy;
    d.read = read_points;
    return d;
}

struct Made {
    int code = -1;
    nclink_error error = NCLINK_ERROR_INIT;
    nclink_adapter* adapter = nullptr;
    ~Made() { nclink_adapter_destroy(adapter); }
};

void make(Made& m, const char* config_json, const std::string& model, const nclink_driver_descriptor* driver) {
    nclink_adapter_options o = NCLINK_ADAPTER_OPTIONS_INIT;
    o.config_json = config_json;
    o.model_path = model.empty() ? nullptr : model.c_str();
    o.driver = driver;
    m.code = nclink_adapter_create(&o, &m.adapter, &m.error);
}

}  // namespace

TEST_CASE("NULL handles and pointers answer 102 (Parameter Missing) and never crash") {
    nclink_error e = NCLINK_ERROR_INIT;
    CHECK(nclink_adapter_start(nullptr, &e) == NCLINK_E_PARAMETER_MISSING);
    CHECK(e.code == NCLINK_E_PARAMETER_MISSING);
    CHECK(std::string(e.message) == "adapter is NULL");
    CHECK(nclink_adapter_start(nullptr, nullptr) == NCLINK_E_PARAMETER_MISSING);  // no error struct: the code alone
    CHECK(nclink_adapter_stop(nullptr, 0) == NCLINK_E_PARAMETER_MISSING);
    nclink_adapter_destroy(nullptr);
    CHECK(nclink_adapter_state(nullptr) == -1);
    nclink_channel* channel = reinterpret_cast<nclink_channel*>(1);
    CHECK(nclink_adapter_push_channel(nullptr, "ch_fast", &channel, &e) == NCLINK_E_PARAMETER_MISSING);
    CHECK(channel == nullptr);
    CHECK(nclink_adapter_push_channel(nullptr, "ch_fast", nullptr, &e) == NCLINK_E_PARAMETER_MISSING);
    nclink_value v{};
    CHECK(nclink_channel_push(nullptr, &v, 1, 0) == NCLINK_E_PARAMETER_MISSING);
    CHECK(nclink_channel_points(nullptr) == 0);
    nclink_channel_release(nullptr);
    CHECK(nclink_adapter_notify(nullptr, "status", &v) == NCLINK_E_PARAMETER_MISSING);
    CHECK(nclink_adapter_notify_json(nullptr, "status", "1") == NCLINK_E_PARAMETER_MISSING);

    nclink_adapter* adapter = reinterpret_cast<nclink_adapter*>(1);
    CHECK(nclink_adapter_create(nullptr, &adapter, &e) == NCLINK_E_PARAMETER_MISSING);
    CHECK(adapter == nullptr);
    CHECK(std::string(e.message) == "options is NULL");
    nclink_adapter_options o = NCLINK_ADAPTER_OPTIONS_INIT;
    CHECK(nclink_adapter_create(&o, nullptr, &e) == NCLINK_E_PARAMETER_MISSING);
    o.config_json = kConfig;
    CHECK(nclink_adapter_create(&o, &adapter, &e) == NCLINK_E_PARAMETER_MISSING);  // no driver
    CHECK(std::string(e.message) == "options.driver is NULL");
    CHECK(adapter == nullptr);
}

TEST_CASE("a wrong struct_size is refused with 405 and a message naming the struct") {
    const nclink_driver_descriptor driver = good_driver();
    for (const std::uint32_t size : {0u, 4u, static_cast<std::uint32_t>(sizeof(nclink_adapter_options) - 1), 1u << 20}) {
        nclink_adapter_options o = NCLINK_ADAPTER_OPTIONS_INIT;
        o.struct_size = size;
        o.config_json = kConfig;
        o.driver = &driver;
        nclink_error e = NCLINK_ERROR_INIT;
        nclink_adapter* adapter = nullptr;
        INFO(size);
        CHECK(nclink_adapter_create(&o, &adapter, &e) == NCLINK_E_VALUE_TYPE);
        CHECK(adapter == nullptr);
        CHECK_THAT(e.message, Catch::StartsWith("nclink_adapter_options.struct_size is " + std::to_string(size)));
    }
    SECTION("the driver's descriptor too, and its ABI version") {
        nclink_driver_descriptor d = good_driver();
        d.struct_size = 8;
        Made m;
        make(m, kConfig, kMill, &d);
        CHECK(m.code == NCLINK_E_VALUE_TYPE);
        CHECK_THAT(m.error.message, Catch::StartsWith("nclink_driver_descriptor.struct_size is 8"));
        d = good_driver();
        d.abi_version = 1;
        Made old;
        make(old, kConfig, kMill, &d);
        CHECK(old.code == NCLINK_E_VALUE_TYPE);
        CHECK_THAT(old.error.message, Catch::Contains("driver ABI version 1 is not supported (this nclink loads version 2)"));
    }
    SECTION("an nclink_error of an older, shorter layout gets only what it has room for") {
        struct {
            nclink_error e;
            char guard[8];
        } shorter;
        std::memset(&shorter, 'G', sizeof shorter);
        shorter.e.struct_size = offsetof(nclink_error, message) + 16;  // a 16-byte message array
        nclink_adapter* adapter = nullptr;
        CHECK(nclink_adapter_create(nullptr, &adapter, &shorter.e) == NCLINK_E_PARAMETER_MISSING);
        CHECK(shorter.e.code == NCLINK_E_PARAMETER_MISSING);
        CHECK(std::string(shorter.e.message) == "options is NULL");  // 15 bytes + NUL fit exactly
        CHECK(shorter.e.message[16] == 'G');                         // nothing written past its struct_size
        shorter.e.struct_size = 2;                                   // too short even for the code: untouched
        shorter.e.code = 7;
        CHECK(nclink_adapter_create(nullptr, &adapter, &shorter.e) == NCLINK_E_PARAMETER_MISSING);
        CHECK(shorter.e.code == 7);
    }
    SECTION("an options struct of an older, shorter layout: the fields it lacks keep their defaults") {
        nclink_adapter_options o = NCLINK_ADAPTER_OPTIONS_INIT;
        o.config_json = kConfig;
        o.model_path = kMill.c_str();
        o.driver = &driver;
        o.log = [](void*, int, const char*) { FAIL("a log callback past struct_size was used"); };
        o.struct_size = offsetof(nclink_adapter_options, log);  // as if log/log_context came later
        // (Still refused: the first published layout has log and log_context.)
        nclink_error e = NCLINK_ERROR_INIT;
        nclink_adapter* adapter = nullptr;
        CHECK(nclink_adapter_create(&o, &adapter, &e) == NCLINK_E_VALUE_TYPE);
        o.struct_size = sizeof o + 64;  // a newer caller: fields we do not know are ignored
        o.log = nullptr;
        struct Bigger {
            nclink_adapter_options o;
            char newer[64];
        } bigger{};
        bigger.o = o;
        CHECK(nclink_adapter_create(&bigger.o, &adapter, &e) == NCLINK_OK);
        nclink_adapter_destroy(adapter);
    }
}

TEST_CASE("a configuration with unknown keys, bad types or no JSON at all is refused with its code and message") {
    const nclink_driver_descriptor driver = good_driver();
    Made unknown;
    make(unknown, R"({"brokr": {"url": "tcp://127.0.0.1:1"}})", kMill, &driver);
    CHECK(unknown.code == NCLINK_E_UNKNOWN_KEYS);
    CHECK(unknown.adapter == nullptr);
    CHECK_THAT(unknown.error.message, Catch::Contains("brokr"));
    Made nested;
    make(nested, R"({"sampling": {"push_chanels": []}})", kMill, &driver);
    CHECK(nested.code == NCLINK_E_UNKNOWN_KEYS);
    CHECK_THAT(nested.error.message, Catch::Contains("push_chanels"));
    Made typed;
    make(typed, R"({"strict": "yes"})", kMill, &driver);
    CHECK(typed.code == NCLINK_E_VALUE_TYPE);
    Made text;
    make(text, "{not json", kMill, &driver);
    CHECK(text.code == NCLINK_E_SYNTAX);
    CHECK(std::string(text.error.message) == "config_json is not JSON text");
    Made plugin;
    make(plugin, R"({"driver": {"plugin": "x.so"}})", kMill, &driver);
    CHECK(plugin.code == NCLINK_E_UNKNOWN_KEYS);
    CHECK_THAT(plugin.error.message, Catch::Contains("the driver is options.driver"));
    Made no_model;
    make(no_model, "{}", "", &driver);
    CHECK(no_model.code == NCLINK_E_PARAMETER_MISSING);

    SECTION("exactly one of config_json and config_path") {
        nclink_adapter_options o = NCLINK_ADAPTER_OPTIONS_INIT;
        o.driver = &driver;
        nclink_error e = NCLINK_ERROR_INIT;
        nclink_adapter* adapter = nullptr;
        CHECK(nclink_adapter_create(&o, &adapter, &e) == NCLINK_E_PARAMETER_MISSING);
        o.config_json = "{}";
        o.config_path = "/nonexistent/adapter.json";
        CHECK(nclink_adapter_create(&o, &adapter, &e) == NCLINK_E_PARAMETER_MISSING);
        CHECK_THAT(e.message, Catch::Contains("not both"));
        o.config_json = nullptr;
        CHECK(nclink_adapter_create(&o, &adapter, &e) != NCLINK_OK);  // a file that is not there
        CHECK_THAT(e.message, Catch::Contains("/nonexistent/adapter.json"));
        CHECK(adapter == nullptr);
    }
    SECTION("a long message is cut at 511 bytes on a character boundary") {
        std::string key;
        while (key.size() < 800) key += "\xe8\xbd\xb4";  // 轴, 3 bytes each
        Made long_key;
        make(long_key, ("{\"" + key + "\": 1}").c_str(), kMill, &driver);
        CHECK(long_key.code == NCLINK_E_UNKNOWN_KEYS);
        const std::string message = long_key.error.message;
        CHECK(message.size() <= 511);
        CHECK(message.size() >= 508);
        const auto at = message.find('\xe8');
        REQUIRE(at != std::string::npos);
        CHECK((message.size() - at) % 3 == 0);  // whole characters only
    }
}

TEST_CASE("a model that does not validate is refused by start with 412 and the problems") {
    const nclink_driver_descriptor driver = good_driver();
    for (const char* bad : {"/invalid/not-json.json", "/invalid/missing-devices.json", "/invalid/duplicate-id.json"}) {
        INFO(bad);
        Made m;
        make(m, kConfig, kModels + bad, &driver);
        REQUIRE(m.code == NCLINK_OK);
        nclink_error e = NCLINK_ERROR_INIT;
        CHECK(nclink_adapter_start(m.adapter, &e) == NCLINK_E_SYNTAX);
        CHECK(e.code == NCLINK_E_SYNTAX);
        CHECK(std::strlen(e.message) > 0);
        CHECK(nclink_adapter_stop(m.adapter, 0) == NCLINK_OK);
    }
    Made missing;
    make(missing, kConfig, "/nonexistent/model.json", &driver);
    REQUIRE(missing.code == NCLINK_OK);
    nclink_error e = NCLINK_ERROR_INIT;
    CHECK(nclink_adapter_start(missing.adapter, &e) != NCLINK_OK);
    CHECK_THAT(e.message, Catch::Contains("/nonexistent/model.json"));
}

TEST_CASE("a driver whose create() refuses makes create fail with the driver's code and reason") {
    const nclink_driver_descriptor driver = good_driver();
    Made m;
    make(m, R"({"driver": {"config": {"refuse": true}}})", kMill, &driver);
    CHECK(m.code == NCLINK_E_UNAVAILABLE);
    CHECK(m.adapter == nullptr);
    CHECK_THAT(m.error.message, Catch::Contains("no CNC on the bus"));
    nclink_driver_descriptor no_read = good_driver();
    no_read.read = nullptr;
    Made r;
    make(r, kConfig, kMill, &no_read);
    CHECK(r.code == NCLINK_E_PARAMETER_MISSING);
    CHECK_THAT(r.error.message, Catch::Contains("lacks required function(s): read"));
}

TEST_CASE("an adapter from a C driver starts, pushes rows, takes notifications, logs, stops and destroys its driver") {
    const nclink_driver_descriptor driver = good_driver();
    struct Log {
        std::mutex mutex;
        std::vector<std::string> lines;
    } log;
    nclink_adapter_options o = NCLINK_ADAPTER_OPTIONS_INIT;
    o.config_json = kConfig;
    o.model_path = kMill.c_str();
    o.driver = &driver;
    o.log_context = &log;
    o.log = [](void* context, int level, const char* message) {
        auto* l = static_cast<Log*>(context);
        std::lock_guard<std::mutex> lock(l->mutex);
        l->lines.push_back(std::to_string(level) + " " + message);
    };
    nclink_error e = NCLINK_ERROR_INIT;
    nclink_adapter* adapter = nullptr;
    const int before = g_instances;
    REQUIRE(nclink_adapter_create(&o, &adapter, &e) == NCLINK_OK);
    CHECK(e.code == 0);
    CHECK(std::string(e.message).empty());
    CHECK(g_instances == before + 1);  // the driver's create() ran
    CHECK(nclink_adapter_state(adapter) == NCLINK_STATE_INITIAL);

    nclink_channel* channel = nullptr;
    CHECK(nclink_adapter_push_channel(adapter, "ch_fast", &channel, &e) == NCLINK_E_UNAVAILABLE);  // not started
    REQUIRE(nclink_adapter_start(adapter, &e) == NCLINK_OK);  // the broker is unreachable: retried in the background

    CHECK(nclink_adapter_push_channel(adapter, "nope", &channel, &e) == NCLINK_E_NODE_NOT_EXISTS);
    CHECK(nclink_adapter_push_channel(adapter, "ch_slow", &channel, &e) == NCLINK_E_VALUE_TYPE);  // not push-mode
    CHECK(nclink_adapter_push_channel(adapter, "ch_fast", nullptr, &e) == NCLINK_E_PARAMETER_MISSING);
    REQUIRE(nclink_adapter_push_channel(adapter, "ch_fast", &channel, &e) == NCLINK_OK);
    REQUIRE(nclink_channel_points(channel) == 6);
    nclink_value row[6];
    for (auto& v : row) {
        v.kind = NCLINK_VALUE_FLOAT64;
        v.as.float64 = 2.5;
    }
    row[5].kind = NCLINK_VALUE_TEXT;
    row[5].as.text = "running";
    row[5].length = 7;
    CHECK(nclink_channel_push(channel, row, 6, 0) == NCLINK_OK);
    CHECK(nclink_channel_push(channel, row, 6, 1764000000000000000LL) == NCLINK_OK);
    CHECK(nclink_channel_push(channel, row, 5, 0) == NCLINK_E_UNAVAILABLE);  // wrong count
    CHECK(nclink_channel_push(channel, nullptr, 6, 0) == NCLINK_E_PARAMETER_MISSING);
    row[2].kind = 99;
    CHECK(nclink_channel_push(channel, row, 6, 0) == NCLINK_E_UNAVAILABLE);  // unknown kind: not queued
    row[2].kind = NCLINK_VALUE_TEXT;
    row[2].as.text = nullptr;
    row[2].length = 3;
    CHECK(nclink_channel_push(channel, row, 6, 0) == NCLINK_E_UNAVAILABLE);  // NULL text with a length

    nclink_value v{};
    v.kind = NCLINK_VALUE_TEXT;
    v.as.text = "running";
    v.length = 7;
    CHECK(nclink_adapter_notify(adapter, "status", &v) == NCLINK_OK);
    v.kind = 42;
    CHECK(nclink_adapter_notify(adapter, "status", &v) == NCLINK_E_VALUE_TYPE);
    v.kind = NCLINK_VALUE_JSON;
    v.as.text = "{broken";
    v.length = 7;
    CHECK(nclink_adapter_notify(adapter, "alarm", &v) == NCLINK_E_SYNTAX);
    CHECK(nclink_adapter_notify(adapter, nullptr, &v) == NCLINK_E_PARAMETER_MISSING);
    CHECK(nclink_adapter_notify_json(adapter, "alarm", R"({"code": 1})") == NCLINK_OK);
    CHECK(nclink_adapter_notify_json(adapter, "alarm", "{broken") == NCLINK_E_SYNTAX);

    CHECK(nclink_adapter_stop(adapter, 100) == NCLINK_OK);
    CHECK(nclink_adapter_stop(adapter, 100) == NCLINK_OK);  // idempotent
    row[2].kind = NCLINK_VALUE_NULL;
    CHECK(nclink_channel_push(channel, row, 6, 0) == NCLINK_E_UNAVAILABLE);  // the adapter stopped
    nclink_adapter_destroy(adapter);
    CHECK(g_instances == before);                                            // the driver's destroy() ran
    CHECK(nclink_channel_push(channel, row, 6, 0) == NCLINK_E_UNAVAILABLE);  // a handle outlives its adapter
    nclink_channel_release(channel);
    std::lock_guard<std::mutex> lock(log.mutex);
    CHECK_FALSE(log.lines.empty());
}

TEST_CASE("nclink_error_message names table-19 codes") {
    CHECK(std::string(nclink_error_message(0)) == "OK");
    CHECK(std::string(nclink_error_message(401)) == "Node not exists");
    CHECK(std::string(nclink_error_message(412)) == "syntax error");
    CHECK(std::string(nclink_error_message(-7)) == "vendor error");
    CHECK(std::string(nclink_error_message(999)) == "unknown error");
}

TEST_CASE("a push channel handle follows a model change: the replanned channel is swapped in at the next push") {
    const nclink_driver_descriptor driver = good_driver();
    Made m;
    make(m, kConfig, kMill, &driver);
    REQUIRE(m.code == NCLINK_OK);
    nclink_error e = NCLINK_ERROR_INIT;
    REQUIRE(nclink_adapter_start(m.adapter, &e) == NCLINK_OK);
    nclink_channel* channel = nullptr;
    REQUIRE(nclink_adapter_push_channel(m.adapter, "ch_fast", &channel, &e) == NCLINK_OK);
    nclink_value row[6] = {};
    CHECK(nclink_channel_push(channel, row, 6, 0) == NCLINK_OK);

    std::ifstream in(kMill);
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    auto replaced = m.adapter->adapter->replace_model(text);  // as a Probe/Set does
    REQUIRE(replaced.ok());
    // The channel taken before was retired with the old model; the handle
    // now pushes into the new one.
    CHECK(nclink_channel_push(channel, row, 6, 0) == NCLINK_OK);
    CHECK(nclink_channel_push(channel, row, 6, 0) == NCLINK_OK);
    CHECK(nclink_channel_points(channel) == 6);
    nclink_adapter_stop(m.adapter, 100);
    nclink_channel_release(channel);
}
