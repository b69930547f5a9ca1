// One parse of a model file for every adapter that serves it.
//
// A gateway runs many machines of one kind from one model file; each adapter
// loading it alone held its own copy of the model's objects and value rules,
// about 0.7 MB per 300-point machine (docs/performance.md, "Memory per
// machine"). A Model is immutable once loaded (LoadResult::model is a
// shared_ptr<const Model>), so the machines can share one: only the terminal
// id differs, and it lives in the adapter (resolve_dev_uuid), not the model.
#pragma once

#include <nclink/export.hpp>
#include <nclink/model.hpp>
#include <nclink/value_rules.hpp>

#include <cstddef>
#include <memory>
#include <string>

namespace nclink {

/// Thread-safe. Holds nothing alive by itself: an entry is reused while some
/// adapter still holds its model, and parsed again after the last one let
/// go or the file changed (size or modification time).
class NCLINK_API ModelCache {
public:
    ModelCache();
    ~ModelCache();
    ModelCache(const ModelCache&) = delete;
    ModelCache& operator=(const ModelCache&) = delete;

    /// load_model_file(path), or the result of its last parse while the
    /// file is unchanged and that model is still in use.
    LoadResult load(const std::string& path);
    /// ValueRules(*model), built once per model while in use.
    std::shared_ptr<const ValueRules> rules(const std::shared_ptr<const Model>& model);
    /// How many times a file was parsed (for tests and statistics).
    std::size_t parses() const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace nclink
