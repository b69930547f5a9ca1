// The index of a loaded model: ids, kinds, owners, component paths, channels.
#include "model_test_util.hpp"

#include <catch2/catch.hpp>

#include <thread>

using namespace nclink;
using nclink::test::model_path;

namespace {

std::shared_ptr<const Model> sim_mill() {
    const LoadResult r = load_model_file(model_path("sim-mill.json"));
    REQUIRE(r.ok());
    return r.model;
}

}  // namespace

TEST_CASE("id lookup gives kind, owning device, parent and component path") {
    const auto m = sim_mill();
    const ObjectInfo* pos = m->find("x_position");
    REQUIRE(pos != nullptr);
    CHECK(pos->kind == ObjectKind::data_item);
    CHECK(pos->device_id == "mill");
    CHECK(pos->parent_id == "axis_x");
    CHECK(pos->path == "/MACHINE@0001/AXIS@X/POSITION");
    CHECK(pos->pointer == "/devices/0/components/0/dataItems/0");

    CHECK(m->find("mill")->kind == ObjectKind::device);
    CHECK(m->find("nclink-sim")->kind == ObjectKind::root);
    CHECK(m->find("axis_x")->kind == ObjectKind::component);
    CHECK(m->find("tools")->kind == ObjectKind::config_item);
    CHECK(m->find("ch_fast")->kind == ObjectKind::sample_channel);
    CHECK(m->find("reset")->kind == ObjectKind::method);
    CHECK(m->find("reset")->device_id.empty());
    CHECK(m->find("reset")->path == "/NC_LINK_ROOT/METHOD");
    CHECK(m->find("nope") == nullptr);

    // Typed lookups refuse the wrong kind.
    CHECK(m->data_object("x_position") != nullptr);
    CHECK(m->data_object("ch_fast") == nullptr);
    CHECK(m->channel("x_position") == nullptr);
    CHECK(m->method("cycle_start") != nullptr);
    CHECK(m->component("axis_x")->number == "X");
    CHECK(m->device("axis_x") == nullptr);

    CHECK(m->owning_device("x_position")->id == "mill");
    CHECK(m->owning_device("mill")->id == "mill");
    CHECK(m->owning_device("reset") == nullptr);
}

TEST_CASE("data objects expose their attributes") {
    const auto m = sim_mill();
    const DataObject* tools = m->data_object("tools");
    REQUIRE(tools != nullptr);
    CHECK(tools->kind == DataKind::list);
    CHECK(tools->setable);
    CHECK(tools->config);
    CHECK(tools->type == "TOOL");
    CHECK_FALSE(tools->value.has_value());
    const DataObject* maker = m->data_object("cnc_manufacturer");
    REQUIRE(maker->value.has_value());
    CHECK(*maker->value == "nclink");
    CHECK(m->data_object("parameters")->kind == DataKind::dict);
    CHECK(m->data_object("x_speed")->units == "mm/min");
    CHECK_FALSE(m->data_object("x_speed")->setable);
    CHECK(m->data_object("feed_override")->setable);
    CHECK(m->data_object("status")->kind == DataKind::single);
    const Json& args = m->method("program_transfer")->args;  // table 6: an array of parameters
    REQUIRE(args.is_array());
    CHECK(args.at(0).at("name") == "operation");
    CHECK(args.at(0).at("default") == "push");
}

TEST_CASE("path lookup lists every id sharing a path, in file order") {
    const auto m = sim_mill();
    CHECK(m->ids_at_path("/MACHINE@0001/AXIS@Y/SPEED") == std::vector<std::string>{"y_speed"});
    CHECK(m->ids_at_path("/NC_LINK_ROOT/METHOD") ==
          std::vector<std::string>{"cycle_start", "feed_hold", "reset", "program_transfer"});
    CHECK(m->ids_at_path("/MACHINE@0001/SAMPLE_CHANNEL") == std::vector<std::string>{"ch_fast", "ch_slow"});
    CHECK(m->ids_at_path("/MACHINE@0001/CONTROLLER/MANUFACTURER") == std::vector<std::string>{"cnc_manufacturer"});
    CHECK(m->ids_at_path("/nowhere").empty());
}

TEST_CASE("channels keep their data items in column order") {
    const auto m = sim_mill();
    const SampleChannel* fast = m->channel("ch_fast");
    REQUIRE(fast != nullptr);
    CHECK(fast->sample_interval_ms == 1);
    CHECK(fast->upload_interval_ms == 100);
    CHECK(fast->device_id == "mill");
    const auto items = m->channel_items("ch_fast");
    REQUIRE(items.size() == 6);
    CHECK(items[0]->id == "x_position");
    CHECK(items[3]->id == "x_speed");
    CHECK(items[5]->id == "z_speed");
    const SampleChannel* slow = m->channel("ch_slow");
    CHECK(slow->sample_interval_ms == 100);
    CHECK(slow->upload_interval_ms == 1000);
    CHECK(m->channel_items("no_channel").empty());
}

TEST_CASE("children lists keep file order for serialization") {
    const auto m = sim_mill();
    const Device& d = m->devices()[0];
    CHECK(d.children.components == std::vector<std::string>{"axis_x", "axis_y", "axis_z", "spindle", "controller"});
    CHECK(d.children.configs.at(4) == "ch_fast");
    CHECK(m->root().children.components == std::vector<std::string>{"mill"});
    CHECK(m->root().children.configs.size() == 4);
}

TEST_CASE("source is kept verbatim and two objects may share a path") {
    const LoadResult r = parse_model(R"({"id":"r","type":"NC_LINK_ROOT","version":"1.0.0",
      "devices":[{"id":"d","type":"MACHINE","guid":"g","version":"1.0.0",
        "components":[{"id":"a1","type":"AXIS","dataItems":[
          {"id":"p1","type":"POSITION","source":"NC_LINK_ROOT:MACHINE#0001:AXIS"},
          {"id":"p2","type":"POSITION"}]}]}]})");
    INFO(nclink::test::describe(r));
    REQUIRE(r.ok());
    CHECK(r.problems.empty());
    CHECK(r.model->data_object("p1")->source == "NC_LINK_ROOT:MACHINE#0001:AXIS");
    CHECK(r.model->find("p1")->source == "NC_LINK_ROOT:MACHINE#0001:AXIS");
    CHECK(r.model->find("p2")->source.empty());
    CHECK(r.model->ids_at_path("/MACHINE/AXIS/POSITION") == std::vector<std::string>{"p1", "p2"});
}

TEST_CASE("dev_uuid: override, else guid, else device id") {
    Device d;
    d.id = "0103";
    CHECK(resolve_dev_uuid(d) == "0103");
    d.guid = "dev_uuid_1";
    CHECK(resolve_dev_uuid(d) == "dev_uuid_1");
    CHECK(resolve_dev_uuid(d, "from-config") == "from-config");
    CHECK(resolve_dev_uuid(sim_mill()->devices()[0]) == "nclink-sim-mill-01");
}

TEST_CASE("a model is safe to read from many threads") {
    const auto m = sim_mill();
    std::vector<std::thread> threads;
    for (int t = 0; t < 4; ++t)
        threads.emplace_back([&m] {
            for (int i = 0; i < 2000; ++i) {
                (void)m->find("x_position");
                (void)m->channel_items("ch_slow");
                (void)m->ids_at_path("/MACHINE@0001/AXIS@Z/POSITION");
            }
        });
    for (auto& th : threads) th.join();
    CHECK(m->find("z_position")->path == "/MACHINE@0001/AXIS@Z/POSITION");
}

TEST_CASE("a loaded model keeps no spare capacity in its object vectors") {
    // A gateway holds one model per machine for as long as it serves it:
    // what the vectors reserved while growing is given back (ModelBuilder::finish).
    const auto model = sim_mill();
    const Model& m = *model;
    REQUIRE(m.data_objects().size() > 8);
    CHECK(m.data_objects().capacity() == m.data_objects().size());
    CHECK(m.objects().capacity() == m.objects().size());
    CHECK(m.components().capacity() == m.components().size());
    CHECK(m.devices().capacity() == m.devices().size());
    CHECK(m.channels().capacity() == m.channels().size());
    CHECK(m.methods().capacity() == m.methods().size());
}
