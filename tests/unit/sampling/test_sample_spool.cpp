// The sample spool (src/sampling/sample_spool.*): offline store-and-forward
// of Sample DTUs, over a scripted transport (link state and backlog set by
// the test) and once over the in-process loopback broker.
#include "sampling/sample_spool.hpp"

#include <nclink/testing/loopback_transport.hpp>

#include "support/recording_transport.hpp"
#include "support/wait.hpp"

#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <mutex>
#include <random>

using namespace nclink;
using namespace nclink::sampling_detail;
using nclink::test::eventually;

namespace {

/// Starts disconnected: the spool's tests bring the link up themselves.
struct ScriptedTransport final : nclink::test::RecordingTransport {
    ScriptedTransport() { link = LinkState::disconnected; }
};

/// A Sample DTU whose only varying value is its sequence number.
Message dtu(int n, std::size_t pad = 0) {
    Json j{{"guid", "dev"},
           {"id", "ch"},
           {"beginTime", std::to_string(1000 + n)},
           {"data", Json::array({Json{{"data", Json::array({n})}}})}};
    if (pad) j["pad"] = std::string(pad, 'x');
    return Message{"Sample/dev/ch", j.dump(), 0, false};
}

int seq_of(const Message& m) { return Json::parse(m.payload)["data"][0]["data"][0].get<int>(); }
bool marked(const Message& m) { return is_replayed(Json::parse(m.payload)); }

std::string scratch(const std::string& name) {
    const auto dir =
        std::filesystem::temp_directory_path() / ("nclink-spool-" + name + "-" + std::to_string(std::random_device{}()));
    std::filesystem::remove_all(dir);
    return dir.string();
}

struct DirGuard {
    std::string path;
    ~DirGuard() {
        std::error_code ec;
        std::filesystem::remove_all(path, ec);
    }
};

std::vector<int> seqs(const std::vector<Message>& ms) {
    std::vector<int> out;
    for (const auto& m : ms) out.push_back(seq_of(m));
    return out;
}

std::vector<int> range(int from, int to) {  // [from, to)
    std::vector<int> out;
    for (int i = from; i < to; ++i) out.push_back(i);
    return out;
}

}  // namespace

TEST_CASE("mark_replayed adds the marker without touching the rest") {
    const std::string plain = R"({"guid":"d","id":"c","beginTime":"1","data":[{"data":[1,2]}]})";
    const Json marked_dtu = Json::parse(mark_replayed(plain));
    CHECK(is_replayed(marked_dtu));
    CHECK(marked_dtu["privateInfo"] == Json{{"replayed", true}});
    Json without = marked_dtu;
    without.erase("privateInfo");
    CHECK(without == Json::parse(plain));
    CHECK_FALSE(is_replayed(Json::parse(plain)));

    CHECK(Json::parse(mark_replayed("{}")) == Json{{"privateInfo", {{"replayed", true}}}});
    CHECK(Json::parse(mark_replayed(" { \"a\" : 1 } \n"))["privateInfo"]["replayed"] == true);

    // An existing privateInfo keeps its keys; a non-object one is kept under "value".
    const Json kept = Json::parse(mark_replayed(R"({"id":"c","privateInfo":{"vendor":7}})"));
    CHECK(kept["privateInfo"] == Json{{"vendor", 7}, {"replayed", true}});
    CHECK(Json::parse(mark_replayed(R"({"id":"c","privateInfo":null})"))["privateInfo"] == Json{{"replayed", true}});
    CHECK(Json::parse(mark_replayed(R"({"id":"c","privateInfo":"x"})"))["privateInfo"] == Json{{"value", "x"}, {"replayed", true}});
    // A string value mentioning privateInfo is not mistaken for the key.
    const Json tricky = Json::parse(mark_replayed(R"({"id":"say \"privateInfo\""})"));
    CHECK(tricky["id"] == "say \"privateInfo\"");
    CHECK(is_replayed(tricky));

    // Not a JSON object: unchanged, never thrown.
    CHECK(mark_replayed("not json") == "not json");
    CHECK(mark_replayed("[1,2]") == "[1,2]");
    CHECK(mark_replayed(R"({"privateInfo": )") == R"({"privateInfo": )");
    CHECK(mark_replayed("") == "");
}

TEST_CASE("spool passes DTUs straight through while the link is up") {
    ScriptedTransport t;
    t.link = LinkState::connected;
    SampleSpool spool({}, t, {});
    REQUIRE(spool.start().ok());
    for (int i = 0; i < 5; ++i) spool.publish(dtu(i));
    const auto sent = t.messages();
    REQUIRE(seqs(sent) == range(0, 5));
    for (const auto& m : sent) CHECK_FALSE(marked(m));
    const auto s = spool.stats();
    CHECK(s.spooled == 0);
    CHECK(s.replayed == 0);
}

TEST_CASE("spool keeps DTUs while offline and replays them in order and marked before new data") {
    ScriptedTransport t;
    SampleSpool spool({}, t, {});
    REQUIRE(spool.start().ok());  // link down from the start
    for (int i = 0; i < 50; ++i) spool.publish(dtu(i));
    CHECK(t.count() == 0);
    CHECK(spool.stats().spooled == 50);
    CHECK(spool.stats().pending == 50);

    // Hold the replay back (transport backlog full), then let live data arrive
    // behind it: it must queue, not overtake.
    t.backlog = 1000;
    t.link = LinkState::connected;
    spool.on_link(LinkState::connected);
    for (int i = 50; i < 60; ++i) spool.publish(dtu(i));
    CHECK(t.count() == 0);
    t.backlog = 0;
    REQUIRE(eventually([&] { return t.count() == 60; }));
    const auto sent = t.messages();
    CHECK(seqs(sent) == range(0, 60));
    for (const auto& m : sent) CHECK(marked(m));  // all held by the spool
    REQUIRE(eventually([&] { return spool.empty(); }));

    // Once drained, live again: unmarked and straight through.
    spool.publish(dtu(60));
    REQUIRE(t.count() == 61);
    CHECK_FALSE(marked(t.messages().back()));
    const auto s = spool.stats();
    CHECK(s.spooled == 60);
    CHECK(s.replayed == 60);
    CHECK(s.dropped == 0);
    CHECK(s.pending == 0);
    CHECK(s.memory_bytes == 0);
}

TEST_CASE("spool replay is paced by the transport backlog") {
    ScriptedTransport t;
    SpoolOptions o;
    o.replay_backlog = 4;
    SampleSpool spool(o, t, {});
    REQUIRE(spool.start().ok());
    for (int i = 0; i < 20; ++i) spool.publish(dtu(i));
    t.backlog = 4;  // at the limit: nothing moves
    t.link = LinkState::connected;
    spool.on_link(LinkState::connected);
    std::this_thread::sleep_for(std::chrono::milliseconds(30));
    CHECK(t.count() == 0);
    t.backlog = 3;
    REQUIRE(eventually([&] { return t.count() == 20; }));
    CHECK(seqs(t.messages()) == range(0, 20));
}

TEST_CASE("spool stops replaying when the link drops again and resumes in order") {
    ScriptedTransport t;
    SampleSpool spool({}, t, {});
    REQUIRE(spool.start().ok());
    for (int i = 0; i < 10; ++i) spool.publish(dtu(i));
    t.backlog = 1000;
    t.link = LinkState::connected;
    spool.on_link(LinkState::connected);
    t.link = LinkState::disconnected;
    spool.on_link(LinkState::disconnected);
    t.backlog = 0;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    CHECK(t.count() == 0);
    for (int i = 10; i < 15; ++i) spool.publish(dtu(i));
    t.link = LinkState::connected;
    spool.on_link(LinkState::connected);
    REQUIRE(eventually([&] { return t.count() == 15; }));
    CHECK(seqs(t.messages()) == range(0, 15));
}

TEST_CASE("spool drops the oldest DTUs when its memory budget is full and counts them") {
    ScriptedTransport t;
    SpoolOptions o;
    const std::size_t one = dtu(10, 200).topic.size() + dtu(10, 200).payload.size();
    o.memory_bytes = one * 10 + one / 2;  // 10 fit
    SampleSpool spool(o, t, {});
    REQUIRE(spool.start().ok());
    for (int i = 10; i < 35; ++i) spool.publish(dtu(i, 200));  // same size (two-digit numbers)
    auto s = spool.stats();
    CHECK(s.spooled == 25);
    CHECK(s.dropped == 15);
    CHECK(s.dropped_bytes == 15 * one);
    CHECK(s.pending == 10);
    CHECK(s.memory_bytes <= o.memory_bytes);
    t.link = LinkState::connected;
    spool.on_link(LinkState::connected);
    REQUIRE(eventually([&] { return t.count() == 10; }));
    CHECK(seqs(t.messages()) == range(25, 35));  // the newest, intact and in order
}

TEST_CASE("spool without a memory budget drops what is produced offline") {
    ScriptedTransport t;
    SpoolOptions o;
    o.memory_bytes = 0;
    SampleSpool spool(o, t, {});
    REQUIRE(spool.start().ok());
    spool.publish(dtu(1));
    spool.publish(dtu(2));
    CHECK(spool.stats().dropped == 2);
    t.link = LinkState::connected;
    spool.on_link(LinkState::connected);
    spool.publish(dtu(3));
    REQUIRE(eventually([&] { return t.count() == 1; }));
    CHECK(seq_of(t.messages()[0]) == 3);
    CHECK_FALSE(marked(t.messages()[0]));
}

TEST_CASE("spool moves the oldest DTUs to disk segments and replays disk then memory in order") {
    DirGuard dir{scratch("spill")};
    ScriptedTransport t;
    SpoolOptions o;
    o.memory_bytes = 64u << 10;  // segments of 16 KiB
    o.disk_bytes = 4u << 20;
    o.disk_dir = dir.path;
    SampleSpool spool(o, t, {});
    REQUIRE(spool.start().ok());
    // ~300 B each, 1000 of them = ~300 KB: far more than RAM holds.
    for (int i = 0; i < 1000; ++i) {
        spool.publish(dtu(i, 200));
        if (i % 50 == 0) REQUIRE(eventually([&] { return spool.stats().memory_bytes <= o.memory_bytes / 2 + 400; }));
    }
    REQUIRE(eventually([&] { return spool.stats().memory_bytes <= o.memory_bytes / 2; }));
    auto s = spool.stats();
    CHECK(s.dropped == 0);
    CHECK(s.spilled > 500);
    CHECK(s.disk_segments > 5);
    CHECK(s.pending == 1000);
    CHECK(s.disk_bytes > 0);
    t.link = LinkState::connected;
    spool.on_link(LinkState::connected);
    REQUIRE(eventually([&] { return t.count() == 1000; }));
    CHECK(seqs(t.messages()) == range(0, 1000));
    REQUIRE(eventually([&] { return spool.stats().disk_segments == 0; }));
    s = spool.stats();
    CHECK(s.disk_bytes == 0);
    CHECK(s.replayed == 1000);
    CHECK(std::filesystem::is_empty(dir.path));  // segments deleted once replayed
}

TEST_CASE("spool disk budget drops the oldest segment when full") {
    DirGuard dir{scratch("diskfull")};
    ScriptedTransport t;
    SpoolOptions o;
    o.memory_bytes = 64u << 10;
    o.disk_bytes = 64u << 10;  // about 4 segments of 16 KiB
    o.disk_dir = dir.path;
    SampleSpool spool(o, t, {});
    REQUIRE(spool.start().ok());
    for (int i = 0; i < 1000; ++i) {
        spool.publish(dtu(i, 200));
        if (i % 50 == 0) REQUIRE(eventually([&] { return spool.stats().memory_bytes <= o.memory_bytes / 2 + 400; }));
    }
    REQUIRE(eventually([&] { return spool.stats().memory_bytes <= o.memory_bytes / 2; }));
    const auto before = spool.stats();
    CHECK(before.dropped > 0);
    CHECK(before.pending + before.dropped == 1000);
    t.link = LinkState::connected;
    spool.on_link(LinkState::connected);
    REQUIRE(eventually([&] { return spool.empty(); }));
    // (A spill still under way at `before` may have dropped one more segment.)
    const auto after = spool.stats();
    CHECK(after.disk_bytes == 0);
    REQUIRE(t.count() + after.dropped == 1000);
    // What is left is the newest part, contiguous and in order.
    CHECK(seqs(t.messages()) == range(static_cast<int>(after.dropped), 1000));
}

TEST_CASE("spool keeps what is spooled on disk across a stop and replays it after the next start") {
    DirGuard dir{scratch("restart")};
    SpoolOptions o;
    o.disk_bytes = 1u << 20;
    o.disk_dir = dir.path;
    {
        ScriptedTransport t;
        SampleSpool spool(o, t, {});
        REQUIRE(spool.start().ok());
        for (int i = 0; i < 30; ++i) spool.publish(dtu(i));
        spool.stop();  // offline: RAM goes to disk
        CHECK(spool.stats().pending == 30);
        spool.publish(dtu(99));  // after stop: dropped, counted
        CHECK(spool.stats().dropped == 1);
    }
    // A crash while writing leaves a .tmp: never read, removed.
    std::ofstream(dir.path + "/00000000000000ff-3.seg.tmp") << "garbage";
    ScriptedTransport t;
    t.link = LinkState::connected;
    SampleSpool spool(o, t, {});
    REQUIRE(spool.start().ok());
    REQUIRE(eventually([&] { return t.count() == 30; }));
    CHECK(seqs(t.messages()) == range(0, 30));
    for (const auto& m : t.messages()) CHECK(marked(m));
    REQUIRE(eventually([&] { return spool.empty(); }));
    spool.publish(dtu(30));
    REQUIRE(t.count() == 31);
    CHECK_FALSE(marked(t.messages().back()));
    CHECK_FALSE(std::filesystem::exists(dir.path + "/00000000000000ff-3.seg.tmp"));
}

TEST_CASE("spool replays a damaged segment up to the damage and counts the rest") {
    DirGuard dir{scratch("damaged")};
    std::vector<Message> batch;
    for (int i = 0; i < 10; ++i) batch.push_back(dtu(i));
    auto written = write_segment(dir.path, 1, batch);
    REQUIRE(written.ok());
    // Flip one byte inside the 6th record's payload.
    std::string bytes;
    {
        std::ifstream in(written.value().path, std::ios::binary);
        bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    }
    std::size_t at = 8;
    for (int i = 0; i < 5; ++i) at += segment_record_size(batch[static_cast<std::size_t>(i)]);
    bytes[at + 12 + batch[5].topic.size() + 3] ^= 0x20;
    std::ofstream(written.value().path, std::ios::binary | std::ios::trunc) << bytes;

    SpoolOptions o;
    o.disk_bytes = 1u << 20;
    o.disk_dir = dir.path;
    ScriptedTransport t;
    t.link = LinkState::connected;
    SampleSpool spool(o, t, {});
    REQUIRE(spool.start().ok());
    REQUIRE(eventually([&] { return t.count() == 5 && spool.empty(); }));
    CHECK(seqs(t.messages()) == range(0, 5));
    CHECK(spool.stats().dropped == 5);
}

TEST_CASE("spool segment encoding round-trips topic payload and qos") {
    std::vector<Message> batch{Message{"Sample/a/b", std::string("x\0y", 3), 1, false}, Message{"t", "", 0, false}};
    const auto contents = decode_segment(encode_segment(batch), 2);
    REQUIRE(contents.messages.size() == 2);
    CHECK(contents.damaged == 0);
    CHECK(contents.messages[0].topic == "Sample/a/b");
    CHECK(contents.messages[0].payload == std::string("x\0y", 3));
    CHECK(contents.messages[0].qos == 1);
    CHECK(contents.messages[1].payload.empty());
    // Cut short anywhere: never more than the whole records before the cut.
    const std::string whole = encode_segment(batch);
    for (std::size_t cut = 0; cut < whole.size(); ++cut) {
        const auto part = decode_segment(whole.substr(0, cut), 2);
        CHECK(part.messages.size() + part.damaged == 2);
        CHECK(part.messages.size() < 2);
    }
    CHECK(crc32("123456789", 9) == 0xCBF43926u);  // the standard check value
}

TEST_CASE("spool stop with the link up and no disk hands the rest to the transport") {
    ScriptedTransport t;
    SampleSpool spool({}, t, {});
    REQUIRE(spool.start().ok());
    for (int i = 0; i < 5; ++i) spool.publish(dtu(i));
    t.backlog = 1000;  // the replay thread cannot move anything
    t.link = LinkState::connected;
    spool.on_link(LinkState::connected);
    spool.stop();
    CHECK(seqs(t.messages()) == range(0, 5));
    CHECK(spool.stats().replayed == 5);
}

TEST_CASE("spool over the loopback broker: offline DTUs arrive after reconnect in order and marked") {
    LoopbackBroker broker;
    LoopbackOptions ao;
    ao.client_id = "app";
    auto app = make_loopback_transport(broker, ao);
    std::mutex mutex;
    std::vector<Message> got;
    app->set_message_handler([&](const Message& m) {
        std::lock_guard<std::mutex> lock(mutex);
        got.push_back(m);
    });
    REQUIRE(app->start().ok());
    REQUIRE(app->subscribe({"Sample/#", "probe"}, 1).ok());

    LoopbackOptions so;
    so.client_id = "adapter";
    auto link = make_loopback_transport(broker, so);
    SampleSpool spool({}, *link, {});
    // The spool hears of the reconnect only once the application has
    // resubscribed (else the replay could race the application's SUBSCRIBE).
    std::atomic<bool> hold_connect{false};
    link->set_state_handler([&](LinkState s, std::string_view) {
        if (s != LinkState::connected || !hold_connect) spool.on_link(s);
    });
    REQUIRE(link->start().ok());
    REQUIRE(eventually([&] { return link->state() == LinkState::connected && app->state() == LinkState::connected; }));
    REQUIRE(spool.start().ok());
    auto received = [&] {
        std::lock_guard<std::mutex> lock(mutex);
        return got;
    };
    for (int i = 0; i < 10; ++i) spool.publish(dtu(i));
    REQUIRE(eventually([&] { return received().size() == 10; }));
    hold_connect = true;
    broker.set_online(false);
    REQUIRE(eventually([&] { return link->state() != LinkState::connected; }));
    for (int i = 10; i < 40; ++i) spool.publish(dtu(i));
    CHECK(spool.stats().spooled == 30);
    broker.set_online(true);
    REQUIRE(eventually([&] { return link->state() == LinkState::connected; }));
    REQUIRE(eventually([&] {
        (void)link->publish(Message{"probe", "p", 1, false});
        return eventually([&] { return received().size() > 10; }, std::chrono::milliseconds(50));
    }));
    spool.on_link(LinkState::connected);
    auto samples = [&] {
        std::vector<Message> out;
        for (auto& m : received())
            if (m.topic != "probe") out.push_back(m);
        return out;
    };
    REQUIRE(eventually([&] { return samples().size() == 40; }));
    const auto all = samples();
    CHECK(seqs(all) == range(0, 40));
    for (std::size_t i = 0; i < all.size(); ++i) CHECK(marked(all[i]) == (i >= 10));
    spool.stop();
    link->stop(std::chrono::milliseconds(0));
    app->stop(std::chrono::milliseconds(0));
}
