#include "agent/state_store.hpp"

#include "core/atomic_file.hpp"

#include <fmt/format.h>

#include <filesystem>
#include <fstream>
#include <sstream>

namespace nclink::agent_detail {
namespace {

// Terminal ids may hold any UTF-8 but '/', so they are not safe file names.
std::string hex_name(const std::string& id) {
    std::string out;
    for (unsigned char c : id) out += fmt::format("{:02x}", c);
    return out;
}

std::optional<std::string> read_text(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return std::nullopt;
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

}  // namespace

std::string StateStore::registry_path() const { return (std::filesystem::path(dir_) / "registry.json").string(); }

std::string StateStore::model_path(const std::string& dev) const {
    return (std::filesystem::path(dir_) / "models" / (hex_name(dev) + ".json")).string();
}

Result<void> StateStore::load(Registrar& registrar, Presence& presence, ModelCache& models, const Logger& log) const {
    if (!enabled()) return ok_result();
    if (auto text = read_text(registry_path())) {
        const Json doc = Json::parse(*text, nullptr, false);
        if (!doc.is_object() || !doc.contains("terminals") || !doc["terminals"].is_object())
            return make_error(ErrorCode::syntax_error, fmt::format("{} is not an agent registry", registry_path()));
        for (auto it = doc["terminals"].begin(); it != doc["terminals"].end(); ++it) {
            const Json& t = it.value();
            if (!t.is_object()) continue;
            Registration r;
            r.kind = kind_from_string(t.value("kind", std::string()));
            r.registered_at_s = t.value("registeredAt", std::int64_t{0});
            registrar.restore(it.key(), r);
            presence.remember(it.key(), r.kind, t.value("lastAlive", std::int64_t{0}));
        }
    }
    std::error_code ec;
    const auto dir = std::filesystem::path(dir_) / "models";
    if (!std::filesystem::is_directory(dir, ec)) return ok_result();
    for (const auto& file : std::filesystem::directory_iterator(dir, ec)) {
        if (file.path().extension() != ".json") continue;
        const auto text = read_text(file.path().string());
        const Json doc = text ? Json::parse(*text, nullptr, false) : Json();
        if (!doc.is_object() || !doc.contains("dev") || !doc["dev"].is_string() || !doc.contains("model") ||
            !doc["model"].is_object()) {
            log.warn("agent: {} is not a cached model; skipped", file.path().string());
            continue;
        }
        CachedModel entry;
        entry.version = doc.value("version", std::string());
        entry.model_version = entry.version;
        entry.model = doc["model"];
        entry.fetched_at_s = doc.value("fetchedAt", std::int64_t{0});
        models.restore(doc["dev"].get<std::string>(), std::move(entry));
    }
    return ok_result();
}

Result<void> StateStore::save_registry(const Registrar& registrar, const Presence& presence) const {
    if (!enabled()) return ok_result();
    Json terminals = Json::object();
    for (const auto& [tid, r] : registrar.all()) {
        Kind kind = presence.kind(tid);
        if (kind == Kind::unknown) kind = r.kind;
        terminals[tid] = {
            {"kind", to_string(kind)}, {"registeredAt", r.registered_at_s}, {"lastAlive", presence.last_alive_s(tid)}};
    }
    const Json doc = {{"format", 1}, {"terminals", std::move(terminals)}};
    return core_detail::write_file_atomically(registry_path(), doc.dump(2, ' ', false, Json::error_handler_t::replace));
}

Result<void> StateStore::save_model(const std::string& dev, const CachedModel& entry) const {
    if (!enabled() || !entry.model) return ok_result();
    const Json doc = {{"dev", dev}, {"version", entry.model_version}, {"fetchedAt", entry.fetched_at_s}, {"model", *entry.model}};
    return core_detail::write_file_atomically(model_path(dev), doc.dump(-1, ' ', false, Json::error_handler_t::replace));
}

}  // namespace nclink::agent_detail
