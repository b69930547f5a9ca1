// The MTConnect documents read with libxml2 (probe_document, streams_document):
// bad input is a clear error, never a crash.
#include "mtconnect/probe_document.hpp"
#include "mtconnect/streams_document.hpp"

#include <catch2/catch.hpp>

#include <string>

using namespace nclink;
using namespace nclink::mtconnect;

namespace {

const char* const kStreams = R"(<?xml version="1.0" encoding="UTF-8"?>
<MTConnectStreams xmlns="urn:mtconnect.org:MTConnectStreams:1.4">
  <Header creationTime="2024-01-01T00:00:00Z" sender="a" instanceId="42" version="1.4.0" bufferSize="16"
          nextSequence="108" firstSequence="90" lastSequence="107"/>
  <Streams>
    <DeviceStream name="VMC" uuid="u1">
      <ComponentStream component="Linear" componentId="X1">
        <Samples>
          <Position dataItemId="Xact" sequence="105" timestamp="2024-01-01T00:00:00Z">12.5</Position>
          <Position dataItemId="Xact" sequence="101" timestamp="2024-01-01T00:00:00Z">10</Position>
        </Samples>
        <Condition>
          <Fault dataItemId="Xtravel" sequence="103" nativeCode="E7" timestamp="2024-01-01T00:00:00Z">Overtravel</Fault>
          <Warning dataItemId="Xtravel" sequence="104" nativeCode="W1" timestamp="2024-01-01T00:00:00Z"/>
        </Condition>
      </ComponentStream>
      <ComponentStream component="Path" componentId="p">
        <Events>
          <Execution dataItemId="execution" sequence="102" timestamp="2024-01-01T00:00:00Z">ACTIVE</Execution>
        </Events>
      </ComponentStream>
    </DeviceStream>
  </Streams>
</MTConnectStreams>)";

}  // namespace

TEST_CASE("a Streams document is read in sequence order, conditions with their level and code") {
    auto r = read_streams(kStreams);
    REQUIRE(r.ok());
    REQUIRE_FALSE(r->is_error());
    const StreamsDocument& d = r->streams;
    CHECK(d.instance_id == "42");
    CHECK(d.next_sequence == 108);
    CHECK(d.first_sequence == 90);
    CHECK(d.last_sequence == 107);
    REQUIRE(d.observations.size() == 5);
    std::uint64_t last = 0;
    for (const auto& o : d.observations) {
        CHECK(o.sequence > last);
        last = o.sequence;
    }
    CHECK(d.observations[0].item_id == "Xact");
    CHECK(d.observations[0].text == "10");
    CHECK(d.observations[2].condition);
    CHECK(d.observations[2].element == "Fault");
    CHECK(d.observations[2].native_code == "E7");
    CHECK(d.observations[2].text == "Overtravel");
    CHECK(d.observations[3].element == "Warning");
    CHECK(d.observations[4].text == "12.5");
}

TEST_CASE("an MTConnectError answer is reported with its codes") {
    const char* error = R"(<?xml version="1.0"?>
<MTConnectError xmlns="urn:mtconnect.org:MTConnectError:1.4"><Header instanceId="42" sender="a" version="1.4.0" creationTime="x" bufferSize="1"/>
<Errors><Error errorCode="OUT_OF_RANGE">'from' must be greater than 89</Error></Errors></MTConnectError>)";
    auto r = read_streams(error);
    REQUIRE(r.ok());
    REQUIRE(r->is_error());
    CHECK(r->error_codes == std::vector<std::string>{"OUT_OF_RANGE"});
    CHECK(r->error_text == "OUT_OF_RANGE: 'from' must be greater than 89");

    auto p = read_probe(error);
    REQUIRE_FALSE(p.ok());
    CHECK(p.error().message.find("OUT_OF_RANGE") != std::string::npos);
}

TEST_CASE("malformed or unexpected documents give clear errors") {
    struct Case {
        const char* text;
        const char* says;
    };
    const Case probes[] = {
        {"", "not well-formed"},
        {"<MTConnectDevices><Header instanceId='1'/><Devices>", "not well-formed"},
        {"this is not xml", "not well-formed"},
        {"<?xml version='1.0'?><html><body>502 Bad Gateway</body></html>", "expected an MTConnectDevices document, got <html>"},
        {"<MTConnectDevices><Devices/></MTConnectDevices>", "without a Header"},
        {"<MTConnectDevices><Header instanceId='1'/></MTConnectDevices>", "without Devices"},
        {"<MTConnectDevices><Header instanceId='1'/><Devices/></MTConnectDevices>", "lists no device"},
        {"<MTConnectDevices><Header instanceId='1'/><Devices><Device id='d' uuid='u'><DataItems>"
         "<DataItem category='SAMPLE' type='POSITION'/></DataItems></Device></Devices></MTConnectDevices>",
         "lacks id, category or type"},
        // An entity expansion bomb is not expanded (no DTD processing).
        {"<?xml version='1.0'?><!DOCTYPE a [<!ENTITY x 'xxxxxxxxxx'><!ENTITY y '&x;&x;&x;&x;&x;'>]>"
         "<MTConnectDevices>&y;</MTConnectDevices>",
         "without a Header"},
    };
    for (const auto& c : probes) {
        INFO(c.text);
        auto r = read_probe(c.text);
        REQUIRE_FALSE(r.ok());
        CHECK(r.error().code == ErrorCode::syntax_error);
        CHECK(r.error().message.find(c.says) != std::string::npos);
    }
    const Case streams[] = {
        {"<MTConnectStreams><Header instanceId='1'", "not well-formed"},
        {"<MTConnectStreams/>", "without a Header"},
        {"<MTConnectStreams><Header instanceId='1' nextSequence='x' firstSequence='1' lastSequence='1'/></MTConnectStreams>",
         "lacks instanceId, nextSequence"},
        {"<MTConnectDevices/>", "expected an MTConnectStreams document"},
    };
    for (const auto& c : streams) {
        INFO(c.text);
        auto r = read_streams(c.text);
        REQUIRE_FALSE(r.ok());
        CHECK(r.error().message.find(c.says) != std::string::npos);
    }
}
