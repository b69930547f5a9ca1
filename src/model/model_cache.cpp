// ModelCache (include/nclink/model_cache.hpp): parsed models and their value
// rules, shared by the adapters that load the same unchanged file.
#include <nclink/model_cache.hpp>

#include <filesystem>
#include <map>
#include <mutex>
#include <system_error>
#include <vector>

namespace nclink {

namespace {

// What tells an unchanged file: its size and modification time. A file
// rewritten within the file system's time resolution with the same size is
// taken for the old one; model files change by deployment, not that fast.
struct FileStamp {
    std::uintmax_t size = 0;
    std::filesystem::file_time_type written{};
    bool operator==(const FileStamp& o) const { return size == o.size && written == o.written; }
};

std::optional<FileStamp> stamp_of(const std::string& path) {
    std::error_code ec;
    FileStamp s;
    s.size = std::filesystem::file_size(path, ec);
    if (ec) return std::nullopt;
    s.written = std::filesystem::last_write_time(path, ec);
    if (ec) return std::nullopt;
    return s;
}

// One load's model and document under one owner (ModelCache::load()).
struct Parsed {
    std::shared_ptr<const Model> model;
    std::shared_ptr<const std::string> document;
};

}  // namespace

struct ModelCache::Impl {
    struct Entry {
        FileStamp stamp;
        std::weak_ptr<const Model> model;
        std::weak_ptr<const std::string> document;
        std::vector<Problem> problems;
    };
    mutable std::mutex mutex;
    std::map<std::string, Entry> files;
    // Keyed by the model's address; the weak pointer tells a live model from
    // a later one at the same address.
    std::map<const Model*, std::pair<std::weak_ptr<const Model>, std::weak_ptr<const ValueRules>>> rules;
    std::size_t parses = 0;
};

ModelCache::ModelCache() : impl_(std::make_unique<Impl>()) {}
ModelCache::~ModelCache() = default;

LoadResult ModelCache::load(const std::string& path) {
    const auto stamp = stamp_of(path);
    std::lock_guard<std::mutex> lock(impl_->mutex);
    if (stamp) {
        const auto found = impl_->files.find(path);
        if (found != impl_->files.end() && found->second.stamp == *stamp) {
            LoadResult hit;
            hit.model = found->second.model.lock();
            hit.document = found->second.document.lock();
            if (hit.model && hit.document) {
                hit.problems = found->second.problems;
                return hit;
            }
        }
    }
    // Parsed under the lock: machines started together wait for one parse
    // rather than each making its own.
    LoadResult loaded = load_model_file(path);
    ++impl_->parses;
    if (loaded.model && loaded.document) {
        // The model and its document live as long as either is held. A
        // loader that keeps only the model (a simulated machine's driver
        // needs no document) would otherwise let the document go at once,
        // the entry would no longer match, and every machine after it would
        // parse the file again and hold a model of its own (0.1 MB a
        // 300-point machine in a gateway, docs/performance.md).
        const auto both = std::make_shared<const Parsed>(Parsed{std::move(loaded.model), std::move(loaded.document)});
        loaded.model = std::shared_ptr<const Model>(both, both->model.get());
        loaded.document = std::shared_ptr<const std::string>(both, both->document.get());
    }
    if (stamp && loaded.model && loaded.document)
        impl_->files[path] = Impl::Entry{*stamp, loaded.model, loaded.document, loaded.problems};
    else impl_->files.erase(path);
    return loaded;
}

std::shared_ptr<const ValueRules> ModelCache::rules(const std::shared_ptr<const Model>& model) {
    if (!model) return std::make_shared<const ValueRules>();
    std::lock_guard<std::mutex> lock(impl_->mutex);
    // Forget the rules of models nobody holds any more.
    for (auto it = impl_->rules.begin(); it != impl_->rules.end();)
        it = it->second.first.expired() ? impl_->rules.erase(it) : std::next(it);
    auto& slot = impl_->rules[model.get()];
    if (auto kept = slot.second.lock(); kept && slot.first.lock() == model) return kept;
    auto made = std::make_shared<const ValueRules>(*model);
    slot = {model, made};
    return made;
}

std::size_t ModelCache::parses() const {
    std::lock_guard<std::mutex> lock(impl_->mutex);
    return impl_->parses;
}

}  // namespace nclink
