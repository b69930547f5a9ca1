// Turns to connect on a shared MQTT loop (transport/connect_turns.hpp).
#include "transport/connect_turns.hpp"

#include <catch2/catch.hpp>

#include <array>

using nclink::transport_detail::ConnectTurns;
using nclink::transport_detail::LoopMember;

namespace {
// Only the addresses are used: members are never called.
std::array<char, 8> g_members;
LoopMember* member(int i) { return reinterpret_cast<LoopMember*>(&g_members[static_cast<std::size_t>(i)]); }
}  // namespace

TEST_CASE("connect turns: at most the limit connect at once, the rest in the order they asked") {
    ConnectTurns turns(2);
    CHECK(turns.take(member(0)));
    CHECK(turns.take(member(1)));
    CHECK_FALSE(turns.take(member(2)));
    CHECK_FALSE(turns.take(member(3)));
    CHECK_FALSE(turns.take(member(2)));  // asking again keeps its place
    CHECK(turns.waiting() == 2);
    CHECK(turns.connecting() == 2);
    // A CONNACK (or a failure) passes the turn to the oldest waiting.
    CHECK(turns.release(member(1)) == member(2));
    CHECK(turns.take(member(2)));  // its turn, given while it waited
    CHECK(turns.release(member(0)) == member(3));
    CHECK(turns.release(member(2)) == nullptr);  // nobody waits
    // A newcomer does not pass the ones already waiting.
    CHECK(turns.take(member(4)));
    CHECK_FALSE(turns.take(member(5)));
    CHECK_FALSE(turns.take(member(6)));
    CHECK(turns.release(member(3)) == member(5));
}

TEST_CASE("connect turns: a member that leaves gives back its turn or its place") {
    ConnectTurns turns(1);
    CHECK(turns.take(member(0)));
    CHECK_FALSE(turns.take(member(1)));
    CHECK_FALSE(turns.take(member(2)));
    CHECK(turns.release(member(1)) == nullptr);  // left while waiting: the turn is still taken
    CHECK(turns.waiting() == 1);
    CHECK(turns.release(member(0)) == member(2));  // member 1's place is skipped
    CHECK(turns.release(member(7)) == nullptr);    // holds nothing: nothing changes
    CHECK(turns.connecting() == 1);
    CHECK(turns.release(member(2)) == nullptr);
    CHECK(turns.connecting() == 0);
}

TEST_CASE("connect turns: limit 0 lets every connection go at once") {
    ConnectTurns turns(0);
    for (int i = 0; i < 8; ++i) CHECK(turns.take(member(i)));
    CHECK(turns.waiting() == 0);
    CHECK(turns.release(member(0)) == nullptr);
}
