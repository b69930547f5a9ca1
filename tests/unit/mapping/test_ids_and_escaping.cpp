// The identifier contract (NC-Link id <-> MTConnect XML ID) and XML escaping.
#include "mapping_test_util.hpp"

#include <catch2/catch.hpp>

#include <regex>
#include <set>

using namespace nclink;

TEST_CASE("mtconnect_id keeps ASCII XML names as they are") {
    for (const char* id : {"x_position", "axis_x", "a", "A.b-c_d", "mill", "sample_channel0"}) CHECK(mtconnect_id(id) == id);
}

TEST_CASE("mtconnect_id escapes ids that are no XML name behind an underscore") {
    CHECK(mtconnect_id("0103") == "_0103");
    CHECK(mtconnect_id("0103080402") == "_0103080402");
    CHECK(mtconnect_id("a b") == "_a_20b");
    CHECK(mtconnect_id("a:b") == "_a_3Ab");
    CHECK(mtconnect_id("_x") == "__5Fx");
    CHECK(mtconnect_id("") == "_");
    CHECK(mtconnect_id("轴") == "__E8_BD_B4");
    CHECK(mtconnect_id("a&b<c>\"'") == "_a_26b_3Cc_3E_22_27");
}

TEST_CASE("escaped ids are valid xs:ID values and map back to the NC-Link id") {
    const std::regex ncname("^[A-Za-z_][A-Za-z0-9._-]*$");
    const char* ids[] = {"0103",           "a b",      "_x", "__",  "x_5F", "a_20b", "轴号", "1.5", "-a", "a\tb",
                         "emergency stop", "ns=1;s=x", "",   "x/y", "_0103"};
    std::set<std::string> seen;
    for (const char* id : ids) {
        const std::string mt = mtconnect_id(id);
        INFO(id << " -> " << mt);
        CHECK(std::regex_match(mt, ncname));
        const auto back = nclink_id_from_mtconnect(mt);
        REQUIRE(back.has_value());
        CHECK(*back == id);
        CHECK(seen.insert(mt).second);  // injective over the sample
    }
}

TEST_CASE("nclink_id_from_mtconnect rejects text mtconnect_id never writes") {
    CHECK_FALSE(nclink_id_from_mtconnect("").has_value());
    CHECK_FALSE(nclink_id_from_mtconnect("__41").has_value());  // "A" is written as "A"
    CHECK_FALSE(nclink_id_from_mtconnect("_A").has_value());    // so is this one
    CHECK_FALSE(nclink_id_from_mtconnect("__4").has_value());   // cut escape
    CHECK_FALSE(nclink_id_from_mtconnect("__zz").has_value());  // not an escape
    CHECK_FALSE(nclink_id_from_mtconnect("__5f").has_value());  // lower-case hex
    CHECK_FALSE(nclink_id_from_mtconnect("1abc").has_value());  // no XML name
    CHECK_FALSE(nclink_id_from_mtconnect("a b").has_value());
    CHECK(nclink_id_from_mtconnect("_30") == std::optional<std::string>("30"));
    CHECK(nclink_id_from_mtconnect("_a_20b") == std::optional<std::string>("a b"));
}

TEST_CASE("xml_escape escapes markup and keeps white space through parsers") {
    CHECK(xml_escape("a&b<c>d\"e'f") == "a&amp;b&lt;c&gt;d&quot;e&apos;f");
    CHECK(xml_escape("l1\nl2\tx\r") == "l1&#10;l2&#9;x&#13;");
    CHECK(xml_escape("plain 数控 ✓ 😀") == "plain 数控 ✓ 😀");
}

TEST_CASE("xml_escape replaces what XML 1.0 forbids with U+FFFD") {
    const std::string fffd = "\xEF\xBF\xBD";
    CHECK(xml_escape(std::string("a\0b", 3)) == "a" + fffd + "b");
    CHECK(xml_escape("\x01\x08\x0B\x0C\x1F") == fffd + fffd + fffd + fffd + fffd);
    CHECK(xml_escape("\xEF\xBF\xBE") == fffd);                // U+FFFE
    CHECK(xml_escape("\xEF\xBF\xBF") == fffd);                // U+FFFF
    CHECK(xml_escape("\xC3\x28") == fffd + "(");              // broken sequence
    CHECK(xml_escape("\xC0\xAF") == fffd + fffd);             // overlong '/'
    CHECK(xml_escape("\xED\xA0\x80") == fffd + fffd + fffd);  // surrogate
    CHECK(xml_escape("\xE6\x95") == fffd + fffd);             // cut at the end
    CHECK(xml_escape("\x7F") == "\x7F");                      // DEL is a Char
}

TEST_CASE("id_prefix puts the escaped prefix and a dot before every MTConnect id, generated ones too") {
    const auto model = test::load_mapping_model("sim-mill.json");
    MappingOptions plain = test::fixed_options();
    auto without = mtconnect_mapping(*model, plain);
    REQUIRE(without.ok());
    for (const std::string prefix : {"nclink-sim-mill-02", "0001"}) {
        MappingOptions options = plain;
        options.id_prefix = prefix;
        const std::string expected = mtconnect_id(prefix) + ".";
        auto with = mtconnect_mapping(*model, options);
        REQUIRE(with.ok());
        CHECK(with->devices().front().id == expected + without->devices().front().id);
        CHECK(with->devices().front().availability_id == expected + without->devices().front().availability_id);
        CHECK(with->devices().front().uuid == without->devices().front().uuid);  // only ids change
        for (const auto& item : without->items()) {
            if (item.id.empty()) continue;
            const MtDataItem* prefixed = with->find(item.item_id);
            REQUIRE(prefixed);
            CHECK(prefixed->id == expected + item.id);
            CHECK(prefixed->component_id == expected + item.component_id);
            CHECK(prefixed->name == item.name);
            CHECK(with->find_by_mtconnect_id(prefixed->id) == prefixed);
        }
        // Every id attribute of the document, containers included, carries the prefix.
        auto doc = map_to_mtconnect(*model, options);
        REQUIRE(doc.ok());
        const std::regex id_attribute(" id=\"([^\"]*)\"");
        int ids = 0;
        for (auto it = std::sregex_iterator(doc->xml.begin(), doc->xml.end(), id_attribute); it != std::sregex_iterator();
             ++it, ++ids) {
            INFO((*it)[1]);
            CHECK(std::string((*it)[1]).rfind(expected, 0) == 0);
        }
        CHECK(ids > 10);
    }
}
