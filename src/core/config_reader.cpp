#include "core/config_reader.hpp"

#include "core/nearest.hpp"

#include <algorithm>
#include <cctype>

namespace nclink::core_detail {
namespace {

std::string folded(std::string_view word) {
    std::string out;
    for (char c : word)
        if (c != '_' && c != '-') out += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return out;
}

}  // namespace

std::optional<std::string> nearest_key(std::string_view word, const std::vector<std::string>& candidates) {
    const std::string w = folded(word);
    if (w.empty() || word.size() > 128) return std::nullopt;
    std::optional<std::string> best;
    std::size_t best_distance = 0;
    for (const auto& candidate : candidates) {
        const std::string c = folded(candidate);
        // Folded first, so "keepAliveS" and "client-id" are 1-2 edits from
        // "keep_alive_s" and "client_id" (edit_distance: core/nearest.hpp).
        std::size_t d = edit_distance(w, c);
        // A key that holds the word whole ("timeout" in "request_timeout_ms")
        // is a good guess too, though many edits away.
        if (d > 2 && w.size() >= 4 && c.find(w) != std::string::npos) d = 2;
        if (!best || d < best_distance) best = candidate, best_distance = d;
    }
    // Close enough to be a typo: at most 2 edits, and fewer than a third of
    // the word for short words ("url" for "uri", not "tls" for "url").
    if (!best || best_distance > 2 || best_distance * 3 > std::max<std::size_t>(w.size(), 3)) return std::nullopt;
    return best;
}

std::string pointer_append(std::string pointer, std::string_view key) {
    pointer += '/';
    for (char c : key) {
        if (c == '~') pointer += "~0";
        else if (c == '/') pointer += "~1";
        else pointer += c;
    }
    return pointer;
}

std::string pointer_of_where(std::string_view where) {
    std::string pointer;
    std::size_t start = 0;
    while (start < where.size()) {
        std::size_t dot = where.find('.', start);
        if (dot == std::string_view::npos) dot = where.size();
        if (dot > start) pointer = pointer_append(std::move(pointer), where.substr(start, dot - start));
        start = dot + 1;
    }
    return pointer;
}

Error ConfigReader::fail(ErrorCode code, std::string_view key, std::string_view text) const {
    const bool sentence = text.rfind("must", 0) == 0;
    std::string_view where = where_;
    if (key.empty() && !where.empty() && where.back() == '.') where.remove_suffix(1);  // the section itself
    Error e = make_error(code, fmt::format("configuration: {}{}{}{}", where, key, sentence ? " " : ": ", text));
    e.pointer = key.empty() ? pointer_ : pointer_append(pointer_, key);
    return e;
}

Result<void> ConfigReader::no_unknown_keys() const {
    if (!object_.is_object()) return ok_result();
    for (auto it = object_.begin(); it != object_.end(); ++it) {
        if (seen_.count(it.key())) continue;
        std::string text = "unknown key";
        if (auto guess = nearest_key(it.key(), order_)) text += fmt::format("; did you mean \"{}\"?", *guess);
        std::string valid;
        for (const auto& k : order_) valid += (valid.empty() ? "" : ", ") + k;
        text += order_.empty() ? " (no keys are valid here)" : fmt::format(" (valid keys: {})", valid);
        return fail(ErrorCode::keys_of_arguments, it.key(), text);
    }
    return ok_result();
}

}  // namespace nclink::core_detail
