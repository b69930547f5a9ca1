// serialize is a fixed point: parse(serialize(parse(f))) == parse(f) for models/.
#include "model_test_util.hpp"

#include <catch2/catch.hpp>

using namespace nclink;
using nclink::test::describe;

TEST_CASE("every loadable file in models/ round-trips through serialize") {
    std::size_t loaded = 0;
    for (const auto& dir : {nclink::test::models_dir(), nclink::test::model_path("invalid")}) {
        for (const auto& file : nclink::test::json_files(dir)) {
            INFO(file.string());
            const LoadResult first = load_model_file(file.string());
            if (dir == nclink::test::models_dir()) REQUIRE(first.ok());
            if (!first.ok()) continue;
            ++loaded;
            const std::string text = serialize_model(*first.model);
            const LoadResult second = parse_model(text);
            INFO(text << "\n" << describe(second));
            REQUIRE(second.ok());
            CHECK(*second.model == *first.model);
            // Serialized output is chapter-6 clean: no aliases, versions present.
            CHECK(second.count(Severity::conformance) <= first.count(Severity::conformance));
            // And a second pass changes nothing at all.
            CHECK(serialize_model(*second.model) == text);
        }
    }
    CHECK(loaded >= 4 + 40);
}

TEST_CASE("serialize writes chapter-6 spelling in table order with 2-space indent") {
    const LoadResult r = load_model_file(nclink::test::model_path("appendix-b.json"));
    REQUIRE(r.ok());
    const std::string text = serialize_model(*r.model);
    CHECK(text.find("\"dataType\"") == std::string::npos);
    CHECK(text.find("\"settable\"") == std::string::npos);
    CHECK(text.find("\"datatype\": \"list\"") != std::string::npos);
    CHECK(text.find("\"setable\": true") != std::string::npos);
    CHECK(text.rfind("{\n  \"id\": \"01\",\n  \"name\": ", 0) == 0);
    // id, name, type, description: in that order, not alphabetical
    const auto id = text.find("\"id\": \"0103\"");
    const auto name = text.find("\"name\": \"数控机床\"", id);
    const auto type = text.find("\"type\": \"MACHINE\"");
    const auto version = text.find("\"version\": \"1.0.0\"", id);
    CHECK(id < name);
    CHECK(name < version);
    CHECK(type > id);
    CHECK(type < name + 40);
    // Sample intervals stay integers.
    CHECK(text.find("\"sampleInterval\": 2000") != std::string::npos);
}

TEST_CASE("model equality sees attribute changes and ignores pointers") {
    const LoadResult a = load_model_file(nclink::test::model_path("sim-mill.json"));
    REQUIRE(a.ok());
    Json doc = model_to_json(*a.model);
    CHECK(*parse_model(doc.dump()).model == *a.model);
    doc["devices"][0]["components"][0]["dataItems"][0]["units"] = "m";
    const LoadResult b = parse_model(doc.dump());
    REQUIRE(b.ok());
    CHECK(*b.model != *a.model);
}
