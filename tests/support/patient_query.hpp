// A Query of the FakeDriver's two items ("pos", "status" of "test-dev",
// adapter_fixture.hpp), asked again until answered: after a (re)connection,
// or through a broker cluster, the adapter's SUBSCRIBE may still be on its way.
#pragma once

#include "support/wait.hpp"

#include <nclink/client.hpp>

#include <catch2/catch.hpp>

#include <chrono>
#include <vector>

namespace nclink::test {

inline std::vector<QueryResult> patient_query(Client& client, std::chrono::milliseconds within = std::chrono::seconds(30)) {
    RequestOptions patient;
    patient.timeout = std::chrono::seconds(3);
    Result<std::vector<QueryResult>> answer = make_error(ErrorCode::unavailable, "not asked yet");
    REQUIRE(eventually(
        [&] {
            answer = client.query("test-dev", {{"pos", std::nullopt}, {"status", std::nullopt}}, patient);
            return answer.ok();
        },
        within));
    return std::move(answer).value();
}

}  // namespace nclink::test
