// The checks of the conformance tester as pure functions: each takes a DTU
// (already parsed JSON) and what the model/request lead us to expect, and
// returns every problem found (empty = conforming). No I/O, no clocks: the
// runner (runner.hpp) feeds them what came off the wire, unit tests feed them
// good and bad DTUs.
//
// Reference: GB/T 41970-2022 chapter 8 tables 18-52 and docs/wire.md
// (the project's wire decisions); see docs/conformance.md for the mapping.
#pragma once

#include "conform/record.hpp"

#include <nclink/json.hpp>
#include <nclink/model.hpp>
#include <nclink/transport.hpp>

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace nclink::conform {

using Problems = std::vector<std::string>;

/// The payload as a JSON object, or why not ("not JSON: ...", "not an object").
std::optional<Json> parse_object(std::string_view payload, std::string* why = nullptr);

// ---- status and envelope (tables 18-20, 8.1.3) -------------------------------

/// "code" is "OK".
bool is_ok(const Json& dtu);
/// How "not supported" is told apart from a failure: an NG answer with error
/// 202 (Unavailable, table 19: "数据或服务不可用"), or reason "Unavailable", or a
/// reason saying "not supported"/"unsupported" (any case). Only such answers
/// and silence on an optional feature count as not supported.
bool says_not_supported(const Json& dtu);
/// code is "OK"/"NG"; reason, when present, a string; error, when present, a number.
Problems check_status_keys(const Json& dtu);
/// "@id" echoed verbatim (when the request had one); guid equal to `dev` (and
/// present when `guid_required`, as tables 33-52 require).
Problems check_envelope(const Json& dtu, const Json& sent_id, std::string_view dev, bool guid_required);

// ---- connection (table 55) ----------------------------------------------------

/// Register/Response (table 22): cli_uuid is ours, code OK.
Problems check_register_response(const Json& dtu, const Json& sent_id, std::string_view cli_uuid);
/// Discovery/Response (tables 24/25): guid = ex, code OK, deviceList entries
/// well formed, and `dev` listed.
Problems check_discovery_response(const Json& dtu, const Json& sent_id, std::string_view ex, std::string_view dev);

// ---- model (table 56, 9.3.2) ----------------------------------------------------

struct ProbeCheck {
    Problems problems;
    std::optional<Json> model;  ///< the probe as a JSON object (given as an object or a string holding JSON)
};
/// Probe/Query/Response (table 29): code OK with a probe object.
ProbeCheck check_probe_response(const Json& dtu, const Json& sent_id, std::string_view dev);

/// The device of `model` that `dev` names (resolve_dev_uuid), else the only
/// device; nullptr when neither.
const Device* device_for(const Model& model, std::string_view dev);
/// Data objects the adapter of `device` serves: its own and the root's.
std::vector<const DataObject*> served_items(const Model& model, const Device& device);
/// C.1 object counts: standard vocabulary (tables 8, 10, 12, 13) vs custom types.
ObjectCounts count_objects(const Model& model);
/// "1.0.0" -> "1.0.1", "v1.2" -> "v1.2.1", "" -> "1.0.1", anything else gets ".1".
std::string bump_version(std::string_view version);

// ---- Query / Set (table 57) ----------------------------------------------------

/// Query/Response (table 33): envelope, one entry per requested id in order,
/// each with id, code and on OK a `values` array. Entry problems are prefixed
/// with the item id.
Problems check_query_response(const Json& dtu, const Json& sent_id, std::string_view dev, const std::vector<std::string>& ids);
/// The `values` of a whole-item Query of `item` (docs/values.md: `[value]` for every
/// kind): one element; an array (or null) for a list, an object (or null) for
/// a dict; equal to the model's fixed `value` when it has one.
Problems check_whole_value(const DataObject& item, const Json& values);
/// get_length answer `[n]` matching the whole list (when known).
Problems check_list_length(const Json& values, const Json& whole);
/// get_keys answer: strings, the keys of the whole dict (when known).
Problems check_dict_keys(const Json& values, const Json& whole);
/// Set/Response (table 35): envelope, one `results` entry per id in order.
Problems check_set_response(const Json& dtu, const Json& sent_id, std::string_view dev, const std::vector<std::string>& ids);
/// The `code`/`error` of entry `index` of a Query/Set answer's values/results.
const Json* result_entry(const Json& dtu, std::size_t index);

// ---- sampling (tables 36, 42; table 58 and 60) -----------------------------------

struct ChannelSpec {
    std::string id;
    std::size_t columns = 0;  ///< sampled data items (entries of `data`)
    double sample_ms = 0;
    double upload_ms = 0;
    /// Rows one DTU should carry: uploadInterval / sampleInterval (at least 1).
    double expected_rows() const;
};
struct SampleShape {
    std::int64_t begin_time = 0;
    std::size_t rows = 0;
};
struct SampleCheck {
    Problems problems;
    std::optional<SampleShape> shape;  ///< when data and beginTime could be read
};
/// One Sample DTU: guid = dev, id = channel, beginTime a string of epoch ms,
/// one {"data":[...]} per column, every column the same number of rows,
/// rows plausible for the intervals.
SampleCheck check_sample_dtu(const Json& dtu, std::string_view dev, const ChannelSpec& spec);

struct SampleArrival {
    std::int64_t begin_time = 0;
    std::size_t rows = 0;
    std::int64_t arrived_ms = 0;  ///< tester's clock
};
/// A run of Sample DTUs of one channel, in arrival order: beginTime increasing
/// and continuous (next = begin + rows x sampleInterval, within tolerance),
/// rows and upload pace near the model's intervals (medians, so one late
/// message does not fail the channel).
Problems check_sample_sequence(const std::vector<SampleArrival>& run, const ChannelSpec& spec);

/// Register/Sample/Response (table 39): envelope, code; on OK a channel id.
Problems check_sample_register_response(const Json& dtu, const Json& sent_id, std::string_view dev);
/// Unregister/Sample|Event/Response (tables 41, 51).
Problems check_unregister_response(const Json& dtu, const Json& sent_id, std::string_view dev);

// ---- events (table 59) ----------------------------------------------------------

/// Register/Event/Response (table 49): envelope, code; on OK an event id.
Problems check_event_register_response(const Json& dtu, const Json& sent_id, std::string_view dev);
/// Event (table 52, figure 17): guid, id = event id, time a number of epoch
/// ms, event {id = item, value}.
Problems check_event_data(const Json& dtu, std::string_view dev, std::string_view event_id, std::string_view item_id);

// ---- methods (table 62) -----------------------------------------------------------

/// Method/Status (table 44).
Problems check_method_status(const Json& dtu, std::string_view dev, std::string_view method_id);
/// Method/Result (table 45): @id of the call, result finished/canceled/error, code.
Problems check_method_result(const Json& dtu, const Json& sent_id, std::string_view dev, std::string_view method_id);
/// Method/Control/Response (table 47).
Problems check_method_control_response(const Json& dtu, const Json& sent_id, std::string_view dev, std::string_view method_id);

// ---- state (table 61) ------------------------------------------------------------

/// Notify/State/{dev} (table 37, docs/wire.md): a JSON object, state "online" (the
/// adapter is serving), tid = dev when present, retained.
Problems check_notify_state(const Message& message, std::string_view dev);

/// True for a plausible epoch time in milliseconds (2000-01-01 .. 2100-01-01):
/// catches seconds and relative times.
bool plausible_epoch_ms(std::int64_t ms);

}  // namespace nclink::conform
