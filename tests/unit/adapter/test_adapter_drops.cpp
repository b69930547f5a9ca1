// The statistics' "drops" object (docs/delivery.md, "Counted drops"): the
// adapter's own causes plus each feature's, which the feature names itself
// (DropCounts) both live (housekeeping) and from a statistics snapshot.
#include "adapter/adapter_features.hpp"
#include "adapter/drop_reporter.hpp"
#include "support/adapter_fixture.hpp"

#include <catch2/catch.hpp>

#include <map>
#include <set>
#include <string>

using namespace nclink;
using namespace nclink::test;

namespace {

std::map<std::string, std::uint64_t> as_map(const feature_detail::DropCounts& d) {
    std::map<std::string, std::uint64_t> out;
    for (const auto& [cause, count] : d.causes()) out[cause] = count;
    return out;
}

}  // namespace

TEST_CASE("drop counts: a cause added twice sums, a zero is kept, the order is first added") {
    feature_detail::DropCounts d;
    d.add("b", 0);
    d.add("a", 2);
    d.add("b", 3);
    d.add("a", 1);
    REQUIRE(d.causes().size() == 2);
    CHECK(d.causes()[0] == std::pair<std::string, std::uint64_t>{"b", 3});
    CHECK(d.causes()[1] == std::pair<std::string, std::uint64_t>{"a", 3});
}

TEST_CASE("feature drops from a statistics snapshot: each feature reads its own causes back") {
    const Json features = {
        {"sampling",
         {{"channels", Json::array({Json{{"drops", 3}}, Json{{"drops", 4}}})}, {"spool", {{"dropped", 2}}}, {"publish_errors", 1}}},
        {"events", {{"dropped_values", 5}, {"publish_errors", 6}}},
        {"methods", Json::object()}};
    feature_detail::DropCounts d;
    adapter_detail::feature_drops_from_stats(features, d);
    CHECK(as_map(d) == std::map<std::string, std::uint64_t>{{"sample_ring_full", 7},
                                                            {"sample_spool_full", 2},
                                                            {"sample_publish_refused", 1},
                                                            {"event_values_queue_full", 5},
                                                            {"events_publish_refused", 6}});
    feature_detail::DropCounts none;
    adapter_detail::feature_drops_from_stats(Json::object(), none);  // no feature in the snapshot: every cause at 0
    CHECK(as_map(none) == std::map<std::string, std::uint64_t>{{"sample_ring_full", 0},
                                                               {"sample_spool_full", 0},
                                                               {"sample_publish_refused", 0},
                                                               {"event_values_queue_full", 0},
                                                               {"events_publish_refused", 0}});
    const Json drops = adapter_detail::drops_by_cause(d, 8, 9);
    CHECK(drops["offline_buffer_full"] == 8);
    CHECK(drops["requests_shed"] == 9);
    CHECK(drops["sample_ring_full"] == 7);
    CHECK(drops.size() == 7);
}

TEST_CASE("a running adapter's statistics list every cause of drops, its own and each feature's") {
    AdapterFixture f;
    const Json drops = to_json(f.adapter->stats())["drops"];
    std::set<std::string> causes;
    for (const auto& [cause, count] : drops.items()) {
        causes.insert(cause);
        CHECK(count == 0);
    }
    CHECK(causes == std::set<std::string>{"offline_buffer_full", "requests_shed", "sample_ring_full", "sample_spool_full",
                                          "sample_publish_refused", "event_values_queue_full", "events_publish_refused"});
}
