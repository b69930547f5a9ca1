// The request handlers of the adapter: each turns one decoded request into
// its response DTU against one model snapshot. They run on request workers
// and call the driver through its runner (deadlines, serialization).
#pragma once

#include "adapter/model_host.hpp"
#include "driver/driver_runner.hpp"
#include "feature/value_guard.hpp"

#include <nclink/dtu.hpp>

#include <functional>
#include <string>

namespace nclink::adapter_detail {

struct HandlerContext {
    const feature_detail::ModelState& state;
    driver_detail::DriverRunner& driver;
    const ModelHost& host;
    const std::string& dev;
    const Logger& logger;
    /// The SDK-provided statistics item (SamplingConfig::stats_item, "" = none):
    /// a Query of this id, when the model has no item of that id, answers
    /// stats() as a dict value.
    std::string stats_item = {};
    std::function<Json()> stats = {};
    /// Set when the request's deadline passed while the driver still had it
    /// (driver-affine Query, or a driver-affine Set its worker never
    /// started): driver items answer this error, the driver is not called;
    /// SDK-held items answer (and are set) as usual.
    const Error* driver_expired = nullptr;
    /// Checks the driver's values against chapter 7 (null: not checked).
    feature_detail::ValueGuard* values = nullptr;
};

/// 8.2.11/8.2.12: the answer's text, one result per requested item, in
/// order. SDK-held items are answered from the store, the rest read from the
/// driver in one batch.
std::string handle_query(const QueryRequest& request, const HandlerContext& context);

/// 8.2.13/8.2.14: one result per item, in order. `setable` is enforced (301);
/// SDK-held items change in the store (and are persisted); driver items are
/// validated against the current value and written through the driver.
SetResponse handle_set(const SetRequest& request, const HandlerContext& context);

/// 8.2.7/8.2.8.
/// The Probe/Query answer as payload text: `probe` is the model as provided
/// (the vendor's file, byte for byte; 8.2.8), spliced in as the JSON object
/// it is, so "1.0" stays "1.0" and the key order and spacing are the vendor's.
std::string handle_probe_query(const ProbeQueryRequest& request, const HandlerContext& context);

/// Text of every problem that makes a Probe/Set model unacceptable (fatal, and
/// conformance when strict), "" when acceptable.
std::string refusal_reasons(const LoadResult& loaded, bool strict);

}  // namespace nclink::adapter_detail
