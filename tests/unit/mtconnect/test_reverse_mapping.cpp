// GB/T 39561.3 appendix A read in reverse (drivers/mtconnect/reverse_mapping.hpp).
#include "support/model_items.hpp"
#include "mtconnect/probe_document.hpp"
#include "mtconnect/reverse_mapping.hpp"

#include <nclink/mapping.hpp>
#include <nclink/model.hpp>

#include <catch2/catch.hpp>

#include <map>
#include <set>
#include <string>

using namespace nclink;
using namespace nclink::mtconnect;

namespace {

const std::string kSimMill = std::string(NCLINK_MODELS_DIR) + "/sim-mill.json";

/// A device as a third-party agent describes it: names and types nclink did not write.
const char* const kForeignProbe = R"(<?xml version="1.0" encoding="UTF-8"?>
<MTConnectDevices xmlns="urn:mtconnect.org:MTConnectDevices:1.3">
  <Header creationTime="2024-01-01T00:00:00Z" sender="agent" instanceId="1700000000" version="1.3.0" bufferSize="131072"/>
  <Devices>
    <Device id="d1" name="VMC" uuid="vmc-3axis-001">
      <Description manufacturer="Acme" model="V5" serialNumber="A-77">Acme vertical mill</Description>
      <DataItems>
        <DataItem category="EVENT" id="avail" type="AVAILABILITY"/>
        <DataItem category="EVENT" id="clock" name="clock" type="CLOCK_TIME"/>
      </DataItems>
      <Components>
        <Axes id="ax">
          <Components>
            <Linear id="X1" name="X">
              <DataItems>
                <DataItem category="SAMPLE" id="Xact" type="POSITION" subType="ACTUAL" units="MILLIMETER"/>
                <DataItem category="SAMPLE" id="Xcmd" type="POSITION" subType="COMMANDED" units="MILLIMETER"/>
                <DataItem category="SAMPLE" id="Xtemp" type="TEMPERATURE" units="CELSIUS"/>
                <DataItem category="CONDITION" id="Xtravel" type="POSITION"/>
              </DataItems>
            </Linear>
            <Rotary id="C1" name="C">
              <DataItems>
                <DataItem category="SAMPLE" id="Srpm" name="Srpm" type="ROTARY_VELOCITY" subType="ACTUAL" units="REVOLUTION/MINUTE"><Source>spindle_speed</Source></DataItem>
                <DataItem category="EVENT" id="Sdir" type="DIRECTION" subType="ROTARY"/>
              </DataItems>
            </Rotary>
          </Components>
        </Axes>
        <Controller id="cont" name="controller">
          <DataItems>
            <DataItem category="CONDITION" id="logic" type="LOGIC_PROGRAM"/>
            <DataItem category="CONDITION" id="system" type="SYSTEM"/>
          </DataItems>
          <Components>
            <Path id="path1" name="path">
              <DataItems>
                <DataItem category="EVENT" id="execution" type="EXECUTION"/>
                <DataItem category="EVENT" id="mode" type="CONTROLLER_MODE"/>
                <DataItem category="EVENT" id="program" type="PROGRAM"/>
                <DataItem category="SAMPLE" id="feed" type="PATH_FEEDRATE" subType="ACTUAL" units="MILLIMETER/SECOND"/>
              </DataItems>
            </Path>
          </Components>
        </Controller>
        <Door id="door1" name="door">
          <DataItems><DataItem category="EVENT" id="doorState" type="DOOR_STATE"/></DataItems>
        </Door>
      </Components>
    </Device>
  </Devices>
</MTConnectDevices>)";

using nclink::test::model_items;

}  // namespace

TEST_CASE("reverse mapping gives back the types, units and ids nclink's own forward mapping wrote") {
    const LoadResult loaded = load_model_file(kSimMill);
    REQUIRE(loaded.ok());
    MappingOptions mo;
    mo.id_prefix = "nclink-sim-mill-01";  // as nclink-bridge writes them
    auto doc = map_to_mtconnect(*loaded.model, mo);
    REQUIRE(doc.ok());
    auto probe = read_probe(doc->xml);
    REQUIRE(probe.ok());
    auto reversed = reverse_map(probe.value());
    REQUIRE(reversed.ok());
    CHECK(reversed->dev_uuid == "nclink-sim-mill-01");

    // The generated model is a model nclink loads.
    const LoadResult again = parse_model(reversed->model.dump());
    for (const auto& p : again.problems)
        if (p.severity == Severity::fatal) FAIL(p.pointer << ": " << p.message);
    REQUIRE(again.ok());

    auto original = mtconnect_mapping(*loaded.model);
    REQUIRE(original.ok());
    const auto back = model_items(reversed->model);
    const auto before = model_items(model_to_json(*loaded.model));
    int compared = 0;
    for (const MtDataItem& mt : original->items()) {
        if (mt.target != MtTarget::data_item && mt.target != MtTarget::fallback) continue;
        INFO(mt.item_id);
        const auto it = back.find(mt.item_id);
        REQUIRE(it != back.end());
        const Json& was = before.at(mt.item_id);
        CHECK(it->second["type"] == was["type"]);
        CHECK(it->second.value("units", "") == was.value("units", ""));
        if (was.contains("value")) CHECK(it->second["value"] == was["value"]);
        ++compared;
    }
    CHECK(compared > 30);
    // The sample channels' items come back in channels (sampleRate, A.4 h),
    // at no less than 100 ms: the sim's 1 ms and 100 ms channels are one.
    const Json& configs = reversed->model["devices"][0]["configs"];
    const Json* channel = nullptr;
    for (const auto& c : configs)
        if (c["type"] == "SAMPLE_CHANNEL") channel = &c;
    REQUIRE(channel);
    CHECK((*channel)["sampleInterval"] == 100);
    CHECK((*channel)["uploadInterval"] == 1000);
    std::set<std::string> sampled;
    for (const auto& i : (*channel)["ids"]) sampled.insert(i["id"].get<std::string>());
    CHECK(sampled.count("x_position"));
    CHECK(sampled.count("spindle_speed"));
    CHECK(sampled.count("status"));
    // AVAILABILITY is the machine link, not an item; nothing else lacks a counterpart.
    REQUIRE(reversed->unmatched.size() == 1);
    CHECK(reversed->unmatched[0].mtconnect == "EVENT AVAILABILITY");
}

TEST_CASE("reverse mapping of a third-party agent's device: rows in reverse, the rest named") {
    auto probe = read_probe(kForeignProbe);
    REQUIRE(probe.ok());
    CHECK(probe->instance_id == "1700000000");
    auto r = reverse_map(probe.value());
    REQUIRE(r.ok());
    const auto items = model_items(r->model);
    const Json& device = r->model["devices"][0];
    CHECK(device["guid"] == "vmc-3axis-001");
    CHECK(device["type"] == "MACHINE");

    CHECK(items.at("Xact")["type"] == "POSITION");
    CHECK(items.at("Xact")["units"] == "mm");
    // Only the subType differs: read as POSITION, with a note.
    CHECK(items.at("Xcmd")["type"] == "POSITION");
    bool noted = false;
    for (const auto& n : r->notes) noted = noted || n.find("Xcmd") != std::string::npos;
    CHECK(noted);
    CHECK(items.at("Xtemp")["type"] == "TEMPERATURE");
    CHECK(items.at("Xtemp")["units"] == "°C");
    // Inside a Rotary axis a spindle's speed; its Source is the SHDR key.
    CHECK(items.at("Srpm")["type"] == "SPINDLE_SPEED");
    CHECK(items.at("Srpm")["units"] == "r/min");
    CHECK(r->find_shdr("spindle_speed") == r->find_mt("Srpm"));
    CHECK(items.at("Sdir")["type"] == "SPINDLE_MODE");
    // The controller's Path folds into the CONTROLLER.
    CHECK(items.at("execution")["type"] == "STATUS");
    CHECK(items.at("mode")["type"] == "WORK_MODE");
    CHECK(items.at("feed")["type"] == "FEED_SPEED");
    CHECK(items.at("feed")["units"] == "mm/s");
    // Conditions become WARNING items; a non-SYSTEM one says what it was.
    CHECK(items.at("system")["type"] == "WARNING");
    CHECK(items.at("logic")["type"] == "WARNING");
    CHECK(items.at("logic")["description"].get<std::string>().find("LOGIC_PROGRAM") != std::string::npos);
    CHECK(items.at("Xtravel")["type"] == "WARNING");
    // Description attributes -> fixed configs.
    CHECK(items.at("d1_manufacturer")["value"] == "Acme");
    CHECK(items.at("d1_serial_number")["value"] == "A-77");
    CHECK(items.at("X1_category")["value"] == "linear");
    CHECK(items.at("C1_category")["value"] == "rotary");
    CHECK(items.at("doorState")["type"] == "DOOR_CLOSED");

    // No counterpart: the type is kept and named in the description, and listed.
    CHECK(items.at("clock")["type"] == "CLOCK_TIME");
    CHECK(items.at("clock")["description"] == "MTConnect EVENT CLOCK_TIME (no NC-Link counterpart)");
    std::set<std::string> unmatched;
    for (const auto& u : r->unmatched) unmatched.insert(u.mt_id);
    CHECK(unmatched == std::set<std::string>{"avail", "clock", "door1"});
    bool door_component = false;
    for (const auto& c : device["components"])
        if (c["id"] == "door1") door_component = c["type"] == "COMPONENT" && c["description"] == "MTConnect Door";
    CHECK(door_component);

    const LoadResult loaded = parse_model(r->model.dump());
    for (const auto& p : loaded.problems)
        if (p.severity == Severity::fatal) FAIL(p.pointer << ": " << p.message);
    CHECK(loaded.ok());

    SECTION("a device chosen by name, and an unknown one") {
        ReverseOptions o;
        o.device = "VMC";
        CHECK(reverse_map(probe.value(), o).ok());
        o.device = "lathe";
        auto none = reverse_map(probe.value(), o);
        REQUIRE_FALSE(none.ok());
        CHECK(none.error().code == ErrorCode::node_not_exists);
    }
}
