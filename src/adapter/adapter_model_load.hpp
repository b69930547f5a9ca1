// Which model file a start serves (adapter.cpp's start()): the shipped one,
// or the one a Probe/Set or replace_model() persisted, and why, in the log.
#pragma once

#include "adapter/model_host.hpp"

#include <nclink/adapter_config.hpp>
#include <nclink/log.hpp>
#include <nclink/model.hpp>
#include <nclink/result.hpp>

namespace nclink::adapter_detail {

/// The model to serve, loaded and checked (refused models are an error
/// naming every problem); removes a persisted model a newer shipped one
/// replaces.
Result<LoadResult> load_adapter_model(const AdapterConfig& config, const ModelHost& host, const Logger& logger);

}  // namespace nclink::adapter_detail
