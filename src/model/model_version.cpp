#include <nclink/model_version.hpp>

#include <algorithm>
#include <cstdint>
#include <vector>

namespace nclink {
namespace {

/// The numbers of a version, or nullopt when it is not of the chapter-6 form.
std::optional<std::vector<std::uint64_t>> parts_of(std::string_view v) {
    if (!v.empty() && (v.front() == 'v' || v.front() == 'V')) v.remove_prefix(1);
    if (v.empty()) return std::nullopt;
    std::vector<std::uint64_t> parts;
    std::uint64_t number = 0;
    std::size_t digits = 0;
    for (std::size_t i = 0; i <= v.size(); ++i) {
        if (i == v.size() || v[i] == '.') {
            if (digits == 0) return std::nullopt;  // "1..2", "1.", ".1"
            parts.push_back(number);
            number = 0;
            digits = 0;
            continue;
        }
        if (v[i] < '0' || v[i] > '9' || ++digits > 18) return std::nullopt;
        number = number * 10 + static_cast<std::uint64_t>(v[i] - '0');
    }
    return parts;
}

}  // namespace

std::optional<int> compare_model_versions(std::string_view a, std::string_view b) noexcept {
    try {
        const auto pa = parts_of(a), pb = parts_of(b);
        if (!pa || !pb) return std::nullopt;
        const std::size_t n = std::max(pa->size(), pb->size());
        for (std::size_t i = 0; i < n; ++i) {
            const std::uint64_t x = i < pa->size() ? (*pa)[i] : 0, y = i < pb->size() ? (*pb)[i] : 0;
            if (x != y) return x < y ? -1 : 1;
        }
        return 0;
    } catch (...) {  // allocation failure: no order can be told
        return std::nullopt;
    }
}

bool is_model_version(std::string_view version) noexcept {
    try {
        return parts_of(version).has_value();
    } catch (...) {
        return false;
    }
}

std::string next_model_version(std::string_view version) {
    if (!is_model_version(version)) return std::string(version) + ".1";
    const std::size_t dot = version.rfind('.');
    const std::size_t start = dot == std::string_view::npos ? (version.front() == 'v' || version.front() == 'V' ? 1 : 0) : dot + 1;
    const std::uint64_t last = std::stoull(std::string(version.substr(start)));
    return std::string(version.substr(0, start)) + std::to_string(last + 1);
}

}  // namespace nclink
