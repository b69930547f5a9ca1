// What an MTConnect agent makes of the bridge's SHDR (docs/bridge.md
// "SHDR"): the bridge's /probe as the agent's Devices file, the bridge's SHDR
// lines as its adapter, read by support/shdr_agent.hpp (the agent's
// documented SHDR reading). Every item the bridge shows in /current must
// show the same in the agent, the list and dict items (tool table, machine
// parameters, work coordinate systems: EVENT MESSAGE x:<type>) included.
#include "bridge/bridge_store.hpp"
#include "bridge/mtconnect_api.hpp"
#include "bridge/mtconnect_documents.hpp"
#include "bridge/shdr.hpp"

#include "support/shdr_agent.hpp"

#include <catch2/catch.hpp>
#include <libxml/parser.h>
#include <libxml/tree.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <map>
#include <sstream>

using namespace nclink;
using namespace nclink::bridge;
using nclink::test::ShdrAgent;

namespace {

Json sim_mill_model() {
    std::ifstream in(std::string(NCLINK_MODELS_DIR) + "/sim-mill.json");
    REQUIRE(in);
    std::stringstream text;
    text << in.rdbuf();
    return Json::parse(text.str());
}

/// dataItemId -> observation element text (conditions: the element name in
/// lower case, "normal", "fault", ...) of a Streams document.
std::map<std::string, std::string> observations(const std::string& streams) {
    std::map<std::string, std::string> out;
    std::unique_ptr<xmlDoc, void (*)(xmlDocPtr)> doc(
        xmlReadMemory(streams.data(), static_cast<int>(streams.size()), "s.xml", "UTF-8", XML_PARSE_NONET), xmlFreeDoc);
    REQUIRE(doc);
    std::function<void(const xmlNode*, bool)> walk = [&](const xmlNode* n, bool condition) {
        for (; n; n = n->next) {
            if (n->type != XML_ELEMENT_NODE) continue;
            const std::string name = reinterpret_cast<const char*>(n->name);
            xmlChar* id = xmlGetProp(n, reinterpret_cast<const xmlChar*>("dataItemId"));
            if (id) {
                std::string text;
                if (condition) {
                    text = name;
                    for (auto& c : text) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
                } else {
                    xmlChar* content = xmlNodeGetContent(n);
                    text = content ? reinterpret_cast<const char*>(content) : "";
                    xmlFree(content);
                }
                out[reinterpret_cast<const char*>(id)] = text;
                xmlFree(id);
                continue;
            }
            walk(n->children, condition || name == "Condition");
        }
    };
    walk(xmlDocGetRootElement(doc.get()), false);
    return out;
}

/// A value of the right kind for every item of `dev`, the list and dict ones
/// with '|', quotes and backslashes in their text.
void fill(BridgeStore& store, const std::string& dev, std::int64_t time) {
    std::vector<std::pair<std::string, Json>> values;
    store.read([&](const BridgeState& st) {
        const DeviceEntry* d = st.find_device(dev);
        REQUIRE(d);
        for (ItemIndex i : d->items) {
            const ItemEntry& item = st.items[i];
            if (item.availability || item.constant) continue;
            Json v;
            switch (item.mt.value_form) {
                case MtValueForm::number: v = 12.5; break;
                case MtValueForm::integer: v = 7; break;
                case MtValueForm::enumerated: v = item.mt.values.empty() ? Json("x") : Json(item.mt.values.front().first); break;
                case MtValueForm::condition: v = Json::array({Json{{"number", 1001}, {"text", "Spindle | overload"}}}); break;
                case MtValueForm::text: v = "text of " + item.nclink_id; break;
            }
            values.emplace_back(item.nclink_id, v);
        }
        return 0;
    });
    for (auto& [id, v] : values) {
        if (id == "tools")
            v = Json::array({Json{{"id", "T1"}, {"length", 101.5}, {"name", "end mill | 10 \"HSS\""}},
                             Json{{"id", "T2"}, {"length", 88.25}, {"name", "drill \\ 6"}}});
        if (id == "parameters") v = Json{{"1001", 12}, {"feed_max", 6000.5}, {"name", "a|b"}};
        if (id == "coordinates") v = Json::array({Json{{"id", "G54"}, {"x", -100.5}, {"y", 20}, {"z", 0}}});
        store.update(dev, id, v, time);
    }
}

/// The same value: equal text, or numbers equal to 1e-9 (the agent writes a
/// value it converted from nativeUnits with its own digits).
bool same_value(const std::string& agent, const std::string& bridge) {
    if (agent == bridge) return true;
    char* end_a = nullptr;
    char* end_b = nullptr;
    const double a = std::strtod(agent.c_str(), &end_a);
    const double b = std::strtod(bridge.c_str(), &end_b);
    if (agent.empty() || bridge.empty() || *end_a != '\0' || *end_b != '\0') return false;
    return std::fabs(a - b) <= 1e-9 * std::max(1.0, std::fabs(b));
}

/// The agent's view after reading the bridge's whole SHDR snapshot.
ShdrAgent agent_of(const BridgeStore& store, const MtConnectApi& api) {
    ShdrAgent agent(api.probe("").body);
    std::string shdr;
    store.read([&](const BridgeState& st) {
        for (const auto& d : st.devices)
            for (ItemIndex i : d.items)
                if (st.buffer.latest()[i]) shdr += shdr_lines(d, st.items[i], *st.buffer.latest()[i]);
        return 0;
    });
    agent.feed(shdr);
    return agent;
}

}  // namespace

TEST_CASE("SHDR values come back to the agent as sent: quoted when they hold '|' or start with a quote") {
    for (const char* text : {"plain", "a|b", "\"quoted\" word", "\"", "back\\slash", "ends with \\", "|", "  lead",
                             "[{\"id\":\"T1\",\"name\":\"a|b\"}]", "{\"k\":\"\\\"|\\\\\"}", "with \"inner\" quotes"}) {
        INFO(text);
        const std::string field = shdr_value(text);
        CHECK(field.find('\n') == std::string::npos);
        const std::string devices =
            "<MTConnectDevices><Devices><Device uuid=\"u\" name=\"D\" id=\"d\"><DataItems>"
            "<DataItem category=\"EVENT\" id=\"m\" type=\"MESSAGE\"/>"
            "<DataItem category=\"EVENT\" id=\"p\" type=\"PROGRAM\"/></DataItems></Device></Devices></MTConnectDevices>";
        ShdrAgent agent(devices);
        agent.feed("2024-01-01T00:00:00.000Z|u:m||" + field + "\n2024-01-01T00:00:00.000Z|u:p|" + field + "\n");
        CHECK(agent.problems().empty());
        for (const char* id : {"m", "p"}) {
            REQUIRE(agent.current(id));
            CHECK(agent.current(id)->available);
            CHECK(agent.current(id)->value == text);
        }
    }
    CHECK(shdr_value("a\nb\tc") == "a b c");  // no line break can be carried
    CHECK(shdr_value("plain") == "plain");    // nothing quoted that needs no quoting
}

TEST_CASE("an agent reading the bridge's SHDR shows every item of the sim mill as the bridge does, lists and dicts included") {
    BridgeStore store(4096, "test", 7);
    const std::string dev = "nclink-sim-mill-01";
    store.add_device(dev);
    REQUIRE(store.set_model(dev, sim_mill_model()).ok());
    store.set_state(dev, "online");
    fill(store, dev, 1700000000000);
    const MtConnectApi api(store);
    const ShdrAgent agent = agent_of(store, api);
    INFO("agent problems: " << agent.problems().size() << (agent.problems().empty() ? "" : " first: " + agent.problems().front()));
    CHECK(agent.problems().empty());

    const auto shown = observations(api.current("", {}).body);
    REQUIRE(shown.size() > 30);
    std::size_t compared = 0;
    for (const auto& [id, text] : shown) {
        INFO(id << " bridge: " << text);
        const ShdrAgent::Current* c = agent.current(id);
        REQUIRE(c);
        if (text == "UNAVAILABLE" || text == "unavailable") {
            CHECK_FALSE(c->available);
            continue;
        }
        REQUIRE(c->available);
        INFO("agent: " << c->value);
        if (!c->level.empty()) CHECK(c->level == text);
        else CHECK(same_value(c->value, text));
        ++compared;
    }
    CHECK(compared == shown.size());  // the fill gave every item a value the bridge shows

    // The three list and dict items carry the value NC-Link has, as JSON text.
    const std::map<std::string, Json> structured = {
        {"tools", Json::array({Json{{"id", "T1"}, {"length", 101.5}, {"name", "end mill | 10 \"HSS\""}},
                               Json{{"id", "T2"}, {"length", 88.25}, {"name", "drill \\ 6"}}})},
        {"parameters", Json{{"1001", 12}, {"feed_max", 6000.5}, {"name", "a|b"}}},
        {"coordinates", Json::array({Json{{"id", "G54"}, {"x", -100.5}, {"y", 20}, {"z", 0}}})}};
    for (const auto& [nclink_id, value] : structured) {
        INFO(nclink_id);
        const ShdrAgent::Current* c = agent.current(dev + "." + nclink_id);
        REQUIRE(c);
        REQUIRE(c->available);
        CHECK(Json::parse(c->value) == value);
    }

    // Offline: every item UNAVAILABLE in the agent too (constants keep their value).
    store.set_state(dev, "offline");
    const ShdrAgent offline = agent_of(store, api);
    for (const auto& [id, text] : observations(api.current("", {}).body)) {
        INFO(id << " bridge: " << text);
        const ShdrAgent::Current* c = offline.current(id);
        REQUIRE(c);
        if (text == "UNAVAILABLE" || text == "unavailable") CHECK_FALSE(c->available);
        else CHECK(same_value(c->value, text));
    }
}

TEST_CASE("two machines of one model reach the agent each under its own device") {
    const char* model = R"({
      "id": "root", "type": "NC_LINK_ROOT", "version": "1.0",
      "devices": [{"id": "mill", "name": "Mill", "type": "MACHINE", "guid": "mill-01", "version": "1.0",
        "components": [{"id": "axis_x", "type": "AXIS", "number": "X",
                        "dataItems": [{"id": "x_position", "type": "POSITION", "units": "mm"}]}]}]
    })";
    BridgeStore store(64, "test", 7);
    for (const char* dev : {"mill-01", "mill-02"}) {
        store.add_device(dev);
        REQUIRE(store.set_model(dev, Json::parse(model)).ok());
        store.set_state(dev, "online");
    }
    store.update("mill-01", "x_position", 1.5, 1700000000000);
    store.update("mill-02", "x_position", 2.5, 1700000000001);
    const MtConnectApi api(store);
    const ShdrAgent agent = agent_of(store, api);
    CHECK(agent.problems().empty());
    REQUIRE(agent.current("mill-01.x_position"));
    REQUIRE(agent.current("mill-02.x_position"));
    CHECK(agent.current("mill-01.x_position")->value == "1.5");
    CHECK(agent.current("mill-02.x_position")->value == "2.5");
}

TEST_CASE(
    "a sample in units an agent converts goes in its nativeUnits, any other converted: the agent shows the bridge's value") {
    // One item per NC-Link unit the mapping gives nativeUnits (docs/mapping.md
    // "Units"); the agent converts a SAMPLE from nativeUnits to units by itself.
    const std::vector<std::pair<std::string, std::string>> units = {{"mm/min", "SPEED"},
                                                                    {"m/min", "SPEED"},
                                                                    {"rad", "POSITION"},
                                                                    {"μm", "POSITION"},
                                                                    {"m", "POSITION"},
                                                                    {"rad/s", "SPEED"},
                                                                    {"DEGREE/MINUTE", "SPEED"},
                                                                    {"RADIAN/MINUTE", "SPEED"},
                                                                    {"MICRO_RADIAN", "POSITION"},
                                                                    {"rad/s²", "ACCELERATION"},
                                                                    {"REVOLUTION/SECOND", "SPINDLE_SPEED"},
                                                                    {"mA", "CURRENT"},
                                                                    {"kW·h", "ENERGY"},
                                                                    {"W·h", "ENERGY"},
                                                                    {"JOULE", "ENERGY"},
                                                                    {"kW", "POWER"},
                                                                    {"mW", "POWER"},
                                                                    {"°F", "TEMPERATURE"},
                                                                    {"CENTIPOISE", "VISCOSITY"},
                                                                    {"kHz", "FREQUENCY"},
                                                                    {"mL/s", "FLOW"},
                                                                    {"kΩ", "RESISTANCE"}};
    Json items = Json::array();
    for (std::size_t i = 0; i < units.size(); ++i)
        items.push_back(Json{{"id", "v" + std::to_string(i)}, {"type", units[i].second}, {"units", units[i].first}});
    const Json model = {
        {"id", "root"},
        {"type", "NC_LINK_ROOT"},
        {"version", "1.0"},
        {"devices",
         Json::array({Json{
             {"id", "m"}, {"name", "M"}, {"type", "MACHINE"}, {"guid", "m-01"}, {"version", "1.0"}, {"dataItems", items}}})}};
    BridgeStore store(256, "test", 7);
    store.add_device("m-01");
    REQUIRE(store.set_model("m-01", model).ok());
    store.set_state("m-01", "online");
    for (std::size_t i = 0; i < units.size(); ++i) store.update("m-01", "v" + std::to_string(i), 37.5 + i, 1700000000000);
    const MtConnectApi api(store);
    const ShdrAgent agent = agent_of(store, api);
    CHECK(agent.problems().empty());
    const std::string probe = api.probe("").body;
    std::size_t compared = 0;
    for (const auto& [id, text] : observations(api.current("", {}).body)) {
        if (id == "m-01.m_avail") continue;
        const ShdrAgent::Current* c = agent.current(id);
        REQUIRE(c);
        INFO(id << " bridge: " << text << " agent: " << c->value);
        REQUIRE(c->available);
        CHECK(same_value(c->value, text));
        ++compared;
    }
    CHECK(compared == units.size());
    std::size_t declared = 0;  // every item is a SAMPLE with nativeUnits
    for (auto at = probe.find("nativeUnits=\""); at != std::string::npos; at = probe.find("nativeUnits=\"", at + 1)) ++declared;
    CHECK(declared == units.size());
    CHECK(probe.find("nativeUnits=\"MILLIMETER/MINUTE\"") != std::string::npos);
    CHECK(probe.find("nativeUnits=\"FAHRENHEIT\"") != std::string::npos);
}
