// Runs the test items of GB/T 41970-2022 tables 55-62 against one adapter
// over a connected Wire and fills in the test record of table C.1.
//
// Safety: read-only unless `allow_write`; with it, every change is undone
// (Set restores the original value, Probe/Set restores the original model),
// and only the method named by `method` is ever called.
//
// Threads: run() blocks the calling thread; it is not reentrant.
#pragma once

#include "conform/record.hpp"
#include "conform/wire.hpp"

#include <nclink/json.hpp>
#include <nclink/log.hpp>

#include <chrono>
#include <optional>
#include <set>
#include <string>
#include <vector>

namespace nclink::conform {

struct RunOptions {
    std::string device;        ///< dev_uuid under test (required)
    std::string broker;        ///< for the record only
    bool allow_write = false;  ///< Set, Probe/Set and method items (else skipped)
    /// How long to wait for the answer to one request.
    std::chrono::milliseconds timeout{3000};
    /// Longest wait for a run of Sample DTUs (slow channels are cut here).
    std::chrono::milliseconds max_wait{30000};
    std::string method;               ///< method to call (with allow_write); "" = none
    std::optional<Json> method_args;  ///< its args (default: the model's `args`)
    Logger logger;                    ///< progress lines
    /// Feature groups to run after the basics (connection, state, probe,
    /// model file, query), by item key prefix: "sampling", "event",
    /// "dynamic", "set", "model-set", "method". Empty: all. The others are
    /// skipped. (Tests use it to repeat one group.)
    std::set<std::string> only;
};

/// The filters the tester subscribes to before run(): every response, sample,
/// event, method and state topic of `dev` and the agent's answers to `ex`.
std::vector<std::string> tester_subscriptions(const std::string& dev, const std::string& ex);

/// Runs every item; `wire` must be connected (Wire::connect with
/// tester_subscriptions). The record's date/tool fields are filled in too.
TestRecord run_conformance(Wire& wire, const RunOptions& options);

}  // namespace nclink::conform
