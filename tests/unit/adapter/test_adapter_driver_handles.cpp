// The driver contract at the adapter: ids resolved to handles once per
// model (Driver::bind), reads and writes carrying them, points the driver
// does not serve answered without a call, link() gating the driver, and a
// driver's error code and reason reaching the wire unchanged (docs/wire.md,
// "Vendor errors"), from a C++ driver and from a C plugin.
#include "support/adapter_fixture.hpp"

#include <algorithm>
#include <fstream>

using namespace nclink;
using namespace nclink::test;

namespace {

// FakeDriver with handles: "pos" is 1, "ovr" is 2, "status" not served;
// every other point by id. Records what each call got.
class BindingDriver final : public FakeDriver {
public:
    Result<void> bind(const std::vector<BindPoint>& points, std::vector<PointHandle>& handles) override {
        std::lock_guard<std::mutex> lock(mutex);
        ++binds;
        bound_ids.clear();
        for (std::size_t i = 0; i < points.size(); ++i) {
            bound_ids.push_back(points[i].id);
            if (points[i].id == "pos") handles[i] = 1;
            if (points[i].id == "ovr") handles[i] = 2;
            if (points[i].id == "status") handles[i] = not_served;
            if (points[i].id == "m_start" && points[i].method) handles[i] = 99;
            if (points[i].id == "temp") handles[i] = 3;
        }
        if (refuse_next) return make_error(ErrorCode::value_type, "this firmware has no TEMPERATURE sensor");
        return ok_result();
    }
    void read(const std::vector<PointRef>& points, std::vector<Result<Json>>& results) override {
        {
            std::lock_guard<std::mutex> lock(mutex);
            for (const auto& p : points) read_handles.emplace_back(p.id, p.handle);
        }
        FakeDriver::read(points, results);
        for (std::size_t i = 0; i < points.size(); ++i) {
            if (points[i].handle == 1 && vendor_fault) results[i] = vendor_error(-7, "spindle drive fault E7");
            if (points[i].handle == 3) results[i] = Json(21.5);
        }
    }
    Result<void> write(const WriteRequest& request) override {
        {
            std::lock_guard<std::mutex> lock(mutex);
            write_handles.emplace_back(request.id, request.handle);
        }
        if (request.handle == 2 && vendor_fault) return vendor_error(-12, "axis clamp engaged");
        if (request.handle == 2 && table_fault)
            return make_error(ErrorCode::out_of_range, "override above 120 % is locked by the PLC");
        return FakeDriver::write(request);
    }
    MachineLinkStatus link() const override {
        if (link_down) return {MachineLink::disconnected, "CNC cable unplugged"};
        return {MachineLink::connected, {}};
    }

    int binds = 0;
    bool refuse_next = false;
    std::atomic<bool> vendor_fault{false};
    std::atomic<bool> table_fault{false};
    std::atomic<bool> link_down{false};
    std::vector<std::string> bound_ids;
    std::vector<std::pair<std::string, PointHandle>> read_handles;
    std::vector<std::pair<std::string, PointHandle>> write_handles;
};

struct HandleFixture : AdapterFixture {
    HandleFixture() : AdapterFixture({}, false) {
        driver = binding;
        start();
    }
    std::shared_ptr<BindingDriver> binding = std::make_shared<BindingDriver>();
};

}  // namespace

TEST_CASE("bind runs once per model: every driver point and method, SDK-held items left out") {
    HandleFixture f;
    std::lock_guard<std::mutex> lock(f.binding->mutex);
    CHECK(f.binding->binds == 1);
    const auto& ids = f.binding->bound_ids;
    for (const char* id : {"pos", "status", "ovr", "tools", "params", "m_start"})
        CHECK(std::find(ids.begin(), ids.end(), id) != ids.end());
    CHECK(std::find(ids.begin(), ids.end(), "maker") == ids.end());  // a fixed value: the SDK's
}

TEST_CASE("query and set hand the driver its handles, a point it does not serve answers 202 without a call") {
    HandleFixture f;
    const Json r = f.query(Json::array({Json{{"id", "pos"}}, Json{{"id", "status"}}, Json{{"id", "tools"}}}));
    const Json& v = r["values"];
    CHECK(v[0]["values"] == Json::array({12.5}));
    CHECK(v[1]["error"] == 202);
    CHECK(v[1]["privateInfo"]["message"] == "the driver does not serve status");
    CHECK(v[2]["code"] == "OK");
    const Json s = f.set(Json::array({Json{{"id", "ovr"}, {"params", {{"value", 90}}}}}));
    CHECK(s["results"][0]["code"] == "OK");
    CHECK(f.driver->value("ovr") == 90);
    std::lock_guard<std::mutex> lock(f.binding->mutex);
    using Seen = std::pair<std::string, PointHandle>;
    const auto& reads = f.binding->read_handles;
    CHECK(std::find(reads.begin(), reads.end(), Seen{"pos", 1}) != reads.end());
    CHECK(std::find(reads.begin(), reads.end(), Seen{"tools", no_handle}) != reads.end());
    for (const auto& [id, handle] : reads) CHECK(id != "status");  // never asked
    CHECK(f.binding->write_handles == std::vector<Seen>{{"ovr", 2}});
}

TEST_CASE("a model change binds again, a refused bind keeps the model in force") {
    HandleFixture f;
    Json model = Json::parse(std::ifstream(test_model_path()));
    model["devices"][0]["version"] = "1.1.0";
    model["devices"][0]["dataItems"].push_back(Json{{"id", "temp"}, {"type", "TEMPERATURE"}});
    SECTION("taken: the new point is read by its new handle") {
        const Json r = f.app->request("Probe/Set/Request/test-dev/app", "Probe/Set/Response/test-dev/app",
                                      Json{{"@id", "ps"}, {"guid", "test-dev"}, {"probe", model}});
        CHECK(r["code"] == "OK");
        {
            std::lock_guard<std::mutex> lock(f.binding->mutex);
            CHECK(f.binding->binds == 2);
        }
        CHECK(f.query(Json::array({Json{{"id", "temp"}}}))["values"][0]["values"] == Json::array({21.5}));
    }
    SECTION("refused: the driver's code and reason answer the Probe/Set") {
        {
            std::lock_guard<std::mutex> lock(f.binding->mutex);
            f.binding->refuse_next = true;
        }
        const Json r = f.app->request("Probe/Set/Request/test-dev/app", "Probe/Set/Response/test-dev/app",
                                      Json{{"@id", "ps"}, {"guid", "test-dev"}, {"probe", model}});
        CHECK(r["code"] == "NG");
        CHECK(r["error"] == 405);
        CHECK(r["privateInfo"]["message"] == "this firmware has no TEMPERATURE sensor");
        CHECK(f.adapter->model()->data_object("temp") == nullptr);
        CHECK(f.query(Json::array({Json{{"id", "pos"}}}))["values"][0]["values"] == Json::array({12.5}));
    }
}

TEST_CASE("a C++ driver's vendor code and reason reach the Query and Set answers unchanged") {
    HandleFixture f;
    f.binding->vendor_fault = true;
    const Json q = f.query(Json::array({Json{{"id", "pos"}}}));
    CHECK(q["values"][0] == Json{{"id", "pos"},
                                 {"code", "NG"},
                                 {"error", -7},
                                 {"reason", "spindle drive fault E7"},
                                 {"privateInfo", {{"message", "spindle drive fault E7"}}}});
    const Json s = f.set(Json::array({Json{{"id", "ovr"}, {"params", {{"value", 90}}}}}));
    CHECK(s["results"][0]["error"] == -12);
    CHECK(s["results"][0]["reason"] == "axis clamp engaged");
    f.binding->vendor_fault = false;
    f.binding->table_fault = true;
    const Json t = f.set(Json::array({Json{{"id", "ovr"}, {"params", {{"value", 90}}}}}));
    CHECK(t["results"][0]["error"] == 101);
    CHECK(t["results"][0]["reason"] == "Out of Range");  // table 19's words
    CHECK(t["results"][0]["privateInfo"]["message"] == "override above 120 % is locked by the PLC");
}

TEST_CASE("while link() says disconnected the driver is not called and items say why") {
    HandleFixture f;
    f.binding->link_down = true;
    const Json q = f.query(Json::array({Json{{"id", "pos"}}, Json{{"id", "maker"}}}));
    CHECK(q["values"][0]["error"] == 202);
    CHECK(q["values"][0]["privateInfo"]["message"] == "machine disconnected: CNC cable unplugged");
    CHECK(q["values"][1]["code"] == "OK");  // the SDK's own items still answer
    const auto stats = f.adapter->stats();
    CHECK(stats.machine_link.state == MachineLink::disconnected);
    CHECK(stats.machine_link.reason == "CNC cable unplugged");
}

TEST_CASE("a C plugin's vendor code and reason reach the Query and Set answers unchanged") {
    AdapterFixture f({}, false);
    f.driver = nullptr;
    f.config.driver_plugin = std::string(NCLINK_TEST_PLUGIN_DIR) + "/c_counter.so";
    f.config.driver_config = Json{{"vendor_id", "ovr"}};
    f.start();
    const Json q = f.query(Json::array({Json{{"id", "ovr"}}, Json{{"id", "pos"}}}));
    CHECK(q["values"][0]["error"] == -7);
    CHECK(q["values"][0]["reason"] == "spindle drive fault E7");
    CHECK(q["values"][1]["code"] == "OK");  // the counter
    const Json s = f.set(Json::array({Json{{"id", "ovr"}, {"params", {{"value", 90}}}}}));
    CHECK(s["results"][0]["error"] == -12);
    CHECK(s["results"][0]["reason"] == "axis clamp engaged");
}
