// The test record of GB/T 41970-2022 table C.1: what was tested, each item's
// outcome with the evidence (the DTU that failed and why), the object counts
// of the model and the overall verdict. Plain data; rendering is in report.hpp.
#pragma once

#include <nclink/json.hpp>

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace nclink::conform {

/// pass / fail / not supported (the adapter says so, or stays silent on an
/// optional feature) / skipped (the tester did not run it: no --allow-write,
/// a precondition missing).
enum class Outcome { pass, fail, not_supported, skipped };

std::string_view to_string(Outcome outcome) noexcept;  ///< "pass", "fail", "not supported", "skipped"

/// One piece of evidence: why, and the DTU (verbatim, truncated when huge)
/// with the topic it travelled on. topic/dtu may be empty (e.g. "no answer").
struct Evidence {
    std::string note;
    std::string topic;
    std::string dtu;
};

/// One row of table C.1 (one test item of tables 55-62).
struct ItemResult {
    std::string key;            ///< stable id: "register", "query", "event-data", ...
    std::string title;          ///< "Data query"
    std::string c1_row;         ///< the C.1 row: "数据查询"
    std::string clause;         ///< "table 57 item 1, 8.2.11/8.2.12"
    bool c1_mandatory = false;  ///< C.1 marks the row 必选项
    /// Not supported makes the verdict fail (table 17: adapters "应支持").
    bool required = false;
    Outcome outcome = Outcome::pass;
    std::string summary;             ///< one line: what was checked / why the outcome
    std::vector<std::string> notes;  ///< observations that are not failures
    std::vector<Evidence> evidence;  ///< failures (and the DTU behind a not-supported)

    /// Records a failure (fail dominates every other outcome).
    void fail(std::string note, std::string topic = {}, std::string dtu = {});
    /// Not supported (unless already failed).
    void not_supported(std::string why, std::string topic = {}, std::string dtu = {});
    /// Skipped (unless already decided otherwise).
    void skip(std::string why);
    std::size_t failures() const noexcept;
};

/// Object counts of the model-file check (C.1 "模型文件数据项定义检查").
struct ObjectCounts {
    std::size_t components_standard = 0;  ///< `type` in table 8
    std::size_t components_custom = 0;
    std::size_t data_standard = 0;  ///< `type` in tables 10, 12, 13
    std::size_t data_custom = 0;
    std::size_t channels = 0;
    std::size_t methods = 0;
};

enum class Verdict { pass, fail };

struct TestRecord {
    // Basic information (C.1 "基本信息").
    std::string device;  ///< dev_uuid under test
    std::string broker;
    std::string client_id;  ///< the tester's ex_cid
    std::string date;       ///< ISO 8601 UTC, start of the run
    std::string tool = "nclink-conform";
    std::string tool_version;
    std::string model_version;  ///< the device's version from the probe ("" if no model)
    bool allow_write = false;

    std::optional<ObjectCounts> objects;  ///< absent when no model could be read
    std::vector<ItemResult> items;

    /// fail when an item failed, or a required item is not supported.
    Verdict verdict() const;
    std::size_t count(Outcome outcome) const;
    const ItemResult* find(std::string_view key) const;
};

/// Cuts a DTU text for evidence (keeps the head, says how much was cut).
std::string clip(std::string text, std::size_t max = 4000);

}  // namespace nclink::conform
