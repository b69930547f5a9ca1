// The agent's picture (agent/agent_picture.hpp): what it knows of the
// terminals, reachable only under its lock, and the small decisions every
// handler shares.
#include "agent/agent_picture.hpp"

#include <nclink/dtu.hpp>
#include <nclink/topics.hpp>

#include <catch2/catch.hpp>

#include <atomic>
#include <thread>

using namespace nclink;
using namespace nclink::agent_detail;
using namespace std::chrono_literals;

namespace {
const Clock::Steady t0{};
}

TEST_CASE("agent picture: the first DTU of a terminal makes it online once, and is a registry change") {
    Picture picture(10s, 10s);
    picture.with([](Picture::State& p) {
        CHECK(p.saw("mill-1", Kind::adapter, t0, 100));
        CHECK_FALSE(p.saw("mill-1", Kind::adapter, t0 + 1s, 101));  // already online
        CHECK(p.presence.kind("mill-1") == Kind::adapter);
        CHECK(p.presence.status("mill-1") == Status::online);
        CHECK(p.saves.take(false).registry == false);  // nothing is written before the files were read
        p.saves.loaded();
        CHECK(p.saw("app-1", Kind::application, t0, 100));
        CHECK(p.saves.take(false).registry);
    });
}

TEST_CASE("agent picture: its own Notify/State comes back once per announcement and is recognised") {
    Picture picture(10s, 10s);
    picture.with([](Picture::State& p) {
        const Message m = p.announce("mill-1", Status::online);
        CHECK(m.topic == topics::notify_state("mill-1"));
        CHECK(m.retained);
        CHECK(decode<NotifyState>(m.payload).value().state == "online");
        (void)p.announce("mill-1", Status::online);
        CHECK(p.own_echo("mill-1", "online"));
        CHECK(p.own_echo("mill-1", "online"));
        CHECK_FALSE(p.own_echo("mill-1", "online"));  // a third is somebody else's
        CHECK_FALSE(p.own_echo("mill-2", "online"));
        (void)p.announce("mill-1", Status::offline);
        CHECK_FALSE(p.own_echo("mill-1", "online"));
        CHECK(p.own_echo("mill-1", "offline"));
    });
}

TEST_CASE("agent picture: pairs are `initial` until serving starts, then follow presence") {
    Picture picture(10s, 10s);
    picture.with([](Picture::State& p) {
        CHECK(p.pair_state("app-1", "mill-1") == AgentState::initial);
        p.started_serving = true;
        CHECK(p.pair_state("app-1", "mill-1") == agent_state_of(true, true));  // unknown counts as online
        CHECK(p.presence.set_state("mill-1", Status::offline, t0, 100));
        CHECK(p.pair_state("app-1", "mill-1") == agent_state_of(true, false));
        CHECK(p.pair_state(std::nullopt, "mill-1") == agent_state_of(true, false));
    });
}

TEST_CASE("agent picture: own request ids are fresh and name the agent and the purpose") {
    Picture picture(10s, 10s);
    picture.with([](Picture::State& p) {
        CHECK(p.next_id("agent-1", "fetch") == "agent-1-fetch-1");
        CHECK(p.next_id("agent-1", "kind") == "agent-1-kind-2");
    });
}

TEST_CASE("agent picture: terminals lists the present and the registered, once each") {
    Picture picture(10s, 10s);
    picture.with([](Picture::State& p) {
        p.registrar = std::make_unique<Registrar>(TerminalIdRule::make(RegistrationPolicy{}).value(), RegistrationPolicy{});
        p.registrar->record("mill-1", Kind::adapter, 50, 1);
        p.registrar->record("mill-2", Kind::adapter, 60, 1);
        (void)p.saw("mill-1", Kind::adapter, t0, 100);
        (void)p.saw("app-1", Kind::application, t0, 100);
    });
    const auto list = picture.with([](const Picture::State& p) { return p.terminals(); });
    REQUIRE(list.size() == 3);
    CHECK(list[0].id == "app-1");
    CHECK(list[0].kind == "application");
    CHECK_FALSE(list[0].registered);
    CHECK(list[1].id == "mill-1");
    CHECK(list[1].registered);
    CHECK(list[1].status == "online");
    CHECK(list[2].id == "mill-2");
    CHECK(list[2].registered);
}

TEST_CASE("agent picture: with() excludes other threads while its function runs") {
    Picture picture(10s, 10s);
    std::atomic<int> inside{0}, overlaps{0};
    auto worker = [&] {
        for (int i = 0; i < 2000; ++i)
            picture.with([&](Picture::State& p) {
                if (inside.fetch_add(1) != 0) ++overlaps;
                (void)p.next_id("a", "x");
                inside.fetch_sub(1);
            });
    };
    std::thread a(worker), b(worker);
    a.join();
    b.join();
    CHECK(overlaps == 0);
    CHECK(picture.with([](Picture::State& p) { return p.next_id("a", "x"); }) == "a-x-4001");
}
